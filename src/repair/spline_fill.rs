//! Filling a hole with the 2022 paper's spline where its surroundings are a height field:
//! the rings of vertices around the hole are projected on their least-squares plane, the
//! smoothing spline of their heights is fitted with the hole's cells filled (Kouibia &
//! Pasadas 2022 §4, the cells without data as H_h), and the hole's polygon is triangulated
//! (constrained Delaunay, interior points at the border's edge length) with its interior
//! points lifted onto the filled spline.

use nalgebra::{Matrix3, SymmetricEigen, Vector3};
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use crate::fit::data::ScatteredData;
use crate::fit::fill::FillVariant;
use crate::fit::pipeline::{fit_and_fill, FitSetup, HoleSource, SpaceKind};
use crate::mesh::planar::{distance, distance_to_border, is_simple, point_in_polygon, signed_area};

/// Rings of vertices around the hole whose heights the spline fits.
const RINGS: usize = 3;
/// The smoothing weight ε of the fit, in coordinates scaled to the rings' extent.
const EPSILON: f64 = 1e-6;
/// Most interior points of one filled hole.
const MAX_INTERIOR_POINTS: usize = 200_000;
/// Most border edges of a hole filled this way: the simplicity check and each interior
/// point's distance to the border go over every edge (a larger hole gets a fan).
const MAX_BORDER_EDGES: usize = 2000;

/// A corner of a filling triangle: a vertex of the hole's border (by its position in the
/// cycle) or a new interior point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Corner {
    Border(usize),
    Interior(usize),
}

/// The filling of one hole: new points and triangles, each running as the cycle does.
#[derive(Debug, Clone)]
pub struct SplineFilling {
    pub points: Vec<[f64; 3]>,
    pub triangles: Vec<[Corner; 3]>,
    /// Cells per side of the fitted spline and data points it fitted.
    pub cells: usize,
    pub data_points: usize,
}

/// The facets around each vertex, for the rings.
pub struct VertexFacets {
    offsets: Vec<usize>,
    facets: Vec<u32>,
}

impl VertexFacets {
    pub fn new(vertex_count: usize, faces: &[Option<Vec<u32>>]) -> Self {
        let mut counts = vec![0usize; vertex_count + 1];
        for corners in faces.iter().flatten() {
            for &v in corners {
                counts[v as usize + 1] += 1;
            }
        }
        for i in 0..vertex_count {
            counts[i + 1] += counts[i];
        }
        let mut next = counts.clone();
        let mut facets = vec![0u32; counts[vertex_count]];
        for (f, corners) in faces.iter().enumerate() {
            for &v in corners.iter().flatten() {
                facets[next[v as usize]] = f as u32;
                next[v as usize] += 1;
            }
        }
        VertexFacets {
            offsets: counts,
            facets,
        }
    }

    fn of(&self, v: u32) -> &[u32] {
        &self.facets[self.offsets[v as usize]..self.offsets[v as usize + 1]]
    }
}

/// The spline filling of the hole bounded by `cycle` (vertex ids in the order the new
/// facets run), or why the hole is not filled this way: its surroundings are not a height
/// field over their plane, the border does not project to a simple polygon, or the fit
/// fails.
pub fn spline_fill(
    cycle: &[u32],
    positions: &[[f64; 3]],
    faces: &[Option<Vec<u32>>],
    around: &VertexFacets,
) -> Result<SplineFilling, String> {
    if cycle.len() > MAX_BORDER_EDGES {
        return Err(format!(
            "its border has more than {MAX_BORDER_EDGES} edges (the spline fill's bound)"
        ));
    }
    let (ring_vertices, ring_facets) = rings(cycle, faces, around);
    let points: Vec<[f64; 3]> = ring_vertices
        .iter()
        .map(|&v| positions[v as usize])
        .collect();
    let frame = Frame::fit(&points).ok_or("its surroundings are degenerate (collinear)")?;
    // Height field: every facet around the hole projects with the same orientation.
    let mut sign = 0.0;
    for &f in &ring_facets {
        let corners = faces[f as usize].as_ref().expect("live facet");
        let area = signed_area(
            &corners
                .iter()
                .map(|&v| frame.uv(positions[v as usize]))
                .collect::<Vec<_>>(),
        );
        if sign == 0.0 {
            sign = area.signum();
        }
        if area * sign <= 0.0 {
            return Err(format!(
                "its surroundings are not a height field over their plane (facet {f} folds over)"
            ));
        }
    }
    let border: Vec<[f64; 2]> = cycle
        .iter()
        .map(|&v| frame.uv(positions[v as usize]))
        .collect();
    // The new facets run as the cycle does and must cover the hole beside the surrounding
    // facets, not on top of them (an outer border encloses its surface instead).
    if signed_area(&border) * sign <= 0.0 {
        return Err(
            "its surroundings lie inside its border in projection (an outer border, not a hole)"
                .into(),
        );
    }
    if !is_simple(&border) {
        return Err("its border does not project to a simple polygon".into());
    }
    let data = ScatteredData {
        params: points.iter().map(|&p| frame.uv(p)).collect(),
        points: points
            .iter()
            .map(|&p| {
                let [u, v] = frame.uv(p);
                [u, v, frame.height(p)]
            })
            .collect(),
    };
    let cells = ((data.params.len() as f64 / 4.0).sqrt().round() as usize).clamp(3, 12);
    let setup = FitSetup {
        space: SpaceKind::Biquadratic,
        cells: [cells, cells],
        epsilon: EPSILON,
        hole: HoleSource::CellsWithoutData,
        variant: FillVariant::Paper,
        shape: None,
    };
    let spline = fit_and_fill(&data, &setup).map_err(|e| format!("the spline fit failed: {e}"))?;

    let spacing = (0..border.len())
        .map(|k| distance(border[k], border[(k + 1) % border.len()]))
        .sum::<f64>()
        / border.len() as f64;
    let interior = interior_points(&border, spacing)?;
    let triangles = triangulate(&border, &interior)?;
    let lifted = interior
        .iter()
        .map(|&[u, v]| {
            let value = spline
                .eval(u, v)
                .map_err(|e| format!("the spline at ({u}, {v}): {e}"))?;
            let p = frame.point(u, v, value[2]);
            if p.iter().all(|x| x.is_finite()) {
                Ok(p)
            } else {
                Err(format!("the spline is not finite at ({u}, {v})"))
            }
        })
        .collect::<Result<Vec<_>, String>>()?;
    Ok(SplineFilling {
        points: lifted,
        triangles,
        cells,
        data_points: data.params.len(),
    })
}

/// The vertices within `RINGS` rings of the cycle and the facets they span.
fn rings(cycle: &[u32], faces: &[Option<Vec<u32>>], around: &VertexFacets) -> (Vec<u32>, Vec<u32>) {
    let mut seen_vertex: std::collections::HashSet<u32> = cycle.iter().copied().collect();
    let mut seen_facet = std::collections::HashSet::new();
    let mut vertices: Vec<u32> = cycle.to_vec();
    let mut facets = Vec::new();
    let mut frontier: Vec<u32> = cycle.to_vec();
    for _ in 0..RINGS {
        let mut next = Vec::new();
        for &v in &frontier {
            for &f in around.of(v) {
                if !seen_facet.insert(f) {
                    continue;
                }
                facets.push(f);
                for &w in faces[f as usize].iter().flatten() {
                    if seen_vertex.insert(w) {
                        vertices.push(w);
                        next.push(w);
                    }
                }
            }
        }
        frontier = next;
    }
    (vertices, facets)
}

/// The rings' least-squares plane, with coordinates scaled to their extent.
struct Frame {
    origin: Vector3<f64>,
    axes: [Vector3<f64>; 3],
    scale: f64,
}

impl Frame {
    fn fit(points: &[[f64; 3]]) -> Option<Frame> {
        let n = points.len() as f64;
        let origin = points
            .iter()
            .fold(Vector3::zeros(), |s, p| s + Vector3::from(*p))
            / n;
        let mut covariance = Matrix3::zeros();
        for p in points {
            let d = Vector3::from(*p) - origin;
            covariance += d * d.transpose();
        }
        let eigen = SymmetricEigen::new(covariance);
        let mut order = [0, 1, 2];
        order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
        let axis = |k: usize| eigen.eigenvectors.column(order[k]).into_owned();
        let (e1, e2) = (axis(0), axis(1));
        let normal = e1.cross(&e2);
        let scale = points
            .iter()
            .map(|p| (Vector3::from(*p) - origin).norm())
            .fold(0.0, f64::max);
        (eigen.eigenvalues[order[1]] > 1e-12 * eigen.eigenvalues[order[0]] && scale > 0.0)
            .then_some(Frame {
                origin,
                axes: [e1, e2, normal],
                scale,
            })
    }

    fn uv(&self, p: [f64; 3]) -> [f64; 2] {
        let d = Vector3::from(p) - self.origin;
        [
            self.axes[0].dot(&d) / self.scale,
            self.axes[1].dot(&d) / self.scale,
        ]
    }

    fn height(&self, p: [f64; 3]) -> f64 {
        self.axes[2].dot(&(Vector3::from(p) - self.origin)) / self.scale
    }

    fn point(&self, u: f64, v: f64, h: f64) -> [f64; 3] {
        let p = self.origin + (self.axes[0] * u + self.axes[1] * v + self.axes[2] * h) * self.scale;
        [p.x, p.y, p.z]
    }
}

/// A lattice of points at `spacing` inside the polygon, none closer than half a spacing to
/// its border.
fn interior_points(border: &[[f64; 2]], spacing: f64) -> Result<Vec<[f64; 2]>, String> {
    let lo = border
        .iter()
        .fold([f64::INFINITY; 2], |m, p| [m[0].min(p[0]), m[1].min(p[1])]);
    let hi = border.iter().fold([f64::NEG_INFINITY; 2], |m, p| {
        [m[0].max(p[0]), m[1].max(p[1])]
    });
    // A hexagonal lattice: rows √3/2 spacings apart, alternate rows shifted by half a
    // spacing, for nearly equilateral triangles.
    let row = spacing * 3f64.sqrt() / 2.0;
    let (nu, nv) = (
        ((hi[0] - lo[0]) / spacing).ceil() as usize + 1,
        ((hi[1] - lo[1]) / row).ceil() as usize + 1,
    );
    if nu.saturating_mul(nv) > 4 * MAX_INTERIOR_POINTS {
        return Err(format!(
            "its interior would take more than {MAX_INTERIOR_POINTS} points"
        ));
    }
    let mut out = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let shift = if j % 2 == 1 { 0.5 } else { 0.0 };
            let q = [lo[0] + (i as f64 + shift) * spacing, lo[1] + j as f64 * row];
            if point_in_polygon(q, border) && distance_to_border(q, border) > 0.5 * spacing {
                out.push(q);
            }
        }
    }
    if out.len() > MAX_INTERIOR_POINTS {
        return Err(format!(
            "its interior would take more than {MAX_INTERIOR_POINTS} points"
        ));
    }
    Ok(out)
}

/// The constrained Delaunay triangulation of the polygon with interior points, its
/// triangles running as the polygon does.
fn triangulate(border: &[[f64; 2]], interior: &[[f64; 2]]) -> Result<Vec<[Corner; 3]>, String> {
    let mut cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::new();
    let mut corner_of = std::collections::HashMap::new();
    let mut handles = Vec::with_capacity(border.len());
    for (k, p) in border.iter().enumerate() {
        let h = cdt
            .insert(Point2::new(p[0], p[1]))
            .map_err(|e| format!("the border's point {k}: {e:?}"))?;
        if corner_of.insert(h.index(), Corner::Border(k)).is_some() {
            return Err("two border vertices project to one point".into());
        }
        handles.push(h);
    }
    for k in 0..border.len() {
        let (a, b) = (handles[k], handles[(k + 1) % border.len()]);
        if !cdt.can_add_constraint(a, b) {
            return Err("its border crosses itself in projection".into());
        }
        cdt.add_constraint(a, b);
    }
    for (k, p) in interior.iter().enumerate() {
        let h = cdt
            .insert(Point2::new(p[0], p[1]))
            .map_err(|e| format!("interior point {k}: {e:?}"))?;
        if corner_of.insert(h.index(), Corner::Interior(k)).is_some() {
            return Err("an interior point fell on another point".into());
        }
    }
    let sign = signed_area(border).signum();
    let mut triangles = Vec::new();
    for face in cdt.inner_faces() {
        let v = face.vertices();
        let q = v.map(|x| [x.position().x, x.position().y]);
        let centroid = [
            (q[0][0] + q[1][0] + q[2][0]) / 3.0,
            (q[0][1] + q[1][1] + q[2][1]) / 3.0,
        ];
        if !point_in_polygon(centroid, border) {
            continue;
        }
        let mut corners = v.map(|x| corner_of[&x.fix().index()]);
        if signed_area(&q) * sign < 0.0 {
            corners.swap(1, 2);
        }
        triangles.push(corners);
    }
    Ok(triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_with_a_point_inside_is_four_triangles_running_as_the_square() {
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let t = triangulate(&square, &[[0.5, 0.5]]).unwrap();
        assert_eq!(t.len(), 4);
        for tri in &t {
            let q = tri.map(|c| match c {
                Corner::Border(k) => square[k],
                Corner::Interior(_) => [0.5, 0.5],
            });
            assert!(signed_area(&q) > 0.0);
        }
    }

    #[test]
    fn a_border_past_the_bound_is_left_to_the_fan() {
        let n = MAX_BORDER_EDGES + 1;
        let positions: Vec<[f64; 3]> = (0..n)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        let cycle: Vec<u32> = (0..n as u32).collect();
        let faces = vec![Some(cycle.clone())];
        let around = VertexFacets::new(n, &faces);
        let why = spline_fill(&cycle, &positions, &faces, &around).unwrap_err();
        assert!(why.contains("more than 2000 edges"), "{why}");
    }
}
