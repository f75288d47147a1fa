//! Curvature samples of the G² surface: a (K + 1) × (K + 1) grid per internal face with
//! the mean curvature as quality — the same layout as the Catmull–Clark limit samples, so
//! the pictures, `--samples` files and HTML reports show the surface that was optimized.

use super::surface::{G2Surface, SecondOrder};
use crate::error::{Error, Result};
use crate::fair::MeshTopology;
use crate::limits::MemoryBudget;
use crate::mesh::{CornerUvs, PolygonMesh};
use crate::subdiv::{LimitSamples, MAX_SAMPLES};

/// Mean curvature from a parametric surface's first and second derivatives; `None` where
/// the tangents are degenerate.
pub fn mean_curvature(d: &[SecondOrder; 3]) -> Option<f64> {
    let get = |o: usize| [d[0][o], d[1][o], d[2][o]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (pu, pv) = (get(1), get(2));
    let n = [
        pu[1] * pv[2] - pu[2] * pv[1],
        pu[2] * pv[0] - pu[0] * pv[2],
        pu[0] * pv[1] - pu[1] * pv[0],
    ];
    let (e, f, g) = (dot(pu, pu), dot(pu, pv), dot(pv, pv));
    let det = e * g - f * f;
    if det.is_nan() || det <= 1e-300 {
        return None;
    }
    let len = det.sqrt();
    let n = n.map(|x| x / len);
    let (l, m, nn) = (dot(get(3), n), dot(get(4), n), dot(get(5), n));
    Some((e * nn - 2.0 * f * m + g * l) / (2.0 * det))
}

/// Samples `mesh`'s G² surface on a `samples` × `samples` grid per internal face.
///
/// # Errors
/// [`Error::InvalidInput`] for `samples` out of 1..=256; errors of [`G2Surface::new`].
pub fn g2_samples(mesh: &PolygonMesh, samples: u32, memory: MemoryBudget) -> Result<LimitSamples> {
    if !(1..=MAX_SAMPLES).contains(&samples) {
        return Err(Error::InvalidInput(format!(
            "samples = {samples}; it must be between 1 and {MAX_SAMPLES}"
        )));
    }
    let topo = MeshTopology::new(mesh)?;
    let surface = G2Surface::new(mesh, &topo.boundary, &topo.special_flags(), memory)?;
    let n = (samples + 1) as usize;
    let mut out = PolygonMesh::default();
    let mut quality = Vec::new();
    let mut uvs = CornerUvs::default();
    let mut degenerate = Vec::new();
    for f in 0..mesh.face_count() {
        if surface.faces[f].is_none() {
            continue;
        }
        let base = out.positions.len() as u32;
        let mut grid: Vec<Option<f64>> = Vec::with_capacity(n * n);
        for j in 0..n {
            for i in 0..n {
                let (u, v) = (i as f64 / samples as f64, j as f64 / samples as f64);
                let d = surface
                    .evaluate(f, &mesh.positions, u, v)
                    .ok_or_else(|| Error::InvalidInput(format!("face {f} has no patch")))?;
                out.positions.push([d[0][0], d[1][0], d[2][0]]);
                grid.push(mean_curvature(&d));
                uvs.coords.push([u, v]);
            }
        }
        // a degenerate sample (no tangent plane) takes its regular grid neighbours' mean,
        // as the Catmull–Clark samples do
        for j in 0..n {
            for i in 0..n {
                let h = grid[j * n + i].unwrap_or_else(|| {
                    degenerate.push(base + (j * n + i) as u32);
                    let around = [
                        (i.wrapping_sub(1), j),
                        (i + 1, j),
                        (i, j.wrapping_sub(1)),
                        (i, j + 1),
                    ];
                    let regular: Vec<f64> = around
                        .iter()
                        .filter(|&&(a, b)| a < n && b < n)
                        .filter_map(|&(a, b)| grid[b * n + a])
                        .collect();
                    if regular.is_empty() {
                        0.0
                    } else {
                        regular.iter().sum::<f64>() / regular.len() as f64
                    }
                });
                quality.push(h);
            }
        }
        let id = |i: usize, j: usize| base + (j * n + i) as u32;
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let quad = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
                out.push_face(&quad);
                uvs.corner_indices.extend(quad);
            }
        }
    }
    out.quality = Some(quality);
    out.uvs = Some(uvs);
    Ok(LimitSamples {
        mesh: out,
        degenerate,
    })
}
