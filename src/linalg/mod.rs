//! A thin layer over faer: the few solves the variational methods need, with our errors.
//! Sparse symmetric positive definite systems (one factorization, several right-hand
//! sides) and equality-constrained quadratic minimization that survives dependent
//! constraints.

pub mod constrained;
pub mod spd;

pub use constrained::{minimize_with_equalities, ConstrainedSolution};
pub use spd::solve_spd;
