//! Univariate polynomials in Bernstein form of any degree — the junction functions, the
//! auxiliary patches' curves and their Hermite interpolants — and the biquintic Coons
//! projector on degree-(9, 9) patches.

use super::bernstein::ORDER;

/// `out[r][i]`: the r-th derivative (r = 0..=`order`) of the degree-n Bernstein polynomial
/// Bᵢⁿ at t (d/dt Bᵢⁿ = n (Bᵢ₋₁ⁿ⁻¹ − Bᵢⁿ⁻¹), applied r times).
pub fn basis(n: usize, t: f64, order: usize) -> Vec<Vec<f64>> {
    let lower = |m: usize| -> Vec<f64> {
        let mut b = vec![0.0; m + 1];
        b[0] = 1.0;
        for level in 1..=m {
            for i in (0..=level).rev() {
                let left = if i > 0 { b[i - 1] * t } else { 0.0 };
                b[i] = b[i] * (1.0 - t) + left;
            }
        }
        b
    };
    (0..=order)
        .map(|r| {
            let mut row = vec![0.0; n + 1];
            if r > n {
                return row;
            }
            let base = lower(n - r);
            let falling: f64 = (0..r).map(|q| (n - q) as f64).product();
            for (i, value) in row.iter_mut().enumerate() {
                let mut sum = 0.0;
                for q in 0..=r {
                    if i >= q && i - q <= n - r {
                        let sign = if (r - q) % 2 == 0 { 1.0 } else { -1.0 };
                        sum += sign * binomial(r, q) * base[i - q];
                    }
                }
                *value = falling * sum;
            }
            row
        })
        .collect()
}

/// The r-th derivative at t of the polynomial with Bernstein coefficients `c`.
pub fn derivative(c: &[f64], t: f64, r: usize) -> f64 {
    let b = basis(c.len() - 1, t, r);
    b[r].iter().zip(c).map(|(w, x)| w * x).sum()
}

/// Bernstein coefficients of the degree-n polynomial with derivatives `at0[m]` (order m)
/// at 0 and `at1[m]` at 1, `at0.len() + at1.len() = n + 1` (two-point Hermite
/// interpolation): the m-th derivative at 0 is n!/(n−m)! Δᵐc₀, at 1 n!/(n−m)! Δᵐc_{n−m}.
pub fn hermite(n: usize, at0: &[f64], at1: &[f64]) -> Vec<f64> {
    debug_assert_eq!(at0.len() + at1.len(), n + 1);
    let mut c = vec![0.0; n + 1];
    let falling = |m: usize| -> f64 { (0..m).map(|q| (n - q) as f64).product() };
    for (m, &d) in at0.iter().enumerate() {
        // Δᵐc₀ = Σ_q (−1)^{m−q} C(m, q) c_q; solve for c_m (coefficient 1).
        let mut rest = 0.0;
        for (q, &cq) in c.iter().enumerate().take(m) {
            let sign = if (m - q) % 2 == 0 { 1.0 } else { -1.0 };
            rest += sign * binomial(m, q) * cq;
        }
        c[m] = d / falling(m) - rest;
    }
    for (m, &d) in at1.iter().enumerate() {
        // Δᵐc_{n−m} = Σ_q (−1)^{m−q} C(m, q) c_{n−m+q}; c_{n−m} has coefficient (−1)^m.
        let mut rest = 0.0;
        for q in 1..=m {
            let sign = if (m - q) % 2 == 0 { 1.0 } else { -1.0 };
            rest += sign * binomial(m, q) * c[n - m + q];
        }
        let sign = if m % 2 == 0 { 1.0 } else { -1.0 };
        c[n - m] = sign * (d / falling(m) - rest);
    }
    c
}

/// Bernstein coefficients of degree `to` of the degree-(`c.len()`−1) polynomial `c`.
pub fn elevate(c: &[f64], to: usize) -> Vec<f64> {
    let mut c = c.to_vec();
    while c.len() <= to {
        let n = c.len();
        let mut next = vec![0.0; n + 1];
        next[0] = c[0];
        next[n] = c[n - 1];
        for i in 1..n {
            let a = i as f64 / n as f64;
            next[i] = a * c[i - 1] + (1.0 - a) * c[i];
        }
        c = next;
    }
    c
}

/// The 10 × 10 matrix of the quintic Hermite projector on degree-9 polynomials: the
/// quintic with the same value and first and second derivatives at 0 and 1, written in
/// degree 9 (`m[i][j]`: coefficient i of the image of B_j⁹).
fn quintic_projector() -> [[f64; ORDER]; ORDER] {
    let mut m = [[0.0; ORDER]; ORDER];
    let (b0, b1) = (basis(ORDER - 1, 0.0, 2), basis(ORDER - 1, 1.0, 2));
    for j in 0..ORDER {
        let at0: Vec<f64> = (0..3).map(|r| b0[r][j]).collect();
        let at1: Vec<f64> = (0..3).map(|r| b1[r][j]).collect();
        let image = elevate(&hermite(5, &at0, &at1), ORDER - 1);
        for (i, v) in image.iter().enumerate() {
            m[i][j] = *v;
        }
    }
    m
}

/// The biquintic Coons patch with the same boundary data (value and first and second cross
/// derivatives on the four sides) as the degree-(9, 9) patch `c` (index `ORDER·a + b`):
/// P_u c + P_v c − P_u P_v c with P the quintic Hermite projector in each direction. It
/// differs from `c` by a combination of the bubbles B₃..₆ ⊗ B₃..₆.
pub fn coons(c: &[f64]) -> Vec<f64> {
    let m = quintic_projector();
    let at = |a: usize, b: usize| c[ORDER * a + b];
    let mut mu = vec![0.0; c.len()]; // P_u c
    let mut mv = vec![0.0; c.len()]; // P_v c
    for a in 0..ORDER {
        for b in 0..ORDER {
            mu[ORDER * a + b] = (0..ORDER).map(|q| m[a][q] * at(q, b)).sum();
            mv[ORDER * a + b] = (0..ORDER).map(|q| m[b][q] * at(a, q)).sum();
        }
    }
    let mut out = vec![0.0; c.len()];
    for a in 0..ORDER {
        for b in 0..ORDER {
            let both: f64 = (0..ORDER).map(|q| m[b][q] * mu[ORDER * a + q]).sum();
            out[ORDER * a + b] = mu[ORDER * a + b] + mv[ORDER * a + b] - both;
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
    fn hermite_data_are_reproduced() {
        // degree 7, five data at 0 and three at 1
        let (at0, at1) = ([1.0, -2.0, 0.5, 3.0, -1.0], [0.25, 4.0, -6.0]);
        let c = hermite(7, &at0, &at1);
        for (m, &d) in at0.iter().enumerate() {
            assert!((derivative(&c, 0.0, m) - d).abs() < 1e-10, "order {m} at 0");
        }
        for (m, &d) in at1.iter().enumerate() {
            assert!((derivative(&c, 1.0, m) - d).abs() < 1e-10, "order {m} at 1");
        }
        let e = elevate(&c, 9);
        for &t in &[0.1, 0.6] {
            assert!((derivative(&e, t, 1) - derivative(&c, t, 1)).abs() < 1e-10);
        }
    }

    #[test]
    fn the_coons_patch_keeps_the_boundary_data_and_drops_bubbles() {
        let c: Vec<f64> = (0..ORDER * ORDER)
            .map(|i| ((i * 37 % 101) as f64 / 50.0) - 1.0)
            .collect();
        let p = coons(&c);
        // Bubble coefficients change, boundary rows (index 0..3 and 7..10) do not matter:
        // compare derivatives on the four sides instead.
        for &t in &[0.0, 0.3, 0.77, 1.0] {
            let bt = basis(ORDER - 1, t, 0);
            for side in [0.0, 1.0] {
                let bs = basis(ORDER - 1, side, 2);
                for derivative in &bs {
                    let eval = |x: &[f64], across_u: bool| -> f64 {
                        let mut s = 0.0;
                        for a in 0..ORDER {
                            for b in 0..ORDER {
                                let w = if across_u {
                                    derivative[a] * bt[0][b]
                                } else {
                                    bt[0][a] * derivative[b]
                                };
                                s += w * x[ORDER * a + b];
                            }
                        }
                        s
                    };
                    for across_u in [true, false] {
                        assert!((eval(&p, across_u) - eval(&c, across_u)).abs() < 1e-9);
                    }
                }
            }
        }
        // Idempotent.
        let q = coons(&p);
        assert!(p.iter().zip(&q).all(|(x, y)| (x - y).abs() < 1e-10));
    }
}
