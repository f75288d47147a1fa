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
/// t ([`super::polynomial::basis`] in fixed-size arrays).
pub fn bernstein_derivatives(t: f64) -> [[f64; ORDER]; 4] {
    let rows = super::polynomial::basis(DEGREE, t, 3);
    std::array::from_fn(|r| std::array::from_fn(|i| rows[r][i]))
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
