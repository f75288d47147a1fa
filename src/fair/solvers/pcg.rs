//! The preconditioned conjugate gradient method (paper §5, final phase of the block
//! method: "the system (7) is solved using the conjugate gradient method [10], with a
//! preconditioner"). H may be indefinite even when every block of the preconditioner is
//! positive definite; CG detects it by a direction of non-positive curvature pᵀHp ≤ 0,
//! and the caller then returns to block iterations, as the paper does.

use rayon::prelude::*;

use crate::fair::functional::evaluation::BlockHessian;
use crate::linalg::dot;

/// Why [`pcg`] stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CgStop {
    /// ‖b − Hx‖ ≤ tolerance · ‖b‖.
    Converged,
    /// A direction with pᵀHp ≤ 0 (or a preconditioned residual with rᵀz ≤ 0): H (or the
    /// preconditioner) is not positive definite.
    Indefinite,
    /// The iteration limit was reached first.
    IterationLimit,
}

/// The outcome of [`pcg`].
#[derive(Debug, Clone, PartialEq)]
pub struct CgOutcome {
    pub x: Vec<f64>,
    pub iterations: usize,
    /// ‖b − Hx‖ / ‖b‖ by the recurrence.
    pub relative_residual: f64,
    pub stop: CgStop,
}

/// y = H x for the symmetric `h` stored as its upper 3 × 3 blocks (the diagonal blocks'
/// upper triangles are mirrored, as the Cholesky factorizer reads them).
pub fn multiply(h: &BlockHessian, x: &[f64]) -> Vec<f64> {
    let n = x.len();
    let chunk = (h.blocks.len() / (4 * rayon::current_num_threads())).max(4096);
    h.blocks
        .par_chunks(chunk)
        .zip(h.values.par_chunks(chunk))
        .fold(
            || vec![0.0; n],
            |mut y, (blocks, values)| {
                for (&(i, j), v) in blocks.iter().zip(values) {
                    let (i, j) = (3 * i as usize, 3 * j as usize);
                    for a in 0..3 {
                        for b in 0..3 {
                            let m = if i == j {
                                v[a.min(b)][a.max(b)]
                            } else {
                                v[a][b]
                            };
                            y[i + a] += m * x[j + b];
                            if i != j {
                                y[j + b] += m * x[i + a];
                            }
                        }
                    }
                }
                y
            },
        )
        .reduce(
            || vec![0.0; n],
            |mut a, b| {
                for (x, y) in a.iter_mut().zip(&b) {
                    *x += y;
                }
                a
            },
        )
}

/// Solves (H + `shift` I) x = b from x = 0 by CG preconditioned with `precondition` (r ↦ B⁻¹ r,
/// which must be symmetric positive definite), until ‖r‖ ≤ `tolerance` · ‖b‖.
pub fn pcg(
    h: &BlockHessian,
    shift: f64,
    b: &[f64],
    precondition: &dyn Fn(&[f64]) -> Vec<f64>,
    tolerance: f64,
    max_iterations: usize,
) -> CgOutcome {
    let operator = |p: &[f64]| {
        let mut hp = multiply(h, p);
        if shift != 0.0 {
            for (y, x) in hp.iter_mut().zip(p) {
                *y += shift * x;
            }
        }
        hp
    };
    pcg_operator(&operator, b, precondition, tolerance, max_iterations)
}

/// [`pcg`] for the symmetric operator `apply` (x ↦ A x).
pub fn pcg_operator(
    apply: &(dyn Fn(&[f64]) -> Vec<f64> + Sync),
    b: &[f64],
    precondition: &dyn Fn(&[f64]) -> Vec<f64>,
    tolerance: f64,
    max_iterations: usize,
) -> CgOutcome {
    let n = b.len();
    let b_norm = dot(b, b).sqrt();
    let mut x = vec![0.0; n];
    let outcome = |x, iterations, residual: f64, stop| CgOutcome {
        x,
        iterations,
        relative_residual: if b_norm > 0.0 { residual / b_norm } else { 0.0 },
        stop,
    };
    if b_norm == 0.0 {
        return outcome(x, 0, 0.0, CgStop::Converged);
    }
    let mut r = b.to_vec();
    let mut z = precondition(&r);
    let mut rz = dot(&r, &z);
    let mut p = z.clone();
    let mut residual = b_norm;
    for k in 0..max_iterations {
        if rz.is_nan() || rz <= 0.0 {
            return outcome(x, k, residual, CgStop::Indefinite);
        }
        let hp = apply(&p);
        let curvature = dot(&p, &hp);
        if curvature.is_nan() || curvature <= 0.0 {
            return outcome(x, k, residual, CgStop::Indefinite);
        }
        let alpha = rz / curvature;
        for i in 0..n {
            x[i] += alpha * p[i];
            r[i] -= alpha * hp[i];
        }
        residual = dot(&r, &r).sqrt();
        if residual <= tolerance * b_norm {
            return outcome(x, k + 1, residual, CgStop::Converged);
        }
        z = precondition(&r);
        let rz_next = dot(&r, &z);
        let beta = rz_next / rz;
        rz = rz_next;
        for i in 0..n {
            p[i] = z[i] + beta * p[i];
        }
    }
    outcome(x, max_iterations, residual, CgStop::IterationLimit)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2-vertex (6 × 6) matrix: blocks (0,0), (0,1), (1,1).
    fn matrix(shift: f64) -> BlockHessian {
        let d = |s: f64| {
            [
                [4.0 + s, 1.0, 0.5],
                [1.0, 3.0 + s, 0.2],
                [0.5, 0.2, 5.0 + s],
            ]
        };
        BlockHessian {
            blocks: vec![(0, 0), (0, 1), (1, 1)],
            values: vec![
                d(shift),
                [[0.3, -0.1, 0.0], [0.2, 0.4, 0.1], [0.0, 0.0, -0.5]],
                d(shift),
            ],
        }
    }

    #[test]
    fn multiply_is_the_symmetric_matrix() {
        let h = matrix(0.0);
        // Column 4 (vertex 1, coordinate 1): upper block (0,1) column 1, diagonal (1,1) column 1.
        let mut e = vec![0.0; 6];
        e[4] = 1.0;
        assert_eq!(multiply(&h, &e), vec![-0.1, 0.4, 0.0, 1.0, 3.0, 0.2]);
    }

    #[test]
    fn cg_solves_and_detects_indefiniteness() {
        let h = matrix(0.0);
        let b = vec![1.0, -2.0, 0.5, 3.0, 0.0, 1.0];
        let identity = |r: &[f64]| r.to_vec();
        let out = pcg(&h, 0.0, &b, &identity, 1e-12, 100);
        assert_eq!(out.stop, CgStop::Converged);
        let r: f64 = multiply(&h, &out.x)
            .iter()
            .zip(&b)
            .map(|(a, b)| (a - b).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(r <= 1e-12 * dot(&b, &b).sqrt());
        let out = pcg(&matrix(-10.0), 0.0, &b, &identity, 1e-12, 100);
        assert_eq!(out.stop, CgStop::Indefinite);
    }
}
