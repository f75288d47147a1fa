//! Curvature maps of the surface the optimizer shapes (either surface, [`surface_samples`]): limit samples with mean curvature as
//! per-vertex quality (MeshLab colours them), of the internal faces only — as in the paper
//! (§2) the boundary faces carry no surface, their limit depends on a boundary rule the
//! method does not use, and their vertices are fixed anyway.

use crate::error::Result;
use crate::fair::surface::g2::samples::g2_samples;
use crate::fair::surface::representation::{RepresentationOptions, SurfaceKind};
use crate::mesh::PolygonMesh;
use crate::subdiv::{
    limit_surface, sample_limit, BoundaryInterpolation, LimitSamples, PatchOptions, SampleOptions,
    SubdivOptions,
};

/// Limit samples of `mesh`'s Catmull–Clark surface on a `samples` × `samples` grid per
/// internal face, mean curvature as quality (see [`sample_limit`]), with OpenSubdiv's
/// adaptive isolation `isolation` around extraordinary vertices.
///
/// # Errors
/// Those of [`limit_surface`] and [`sample_limit`] (e.g. `samples` out of range).
pub fn curvature_samples(mesh: &PolygonMesh, samples: u32, isolation: u32) -> Result<LimitSamples> {
    let options = SubdivOptions {
        boundary: BoundaryInterpolation::None,
        ..Default::default()
    };
    let surface = limit_surface(
        mesh,
        &options,
        &PatchOptions {
            max_isolation: isolation,
            ..Default::default()
        },
    )?;
    sample_limit(&surface, &SampleOptions { samples })
}

/// Curvature samples of the surface `options` choose ([`SurfaceKind`]): the Catmull–Clark
/// limit at `options.isolation`, or Kiciak's G² surface.
///
/// # Errors
/// Those of [`curvature_samples`] or of the G² surface.
pub fn surface_samples(
    mesh: &PolygonMesh,
    samples: u32,
    options: &RepresentationOptions,
) -> Result<LimitSamples> {
    match options.surface {
        SurfaceKind::CatmullClark => curvature_samples(mesh, samples, options.isolation),
        SurfaceKind::G2 => g2_samples(mesh, samples, options.memory),
    }
}
