//! Univariate Hermite splines of degree 2r + 1 and class C^r: r + 1 degrees of freedom per
//! node (the value and the derivatives up to order r). The tensor product of two of them is
//! the Bogner–Fox–Schmit element: r = 1 gives the bicubic C¹ element (value, ∂x, ∂y, ∂xy
//! per node, 2024 paper), r = 2 the biquintic C² element (9 dofs per node, 2004 paper).

use super::basis1d::Basis1d;
use super::grid::Partition;
use crate::error::{Error, Result};

/// Hermite basis of class C^r on a partition. Basis function (r+1)·q + k carries the k-th
/// derivative at node q: its k-th derivative there is 1, all other node dofs are 0.
#[derive(Debug, Clone)]
pub struct Hermite1d {
    partition: Partition,
    r: usize,
    /// Monomial coefficients in t ∈ [0, 1] of the reference shape functions, indexed
    /// [end·(r+1) + k][power]: end 0 is t = 0, end 1 is t = 1.
    shapes: Vec<Vec<f64>>,
}

impl Hermite1d {
    /// The C^r Hermite basis (r = 1: cubic, r = 2: quintic).
    ///
    /// Errors: `InvalidInput` unless 1 ≤ r ≤ 3.
    pub fn new(partition: Partition, r: usize) -> Result<Self> {
        if !(1..=3).contains(&r) {
            return Err(Error::InvalidInput(format!(
                "Hermite continuity must be 1, 2 or 3, got {r}"
            )));
        }
        let n = 2 * r + 2;
        // Row (end, j) of M: the j-th derivative of tᵖ at t = end. Shapes solve M C = I.
        let mut m = vec![vec![0.0; n]; n];
        for end in 0..2 {
            for j in 0..=r {
                for (pw, entry) in m[end * (r + 1) + j].iter_mut().enumerate() {
                    *entry = monomial_derivative(pw, j, end as f64);
                }
            }
        }
        let inv = invert(m).ok_or_else(|| {
            Error::InvalidInput("Hermite shape functions: singular system".into())
        })?;
        // Column c of the inverse is the coefficient vector of shape c.
        let shapes = (0..n)
            .map(|c| (0..n).map(|pw| inv[pw][c]).collect())
            .collect();
        Ok(Self {
            partition,
            r,
            shapes,
        })
    }

    /// Derivatives per node (r + 1).
    pub fn dofs_per_node(&self) -> usize {
        self.r + 1
    }
}

/// d^j/dt^j tᵖ at t.
fn monomial_derivative(p: usize, j: usize, t: f64) -> f64 {
    if j > p {
        return 0.0;
    }
    let mut c = 1.0;
    for q in 0..j {
        c *= (p - q) as f64;
    }
    c * t.powi((p - j) as i32)
}

/// Gauss–Jordan inverse with partial pivoting of a small dense matrix.
fn invert(mut a: Vec<Vec<f64>>) -> Option<Vec<Vec<f64>>> {
    let n = a.len();
    let mut inv: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..n).map(|j| if i == j { 1.0 } else { 0.0 }).collect())
        .collect();
    for col in 0..n {
        let piv = (col..n).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
        if a[piv][col] == 0.0 {
            return None;
        }
        a.swap(col, piv);
        inv.swap(col, piv);
        let d = a[col][col];
        for j in 0..n {
            a[col][j] /= d;
            inv[col][j] /= d;
        }
        for row in 0..n {
            if row != col {
                let f = a[row][col];
                if f != 0.0 {
                    for j in 0..n {
                        a[row][j] -= f * a[col][j];
                        inv[row][j] -= f * inv[col][j];
                    }
                }
            }
        }
    }
    Some(inv)
}

impl Basis1d for Hermite1d {
    fn partition(&self) -> &Partition {
        &self.partition
    }
    fn dim(&self) -> usize {
        (self.partition.intervals() + 1) * (self.r + 1)
    }
    fn degree(&self) -> usize {
        2 * self.r + 1
    }
    fn smoothness(&self) -> usize {
        self.r
    }
    fn local_count(&self) -> usize {
        2 * (self.r + 1)
    }
    fn first_on(&self, interval: usize) -> usize {
        interval * (self.r + 1)
    }
    fn support(&self, k: usize) -> (usize, usize) {
        let q = k / (self.r + 1);
        let last = self.partition.intervals() - 1;
        (q.saturating_sub(1), q.min(last))
    }

    /// Shape function (end, k) scaled by hᵏ so that its k-th x-derivative at the node is 1;
    /// its d-th x-derivative is h^{k−d} times the d-th t-derivative.
    fn eval(&self, interval: usize, x: f64, order: usize, out: &mut [f64]) {
        let b = self.partition.breaks();
        let (a, h) = (b[interval], b[interval + 1] - b[interval]);
        let t = (x - a) / h;
        let no = order + 1;
        for (l, shape) in self.shapes.iter().enumerate() {
            let k = l % (self.r + 1);
            for d in 0..=order {
                let dt: f64 = shape
                    .iter()
                    .enumerate()
                    .map(|(pw, &c)| c * monomial_derivative(pw, d, t))
                    .sum();
                out[l * no + d] = dt * h.powi(k as i32 - d as i32);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::tolerance::{FINITE_DIFFERENCE, ROUND_OFF};

    #[test]
    fn nodal_dofs_are_kronecker() {
        for r in 1..=2 {
            let part = Partition::new(vec![0.0, 0.4, 1.1]).unwrap();
            let b = Hermite1d::new(part, r).unwrap();
            let n = b.local_count();
            let mut out = vec![0.0; n * (r + 1)];
            for (end, x) in [(0usize, 0.4), (1usize, 1.1)] {
                b.eval(1, x, r, &mut out);
                for l in 0..n {
                    for d in 0..=r {
                        let expect = if l == end * (r + 1) + d { 1.0 } else { 0.0 };
                        assert_near!(out[l * (r + 1) + d], expect, ROUND_OFF, "r {r} l {l} d {d}");
                    }
                }
            }
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let h = 1e-5;
        let b = Hermite1d::new(Partition::new(vec![0.0, 0.4, 1.1]).unwrap(), 2).unwrap();
        let (n, o) = (b.local_count(), 6);
        let (mut v, mut vp, mut vm) = (vec![0.0; n * o], vec![0.0; n * o], vec![0.0; n * o]);
        b.eval(1, 0.7, 5, &mut v);
        b.eval(1, 0.7 + h, 5, &mut vp);
        b.eval(1, 0.7 - h, 5, &mut vm);
        for l in 0..n {
            for d in 1..=5 {
                let fd = (vp[l * o + d - 1] - vm[l * o + d - 1]) / (2.0 * h);
                assert_near!(v[l * o + d], fd, FINITE_DIFFERENCE);
            }
        }
    }

    #[test]
    fn cubic_shapes_are_the_classical_ones() {
        // H₀(t) = 1 − 3t² + 2t³ on [0, 1], checked at t = 0.3.
        let b = Hermite1d::new(Partition::new(vec![0.0, 1.0]).unwrap(), 1).unwrap();
        let mut out = vec![0.0; 4];
        b.eval(0, 0.3, 0, &mut out);
        let t: f64 = 0.3;
        assert_near!(out[0], 1.0 - 3.0 * t * t + 2.0 * t.powi(3), ROUND_OFF);
        assert_near!(out[1], t - 2.0 * t * t + t.powi(3), ROUND_OFF);
        assert_near!(out[2], 3.0 * t * t - 2.0 * t.powi(3), ROUND_OFF);
        assert_near!(out[3], -t * t + t.powi(3), ROUND_OFF);
    }
}
