//! The uniform cubic B-spline basis and its derivatives up to third order, and the bicubic
//! tensor product on a 4 × 4 patch of control points — the form of every patch of the
//! limit surface once end caps are B-spline patches.

/// Values of the four uniform cubic B-spline basis functions at `t ∈ [0, 1]` and their
/// first, second and third derivatives: `out[k][i]` = k-th derivative of `B_i`.
pub fn cubic_basis(t: f64) -> [[f64; 4]; 4] {
    let s = 1.0 - t;
    [
        [
            s * s * s / 6.0,
            (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
            (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
            t * t * t / 6.0,
        ],
        [
            -s * s / 2.0,
            1.5 * t * t - 2.0 * t,
            -1.5 * t * t + t + 0.5,
            t * t / 2.0,
        ],
        [s, 3.0 * t - 2.0, 1.0 - 3.0 * t, t],
        [-1.0, 3.0, -3.0, 1.0],
    ]
}

/// Partial derivatives of a surface at a point, all with respect to the same (u, v).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Derivatives {
    pub position: [f64; 3],
    pub du: [f64; 3],
    pub dv: [f64; 3],
    pub duu: [f64; 3],
    pub duv: [f64; 3],
    pub dvv: [f64; 3],
    pub duuu: [f64; 3],
    pub duuv: [f64; 3],
    pub duvv: [f64; 3],
    pub dvvv: [f64; 3],
}

/// Evaluates the bicubic B-spline patch with control points `p` (row-major, `p[4 i + j]` in
/// row `i` along v and column `j` along u, as OpenSubdiv orders them) at `(s, t)` in the
/// unit square. Derivatives are with respect to `(s, t)`.
pub fn eval_patch(p: &[[f64; 3]; 16], s: f64, t: f64) -> Derivatives {
    let bu = cubic_basis(s);
    let bv = cubic_basis(t);
    let term = |a: usize, b: usize| -> [f64; 3] {
        let mut out = [0.0; 3];
        for i in 0..4 {
            for j in 0..4 {
                let w = bu[a][j] * bv[b][i];
                for k in 0..3 {
                    out[k] += w * p[4 * i + j][k];
                }
            }
        }
        out
    };
    Derivatives {
        position: term(0, 0),
        du: term(1, 0),
        dv: term(0, 1),
        duu: term(2, 0),
        duv: term(1, 1),
        dvv: term(0, 2),
        duuu: term(3, 0),
        duuv: term(2, 1),
        duvv: term(1, 2),
        dvvv: term(0, 3),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::tolerance::{FINITE_DIFFERENCE, ROUND_OFF};

    #[test]
    fn partition_of_unity_and_derivatives_sum_to_zero() {
        for t in [0.0, 0.25, 0.5, 0.9, 1.0] {
            let b = cubic_basis(t);
            assert_near!(b[0].iter().sum::<f64>(), 1.0, ROUND_OFF);
            for k in 1..4 {
                assert_near!(b[k].iter().sum::<f64>(), 0.0, ROUND_OFF);
            }
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let h = 1e-5;
        for t in [0.2, 0.5, 0.7] {
            let (lo, hi, mid) = (cubic_basis(t - h), cubic_basis(t + h), cubic_basis(t));
            for k in 0..3 {
                for i in 0..4 {
                    let fd = (hi[k][i] - lo[k][i]) / (2.0 * h);
                    assert_near!(fd, mid[k + 1][i], FINITE_DIFFERENCE);
                }
            }
        }
    }

    #[test]
    fn reproduces_linear_functions() {
        // Control points at knot-centred abscissae i − 1 reproduce x = s exactly.
        let p: [[f64; 3]; 16] =
            std::array::from_fn(|n| [(n % 4) as f64 - 1.0, (n / 4) as f64 - 1.0, 0.0]);
        let d = eval_patch(&p, 0.3, 0.8);
        assert_near!(d.position[0], 0.3, ROUND_OFF);
        assert_near!(d.position[1], 0.8, ROUND_OFF);
        assert_near!(d.du[0], 1.0, ROUND_OFF);
        assert_near!(d.dv[1], 1.0, ROUND_OFF);
        assert_near!(d.duu[0], 0.0, ROUND_OFF);
    }
}
