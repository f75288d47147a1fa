//! The partition of the rectangle R = [a, b] × [c, d] into cells Tₙ × Tₘ.

use crate::error::{Error, Result};

/// A strictly increasing partition a = x₀ < x₁ < … < xₙ = b of an interval.
#[derive(Debug, Clone, PartialEq)]
pub struct Partition {
    breaks: Vec<f64>,
}

impl Partition {
    /// Checks the breakpoints: at least two, finite, strictly increasing.
    ///
    /// Errors: `InvalidInput` naming the first offending breakpoint.
    pub fn new(breaks: Vec<f64>) -> Result<Self> {
        if breaks.len() < 2 {
            return Err(Error::InvalidInput(format!(
                "a partition needs at least 2 breakpoints, got {}",
                breaks.len()
            )));
        }
        for (i, w) in breaks.windows(2).enumerate() {
            if !(w[0].is_finite() && w[1].is_finite() && w[0] < w[1]) {
                return Err(Error::InvalidInput(format!(
                    "breakpoints must be finite and strictly increasing: x[{i}] = {}, x[{}] = {}",
                    w[0],
                    i + 1,
                    w[1]
                )));
            }
        }
        Ok(Self { breaks })
    }

    /// `n` equal intervals of [a, b].
    ///
    /// Errors: `InvalidInput` if `n == 0` or `a >= b` or either is not finite.
    pub fn uniform(a: f64, b: f64, n: usize) -> Result<Self> {
        if n == 0 {
            return Err(Error::InvalidInput(
                "a partition needs at least one interval".into(),
            ));
        }
        let h = (b - a) / n as f64;
        let mut v: Vec<f64> = (0..n).map(|i| a + h * i as f64).collect();
        v.push(b);
        Self::new(v)
    }

    /// The breakpoints.
    pub fn breaks(&self) -> &[f64] {
        &self.breaks
    }

    /// Number of intervals.
    pub fn intervals(&self) -> usize {
        self.breaks.len() - 1
    }

    /// The interval holding `x`: the last i with xᵢ ≤ x, clipped to the last interval so
    /// the right end belongs to it. `None` for NaN or x outside [x₀, xₙ].
    pub fn locate(&self, x: f64) -> Option<usize> {
        let (a, b) = (self.breaks[0], *self.breaks.last()?);
        if !(x >= a && x <= b) {
            return None;
        }
        let i = self.breaks.partition_point(|&t| t <= x);
        Some(i.saturating_sub(1).min(self.intervals() - 1))
    }
}

/// A cell (i, j): [xᵢ, xᵢ₊₁] × [yⱼ, yⱼ₊₁].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Cell {
    pub i: usize,
    pub j: usize,
}

/// The rectangle partitioned into cells.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    pub x: Partition,
    pub y: Partition,
}

impl Grid {
    /// The grid Tₙ × Tₘ.
    pub fn new(x: Partition, y: Partition) -> Self {
        Self { x, y }
    }

    /// nx × ny equal cells of [a, b] × [c, d].
    ///
    /// Errors: as [`Partition::uniform`].
    pub fn uniform(a: f64, b: f64, c: f64, d: f64, nx: usize, ny: usize) -> Result<Self> {
        Ok(Self::new(
            Partition::uniform(a, b, nx)?,
            Partition::uniform(c, d, ny)?,
        ))
    }

    /// Number of cells along x and along y.
    pub fn shape(&self) -> (usize, usize) {
        (self.x.intervals(), self.y.intervals())
    }

    /// Number of cells.
    pub fn cell_count(&self) -> usize {
        self.x.intervals() * self.y.intervals()
    }

    /// The linear index of a cell (row-major in i): i·ny + j.
    pub fn cell_index(&self, c: Cell) -> usize {
        c.i * self.y.intervals() + c.j
    }

    /// The cell of a linear index.
    pub fn cell_at(&self, k: usize) -> Cell {
        let ny = self.y.intervals();
        Cell {
            i: k / ny,
            j: k % ny,
        }
    }

    /// All cells, in linear-index order.
    pub fn cells(&self) -> impl Iterator<Item = Cell> + '_ {
        (0..self.cell_count()).map(|k| self.cell_at(k))
    }

    /// The cell holding (x, y), `None` outside R or for NaN.
    pub fn locate(&self, x: f64, y: f64) -> Option<Cell> {
        Some(Cell {
            i: self.x.locate(x)?,
            j: self.y.locate(y)?,
        })
    }

    /// The corners [x₀, x₁] × [y₀, y₁] of a cell.
    pub fn cell_bounds(&self, c: Cell) -> ([f64; 2], [f64; 2]) {
        let (bx, by) = (self.x.breaks(), self.y.breaks());
        ([bx[c.i], bx[c.i + 1]], [by[c.j], by[c.j + 1]])
    }

    /// The rectangle [a, b] × [c, d].
    pub fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        let (bx, by) = (self.x.breaks(), self.y.breaks());
        ([bx[0], bx[bx.len() - 1]], [by[0], by[by.len() - 1]])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locate_assigns_right_end_to_last_cell_and_rejects_outside() {
        let p = Partition::new(vec![0.0, 0.25, 1.0]).unwrap();
        assert_eq!(p.locate(0.0), Some(0));
        assert_eq!(p.locate(0.25), Some(1));
        assert_eq!(p.locate(1.0), Some(1));
        assert_eq!(p.locate(1.5), None);
        assert_eq!(p.locate(f64::NAN), None);
    }

    #[test]
    fn bad_breakpoints_are_errors() {
        assert!(Partition::new(vec![0.0]).is_err());
        assert!(Partition::new(vec![0.0, 0.0, 1.0]).is_err());
        assert!(Partition::new(vec![0.0, f64::NAN]).is_err());
        assert!(Partition::uniform(0.0, 1.0, 0).is_err());
    }
}
