//! A thin layer over faer: the few solves the variational methods need, with our errors.
//! Sparse symmetric positive definite systems (one factorization, several right-hand
//! sides) and equality-constrained quadratic minimization that survives dependent
//! constraints, and convex QPs with inequality constraints (clarabel).

pub mod constrained;
pub mod qp;
pub mod spd;
pub mod vector;

pub use constrained::{minimize_with_equalities, ConstrainedSolution};
pub use qp::{solve_qp, QpSolution};
pub use spd::solve_spd;
pub use vector::{dot, norm};
