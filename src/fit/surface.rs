//! A spline with values in ℝ³: three coefficient vectors over one scalar space (the
//! papers' V_h = (𝒱_h)³ with basis vᵢ = ωᵢ jₗ).

use crate::error::{Error, Result};
use crate::spline::{Cell, Space};

/// Coefficients of the three components over a scalar space of dimension `dim`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct VectorSpline {
    /// `coeffs[ℓ][k]`: coefficient of ωₖ jₗ.
    pub coeffs: [Vec<f64>; 3],
}

impl VectorSpline {
    /// The zero spline of a space of dimension `dim`.
    pub fn zeros(dim: usize) -> Self {
        Self {
            coeffs: [vec![0.0; dim], vec![0.0; dim], vec![0.0; dim]],
        }
    }

    /// ∂ₓᵃ∂ᵧᵇ of the three components at (x, y), on the cell holding the point.
    ///
    /// Errors: `InvalidInput` if the point is outside the rectangle or NaN, or the
    /// coefficient vectors do not match the space.
    pub fn eval(&self, space: &dyn Space, x: f64, y: f64, a: usize, b: usize) -> Result<[f64; 3]> {
        let cell = space.grid().locate(x, y).ok_or_else(|| {
            Error::InvalidInput(format!(
                "point ({x}, {y}) is outside the spline's rectangle"
            ))
        })?;
        self.eval_on_cell(space, cell, x, y, a, b)
    }

    /// As [`VectorSpline::eval`] with the polynomial pieces of a given cell (for one-sided
    /// values on a cell border).
    ///
    /// Errors: `InvalidInput` if the coefficient vectors do not match the space.
    pub fn eval_on_cell(
        &self,
        space: &dyn Space,
        cell: Cell,
        x: f64,
        y: f64,
        a: usize,
        b: usize,
    ) -> Result<[f64; 3]> {
        if self.coeffs.iter().any(|c| c.len() != space.dim()) {
            return Err(Error::InvalidInput(format!(
                "spline coefficients do not match a space of dimension {}",
                space.dim()
            )));
        }
        let lb = space.eval_on_cell(cell, x, y, a.max(b));
        Ok([
            lb.combine(&self.coeffs[0], a, b),
            lb.combine(&self.coeffs[1], a, b),
            lb.combine(&self.coeffs[2], a, b),
        ])
    }
}
