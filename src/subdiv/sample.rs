//! Sampling the limit surface on a regular grid per ptex face, with mean curvature as
//! per-vertex quality: a curvature map MeshLab colours.

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::mesh::PolygonMesh;
use crate::subdiv::{curvature, Derivatives, PatchSurface, SurfacePoint};

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

/// The sampled limit surface and where its curvature is undefined.
#[derive(Debug, Clone)]
pub struct LimitSamples {
    /// One (K + 1) × (K + 1) grid of quads per ptex face; `quality` = mean curvature, UVs =
    /// the ptex face's (u, v).
    pub mesh: PolygonMesh,
    /// Samples at degenerate points of the limit surface (vanishing or parallel tangents,
    /// e.g. the limit point of a valence-2 vertex), where curvature does not exist: their
    /// `quality` is the mean of their non-degenerate grid neighbours' (0 if none).
    pub degenerate: Vec<u32>,
}

/// Largest accepted [`SampleOptions::samples`].
pub const MAX_SAMPLES: u32 = 256;

/// Samples the limit surface: for every ptex face with a limit surface, a (K + 1) × (K + 1)
/// grid of limit points joined into K × K quads, each vertex carrying the mean curvature
/// as `quality` and the ptex face's (u, v) as UVs. Faces are sampled independently (their
/// border vertices are repeated), so the output is one grid per ptex face; faces without a
/// limit surface (boundary faces under `BoundaryInterpolation::None`) are left out.
/// Degenerate points are listed in [`LimitSamples::degenerate`], never a silent NaN.
///
/// # Errors
/// [`Error::InvalidInput`] unless `1 ≤ samples ≤ MAX_SAMPLES`; [`Error::Ffi`] from
/// evaluation.
pub fn sample_limit(surface: &PatchSurface, options: &SampleOptions) -> Result<LimitSamples> {
    let k = options.samples;
    if !(1..=MAX_SAMPLES).contains(&k) {
        return Err(Error::InvalidInput(format!(
            "samples = {k}; it must be between 1 and {MAX_SAMPLES}"
        )));
    }
    // Ptex faces on rayon's threads, assembled in order.
    let faces: Vec<Option<PtexSamples>> = (0..surface.ptex_face_count() as u32)
        .into_par_iter()
        .map(|ptex| sample_ptex(surface, ptex, k))
        .collect::<Result<_>>()?;
    Ok(assemble(faces.into_iter().flatten(), k))
}

/// The samples' mesh: each face's (k + 1)² grid joined into k × k quads, in order.
pub(crate) fn assemble(faces: impl IntoIterator<Item = PtexSamples>, k: u32) -> LimitSamples {
    let n = (k + 1) as usize;
    let mut mesh = PolygonMesh::default();
    let mut quality = Vec::new();
    let mut uvs = crate::mesh::CornerUvs::default();
    let mut degenerate = Vec::new();
    for face in faces {
        let base = mesh.positions.len() as u32;
        degenerate.extend(face.degenerate.iter().map(|&i| base + i));
        mesh.positions.extend(face.positions);
        quality.extend(face.quality);
        uvs.coords.extend(face.uvs);
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
    LimitSamples { mesh, degenerate }
}

/// The grid points (u, v) = (i/k, j/k) of one face, row by row.
pub(crate) fn grid_points(k: u32) -> Vec<(f64, f64)> {
    let n = (k + 1) as usize;
    (0..n * n)
        .map(|i| ((i % n) as f64 / k as f64, (i / n) as f64 / k as f64))
        .collect()
}

/// The (k + 1)² samples of one ptex face, row by row; degenerate ones (listed by local
/// index) get the mean curvature of their regular neighbours.
pub(crate) struct PtexSamples {
    positions: Vec<[f64; 3]>,
    quality: Vec<f64>,
    uvs: Vec<[f64; 2]>,
    degenerate: Vec<u32>,
}

/// Samples ptex face `ptex` on a k × k grid; `None` where the face has no limit surface.
fn sample_ptex(surface: &PatchSurface, ptex: u32, k: u32) -> Result<Option<PtexSamples>> {
    let points: Vec<SurfacePoint> = grid_points(k)
        .into_iter()
        .map(|(u, v)| SurfacePoint {
            ptex_face: ptex,
            u,
            v,
        })
        .collect();
    if points.iter().any(|p| surface.locate(p).is_err()) {
        return Ok(None);
    }
    Ok(Some(grid_samples(k, &surface.evaluate(&points)?)))
}

/// One face's samples from the derivatives at its [`grid_points`]: mean curvature as
/// quality, a degenerate point's taken from its regular grid neighbours.
pub(crate) fn grid_samples(k: u32, derivatives: &[Derivatives]) -> PtexSamples {
    let n = (k + 1) as usize;
    let mut out = PtexSamples {
        positions: Vec::with_capacity(n * n),
        quality: Vec::with_capacity(n * n),
        uvs: Vec::with_capacity(n * n),
        degenerate: Vec::new(),
    };
    for (i, ((u, v), d)) in grid_points(k).into_iter().zip(derivatives).enumerate() {
        match curvature(d) {
            Ok(c) => out.quality.push(c.mean),
            Err(_) => {
                out.degenerate.push(i as u32);
                out.quality.push(0.0);
            }
        }
        out.positions.push(d.position);
        out.uvs.push([u, v]);
    }
    for &g in &out.degenerate {
        let (i, j) = ((g as usize % n) as i64, (g as usize / n) as i64);
        let mut sum = 0.0;
        let mut count = 0;
        for (di, dj) in [
            (-1, 0),
            (1, 0),
            (0, -1),
            (0, 1),
            (-1, -1),
            (1, 1),
            (-1, 1),
            (1, -1),
        ] {
            let (a, b) = (i + di, j + dj);
            if a < 0 || b < 0 || a >= n as i64 || b >= n as i64 {
                continue;
            }
            let other = (b as usize * n + a as usize) as u32;
            if !out.degenerate.contains(&other) {
                sum += out.quality[other as usize];
                count += 1;
            }
        }
        out.quality[g as usize] = if count > 0 { sum / count as f64 } else { 0.0 };
    }
    out
}
