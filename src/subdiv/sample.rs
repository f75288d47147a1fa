//! Sampling the limit surface on a regular grid per ptex face, with mean curvature as
//! per-vertex quality: a curvature map MeshLab colours.

use crate::error::{Error, Result};
use crate::mesh::PolygonMesh;
use crate::subdiv::{curvature, PatchSurface, SurfacePoint};

/// Options of [`sample_limit`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SampleOptions {
    /// Grid cells along each side of a ptex face (K): (K + 1)² samples and K² quads per face.
    pub samples: u32,
}

impl Default for SampleOptions {
    fn default() -> Self {
        SampleOptions { samples: 4 }
    }
}

/// Largest accepted [`SampleOptions::samples`].
pub const MAX_SAMPLES: u32 = 256;

/// Samples the limit surface: for every ptex face with a limit surface, a (K + 1) × (K + 1)
/// grid of limit points joined into K × K quads, each vertex carrying the mean curvature
/// as `quality` and the ptex face's (u, v) as UVs. Faces are sampled independently (their
/// border vertices are repeated), so the output is one grid per ptex face; faces without a
/// limit surface (boundary faces under `BoundaryInterpolation::None`) are left out.
///
/// # Errors
/// [`Error::InvalidInput`] unless `1 ≤ samples ≤ MAX_SAMPLES`; [`Error::Topology`] where the
/// limit surface is degenerate (no normal, so no curvature); [`Error::Ffi`] from evaluation.
pub fn sample_limit(surface: &PatchSurface, options: &SampleOptions) -> Result<PolygonMesh> {
    let k = options.samples;
    if !(1..=MAX_SAMPLES).contains(&k) {
        return Err(Error::InvalidInput(format!(
            "samples = {k}; it must be between 1 and {MAX_SAMPLES}"
        )));
    }
    let n = (k + 1) as usize;
    let mut mesh = PolygonMesh::default();
    let mut quality = Vec::new();
    let mut uvs = crate::mesh::CornerUvs::default();
    for ptex in 0..surface.ptex_face_count() as u32 {
        let points: Vec<SurfacePoint> = (0..n * n)
            .map(|i| SurfacePoint {
                ptex_face: ptex,
                u: (i % n) as f64 / k as f64,
                v: (i / n) as f64 / k as f64,
            })
            .collect();
        if points.iter().any(|p| surface.locate(p).is_err()) {
            continue;
        }
        let base = mesh.positions.len() as u32;
        for (p, d) in points.iter().zip(surface.evaluate(&points)?) {
            let c = curvature(&d).map_err(|e| {
                Error::Topology(format!("ptex face {ptex} at ({}, {}): {e}", p.u, p.v))
            })?;
            mesh.positions.push(d.position);
            quality.push(c.mean);
            uvs.coords.push([p.u, p.v]);
        }
        let id = |i: usize, j: usize| base + (j * n + i) as u32;
        for j in 0..k as usize {
            for i in 0..k as usize {
                let quad = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
                mesh.push_face(&quad);
                uvs.corner_indices.extend(quad);
            }
        }
    }
    mesh.quality = Some(quality);
    mesh.uvs = Some(uvs);
    Ok(mesh)
}
