//! Catmull–Clark subdivision surfaces through OpenSubdiv: the only safe door to
//! `ffi::opensubdiv`.
//!
//! - [`refine_uniform`]: the control mesh refined N levels, quads (and UVs) out.
//! - [`PatchSurface`]: the limit surface as bicubic B-spline patches from OpenSubdiv's
//!   feature-adaptive patch table with B-spline end caps, each patch's 16 control points a
//!   fixed linear combination (stencil) of the control vertices; evaluation of positions and
//!   derivatives up to third order, normals and curvatures.
//!
//! Every entry function takes a [`SubdivOptions`]: sharp features (creases, corners) and
//! OpenSubdiv's rules. The boundary rule defaults to edges-and-corners, not OpenSubdiv's
//! own default (none), which leaves boundary faces without a limit surface.

mod bspline;
mod curvature;
mod options;
mod patches;
mod sample;
mod topology;
mod uniform;
pub(crate) use uniform::check_memory as check_refinement_memory;

pub use bspline::{cubic_basis, eval_patch, Derivatives};
pub use curvature::{curvature, normal, Curvature};
pub use options::{
    BoundaryInterpolation, Corner, Crease, CreasingMethod, FaceVaryingInterpolation, SubdivOptions,
    TriangleSubdivision,
};
pub use patches::{
    limit_surface, Patch, PatchOptions, PatchSurface, SurfacePoint, DEFAULT_MAX_STENCIL_WEIGHTS,
};
pub(crate) use sample::{assemble, grid_points, grid_samples};
pub use sample::{sample_limit, LimitSamples, SampleOptions, MAX_SAMPLES};
pub use uniform::{refine_uniform, refined_face_count, BYTES_PER_REFINED_FACE, MAX_LEVELS};

/// OpenSubdiv's version as `(major, minor, patch)`.
pub fn opensubdiv_version() -> (u32, u32, u32) {
    let v = crate::ffi::opensubdiv::version().max(0) as u32;
    (v / 10000, v / 100 % 100, v % 100)
}

/// Refines a cube once inside OpenSubdiv and checks the counts: the library links and runs.
///
/// # Errors
/// [`crate::Error::Ffi`] with OpenSubdiv's message when it does not.
pub fn self_test() -> crate::Result<()> {
    crate::ffi::opensubdiv::self_test()
}
