//! Gauss–Legendre quadrature on [0, 1]: the functional (paper eq. 3 and 5) is integrated
//! patch by patch with a tensor-product rule.

use crate::error::{Error, Result};

/// The largest number of nodes per direction [`gauss_legendre`] gives.
pub const MAX_NODES: usize = 16;

/// Nodes and weights of the `n`-point Gauss–Legendre rule on `[0, 1]` (exact for
/// polynomials of degree `2n − 1`). The nodes are roots of the Legendre polynomial
/// `P_n`, found by Newton's method from Chebyshev guesses.
///
/// # Errors
/// [`Error::InvalidInput`] unless `1 ≤ n ≤ MAX_NODES`.
pub fn gauss_legendre(n: usize) -> Result<Vec<(f64, f64)>> {
    if !(1..=MAX_NODES).contains(&n) {
        return Err(Error::InvalidInput(format!(
            "{n} quadrature nodes per direction; 1..={MAX_NODES} are supported"
        )));
    }
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        // Root i of P_n on [−1, 1], descending.
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (p, d) = legendre(n, x);
            dp = d;
            let dx = p / d;
            x -= dx;
            if dx.abs() <= f64::EPSILON {
                break;
            }
        }
        let (_, d) = legendre(n, x);
        if d != 0.0 {
            dp = d;
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        out.push((0.5 * (1.0 - x), 0.5 * w));
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok(out)
}

/// `(P_n(x), P_n'(x))` by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let k = k as f64;
        let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    let n = n as f64;
    (p1, n * (x * p1 - p0) / (x * x - 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::tolerance::ROUND_OFF;

    #[test]
    fn integrates_monomials_exactly_up_to_degree_2n_minus_1() {
        for n in 1..=MAX_NODES {
            let rule = gauss_legendre(n).unwrap();
            for d in 0..2 * n {
                let q: f64 = rule.iter().map(|&(x, w)| w * x.powi(d as i32)).sum();
                assert_near!(q, 1.0 / (d as f64 + 1.0), ROUND_OFF, "n = {n}, degree {d}");
            }
        }
    }

    #[test]
    fn rejects_zero_nodes() {
        assert!(gauss_legendre(0).is_err());
        assert!(gauss_legendre(MAX_NODES + 1).is_err());
    }
}
