//! The optimizer (paper §5): Newton's method with the exact Hessian and a sparse Cholesky
//! factor; where the Hessian is not positive definite or the Newton step does not decrease
//! F, a search along the Levenberg–Marquardt trajectory (eq. 8–9); the Hessian and its
//! factor are reused while a step cuts the gradient norm by at least a factor 4.

use std::time::Instant;

use crate::error::{Error, Result};
use crate::fair::cholesky::{Factor, Factorizer};
use crate::fair::functional::{Functional, Terms};
use crate::fair::representation::Representation;
use crate::tolerance::ROUND_OFF;

/// What an iteration did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StepKind {
    /// Newton step with a freshly computed Hessian (eq. 7).
    Newton,
    /// Newton step with the previous Hessian's factor.
    ReusedNewton,
    /// Minimum along the Levenberg–Marquardt trajectory (eq. 8–9).
    LevenbergMarquardt,
    /// Backtracking step along −g when no H + νI gave one (a safeguard, not in the paper).
    SteepestDescent,
}

/// One line of the per-iteration log.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Iteration {
    pub terms: Terms,
    pub gradient_norm: f64,
    pub step: StepKind,
    /// ν of eq. 9 for a Levenberg–Marquardt step.
    pub nu: Option<f64>,
}

/// Stopping rules of [`newton`].
#[derive(Debug, Clone, PartialEq)]
pub struct NewtonOptions {
    /// Stop when ‖g‖ ≤ `relative_gradient` · ‖g₀‖.
    pub relative_gradient: f64,
    pub max_iterations: usize,
    /// Reuse the factor while a step divides ‖g‖ by at least this (§5: 4).
    pub reuse_factor: f64,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        NewtonOptions {
            relative_gradient: 1e-8,
            max_iterations: 200,
            reuse_factor: 4.0,
        }
    }
}

/// The outcome of [`newton`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct NewtonReport {
    pub initial: Terms,
    pub initial_gradient_norm: f64,
    pub iterations: Vec<Iteration>,
    pub hessian_evaluations: usize,
    /// Numeric Cholesky factorizations (Newton and Levenberg–Marquardt trials).
    pub factorizations: usize,
    /// Wall-clock seconds spent evaluating Hessians, and in factorizations.
    pub hessian_seconds: f64,
    pub factorization_seconds: f64,
    pub converged: bool,
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn moved(positions: &[[f64; 3]], free: &[u32], delta: &[f64]) -> Vec<[f64; 3]> {
    let mut out = positions.to_vec();
    for (v, &i) in free.iter().enumerate() {
        if i != u32::MAX {
            for a in 0..3 {
                out[v][a] += delta[3 * i as usize + a];
            }
        }
    }
    out
}

/// Whether `new` is an acceptable decrease from `old`: smaller, or equal to round-off.
fn decreases(new: f64, old: f64) -> bool {
    new.is_finite() && (new < old || (new - old).abs() <= ROUND_OFF * old.abs())
}

/// Minimizes F̃ (eq. 6) over the free vertices of `positions`, in place.
///
/// # Errors
/// [`Error::Solver`] when F or its gradient is not finite at the start (a degenerate
/// surface) or no Levenberg–Marquardt step decreases F; the positions reached so far are
/// kept in `positions`.
pub fn newton<R: Representation>(
    functional: &Functional<'_, R>,
    positions: &mut Vec<[f64; 3]>,
    options: &NewtonOptions,
) -> Result<NewtonReport> {
    newton_observed(functional, positions, options, &mut |_| {})
}

/// [`newton`], calling `observe` after each iteration (for progress display).
///
/// # Errors
/// As [`newton`].
pub fn newton_observed<R: Representation>(
    functional: &Functional<'_, R>,
    positions: &mut Vec<[f64; 3]>,
    options: &NewtonOptions,
    observe: &mut dyn FnMut(&Iteration),
) -> Result<NewtonReport> {
    let free = functional.free_index().to_vec();
    let mut factorizer = Factorizer::new(functional.free_count());
    let (mut terms, mut g) = functional.gradient(positions);
    if !terms.f.is_finite() || !g.iter().all(|x| x.is_finite()) {
        return Err(Error::Solver {
            failure: crate::error::SolverFailure::Singular,
            detail: "F or its gradient is not finite at the start: the surface is degenerate \
                     (vanishing tangents) somewhere"
                .into(),
        });
    }
    let g0 = norm(&g);
    let mut report = NewtonReport {
        initial: terms,
        initial_gradient_norm: g0,
        iterations: Vec::new(),
        hessian_evaluations: 0,
        factorizations: 0,
        hessian_seconds: 0.0,
        factorization_seconds: 0.0,
        converged: g0 == 0.0,
    };
    if functional.free_count() == 0 || g0 == 0.0 {
        report.converged = true;
        return Ok(report);
    }
    let mut reusable: Option<Factor> = None;
    // ν of the last Levenberg–Marquardt step: consecutive searches start there instead of
    // climbing from a tiny ν again (each try costs a factorization).
    let mut last_nu: Option<f64> = None;
    while report.iterations.len() < options.max_iterations {
        let gnorm = norm(&g);
        if gnorm <= options.relative_gradient * g0 {
            report.converged = true;
            break;
        }
        // 1. Newton with the kept factor.
        if let Some(factor) = &reusable {
            let delta = factor.newton_step(&g);
            let trial = moved(positions, &free, &delta);
            let (t, gt) = functional.gradient(&trial);
            if decreases(t.f, terms.f) && norm(&gt).is_finite() {
                let effective = norm(&gt) * options.reuse_factor <= gnorm;
                *positions = trial;
                terms = t;
                g = gt;
                report.iterations.push(Iteration {
                    terms,
                    gradient_norm: norm(&g),
                    step: StepKind::ReusedNewton,
                    nu: None,
                });
                observe(report.iterations.last().expect("just pushed"));
                if !effective {
                    reusable = None;
                }
                continue;
            }
            reusable = None;
        }
        // 2. Fresh Hessian, Newton step if positive definite and decreasing.
        let clock = Instant::now();
        let (t0, g0h, h) = functional.hessian(positions);
        report.hessian_evaluations += 1;
        report.hessian_seconds += clock.elapsed().as_secs_f64();
        terms = t0;
        g = g0h;
        let gnorm = norm(&g);
        let clock = Instant::now();
        let factored = factorizer.factor(&h, 0.0);
        report.factorizations += 1;
        report.factorization_seconds += clock.elapsed().as_secs_f64();
        if let Ok(factor) = factored {
            let delta = factor.newton_step(&g);
            let trial = moved(positions, &free, &delta);
            let (t, gt) = functional.gradient(&trial);
            if decreases(t.f, terms.f) && norm(&gt).is_finite() {
                let effective = norm(&gt) * options.reuse_factor <= gnorm;
                *positions = trial;
                terms = t;
                g = gt;
                report.iterations.push(Iteration {
                    terms,
                    gradient_norm: norm(&g),
                    step: StepKind::Newton,
                    nu: None,
                });
                observe(report.iterations.last().expect("just pushed"));
                if effective {
                    reusable = Some(factor);
                }
                continue;
            }
        }
        // 3. Levenberg–Marquardt trajectory: minimize f(ν) = F̃(x + δ_ν) (eq. 8–9) over
        // ν on a geometric grid (factors of 4): grow ν until F decreases, then follow the
        // direction in which F keeps decreasing.
        let scale = h
            .blocks
            .iter()
            .zip(&h.values)
            .filter(|(b, _)| b.0 == b.1)
            .map(|(_, v)| v[0][0].abs() + v[1][1].abs() + v[2][2].abs())
            .sum::<f64>()
            / (3 * functional.free_count()) as f64;
        let mut nu = last_nu.unwrap_or(scale.max(f64::MIN_POSITIVE) * 1e-3);
        let try_nu = |nu: f64,
                      factorizer: &mut Factorizer,
                      report: &mut NewtonReport|
         -> Option<(Terms, Vec<[f64; 3]>)> {
            let clock = Instant::now();
            let factored = factorizer.factor(&h, nu);
            report.factorizations += 1;
            report.factorization_seconds += clock.elapsed().as_secs_f64();
            let factor = factored.ok()?;
            let delta = factor.newton_step(&g);
            let trial = moved(positions, &free, &delta);
            let t = functional.value(&trial);
            (t.f.is_finite() && t.f < terms.f).then_some((t, trial))
        };
        let mut best = None;
        for _ in 0..60 {
            if let Some(found) = try_nu(nu, &mut factorizer, &mut report) {
                best = Some((nu, found));
                break;
            }
            nu *= 4.0;
        }
        if best.is_none() {
            // Safeguard (not in the paper): every H + νI failed to factor or to decrease F
            // (a non-finite Hessian entry at a nearly degenerate point, say). Steepest
            // descent with backtracking still decreases F when the gradient is sound.
            let mut alpha = 1.0 / scale.max(f64::MIN_POSITIVE);
            for _ in 0..60 {
                let delta: Vec<f64> = g.iter().map(|x| -alpha * x).collect();
                let trial = moved(positions, &free, &delta);
                let t = functional.value(&trial);
                if t.f.is_finite() && t.f < terms.f {
                    best = Some((f64::INFINITY, (t, trial)));
                    break;
                }
                alpha *= 0.25;
            }
        }
        let Some((mut best_nu, (mut best_t, mut best_x))) = best else {
            return Err(Error::Solver {
                failure: crate::error::SolverFailure::NotConverged,
                detail: format!(
                    "no step along the Levenberg–Marquardt trajectory decreases F = {:e} \
                     (gradient norm {gnorm:e})",
                    terms.f
                ),
            });
        };
        // f(ν) along the trajectory: move ν by factors of 4 in the direction that lowers
        // F further, until it stops improving.
        let refine: &[f64] = if best_nu.is_finite() {
            &[0.25, 4.0]
        } else {
            &[]
        };
        for &factor in refine {
            let mut moved_any = false;
            for _ in 0..30 {
                match try_nu(best_nu * factor, &mut factorizer, &mut report) {
                    Some((t, x)) if t.f < best_t.f => {
                        best_nu *= factor;
                        best_t = t;
                        best_x = x;
                        moved_any = true;
                    }
                    _ => break,
                }
            }
            if moved_any {
                break;
            }
        }
        if best_nu.is_finite() {
            last_nu = Some(best_nu);
        }
        *positions = best_x;
        let (t, gt) = functional.gradient(positions);
        debug_assert!((t.f - best_t.f).abs() <= ROUND_OFF * t.f.abs().max(1.0));
        terms = t;
        g = gt;
        report.iterations.push(Iteration {
            terms,
            gradient_norm: norm(&g),
            step: if best_nu.is_finite() {
                StepKind::LevenbergMarquardt
            } else {
                StepKind::SteepestDescent
            },
            nu: best_nu.is_finite().then_some(best_nu),
        });
        observe(report.iterations.last().expect("just pushed"));
    }
    if !report.converged {
        report.converged = norm(&g) <= options.relative_gradient * g0;
    }
    Ok(report)
}
