//! The multilevel method for large meshes (issue 18): inexact Newton whose steps are
//! solved by conjugate gradients preconditioned with a multigrid V-cycle, the coarse
//! levels being the coarser control meshes the input was refined from (found by
//! un-subdivision) with Catmull–Clark refinement as the prolongation.

pub(crate) mod block_csr;
pub(crate) mod coarse_start;
pub(crate) mod galerkin;
pub(crate) mod hierarchy;
pub(crate) mod multigrid;
pub(crate) mod patch_smoother;
pub(crate) mod solver;
pub(crate) mod symmetric_csr;
pub(crate) mod unsubdivision;
