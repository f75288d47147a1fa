//! Sampling a parametric spline surface into a quad mesh, for viewing and for MeshLab
//! (per-vertex quality = a scalar such as the local fit error).

use crate::error::{Error, Result};
use crate::mesh::PolygonMesh;

/// A (res + 1) × (res + 1) lattice of [u₀, u₁] × [v₀, v₁] mapped by `surface`, as quads;
/// `quality` gives each vertex's scalar from its (u, v).
///
/// Errors: `InvalidInput` for res = 0 or an empty/non-finite rectangle; any error of
/// `surface` or `quality`.
pub fn sample_mesh(
    u: [f64; 2],
    v: [f64; 2],
    res: usize,
    surface: &dyn Fn(f64, f64) -> Result<[f64; 3]>,
    quality: Option<&dyn Fn(f64, f64) -> Result<f64>>,
) -> Result<PolygonMesh> {
    if res == 0 || !(u[0] < u[1] && v[0] < v[1]) || u.iter().chain(&v).any(|x| !x.is_finite()) {
        return Err(Error::InvalidInput(format!(
            "sampling needs res ≥ 1 and a non-empty finite rectangle, got {res}, {u:?} × {v:?}"
        )));
    }
    let n = res + 1;
    let mut pos = Vec::with_capacity(n * n);
    let mut q = Vec::with_capacity(n * n);
    for i in 0..n {
        for j in 0..n {
            // Clamped: u₀ + (u₁ − u₀)·res/res can round one ulp past u₁, outside the
            // spline's rectangle.
            let s = (u[0] + (u[1] - u[0]) * i as f64 / res as f64).min(u[1]);
            let t = (v[0] + (v[1] - v[0]) * j as f64 / res as f64).min(v[1]);
            let p = surface(s, t)?;
            if !p.iter().all(|x| x.is_finite()) {
                return Err(Error::InvalidInput(format!(
                    "the surface is not finite at (u, v) = ({s}, {t}): {p:?} (data values \
                     near the range of f64? scale them down)"
                )));
            }
            pos.push(p);
            if let Some(f) = quality {
                q.push(f(s, t)?);
            }
        }
    }
    let faces: Vec<[u32; 4]> = (0..res)
        .flat_map(|i| {
            (0..res).map(move |j| {
                let a = (i * n + j) as u32;
                [a, a + n as u32, a + n as u32 + 1, a + 1]
            })
        })
        .collect();
    let mut mesh = PolygonMesh::from_polygons(pos, &faces);
    if quality.is_some() {
        mesh.quality = Some(q);
    }
    Ok(mesh)
}

/// Keeps the faces of a [`sample_mesh`] lattice of `res × res` cells (over [0, 1]²) whose
/// centre (u, v) `keep` accepts; vertices are unchanged.
pub fn keep_faces(mesh: &mut PolygonMesh, res: usize, keep: &dyn Fn(f64, f64) -> bool) {
    let faces: Vec<Vec<u32>> = mesh
        .faces()
        .enumerate()
        .filter(|(k, _)| {
            let (i, j) = (k / res, k % res);
            keep((i as f64 + 0.5) / res as f64, (j as f64 + 0.5) / res as f64)
        })
        .map(|(_, f)| f.to_vec())
        .collect();
    let kept = PolygonMesh::from_polygons(Vec::new(), &faces);
    mesh.face_offsets = kept.face_offsets;
    mesh.face_indices = kept.face_indices;
}

/// A surface given as (u, v) ↦ point.
pub type SurfaceOf<'a> = &'a dyn Fn(f64, f64) -> Result<[f64; 3]>;

/// The papers' three figures over [0, 1]²: the exact surface with its hole, the
/// approximation σ₁ outside the hole, and the filled surface — the last two with the
/// distance to the exact surface as quality, named by `names`.
///
/// Errors: those of the surfaces.
pub fn hole_figures(
    names: [&str; 3],
    exact: SurfaceOf,
    approximation: SurfaceOf,
    filled: SurfaceOf,
    outside_hole: &dyn Fn(f64, f64) -> bool,
) -> Result<Vec<(String, PolygonMesh)>> {
    const RES: usize = 120;
    let distance = crate::mesh::vector::distance;
    let err1 = |u: f64, v: f64| Ok(distance(approximation(u, v)?, exact(u, v)?));
    let err = |u: f64, v: f64| Ok(distance(filled(u, v)?, exact(u, v)?));
    let mut with_hole = sample_mesh([0.0, 1.0], [0.0, 1.0], RES, exact, None)?;
    keep_faces(&mut with_hole, RES, outside_hole);
    let mut approximated = sample_mesh([0.0, 1.0], [0.0, 1.0], RES, approximation, Some(&err1))?;
    keep_faces(&mut approximated, RES, outside_hole);
    let filled_mesh = sample_mesh([0.0, 1.0], [0.0, 1.0], RES, filled, Some(&err))?;
    Ok(vec![
        (names[0].to_string(), with_hole),
        (names[1].to_string(), approximated),
        (names[2].to_string(), filled_mesh),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_counts() {
        let m = sample_mesh(
            [0.0, 1.0],
            [0.0, 2.0],
            4,
            &|u, v| Ok([u, v, u * v]),
            Some(&|u, _| Ok(u)),
        )
        .unwrap();
        assert_eq!(m.vertex_count(), 25);
        assert_eq!(m.face_count(), 16);
        assert_eq!(m.quality.as_ref().unwrap().len(), 25);
        assert!(sample_mesh([0.0, 1.0], [0.0, 1.0], 0, &|u, v| Ok([u, v, 0.0]), None).is_err());
    }

    #[test]
    fn the_last_samples_stay_inside_the_rectangle() {
        // a + (b − a)·7/7 rounds one ulp past b for this rectangle (found by the Python
        // suite's random data); a sample outside it is an error for a spline.
        let (a, b) = (0.0028978161459048556, 0.9021489705265909);
        assert!(a + (b - a) * 7.0 / 7.0 > b);
        let inside = |u: f64, v: f64| {
            if (a..=b).contains(&u) && (a..=b).contains(&v) {
                Ok([u, v, 0.0])
            } else {
                Err(Error::InvalidInput(format!("({u}, {v}) outside")))
            }
        };
        let m = sample_mesh([a, b], [a, b], 7, &inside, None).unwrap();
        assert_eq!(m.positions[m.vertex_count() - 1], [b, b, 0.0]);
    }
}
