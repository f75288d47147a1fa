//! The univariate building block of the tensor-product spaces.

use super::grid::Partition;

/// A univariate piecewise-polynomial space on a partition, with a local basis: the
/// functions non-zero on interval i are a contiguous index range of fixed length.
pub trait Basis1d: Send + Sync {
    /// The partition the space lives on.
    fn partition(&self) -> &Partition;
    /// Number of basis functions.
    fn dim(&self) -> usize;
    /// Polynomial degree of the pieces.
    fn degree(&self) -> usize;
    /// Global smoothness: the space is in C^k.
    fn smoothness(&self) -> usize;
    /// How many basis functions are non-zero on one interval.
    fn local_count(&self) -> usize;
    /// Index of the first basis function non-zero on interval `i`; the others follow.
    fn first_on(&self, interval: usize) -> usize;
    /// The intervals (first, last inclusive) where basis function `k` is not identically zero.
    fn support(&self, k: usize) -> (usize, usize);
    /// Values and derivatives 0..=`order` of the local functions of `interval` at `x`,
    /// written to `out[l * (order + 1) + d]` for local function l and derivative d.
    /// `x` may lie anywhere; the interval's polynomial pieces are evaluated.
    fn eval(&self, interval: usize, x: f64, order: usize, out: &mut [f64]);
}
