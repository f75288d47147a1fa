//! The `Space` abstraction every variational method is written against.

use super::grid::{Cell, Grid};
use super::quadrature::GaussLegendre;
use crate::error::{Error, Result};

/// The basis functions non-zero on one cell, with their values and partial derivatives
/// ∂ₓᵃ∂ᵧᵇ for a, b ≤ `order` at one point.
#[derive(Debug, Clone)]
pub struct LocalBasis {
    /// The cell the point was evaluated on.
    pub cell: Cell,
    /// Global indices of the local basis functions.
    pub indices: Vec<usize>,
    /// Highest derivative order per variable that was evaluated.
    pub order: usize,
    data: Vec<f64>,
}

impl LocalBasis {
    /// Assembles a local basis; `data[l·(o+1)² + a·(o+1) + b]` is ∂ₓᵃ∂ᵧᵇ of local function l.
    pub fn new(cell: Cell, indices: Vec<usize>, order: usize, data: Vec<f64>) -> Self {
        debug_assert_eq!(data.len(), indices.len() * (order + 1) * (order + 1));
        Self {
            cell,
            indices,
            order,
            data,
        }
    }

    /// ∂ₓᵃ∂ᵧᵇ of local function `l` (a, b ≤ `order`).
    #[inline]
    pub fn d(&self, l: usize, a: usize, b: usize) -> f64 {
        let o = self.order + 1;
        self.data[l * o * o + a * o + b]
    }

    /// ∂ₓᵃ∂ᵧᵇ of the spline Σ cₖ φₖ at the point.
    pub fn combine(&self, coeffs: &[f64], a: usize, b: usize) -> f64 {
        self.indices
            .iter()
            .enumerate()
            .map(|(l, &k)| coeffs[k] * self.d(l, a, b))
            .sum()
    }
}

/// A finite-dimensional space of piecewise polynomials on a grid of cells, with a local
/// basis. Methods written against it work for every element (B-splines, BFS C¹, BFS C²).
/// Spaces are plain data, shared across threads (a solved spline evaluated from Python
/// with the GIL released).
pub trait Space: Send + Sync {
    /// The partition of the rectangle.
    fn grid(&self) -> &Grid;
    /// Number of basis functions (of one scalar component).
    fn dim(&self) -> usize;
    /// Polynomial degree per variable of the pieces (bounds the quadrature order).
    fn degree(&self) -> usize;
    /// The space is in C^k(R).
    fn smoothness(&self) -> usize;
    /// Global indices of the basis functions not identically zero on `cell`.
    fn cell_functions(&self, cell: Cell) -> Vec<usize>;
    /// Values and derivatives up to `order` per variable of the local functions of `cell`
    /// at (x, y), using the cell's polynomial pieces (also for points on its border).
    fn eval_on_cell(&self, cell: Cell, x: f64, y: f64, order: usize) -> LocalBasis;
    /// The cells where basis function `k` is not identically zero: the rectangle of cells
    /// from the first to the last (inclusive).
    fn support(&self, k: usize) -> (Cell, Cell);

    /// The Gram block ((φ_p, φ_q)ₘ over `cell`) of the cell's functions, in
    /// [`Self::cell_functions`] order, row-major: Σ_{a+b=m} ∫ ∂ₓᵃ∂ᵧᵇφ_p ∂ₓᵃ∂ᵧᵇφ_q with
    /// `rule` in each variable (exact for rules of degree + 1 points). This default
    /// evaluates the basis at every point of the product rule; tensor-product spaces
    /// override it with the factorized 1D integrals, which give the same matrix faster.
    fn cell_seminorm_gram(&self, cell: Cell, m: usize, rule: &GaussLegendre) -> Vec<f64> {
        let ([x0, x1], [y0, y1]) = self.grid().cell_bounds(cell);
        let nl = self.cell_functions(cell).len();
        let mut local = vec![0.0; nl * nl];
        let mut d = vec![0.0; nl];
        for (x, wx) in rule.on_interval(x0, x1) {
            for (y, wy) in rule.on_interval(y0, y1) {
                let lb = self.eval_on_cell(cell, x, y, m);
                let w = wx * wy;
                for a in 0..=m {
                    for (l, dl) in d.iter_mut().enumerate() {
                        *dl = lb.d(l, a, m - a);
                    }
                    for p in 0..nl {
                        let dp = w * d[p];
                        for q in 0..nl {
                            local[p * nl + q] += dp * d[q];
                        }
                    }
                }
            }
        }
        local
    }

    /// Locates (x, y) and evaluates the local basis there.
    ///
    /// Errors: `InvalidInput` if (x, y) is NaN or outside the rectangle.
    fn eval(&self, x: f64, y: f64, order: usize) -> Result<LocalBasis> {
        let cell = self.grid().locate(x, y).ok_or_else(|| {
            Error::InvalidInput(format!(
                "point ({x}, {y}) is outside the spline's rectangle"
            ))
        })?;
        Ok(self.eval_on_cell(cell, x, y, order))
    }

    /// ∂ₓᵃ∂ᵧᵇ of Σ cₖ φₖ at (x, y).
    ///
    /// Errors: `InvalidInput` if `coeffs.len() != dim()` or the point is outside.
    fn evaluate(&self, coeffs: &[f64], x: f64, y: f64, a: usize, b: usize) -> Result<f64> {
        if coeffs.len() != self.dim() {
            return Err(Error::InvalidInput(format!(
                "{} coefficients for a space of dimension {}",
                coeffs.len(),
                self.dim()
            )));
        }
        Ok(self.eval(x, y, a.max(b))?.combine(coeffs, a, b))
    }
}
