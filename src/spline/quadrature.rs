//! Gauss–Legendre quadrature: n nodes integrate polynomials of degree 2n − 1 exactly, which
//! is what makes the Gram matrices of polynomial pieces exact.

use crate::error::{Error, Result};

/// Nodes and weights of the n-point Gauss–Legendre rule on [−1, 1].
#[derive(Debug, Clone)]
pub struct GaussLegendre {
    /// Nodes in (−1, 1), increasing.
    pub nodes: Vec<f64>,
    /// Positive weights summing to 2.
    pub weights: Vec<f64>,
}

impl GaussLegendre {
    /// The n-point rule, nodes found by Newton's iteration on the Legendre polynomial
    /// Pₙ from the Chebyshev guesses (Golub–Welsch-free, converges quadratically).
    ///
    /// Errors: `InvalidInput` if `n == 0`.
    pub fn new(n: usize) -> Result<Self> {
        if n == 0 {
            return Err(Error::InvalidInput(
                "Gauss–Legendre rule needs at least one node".into(),
            ));
        }
        let mut nodes = vec![0.0; n];
        let mut weights = vec![0.0; n];
        let nf = n as f64;
        for i in 0..n.div_ceil(2) {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (p, d) = legendre(n, x);
                dp = d;
                let dx = p / d;
                x -= dx;
                if dx.abs() <= f64::EPSILON * x.abs().max(1.0) {
                    let (_, d) = legendre(n, x);
                    dp = d;
                    break;
                }
            }
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            nodes[i] = -x;
            nodes[n - 1 - i] = x;
            weights[i] = w;
            weights[n - 1 - i] = w;
        }
        Ok(Self { nodes, weights })
    }

    /// Nodes and weights mapped to [a, b].
    pub fn on_interval(&self, a: f64, b: f64) -> impl Iterator<Item = (f64, f64)> + '_ {
        let half = 0.5 * (b - a);
        let mid = 0.5 * (a + b);
        self.nodes
            .iter()
            .zip(&self.weights)
            .map(move |(&t, &w)| (mid + half * t, half * w))
    }
}

/// Pₙ(x) and Pₙ'(x) by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    let d = n as f64 * (x * p1 - p0) / (x * x - 1.0);
    (p1, d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::tolerance::ROUND_OFF;

    #[test]
    fn integrates_monomials_exactly_up_to_degree_2n_minus_1() {
        for n in 1..=8 {
            let g = GaussLegendre::new(n).unwrap();
            for k in 0..2 * n {
                let q: f64 = g
                    .on_interval(0.5, 2.0)
                    .map(|(x, w)| w * x.powi(k as i32))
                    .sum();
                let exact =
                    (2f64.powi(k as i32 + 1) - 0.5f64.powi(k as i32 + 1)) / (k as f64 + 1.0);
                assert_near!(q, exact, ROUND_OFF, "n = {n}, x^{k}");
            }
        }
    }

    #[test]
    fn zero_nodes_is_an_error() {
        assert!(GaussLegendre::new(0).is_err());
    }
}
