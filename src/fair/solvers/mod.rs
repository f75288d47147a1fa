//! Minimizers of F (paper §5): Newton with Levenberg–Marquardt safeguards on a sparse
//! Cholesky factor, the block (domain-decomposition) method with its Schwarz-preconditioned
//! conjugate gradients, and coarse-to-fine levels (§6).

pub(crate) mod block_method;
pub(crate) mod blocks;
pub(crate) mod cholesky;
pub(crate) mod coarse_correction;
pub(crate) mod coordinate_floor;
pub(crate) mod lattice_rounding;
pub(crate) mod levels;
pub(crate) mod multilevel;
pub(crate) mod newton;
pub(crate) mod pcg;
pub(crate) mod schwarz;
pub(crate) mod step_solver;
