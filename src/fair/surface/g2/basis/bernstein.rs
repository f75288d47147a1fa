//! The Bernstein basis of degree 9 (the special patches' degree in each direction) and its
//! derivatives, for evaluating and constraining patches given by their 10 × 10 Bézier
//! coefficients.

/// Degree of the special patches in u and in v.
pub const DEGREE: usize = 9;
/// Bézier coefficients per direction.
pub const ORDER: usize = DEGREE + 1;
/// Bézier coefficients of one special patch (index `ORDER * a + b`, a along u).
pub const COEFFICIENTS: usize = ORDER * ORDER;

/// `out[r][i]`: the r-th derivative (r = 0..=3) of the degree-9 Bernstein polynomial Bᵢ at
/// t, from the derivatives of lower-degree Bernstein polynomials: d/dt Bᵢⁿ = n (Bᵢ₋₁ⁿ⁻¹ −
/// Bᵢⁿ⁻¹).
pub fn bernstein_derivatives(t: f64) -> [[f64; ORDER]; 4] {
    // basis[n][i] = Bᵢⁿ(t) for n = DEGREE − 3 ..= DEGREE
    let basis = |n: usize| -> Vec<f64> {
        let mut b = vec![0.0; n + 1];
        b[0] = 1.0;
        for m in 1..=n {
            for i in (0..=m).rev() {
                let left = if i > 0 { b[i - 1] * t } else { 0.0 };
                b[i] = b[i] * (1.0 - t) + left;
            }
        }
        b
    };
    let mut out = [[0.0; ORDER]; 4];
    for (r, row) in out.iter_mut().enumerate() {
        let n = DEGREE - r;
        let lower = basis(n);
        // r-th derivative: n!/(n−r)! Σ_k (−1)^(r−k) C(r, k) B_{i−k}^{n−r}
        let falling: f64 = (0..r).map(|q| (DEGREE - q) as f64).product();
        for (i, value) in row.iter_mut().enumerate() {
            let mut sum = 0.0;
            for k in 0..=r {
                if i >= k && i - k <= n {
                    let sign = if (r - k) % 2 == 0 { 1.0 } else { -1.0 };
                    sum += sign * binomial(r, k) * lower[i - k];
                }
            }
            *value = falling * sum;
        }
    }
    out
}

fn binomial(n: usize, k: usize) -> f64 {
    (0..k).fold(1.0, |acc, q| acc * (n - q) as f64 / (q + 1) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivatives_match_finite_differences_and_sum_to_a_partition_of_unity() {
        for &t in &[0.0, 0.13, 0.5, 0.91, 1.0] {
            let d = bernstein_derivatives(t);
            assert!((d[0].iter().sum::<f64>() - 1.0).abs() < 1e-14);
            for (r, row) in d.iter().enumerate().skip(1) {
                assert!(row.iter().sum::<f64>().abs() < 1e-10, "Σ of derivative {r}");
            }
            if t == 0.0 || t == 1.0 {
                continue;
            }
            let h = 1e-6;
            let (lo, hi) = (bernstein_derivatives(t - h), bernstein_derivatives(t + h));
            let span = 2.0 * h;
            for (r, next) in d.iter().skip(1).enumerate() {
                for (i, &exact) in next.iter().enumerate() {
                    let fd = (hi[r][i] - lo[r][i]) / span;
                    assert!((fd - exact).abs() < 1e-4 * (1.0 + exact.abs()));
                }
            }
        }
        // at the ends only the first r + 1 functions have an r-th derivative
        let d = bernstein_derivatives(0.0);
        assert_eq!(d[2][3], 0.0);
        assert!((d[1][0] + 9.0).abs() < 1e-14 && (d[1][1] - 9.0).abs() < 1e-14);
    }
}
