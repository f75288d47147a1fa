//! The finite-element core of the variational-spline methods: spline spaces over a
//! rectangle partitioned into cells, Gauss–Legendre quadrature, and Gram matrices of the
//! Sobolev semi-norms |·|ₘ.
//!
//! Every space here is a tensor product of two univariate spaces (`Basis1d`): B-splines
//! of any degree on non-uniform knots, and Hermite splines (cubic C¹, quintic C²) whose
//! tensor products are the Bogner–Fox–Schmit elements. The core knows nothing of meshes.

pub mod basis1d;
pub mod bspline;
pub mod gram;
pub mod grid;
pub mod hermite;
pub mod quadrature;
pub mod space;
pub mod tensor;

pub use basis1d::Basis1d;
pub use bspline::BSpline1d;
pub use gram::{seminorm_gram, SparseSym};
pub use grid::{Cell, Grid, Partition};
pub use hermite::Hermite1d;
pub use quadrature::GaussLegendre;
pub use space::{LocalBasis, Space};
pub use tensor::TensorSpace;
