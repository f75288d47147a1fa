//! Kiciak's G² surface of a mesh, face by face: an internal face off the special vertices
//! is the bicubic B-spline patch of its 4 × 4 net; a face round a special vertex is one of
//! the k degree-(9, 9) patches of its special element. The optimizer's quadrature rows
//! ([`super::representation`]), the curvature samples and the Bézier export are read from
//! this one description.

use std::sync::Arc;

use super::basis::bernstein::{bernstein_derivatives, COEFFICIENTS, ORDER};
use super::basis::patch_matrix::PatchMatrix;
use super::sabin_net::{directed_edges, first_faces, SabinNet};
use crate::error::{Error, Result};
use crate::fair::surface::representation::check_quad_mesh;
use crate::limits::MemoryBudget;
use crate::mesh::PolygonMesh;
use crate::subdiv::{limit_surface, Derivatives, PatchOptions, SubdivOptions};

/// What carries the surface over one face.
#[derive(Debug, Clone)]
pub enum FacePatch {
    /// A bicubic B-spline patch: its 16 control points' vertex weights (row-major, u along
    /// a row), as OpenSubdiv gives them for a regular face.
    Bicubic(Box<[Vec<(u32, f64)>; 16]>),
    /// Sector `sector` of special element `element` (u along the spoke from the special
    /// vertex, v towards the next spoke).
    Special { element: usize, sector: usize },
}

/// The G² surface's patches.
#[derive(Clone)]
pub struct G2Surface {
    /// One entry per face; `None` for faces that carry no surface (a corner on the
    /// boundary: as in the paper, only internal quads are elements).
    pub faces: Vec<Option<FacePatch>>,
    pub special_elements: Vec<SabinNet>,
    /// The patch matrix of each special element's valence.
    pub bases: Vec<Arc<PatchMatrix>>,
}

impl G2Surface {
    /// The surface of `mesh` with `special` vertices (interior, valence ≠ 4).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a non-quad face or a valence above 16;
    /// [`Error::Topology`] where a special vertex's net is not the quad net the
    /// construction needs, two special vertices share a face, or an ordinary face is not
    /// one regular bicubic patch; errors of OpenSubdiv.
    pub fn new(
        mesh: &PolygonMesh,
        boundary: &[bool],
        special: &[bool],
        memory: MemoryBudget,
    ) -> Result<G2Surface> {
        check_quad_mesh(mesh, boundary, special)?;
        let internal: Vec<bool> = mesh
            .faces()
            .map(|f| f.iter().all(|&v| !boundary[v as usize]))
            .collect();
        let edges = directed_edges(mesh);
        let (first_face, valence) = first_faces(mesh);
        let mut faces: Vec<Option<FacePatch>> = vec![None; mesh.face_count()];
        let mut special_elements = Vec::new();
        let mut bases = Vec::new();
        for v in (0..mesh.vertex_count()).filter(|&v| special[v]) {
            let k = valence[v];
            let element = special_elements.len();
            let net = SabinNet::new(mesh, &edges, v as u32, first_face[v], k)?;
            for (sector, &f) in net.faces.iter().enumerate() {
                if faces[f].is_some() {
                    return Err(Error::Topology(format!(
                        "face {f} touches two special vertices; they must be separated"
                    )));
                }
                faces[f] = Some(FacePatch::Special { element, sector });
            }
            bases.push(PatchMatrix::cached(k)?);
            special_elements.push(net);
        }
        // a face whose corners all have valence 4 is one bicubic patch at level 0
        let surface = limit_surface(
            mesh,
            &SubdivOptions::default(),
            &PatchOptions {
                max_isolation: 1,
                memory,
                ..PatchOptions::default()
            },
        )?;
        let mut covered = vec![false; mesh.face_count()];
        for (p, patch) in surface.patches().iter().enumerate() {
            let f = patch.base_face as usize;
            if !internal[f] || faces[f].is_some() {
                continue;
            }
            if !patch.regular || patch.size != 1.0 || covered[f] {
                return Err(Error::Topology(format!(
                    "face {f} is not one regular bicubic patch (a corner of valence other \
                     than 4 that is not a special vertex?)"
                )));
            }
            covered[f] = true;
            faces[f] = Some(FacePatch::Bicubic(Box::new(surface.patch_weights(p)?)));
        }
        for (f, face) in faces.iter_mut().enumerate() {
            if !internal[f] {
                *face = None;
            } else if face.is_none() {
                return Err(Error::Topology(format!("face {f} has no patch")));
            }
        }
        Ok(G2Surface {
            faces,
            special_elements,
            bases,
        })
    }

    /// Bézier control points of face `f`'s patch (degree 3 or 9 in each direction, index
    /// (degree + 1)·i + j with i along u), for `positions`.
    pub fn bezier(&self, f: usize, positions: &[[f64; 3]]) -> Option<(usize, Vec<[f64; 3]>)> {
        match self.faces.get(f)?.as_ref()? {
            FacePatch::Bicubic(rows) => {
                let spline: Vec<[f64; 3]> = rows
                    .iter()
                    .map(|row| {
                        let mut p = [0.0; 3];
                        for &(v, w) in row {
                            for c in 0..3 {
                                p[c] += w * positions[v as usize][c];
                            }
                        }
                        p
                    })
                    .collect();
                // uniform cubic B-spline → Bézier on one span, in each direction
                const M: [[f64; 4]; 4] = [
                    [1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0, 0.0],
                    [0.0, 4.0 / 6.0, 2.0 / 6.0, 0.0],
                    [0.0, 2.0 / 6.0, 4.0 / 6.0, 0.0],
                    [0.0, 1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0],
                ];
                let mut out = vec![[0.0; 3]; 16];
                for i in 0..4 {
                    for j in 0..4 {
                        for a in 0..4 {
                            for b in 0..4 {
                                // spline row a (v), column b (u)
                                let w = M[i][b] * M[j][a];
                                if w != 0.0 {
                                    for c in 0..3 {
                                        out[4 * i + j][c] += w * spline[4 * a + b][c];
                                    }
                                }
                            }
                        }
                    }
                }
                Some((3, out))
            }
            FacePatch::Special { element, sector } => {
                let net = &self.special_elements[*element];
                let basis = &self.bases[*element];
                let mut out = vec![[0.0; 3]; COEFFICIENTS];
                for (i, point) in out.iter_mut().enumerate() {
                    for (column, v) in net.vertices.iter().enumerate() {
                        if let Some(v) = v {
                            let m = basis.matrix[(sector * COEFFICIENTS + i, column)];
                            for c in 0..3 {
                                point[c] += m * positions[*v as usize][c];
                            }
                        }
                    }
                }
                Some((ORDER - 1, out))
            }
        }
    }

    /// Position and derivatives to third order of face `f`'s patch at each (u, v) of
    /// `points` (its Bézier form computed once).
    pub fn evaluate(
        &self,
        f: usize,
        positions: &[[f64; 3]],
        points: &[(f64, f64)],
    ) -> Option<Vec<Derivatives>> {
        let (degree, control) = self.bezier(f, positions)?;
        Some(
            points
                .iter()
                .map(|&(u, v)| bezier_derivatives(degree, &control, u, v))
                .collect(),
        )
    }
}

/// Position and derivatives to third order of the degree-(d, d) Bézier patch `control`
/// (index (d + 1)·i + j, i along u) at (u, v).
fn bezier_derivatives(degree: usize, control: &[[f64; 3]], u: f64, v: f64) -> Derivatives {
    let (bu, bv) = if degree == 3 {
        (cubic_bernstein(u), cubic_bernstein(v))
    } else {
        let (a, b) = (bernstein_derivatives(u), bernstein_derivatives(v));
        (a.map(|r| r.to_vec()), b.map(|r| r.to_vec()))
    };
    let n = degree + 1;
    let at = |ru: usize, rv: usize| -> [f64; 3] {
        let mut s = [0.0; 3];
        for i in 0..n {
            for j in 0..n {
                let w = bu[ru][i] * bv[rv][j];
                for c in 0..3 {
                    s[c] += w * control[n * i + j][c];
                }
            }
        }
        s
    };
    Derivatives {
        position: at(0, 0),
        du: at(1, 0),
        dv: at(0, 1),
        duu: at(2, 0),
        duv: at(1, 1),
        dvv: at(0, 2),
        duuu: at(3, 0),
        duuv: at(2, 1),
        duvv: at(1, 2),
        dvvv: at(0, 3),
    }
}

/// The cubic Bernstein polynomials and their first three derivatives at t.
fn cubic_bernstein(t: f64) -> [Vec<f64>; 4] {
    let s = 1.0 - t;
    [
        vec![s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t],
        vec![
            -3.0 * s * s,
            3.0 * s * s - 6.0 * t * s,
            6.0 * t * s - 3.0 * t * t,
            3.0 * t * t,
        ],
        vec![6.0 * s, 6.0 * t - 12.0 * s, 6.0 * s - 12.0 * t, 6.0 * t],
        vec![-6.0, 18.0, -18.0, 6.0],
    ]
}
