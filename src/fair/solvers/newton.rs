//! The optimizer (paper §5): Newton's method with the exact Hessian and a sparse Cholesky
//! factor; where the Hessian is not positive definite or the Newton step does not decrease
//! F, a search along the Levenberg–Marquardt trajectory (eq. 8–9); the Hessian and its
//! factor are reused while a step cuts the gradient norm by at least a factor 4.
//!
//! Two departures, both on by default and both reaching the same minimum (tested):
//! a Newton step that does not decrease F is halved up to four times before the search
//! ([`NewtonOptions::newton_halvings`]): far from the minimum the Hessian is often positive
//! definite and its step right but too long; and the trajectory's matrix is the Hessian's
//! Gauss–Newton part instead of the exact Hessian ([`LmMatrix`]): where the exact Hessian
//! of these junctions is strongly indefinite, the steps ν must make up for it are short.

use std::ops::ControlFlow;
use std::time::Instant;

use crate::error::{Error, Result};
use crate::fair::functional::evaluation::{BlockHessian, Functional, HessianKind, Hessians, Terms};
use crate::fair::solvers::cholesky::Factorizer;
use crate::fair::solvers::coarse_correction::{
    lowest_below, CoarseCorrection, COARSE_FORCING, COARSE_SHIFT_FRACTION, COARSE_STEP_LENGTHS,
};
use crate::fair::solvers::coordinate_floor::coordinate_floor;
use crate::fair::solvers::lattice_rounding::lattice_rounding;
use crate::fair::solvers::step_solver::{CholeskySolver, StepSolver};
use crate::fair::surface::representation::Representation;
use crate::linalg::{dot, norm};
use crate::tolerance::ROUND_OFF;

/// What an iteration did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StepKind {
    /// Newton step with a freshly computed Hessian (eq. 7).
    Newton,
    /// Newton step with the previous Hessian's factor.
    ReusedNewton,
    /// A half, quarter, … of a Newton step that did not decrease F
    /// ([`NewtonOptions::newton_halvings`]).
    DampedNewton,
    /// Minimum along the Levenberg–Marquardt trajectory (eq. 8–9).
    LevenbergMarquardt,
    /// Backtracking step along −g when no H + νI gave one (a safeguard, not in the paper).
    SteepestDescent,
    /// At the floor of `f64` coordinates: a Newton step whose rounding is chosen, not to
    /// nearest (`src/fair/solvers/lattice_rounding.rs`).
    LatticeRounding,
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
    /// Stop after this many consecutive Newton steps with a fresh Hessian that change F by
    /// no more than round-off and do not halve ‖g‖, above the coordinates' floor (where
    /// the run chooses the rounding first, [`StepKind::LatticeRounding`], and stops there if
    /// that is not enough): further Hessians would be wasted, and the run says it is
    /// [`NewtonReport::stuck`].
    pub stall_steps: usize,
    /// The matrix M of the Levenberg–Marquardt trajectory (M + νI) δ = −g.
    pub lm_matrix: LmMatrix,
    /// When a Newton step (positive definite Hessian) does not decrease F, try up to this
    /// many halvings of it before the Levenberg–Marquardt search; 0: straight to the
    /// search, as the paper. Beyond the paper; the default 4: far from the minimum the
    /// Newton direction is often right but too long (6237-vertex junction from the raw
    /// start, Cᵢ = 1, an earlier session: 12 Hessians and 37 factorizations instead of 18
    /// and 68).
    pub newton_halvings: usize,
    /// After a Levenberg–Marquardt step that lowered F by more than this fraction of it,
    /// the next iteration evaluates the Hessian's Gauss–Newton part alone and searches the
    /// trajectory again, without the exact Hessian and its Newton trial
    /// ([`LmMatrix::GaussNewton`] only; 1 with [`Self::newton_backoff`] off: always try
    /// Newton, as the paper). Beyond the paper: from a raw mesh the exact Hessian stays
    /// indefinite while the damped steps still lower F by percents, and a pass of the
    /// Gauss–Newton part alone costs about half a pass of both. The default
    /// [`NEWTON_AFTER_DECREASE`].
    pub newton_after_decrease: f64,
    /// After a fresh Hessian whose Newton step failed (not positive definite, or no
    /// decrease even halved), the next 1, then 2, 4, … passes that follow a
    /// Levenberg–Marquardt step evaluate the Gauss–Newton part alone, with no Newton trial;
    /// a Newton step that succeeds resets the count ([`LmMatrix::GaussNewton`] only).
    /// Beyond the paper: on the 94 077-vertex Catmull–Clark junction from the raw mesh, 10
    /// of 13 exact Hessians went to Newton trials that failed, the first pass's and nine in
    /// a row after damped steps that lowered F by 0.01 to 2 % (2026-11-27); with the
    /// backoff, 6 exact Hessians, the same minimum (the 223 487-vertex one: 11 against 23,
    /// 2026-11-28). Off: every such pass has the exact Hessian.
    pub newton_backoff: bool,
    /// How a Levenberg–Marquardt search spends its trials ([`LmSearch`]).
    pub lm_search: LmSearch,
    /// Bend each Levenberg–Marquardt step of the Gauss–Newton trajectory along the
    /// residuals' curvature: δ = v + a/2 with the geodesic acceleration a = −(B + νI)⁻¹
    /// 2 Σ w Jᵀ r_vv (Transtrum and Sethna 2012), when 2‖a‖ ≤ [`ACCELERATION_LIMIT`] ‖v‖;
    /// one more solve with the same set-up and one pass over the quadrature points per
    /// trial ([`LmMatrix::GaussNewton`] only). Beyond the paper. Off by default. It was on by
    /// default for the multilevel method on the Catmull–Clark surface from 90 000 free
    /// vertices, where it halved the damped steps (2026-11-28: 962.8 s against 1268.5 s at
    /// 218 879 free vertices); since the damped phase's 2 × 2 Hessians its steps come out
    /// the same without it, and single runs back to back (2026-11-30,
    /// docs/fairing-at-scale-log.md) took 372.6 and 392.7 s without it against 411.9 and
    /// 395.6 s with it at 218 879 free vertices, 224.0 against 231.6 s at 90 237, the same
    /// minima.
    pub geodesic_acceleration: bool,
    /// Follow each Levenberg–Marquardt step by a step of its matrix in the first coarse
    /// level's subspace ([`crate::fair::solvers::coarse_correction`]); solvers without
    /// coarse levels (the plain method) never do. Beyond the paper. Default
    /// [`CoarseCorrection::Auto`].
    pub coarse_correction: CoarseCorrection,
}

/// The default of [`NewtonOptions::newton_after_decrease`]. From the raw three- and
/// five-tube junctions (14 399, 23 997 and 56 447 vertices, G² surface, 2026-11-27) the
/// first Newton step that succeeded came after Levenberg–Marquardt steps that had lowered F
/// by 0.7 %, 0.11 % and 1.2 %; every Newton trial after a step of more than 2 % failed.
pub const NEWTON_AFTER_DECREASE: f64 = 0.02;

/// The matrix of the Levenberg–Marquardt trajectory.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LmMatrix {
    /// The exact Hessian, as the paper's eq. 8–9.
    Exact,
    /// The Hessian's Gauss–Newton part (S's and Q's densities as sums of squares):
    /// positive semidefinite, so the trajectory needs no ν to overcome negative
    /// curvature, and it leaves out the second-derivative terms that make the exact
    /// model wrong far from the minimum. Beyond the paper; the default: at 14399 vertices
    /// from the raw start 11 exact Hessians instead of 29 (without halved Newton steps,
    /// Cᵢ = 1, an earlier session), same minimum.
    GaussNewton,
}

/// How a Levenberg–Marquardt search ([`Stepper::lm_search`]) spends its trials, each a
/// V-cycle set-up or factorization of H + νI, a solve and a value of F.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LmSearch {
    /// Follow the trajectory while F decreases at all, and raise ν by 4 after a failed
    /// trial. The default.
    #[default]
    Exhaustive,
    /// Stop following the trajectory at the first trial that [`gains`] less than 1 % of
    /// the decrease already found, and raise ν by 16 after a failed trial ([`CLIMB`]). On
    /// the 94 077-vertex Catmull–Clark junction from the raw mesh: 75 set-ups of H + νI
    /// (trials and Newton steps) and 320.1 s against 109 and 368.0 s, the same minimum
    /// (2026-11-28, seventeenth session). Not the default: on the G² surface the same
    /// junction took 560.2 s, 6 + 25 passes, 87 set-ups and 888 CG iterations against
    /// 316.0 s, 4 + 18, 75 and 536, to the same minimum (back to back, the same day).
    Frugal,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        NewtonOptions {
            relative_gradient: 1e-8,
            max_iterations: 200,
            reuse_factor: 4.0,
            stall_steps: 3,
            lm_matrix: LmMatrix::GaussNewton,
            newton_halvings: 4,
            newton_after_decrease: NEWTON_AFTER_DECREASE,
            newton_backoff: true,
            lm_search: LmSearch::Exhaustive,
            geodesic_acceleration: false,
            coarse_correction: CoarseCorrection::Auto,
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
    /// Evaluations of the Hessian's Gauss–Newton part (alone, or with the exact Hessian
    /// in one pass) for the Levenberg–Marquardt search ([`LmMatrix::GaussNewton`]).
    pub gauss_newton_evaluations: usize,
    /// Of those, the passes that evaluated the Gauss–Newton part alone (no exact Hessian,
    /// [`NewtonOptions::newton_after_decrease`]): about half a pass of both.
    pub gauss_newton_only_evaluations: usize,
    /// Matrices H + νI readied for solves (Newton and Levenberg–Marquardt trials): numeric
    /// Cholesky factorizations (plain method), multigrid set-ups with a factorization of
    /// the coarsest level (multilevel method).
    pub factorizations: usize,
    /// Wall-clock seconds spent evaluating Hessians, and readying matrices.
    pub hessian_seconds: f64,
    pub factorization_seconds: f64,
    /// Conjugate-gradient iterations of the multilevel method's solves, and their seconds
    /// (0 for the plain method).
    pub cg_iterations: usize,
    pub cg_seconds: f64,
    /// Cholesky factors of the fine matrix the multilevel method fell back to where its
    /// V-cycle did not serve, and their seconds (0 for the plain method).
    pub fine_factorizations: usize,
    pub fine_factorization_seconds: f64,
    /// Whether the Levenberg–Marquardt steps were bent by their geodesic acceleration
    /// ([`NewtonOptions::geodesic_acceleration`] on a Gauss–Newton trajectory), and the trials
    /// whose step was.
    pub geodesic_acceleration: bool,
    pub accelerated_trials: usize,
    /// Seconds spent on geodesic accelerations (the residuals' curvature and its solve),
    /// and the conjugate-gradient iterations of those solves (in `cg_iterations` too).
    pub acceleration_seconds: f64,
    pub acceleration_cg_iterations: usize,
    /// Whether the Levenberg–Marquardt steps had their coarse-subspace correction
    /// ([`NewtonOptions::coarse_correction`] with coarse levels), the corrections that
    /// lowered F (taken), and the seconds of all tried (their set-ups and CG iterations are
    /// in the totals above too).
    pub coarse_correction: bool,
    pub coarse_corrections: usize,
    pub coarse_correction_seconds: f64,
    /// Wall-clock seconds of the [`StepKind::LatticeRounding`] steps (their Hessian passes,
    /// set-ups and solves are in the totals above too).
    pub lattice_seconds: f64,
    /// The coordinate-descent sweeps of those steps' roundings.
    pub lattice_sweeps: usize,
    /// Whether the near Hessians were raised to F's own nodes after
    /// [`SLOW_NEAR_STEPS`] slow Newton steps from fewer ([`HessianSources::near`]).
    pub near_hessians_raised: bool,
    pub converged: bool,
    /// ‖H u‖ for u the rounding of the free coordinates to `f64` to nearest, at the last
    /// fresh Hessian: about the smallest ‖g‖ a Newton step's stored positions have
    /// ([`crate::fair::solvers::coordinate_floor`]); a chosen rounding
    /// ([`StepKind::LatticeRounding`]) goes below it.
    pub coordinate_floor: Option<f64>,
    /// Stopped above the gradient tolerance with ‖g‖ within [`FLOOR_MARGIN`] times
    /// `coordinate_floor` once the chosen roundings ([`StepKind::LatticeRounding`]) gained
    /// what they could: the tolerance asks for more digits than `f64` coordinates have, and
    /// these positions are as close to the minimum as the run could tell them from their
    /// neighbours. `converged` is false then.
    pub stalled: bool,
    /// Stopped without converging because steps no longer make progress: no step along
    /// the Levenberg–Marquardt trajectory, nor along −g, decreased F (the gradient
    /// disagrees with F there: a nearly folded surface, where √(EG − F²) vanishes between
    /// quadrature points, say), or fresh Newton steps left F and ‖g‖ as they were above
    /// the coordinates' floor ([`NewtonOptions::stall_steps`]). The positions reached are
    /// returned; `converged` is false.
    pub stuck: bool,
    /// Stopped because the caller's observer asked for it (`ControlFlow::Break`): a
    /// progress dialog's cancel button, a C or Python callback. The positions reached are
    /// returned; `converged` says whether they happen to meet the tolerance.
    pub cancelled: bool,
}

impl NewtonReport {
    /// A report of no iterations yet, from F's terms and ‖g‖ at the start.
    pub fn new(initial: Terms, initial_gradient_norm: f64) -> Self {
        NewtonReport {
            initial,
            initial_gradient_norm,
            iterations: Vec::new(),
            hessian_evaluations: 0,
            gauss_newton_evaluations: 0,
            gauss_newton_only_evaluations: 0,
            factorizations: 0,
            hessian_seconds: 0.0,
            factorization_seconds: 0.0,
            cg_iterations: 0,
            cg_seconds: 0.0,
            fine_factorizations: 0,
            fine_factorization_seconds: 0.0,
            geodesic_acceleration: false,
            accelerated_trials: 0,
            acceleration_seconds: 0.0,
            acceleration_cg_iterations: 0,
            coarse_correction: false,
            coarse_corrections: 0,
            coarse_correction_seconds: 0.0,
            lattice_seconds: 0.0,
            lattice_sweeps: 0,
            near_hessians_raised: false,
            converged: initial_gradient_norm == 0.0,
            coordinate_floor: None,
            stalled: false,
            stuck: false,
            cancelled: false,
        }
    }

    /// The ‖g‖ at or below which the run stops at the floor: [`FLOOR_MARGIN`] times the
    /// last coordinate floor, once a fresh Hessian has given one.
    fn floor_stop(&self) -> Option<f64> {
        self.coordinate_floor.map(|floor| FLOOR_MARGIN * floor)
    }

    /// Whether `gradient_norm` is within [`FLOOR_MARGIN`] of the last coordinate floor.
    fn at_coordinate_floor(&self, gradient_norm: f64) -> bool {
        self.floor_stop().is_some_and(|stop| gradient_norm <= stop)
    }

    /// The ‖g‖ at which the run stops: the gradient tolerance `tolerance` (absolute), or
    /// the floor's stop where that is above it.
    fn stopping_gradient(&self, tolerance: f64) -> f64 {
        self.floor_stop()
            .map_or(tolerance, |stop| tolerance.max(stop))
    }

    /// A parenthesized remark for printed summaries: empty when converged.
    pub fn status_note(&self) -> &'static str {
        if self.converged {
            ""
        } else if self.cancelled {
            " (cancelled by the caller)"
        } else if self.stuck {
            " (stopped: steps no longer decrease F or ‖g‖; the surface may be nearly folded)"
        } else if self.stalled {
            " (stopped at the floor of f64 coordinates, above the tolerance)"
        } else {
            " (not converged)"
        }
    }
}

/// `positions` with the free vertices moved by `length` · `delta` (free index `free`).
pub(crate) fn moved(
    positions: &[[f64; 3]],
    free: &[u32],
    delta: &[f64],
    length: f64,
) -> Vec<[f64; 3]> {
    let mut out = positions.to_vec();
    for (p, &i) in out.iter_mut().zip(free) {
        if i != u32::MAX {
            for (a, x) in p.iter_mut().enumerate() {
                *x += length * delta[3 * i as usize + a];
            }
        }
    }
    out
}

/// How close to the coordinates' floor ‖g‖ must come for a run to stop there
/// ([`NewtonReport::stalled`]): the rounded positions' ‖g‖ is about the floor, give or take
/// the luck of a rounding; a Newton step from twice the floor gains less than one rounding.
pub const FLOOR_MARGIN: f64 = 2.0;

/// Whether `new` is an acceptable decrease from `old`: smaller, or equal to round-off.
pub(crate) fn decreases(new: f64, old: f64) -> bool {
    new.is_finite() && (new < old || (new - old).abs() <= ROUND_OFF * old.abs())
}

/// Coordinates above this make F (squares of second derivatives, areas) overflow or lose
/// all precision.
const LARGEST_SENSIBLE_COORDINATE: f64 = 1e75;

/// F's terms and gradient at the start of a run, refused when not finite, with the likelier
/// cause: coordinates so large that F overflows, or a degenerate surface.
pub(crate) fn finite_start(
    terms: Terms,
    g: Vec<f64>,
    positions: &[[f64; 3]],
) -> Result<(Terms, Vec<f64>)> {
    if !terms.f.is_finite() || !g.iter().all(|x| x.is_finite()) {
        let (vertex, largest) = positions
            .iter()
            .enumerate()
            .map(|(v, p)| (v, p.iter().fold(0.0f64, |m, x| m.max(x.abs()))))
            .fold((0, 0.0), |best, c| if c.1 > best.1 { c } else { best });
        let detail = if largest > LARGEST_SENSIBLE_COORDINATE {
            format!(
                "F overflows at the start: vertex {vertex} has a coordinate of magnitude \
                 {largest:e}; scale the mesh to sensible units"
            )
        } else {
            "F or its gradient is not finite at the start: the surface is degenerate \
             (vanishing tangents) somewhere"
                .into()
        };
        return Err(Error::Solver {
            failure: crate::error::SolverFailure::Singular,
            detail,
        });
    }
    Ok((terms, g))
}

/// Minimizes F̃ (eq. 6) over the free vertices of `positions`, in place.
///
/// # Errors
/// [`Error::Solver`] when F or its gradient is not finite at the start (a degenerate
/// surface). When no step decreases F the run stops with [`NewtonReport::stuck`] and the
/// positions reached so far in `positions`.
pub fn newton<R: Representation>(
    functional: &Functional<'_, R>,
    positions: &mut Vec<[f64; 3]>,
    options: &NewtonOptions,
) -> Result<NewtonReport> {
    newton_observed(functional, positions, options, &mut |_| {
        ControlFlow::Continue(())
    })
}

/// A point reached by a trial step.
struct Trial {
    terms: Terms,
    positions: Vec<[f64; 3]>,
}

/// What a Levenberg–Marquardt search ([`Stepper::lm_search`]) found.
struct LmFound {
    /// The ν of the best point along the trajectory, and that point.
    nu: f64,
    trial: Trial,
    /// Where the next search starts: the last ν that still [`gains`] (at or above `nu` when
    /// the search followed the trajectory towards longer steps, at or below it when towards
    /// shorter ones).
    next_start: f64,
}

/// A (possibly halved) Newton step: the point, its gradient and the kind of step.
type NewtonStep = (Trial, Vec<f64>, StepKind);

/// Where a run's Hessians come from: F's own functional, or the same F integrated with
/// fewer quadrature nodes (each Hessian costs (h / n)² as much, the minimum is F's), as
/// the author's program does (its Hessians at 6 × 6 nodes, F at 8 × 8).
pub struct HessianSources<'a, 'r, R: Representation> {
    /// For Newton's steps (after a Newton step).
    pub near: &'a Functional<'r, R>,
    /// Far from the minimum: at the start and after Levenberg–Marquardt steps, where most
    /// Hessians of a run from a raw mesh go and the damped steps gain nothing from a more
    /// accurate model. Not for Newton's last steps: with 2-node Hessians there, a 53-vertex
    /// junction's Catmull–Clark surface (F at 4 nodes) never had a Newton trial succeed
    /// ([`FAR_MODEL_DECREASE`]).
    pub far: &'a Functional<'r, R>,
}

impl<R: Representation> Clone for HessianSources<'_, '_, R> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<R: Representation> Copy for HessianSources<'_, '_, R> {}

impl<'a, 'r, R: Representation> HessianSources<'a, 'r, R> {
    /// F's own Hessians throughout.
    pub fn own(functional: &'a Functional<'r, R>) -> Self {
        HessianSources {
            near: functional,
            far: functional,
        }
    }
}

/// The evaluations one iteration may make, with their counters.
struct Stepper<'a, 'r, R: Representation, S: StepSolver> {
    functional: &'a Functional<'r, R>,
    /// Where the Hessians come from ([`HessianSources`]).
    sources: HessianSources<'a, 'r, R>,
    solver: S,
    report: NewtonReport,
    /// Hessian passes so far: the exact Hessian of pass k has key 2k, its Gauss–Newton
    /// part 2k + 1 ([`StepSolver::ready`]).
    passes: u64,
    /// The relative residual an inexact solver is asked for ([`forcing_term`]; after a step
    /// whose matrix is kept, [`kept_matrix_forcing`], which also serves the fresh step that
    /// follows if the kept matrix's trial fails).
    forcing: f64,
    search: LmSearch,
    /// [`NewtonOptions::geodesic_acceleration`] on a Gauss–Newton trajectory.
    accelerate: bool,
    /// [`NewtonOptions::coarse_correction`] applies to this problem.
    correct: bool,
}

impl<'a, 'r, R: Representation, S: StepSolver> Stepper<'a, 'r, R, S> {
    fn factor(&mut self, h: &BlockHessian, key: u64, nu: f64) -> Option<S::Ready> {
        let clock = Instant::now();
        let factored = self.solver.ready(h, key, nu);
        self.report.factorizations += 1;
        self.report.factorization_seconds += clock.elapsed().as_secs_f64();
        factored
    }

    /// [`Self::newton_trial`] with `factor`, and the factor itself if its step was
    /// effective (cut ‖g‖ by `reuse_factor`, §5) and may serve the next iteration; else
    /// its storage goes back to the factorizer.
    fn newton_kept(
        &mut self,
        factor: S::Ready,
        g: &[f64],
        positions: &[[f64; 3]],
        f: f64,
        options: &NewtonOptions,
    ) -> (Option<NewtonStep>, Option<S::Ready>) {
        let trial = self.newton_trial(&factor, g, positions, f, options.newton_halvings);
        let effective =
            matches!(&trial, Some((_, gt, _)) if norm(gt) * options.reuse_factor <= norm(g));
        if effective {
            return (trial, Some(factor));
        }
        self.solver.recycle(factor);
        (trial, None)
    }

    /// The source of the Hessians far from the minimum or near it ([`HessianSources`]).
    fn source(&self, far: bool) -> &'a Functional<'r, R> {
        if far {
            self.sources.far
        } else {
            self.sources.near
        }
    }

    /// The Hessians of `kind` at `positions` from [`Self::source`].
    fn hessians(&mut self, positions: &[[f64; 3]], kind: HessianKind, far: bool) -> Hessians {
        let clock = Instant::now();
        let out = self.source(far).hessians(positions, kind);
        self.passes += 1;
        if out.exact.is_some() {
            self.report.hessian_evaluations += 1;
        }
        if out.gauss_newton.is_some() {
            self.report.gauss_newton_evaluations += 1;
            if out.exact.is_none() {
                self.report.gauss_newton_only_evaluations += 1;
            }
        }
        self.report.hessian_seconds += clock.elapsed().as_secs_f64();
        out
    }

    /// The Newton step of `factor` (eq. 7) with its new gradient, if it decreases F; else
    /// the first of its `halvings` halves, quarters, … that does
    /// ([`NewtonOptions::newton_halvings`]).
    fn newton_trial(
        &mut self,
        factor: &S::Ready,
        g: &[f64],
        positions: &[[f64; 3]],
        f: f64,
        halvings: usize,
    ) -> Option<NewtonStep> {
        let delta = self.solver.solve(factor, g, self.forcing)?;
        let below = |t: f64| t.partial_cmp(&f) == Some(std::cmp::Ordering::Less);
        (0..=halvings).find_map(|k| {
            let length = 0.5f64.powi(k as i32);
            let trial = moved(positions, self.functional.free_index(), &delta, length);
            // Halved steps are tried by value first: most are refused.
            if k > 0 && !below(self.functional.value(&trial).f) {
                return None;
            }
            let (t, gt) = self.functional.gradient(&trial);
            // The full step may leave F equal to round-off (the stall test needs it).
            let accepted = if k == 0 {
                decreases(t.f, f)
            } else {
                below(t.f)
            };
            (accepted && norm(&gt).is_finite()).then(|| {
                let kind = if k == 0 {
                    StepKind::Newton
                } else {
                    StepKind::DampedNewton
                };
                let trial = Trial {
                    terms: t,
                    positions: trial,
                };
                (trial, gt, kind)
            })
        })
    }

    /// F̃(x + δ_ν) with (H + ν I) δ_ν = −g (eq. 8–9), if it is below `f`, with the ratio
    /// of the decrease to the one the quadratic model of F predicts.
    fn lm_trial(
        &mut self,
        (h, key): (&BlockHessian, u64),
        nu: f64,
        g: &[f64],
        positions: &[[f64; 3]],
        f: f64,
    ) -> Option<(Trial, f64)> {
        let factor = self.factor(h, key, nu)?;
        let step = self.solver.solve(&factor, g, self.forcing).map(|v| {
            if self.accelerate {
                self.accelerated(&factor, v, positions)
            } else {
                v
            }
        });
        self.solver.recycle(factor);
        let step = step?;
        let trial = moved(positions, self.functional.free_index(), &step, 1.0);
        let t = self.functional.value(&trial);
        if !(t.f.is_finite() && t.f < f) {
            return None;
        }
        // −(gᵀδ + ½δᵀHδ), with δᵀHδ = −gᵀδ − ν‖δ‖² from (H + νI)δ = −g: no product
        // with H needed.
        let predicted = 0.5 * (nu * dot(&step, &step) - dot(g, &step));
        let ratio = if predicted > 0.0 {
            (f - t.f) / predicted
        } else {
            f64::INFINITY
        };
        Some((
            Trial {
                terms: t,
                positions: trial,
            },
            ratio,
        ))
    }

    /// The step `v` of `factor` bent by its geodesic acceleration a
    /// ([`NewtonOptions::geodesic_acceleration`]): v + a/2 where 2‖a‖ ≤
    /// [`ACCELERATION_LIMIT`] ‖v‖, else `v`.
    fn accelerated(&mut self, factor: &S::Ready, v: Vec<f64>, positions: &[[f64; 3]]) -> Vec<f64> {
        let clock = Instant::now();
        // A correction to the step: the far Hessians' quadrature serves (fewer nodes).
        let a = self
            .sources
            .far
            .residual_curvature(positions, &v)
            .and_then(|curvature| {
                let forcing = self.forcing.max(ACCELERATION_FORCING);
                let (before, _) = self.solver.krylov_work();
                let a = self.solver.solve(factor, &curvature, forcing);
                self.report.acceleration_cg_iterations += self.solver.krylov_work().0 - before;
                a
            });
        self.report.acceleration_seconds += clock.elapsed().as_secs_f64();
        let Some(a) = a.filter(|a| 2.0 * norm(a) <= ACCELERATION_LIMIT * norm(&v)) else {
            return v;
        };
        self.report.accelerated_trials += 1;
        v.iter().zip(&a).map(|(v, a)| v + 0.5 * a).collect()
    }

    /// Searches for the ν minimizing f(ν) = F̃(x + δ_ν) (eq. 8–9) on a geometric grid
    /// (factors of 4): from `start`, grow ν until F decreases (by 16 at a time with
    /// [`LmSearch::Frugal`]); then follow the trajectory while F keeps decreasing by more
    /// than [`TRAJECTORY_IMPROVEMENT`] of the decrease found (with [`LmSearch::Frugal`],
    /// while each trial [`gains`]), in the direction the quadratic model points to:
    /// towards longer steps (smaller ν) when the decrease matched the model's prediction
    /// (ratio ≥ 3/4) and no smaller ν has failed already, towards shorter ones when it
    /// fell far short (ratio < 1/4), nowhere in between. (Trying both directions every
    /// time cost 124 factorizations at 14399 vertices instead of 100, with the same 29
    /// Hessians, on the exact trajectory; an earlier session's measurement.)
    /// Traced on the 94k five-tube Catmull–Clark junction (fifteenth session), two walks
    /// went on for 15 and 12 trials, the last 8 and 6 of them lowering F by less than 10⁻³
    /// of the decrease already found, and climbs took 2 to 5 failed trials of factor 4.
    ///
    /// Returns the best ν and its point, and where the next search should start
    /// ([`LmFound::next_start`]): the last ν of this one that [`gains`] on the one before.
    /// Below it the step no longer changes with ν (F equal to 7 digits down to ν = 10⁻⁹),
    /// and a search starting there had to climb back one factorization at a time: on the
    /// 94 077-vertex Catmull–Clark junction, 2026-11-27, two searches spent 14 and 12 failed
    /// trials (37 s and 67 s) climbing from ν ≈ 10⁻⁸, most of them below where this start
    /// begins. A search that climbs takes the step it took before; one that succeeds at this
    /// start, above the last best ν, may take a shorter one (the 223 487-vertex junction's
    /// run parted there after 28 steps). `None` when no ν decreases F.
    fn lm_search(
        &mut self,
        h: (&BlockHessian, u64),
        g: &[f64],
        positions: &[[f64; 3]],
        f: f64,
        start: f64,
    ) -> Option<LmFound> {
        let (climb, stop_without_gain) = match self.search {
            LmSearch::Exhaustive => (4.0, false),
            LmSearch::Frugal => (CLIMB, true),
        };
        let mut nu = start;
        let mut best = None;
        // Up to ν = 2¹²⁰ · start either way.
        for _ in 0..(120.0 / climb.log2()) as usize {
            if let Some(found) = self.lm_trial(h, nu, g, positions, f) {
                best = Some((nu, found));
                break;
            }
            nu *= climb;
        }
        let (mut best_nu, (mut best_trial, ratio)) = best?;
        // The largest ν known to fail (the search climbed past it): the walk towards
        // longer steps stays above it.
        let failed = (best_nu > start).then_some(best_nu / climb);
        let direction = if ratio >= 0.75 {
            Some(0.25)
        } else if ratio < 0.25 {
            Some(4.0)
        } else {
            None
        };
        let mut next_start = best_nu;
        if let Some(factor) = direction {
            for _ in 0..30 {
                if failed.is_some_and(|x| best_nu * factor <= x) {
                    break;
                }
                match self.lm_trial(h, best_nu * factor, g, positions, f) {
                    Some((t, _)) if t.terms.f < best_trial.terms.f => {
                        let gained = gains(t.terms.f, best_trial.terms.f, f);
                        let settled =
                            !improves_by(TRAJECTORY_IMPROVEMENT, t.terms.f, best_trial.terms.f, f);
                        best_nu *= factor;
                        best_trial = t;
                        if gained {
                            next_start = best_nu;
                        } else if stop_without_gain || settled {
                            break;
                        }
                    }
                    _ => break,
                }
            }
        }
        Some(LmFound {
            nu: best_nu,
            trial: best_trial,
            next_start,
        })
    }

    /// The point `lm` of a Levenberg–Marquardt step with ν `nu` of the matrix `h`, moved by
    /// that matrix's step in the first coarse level's subspace where that lowers F
    /// ([`crate::fair::solvers::coarse_correction`]), with its gradient (which the next
    /// iteration needs either way).
    fn coarse_correction(
        &mut self,
        (h, key): (&BlockHessian, u64),
        lm: Trial,
        nu: f64,
    ) -> (Trial, Vec<f64>) {
        let clock = Instant::now();
        let (terms, g) = self.functional.gradient(&lm.positions);
        let start = Trial {
            terms,
            positions: lm.positions,
        };
        let step = self
            .factor(h, key, nu * COARSE_SHIFT_FRACTION)
            .and_then(|ready| {
                let step = self.solver.coarse_step(&ready, &g, COARSE_FORCING);
                self.solver.recycle(ready);
                step
            });
        let free = self.functional.free_index();
        let corrected = step.and_then(|d| {
            let points: Vec<_> = COARSE_STEP_LENGTHS
                .iter()
                .map(|&t| moved(&start.positions, free, &d, t))
                .collect();
            let values: Vec<f64> = points.iter().map(|x| self.functional.value(x).f).collect();
            let best = lowest_below(&values, start.terms.f)?;
            let positions = points.into_iter().nth(best).expect("an index of values");
            let (terms, g) = self.functional.gradient(&positions);
            // The value may pass and the gradient not be finite (a nearly folded surface).
            norm(&g)
                .is_finite()
                .then_some((Trial { terms, positions }, g))
        });
        self.report.coarse_correction_seconds += clock.elapsed().as_secs_f64();
        match corrected {
            Some(found) => {
                self.report.coarse_corrections += 1;
                found
            }
            None => (start, g),
        }
    }

    /// At the coordinates' floor: a Newton step solved to `forcing`, then its rounding
    /// chosen by [`lattice_rounding`] until its model predicts `target`; of the two points
    /// the one of lower ‖g‖, with its gradient, if that is below ‖`g`‖ and F is no higher
    /// than `f` beyond round-off. The step's matrix is the last Newton step's (`last_exact`,
    /// and its readied form `kept` if the run kept it), else a fresh exact Hessian's, which
    /// updates the floor's estimate.
    fn lattice_step(
        &mut self,
        last_exact: Option<(BlockHessian, u64)>,
        kept: Option<S::Ready>,
        (g, positions, f): (&[f64], &[[f64; 3]], f64),
        (forcing, target): (f64, f64),
    ) -> Option<NewtonStep> {
        let free = self.functional.free_index();
        let (h, kept) = match last_exact {
            Some((h, key)) => {
                let ready = match kept {
                    Some(ready) => Some(ready),
                    None => self.factor(&h, key, 0.0),
                };
                (h, ready)
            }
            None => {
                if let Some(old) = kept {
                    self.solver.recycle(old);
                }
                let h = self.hessians(positions, HessianKind::Exact, false).exact?;
                self.report.coordinate_floor = Some(coordinate_floor(&h, positions, free));
                let ready = self.factor(&h, 2 * self.passes, 0.0);
                (h, ready)
            }
        };
        let ready = kept?;
        let delta = self.solver.solve(&ready, g, forcing);
        self.solver.recycle(ready);
        let stepped = moved(positions, free, &delta?, 1.0);
        let (stepped_terms, stepped_gradient) = self.functional.gradient(&stepped);
        let rounded = lattice_rounding(&h, &stepped_gradient, &stepped, free, target);
        self.report.lattice_sweeps += rounded.sweeps;
        let mut candidates = vec![(stepped, stepped_terms, stepped_gradient)];
        // A rounding its model says gains nothing is not evaluated.
        if rounded.predicted < norm(&candidates[0].2) {
            let (terms, gradient) = self.functional.gradient(&rounded.positions);
            candidates.push((rounded.positions, terms, gradient));
        }
        candidates
            .into_iter()
            .filter(|(_, t, gt)| decreases(t.f, f) && norm(gt) < norm(g))
            .min_by(|a, b| norm(&a.2).total_cmp(&norm(&b.2)))
            .map(|(positions, terms, gradient)| {
                (
                    Trial { terms, positions },
                    gradient,
                    StepKind::LatticeRounding,
                )
            })
    }

    /// Backtracking along −g (a safeguard, not in the paper) for when no H + νI gave a
    /// decrease: a non-finite Hessian entry at a nearly degenerate point, say.
    fn steepest_descent(
        &self,
        g: &[f64],
        positions: &[[f64; 3]],
        f: f64,
        scale: f64,
    ) -> Option<Trial> {
        let mut alpha = 1.0 / scale;
        for _ in 0..60 {
            let trial = moved(positions, self.functional.free_index(), g, -alpha);
            let t = self.functional.value(&trial);
            if t.f.is_finite() && t.f < f {
                return Some(Trial {
                    terms: t,
                    positions: trial,
                });
            }
            alpha *= 0.25;
        }
        None
    }
}

/// The least relative residual of a [`StepKind::LatticeRounding`] step's solve, which is
/// otherwise solved to the tolerance: the rounding's coordinate descent then takes the
/// step's leftover below it along with the rounding noise (the 223 487-vertex Catmull–Clark
/// junction, 2026-12-07: ‖g‖ 9.19·10⁻³ against 9.24·10⁻³ with the solve to half the
/// tolerance, the tolerance 3.75·10⁻², 22 fewer CG iterations, the step 20.7 s against 30.4 s).
const LATTICE_FORCING: f64 = 1e-2;

/// The gradient a [`StepKind::LatticeRounding`] step's rounding aims at, as a fraction of
/// the tolerance: below it with room for the linear model's error (the evaluated gradient
/// came within 3 to 10 % of the prediction on the 14k and 94k junctions, 2026-11-30), and
/// no further, since every sweep after the first gains less and costs as much.
const LATTICE_TARGET: f64 = 0.25;

/// [`StepKind::LatticeRounding`] steps a run takes at most: on the 14 399-vertex junction
/// (2026-11-30) a second one from the first's point gained nothing.
const LATTICE_STEPS: usize = 2;

/// The factor by which a Levenberg–Marquardt search raises ν after a trial that did not
/// lower F. Climbs from a start far below the ν that works took 2 to 5 failed trials of
/// factor 4 on the 94k and 223k Catmull–Clark junctions (traced, fifteenth session); a
/// search that climbed by 16 and whose step matched the model (ratio ≥ 3/4) tries the ν a
/// quarter of its own, above the one that failed.
const CLIMB: f64 = 16.0;

/// The largest 2‖a‖/‖v‖ of a geodesic acceleration a that bends the step v (Transtrum and
/// Sethna's α, their recommended 0.75): beyond it the second-order path is not trusted.
pub const ACCELERATION_LIMIT: f64 = 0.75;

/// The relative residual a geodesic acceleration is solved to, at least: a/2 is a
/// correction of at most 3/8 of the step ([`ACCELERATION_LIMIT`]), not worth the
/// accuracy of the step itself. Solved to the step's own forcing term instead (and with
/// forward-mode Jᵀ r_vv), the 223 487-vertex Catmull–Clark junction took 2083 CG
/// iterations and 1386.6 s, 291.7 s of them in the accelerations, against 1069, 962.8 s
/// and 81.5 s (2026-11-28).
const ACCELERATION_FORCING: f64 = 0.3;

/// The least improvement along the Levenberg–Marquardt trajectory, as a fraction of the
/// decrease already found, that is worth another trial ν.
const TRAJECTORY_GAIN: f64 = 0.01;

/// Whether a trial reaching `trial` improves on the best point `best` of a search from
/// `f` by more than [`TRAJECTORY_GAIN`] of the decrease `f − best`.
fn gains(trial: f64, best: f64, f: f64) -> bool {
    improves_by(TRAJECTORY_GAIN, trial, best, f)
}

/// Whether a trial reaching `trial` improves on the best point `best` of a search from
/// `f` by more than `fraction` of the decrease `f − best`.
fn improves_by(fraction: f64, trial: f64, best: f64, f: f64) -> bool {
    best - trial > fraction * (f - best)
}

/// The least improvement along the Levenberg–Marquardt trajectory, as a fraction of the
/// decrease already found, for which the walk goes on at all, either way. As ν → 0 (where
/// the long walks are) the steps settle on the Gauss–Newton step and F's improvements
/// shrink with ν, 4 times per trial: traced on the 14 399-vertex junction (2026-11-29), a
/// walk took 14 trials from ν = 7·10⁻⁴ to 10⁻¹¹, improving by 9.6·10⁻⁴, 2.2·10⁻⁴,
/// 5.3·10⁻⁵, … 5·10⁻¹¹ of the decrease; each trial is a matrix set-up and a solve. Past this
/// fraction the rest of such a walk would gain about a third of it.
const TRAJECTORY_IMPROVEMENT: f64 = 1e-4;

/// A Levenberg–Marquardt step that lowered F by less than this fraction of it ends the far
/// nodes' Hessians ([`crate::fair::FairOptions::far_hessian_nodes`]) until the next step
/// that gains more: near a minimum the Newton trials need the near model. With 2 × 2 far
/// nodes and no such rule, the 53-vertex Catmull–Clark junction's Newton trials never
/// succeeded and it crawled along the trajectory (relative decreases 10⁻⁵ to 10⁻⁹ a step)
/// to the iteration limit. On the three-tube Catmull–Clark junctions of 14k and 223k
/// vertices no damped step lowered F by less than 2·10⁻³ (2026-11-29), so there the rule
/// changes nothing; on the 14k G² one a step of 8·10⁻⁴ and on the 94k five-tube
/// Catmull–Clark one four of 3·10⁻⁴ to 7·10⁻⁶ hand the next pass the near nodes.
pub const FAR_MODEL_DECREASE: f64 = 1e-3;

/// Full Newton steps from fresh near Hessians at fewer nodes than F's, one right after the
/// other, that each left ‖g‖ above [`SLOW_NEAR_RATE`] of its value, after which the near
/// Hessians take F's own nodes for the rest of the run (any other step starts the count
/// again). Such a rate is the model's quadrature error, not the
/// nonlinearity: with 3 × 3-node Hessians the 53-vertex Catmull–Clark junction (F at
/// 4 × 4) went on at 0.7 a step for 30 iterations, where its Newton steps at 4 × 4 cut ‖g‖
/// by 10 or more; on the three-tube junctions of 14k and 223k vertices and on the author's
/// meshes no two fresh Newton steps in a row were that slow (2026-12-07). A false alarm
/// costs only the fewer nodes' saving.
pub const SLOW_NEAR_STEPS: usize = 2;

/// See [`SLOW_NEAR_STEPS`].
pub const SLOW_NEAR_RATE: f64 = 0.5;

/// Mean absolute diagonal entry of `h` (at least the smallest positive number): the scale
/// of ν.
pub(crate) fn diagonal_scale(h: &BlockHessian) -> f64 {
    let (sum, count) = h
        .blocks
        .iter()
        .zip(&h.values)
        .filter(|(b, _)| b.0 == b.1)
        .fold((0.0, 0usize), |(s, c), (_, v)| {
            (s + v[0][0].abs() + v[1][1].abs() + v[2][2].abs(), c + 3)
        });
    (sum / count.max(1) as f64).max(f64::MIN_POSITIVE)
}

/// [`newton`], calling `observe` after each iteration (for progress display); when it
/// returns `ControlFlow::Break`, the run stops there with [`NewtonReport::cancelled`].
///
/// # Errors
/// As [`newton`].
pub fn newton_observed<R: Representation>(
    functional: &Functional<'_, R>,
    positions: &mut Vec<[f64; 3]>,
    options: &NewtonOptions,
    observe: &mut dyn FnMut(&Iteration) -> ControlFlow<()>,
) -> Result<NewtonReport> {
    newton_observed_with_hessians(
        functional,
        HessianSources::own(functional),
        positions,
        options,
        observe,
    )
}

/// [`newton_observed`] with the Hessians of `sources` ([`HessianSources`]) and F and its
/// gradient of `functional`: the minimum is `functional`'s.
///
/// # Errors
/// As [`newton`]; [`Error::InvalidInput`] if the sources do not have F's unknowns.
pub fn newton_observed_with_hessians<'a, 'r, R: Representation>(
    functional: &'a Functional<'r, R>,
    sources: HessianSources<'a, 'r, R>,
    positions: &mut Vec<[f64; 3]>,
    options: &NewtonOptions,
    observe: &mut dyn FnMut(&Iteration) -> ControlFlow<()>,
) -> Result<NewtonReport> {
    newton_with_solver(
        functional,
        sources,
        positions,
        options,
        CholeskySolver(Factorizer::new(functional.free_count())),
        observe,
    )
}

/// The relative residual asked of an inexact solve after ‖g‖ went from `previous` to
/// `current` (Eisenstat and Walker's choice 2, γ = 0.9, α = 2, with their safeguard
/// against a sudden drop), at most ½, and no smaller than the ‖g‖ `target` at which the
/// run stops needs (no over-solving of the last step): relative_gradient · ‖g₀‖, or twice
/// the coordinates' floor where the tolerance is below it
/// ([`NewtonReport::stopping_gradient`]). With the tolerance alone, the 223 487-vertex
/// Catmull–Clark junction's last fresh step was solved to 2.5 · 10⁻³ in 199 CG iterations
/// from ‖g‖ = 7.55, where the floor 0.145 asks for 1.9 · 10⁻² (traced, 2026-11-28).
pub(crate) fn forcing_term(last: f64, previous: f64, current: f64, target: f64) -> f64 {
    let mut eta = 0.9 * (current / previous).powi(2);
    let safeguard = 0.9 * last * last;
    if safeguard > 0.1 {
        eta = eta.max(safeguard);
    }
    eta.max(0.5 * target / current).min(0.5)
}

/// The forcing term of a step on a kept matrix ([`Stepper::newton_kept`]), from `eta`
/// ([`forcing_term`]) after ‖g‖ went from `previous` to `current`: no tighter than that
/// contraction. A kept matrix is the Hessian of an earlier point, so its steps converge
/// linearly, at about the last step's rate, and Eisenstat and Walker's choice 2, which
/// squares that rate for a quadratic model, over-solves them: on the 223 487-vertex
/// Catmull–Clark junction the first two steps on the kept matrix were asked for 3.3·10⁻³
/// and 2.8·10⁻³ after contractions of 1/16.5 and 1/17.8 (56 and 41 CG iterations).
/// Applied from [`KEPT_MATRIX_FLOOR_FREE_VERTICES`], whose docs give the measurements.
pub(crate) fn kept_matrix_forcing(eta: f64, previous: f64, current: f64) -> f64 {
    eta.max(current / previous).min(0.5)
}

/// The free vertices from which steps on a kept matrix take [`kept_matrix_forcing`]. The
/// over-solving costs more CG iterations as the problem grows (at the optima the V-cycle
/// contracts by about 0.54, 0.76 and 0.82 an iteration at 14k, 56k and 223k, earlier
/// sessions' measurements, README), while a looser step that falls short of the kept
/// matrix's reuse test costs a fresh Hessian at any size.
/// Measured 2026-12-08 (single runs, both surfaces, the same minima): slower at 5 277 free
/// vertices (one more exact Hessian or kept step: 8.51 and 8.41 s against 8.07 and 7.82 s
/// on the Catmull–Clark surface, 8.64 and 8.46 s against 8.08 and 8.11 s on G²), level at
/// 13 247, level or faster at 54 143 (57.67 s against 59.29 s) and faster at 218 879
/// (Catmull–Clark 422.8 s against 437.7 s, G² 382.7 s against 408.3 s).
pub const KEPT_MATRIX_FLOOR_FREE_VERTICES: usize = 50_000;

/// [`newton_observed_with_hessians`] with the steps solved by `solver`.
///
/// # Errors
/// As [`newton_observed_with_hessians`].
pub(crate) fn newton_with_solver<'a, 'r, R: Representation, S: StepSolver>(
    functional: &'a Functional<'r, R>,
    sources: HessianSources<'a, 'r, R>,
    positions: &mut Vec<[f64; 3]>,
    options: &NewtonOptions,
    solver: S,
    observe: &mut dyn FnMut(&Iteration) -> ControlFlow<()>,
) -> Result<NewtonReport> {
    if ![sources.near, sources.far]
        .iter()
        .all(|s| functional.same_unknowns(s))
    {
        return Err(Error::InvalidInput(
            "Newton: the Hessians' functional has other unknowns than F's".into(),
        ));
    }
    let (mut terms, mut g) = {
        let (terms, g) = functional.gradient(positions);
        finite_start(terms, g, positions)?
    };
    let g0 = norm(&g);
    let correct =
        options.coarse_correction.applies(functional.free_count()) && solver.has_coarse_level();
    let loosen_kept = functional.free_count() >= KEPT_MATRIX_FLOOR_FREE_VERTICES;
    let mut run = Stepper {
        functional,
        sources,
        solver,
        report: NewtonReport::new(terms, g0),
        passes: 0,
        forcing: 0.5,
        search: options.lm_search,
        accelerate: options.geodesic_acceleration && options.lm_matrix == LmMatrix::GaussNewton,
        correct,
    };
    run.report.geodesic_acceleration = run.accelerate;
    run.report.coarse_correction = run.correct;
    if functional.free_count() == 0 || g0 == 0.0 {
        run.report.converged = true;
        return Ok(run.report);
    }
    // The factor of the last effective Newton step (§5).
    let mut reusable: Option<S::Ready> = None;
    // Consecutive fresh Newton steps that changed neither F nor ‖g‖ (see `stall_steps`).
    let mut stalled_steps = 0;
    // Where the next Levenberg–Marquardt search starts (`Stepper::lm_search`).
    let mut next_nu: Option<f64> = None;
    // The fraction of F the last step lowered it by, if it was a Levenberg–Marquardt step.
    let mut last_lm_decrease: Option<f64> = None;
    // Passes left without a Newton trial, and the next such count after a failed trial
    // (`NewtonOptions::newton_backoff`).
    let mut trials_skipped = 0usize;
    let mut next_skip = 1usize;
    let mut lattice_steps_left = LATTICE_STEPS;
    // Slow fresh Newton steps from the near Hessians in a row (`SLOW_NEAR_STEPS`).
    let mut slow_near_steps = 0usize;
    // The exact Hessian of the last Newton step from a fresh pass, with its key: the model
    // of a lattice step (its moves are ulps: a Hessian one step old predicts them).
    let mut last_exact: Option<(BlockHessian, u64)> = None;
    while run.report.iterations.len() < options.max_iterations {
        let gnorm = norm(&g);
        if gnorm <= options.relative_gradient * g0 {
            run.report.converged = true;
            break;
        }
        let mut step = None;
        // Whether `step` is a full Newton step from a fresh pass of the near Hessians at
        // fewer nodes than F's (`SLOW_NEAR_STEPS`).
        let mut near_newton = false;
        // 0. At the coordinates' floor, above the tolerance: the rounding chosen.
        if run.report.at_coordinate_floor(gnorm) {
            if lattice_steps_left > 0 {
                lattice_steps_left -= 1;
                // The step solved to the tolerance itself: its rounding takes the rest.
                let forcing = (options.relative_gradient * g0 / gnorm).clamp(LATTICE_FORCING, 0.5);
                let clock = Instant::now();
                step = run
                    .lattice_step(
                        last_exact.take(),
                        reusable.take(),
                        (&g, positions, terms.f),
                        (forcing, LATTICE_TARGET * options.relative_gradient * g0),
                    )
                    .map(|(trial, gt, kind)| (trial, Some(gt), kind, None));
                run.report.lattice_seconds += clock.elapsed().as_secs_f64();
            }
            if step.is_none() {
                run.report.stalled = true;
                break;
            }
        }
        // 1. Newton with the kept factor.
        // (A lattice step took the kept factor: `reusable` is `None` whenever `step` is set.)
        if let Some(factor) = reusable.take() {
            let trial;
            (trial, reusable) = run.newton_kept(factor, &g, positions, terms.f, options);
            if let Some((trial, gt, kind)) = trial {
                let kind = match kind {
                    StepKind::Newton => StepKind::ReusedNewton,
                    _ => kind,
                };
                step = Some((trial, Some(gt), kind, None));
            }
        }
        // 2. Fresh Hessian: Newton if positive definite and decreasing, else the
        // Levenberg–Marquardt trajectory.
        if step.is_none() {
            // After a Levenberg–Marquardt step the next one is likely too, and so is the
            // first step from a raw mesh: the Hessian's Gauss–Newton part comes from the
            // same pass (about 1.2× the exact Hessian alone, see `HessianKind::Both`).
            let far = matches!(
                run.report.iterations.last().map(|it| it.step),
                None | Some(StepKind::LevenbergMarquardt)
            );
            // The far nodes' model while the damped steps still gain
            // ([`FAR_MODEL_DECREASE`]).
            let far_model = far && last_lm_decrease.is_none_or(|d| d > FAR_MODEL_DECREASE);
            // After a Levenberg–Marquardt step that still lowered F by much, or while
            // backing off after a failed Newton trial, the trajectory alone: no exact
            // Hessian, no Newton trial (`NewtonOptions::newton_after_decrease`,
            // `NewtonOptions::newton_backoff`).
            let backing_off = trials_skipped > 0 && last_lm_decrease.is_some();
            if backing_off {
                trials_skipped -= 1;
            }
            let trajectory_only = options.lm_matrix == LmMatrix::GaussNewton
                && (backing_off
                    || last_lm_decrease.is_some_and(|d| d > options.newton_after_decrease));
            let kind = if trajectory_only {
                HessianKind::GaussNewton
            } else if options.lm_matrix == LmMatrix::GaussNewton && far {
                HessianKind::Both
            } else {
                HessianKind::Exact
            };
            last_exact = None;
            let hessians = run.hessians(positions, kind, far_model);
            // F and g at `positions` are known; the Hessians' pass has them again, from
            // the same quadrature unless the Hessians come from fewer nodes.
            if std::ptr::eq(run.source(far_model), functional) {
                terms = hessians.terms;
                g = hessians.gradient;
            }
            let exact_key = 2 * run.passes;
            let gauss_newton = hessians.gauss_newton;
            let exact = hessians.exact;
            if let Some(h) = &exact {
                run.report.coordinate_floor =
                    Some(coordinate_floor(h, positions, functional.free_index()));
                if let Some(factor) = run.factor(h, exact_key, 0.0) {
                    let trial;
                    (trial, reusable) = run.newton_kept(factor, &g, positions, terms.f, options);
                    if let Some((trial, gt, kind)) = trial {
                        near_newton = kind == StepKind::Newton
                            && !far_model
                            && !std::ptr::eq(run.sources.near, functional);
                        step = Some((trial, Some(gt), kind, None));
                    }
                }
                if step.is_some() {
                    next_skip = 1;
                } else if options.newton_backoff {
                    trials_skipped = next_skip;
                    next_skip = next_skip.saturating_mul(2);
                }
            }
            if step.is_some() {
                last_exact = exact.map(|h| (h, exact_key));
            } else {
                let (h, key) = match (options.lm_matrix, gauss_newton, exact) {
                    (LmMatrix::Exact, _, Some(h)) => (h, exact_key),
                    (LmMatrix::GaussNewton, Some(gn), _) => (gn, exact_key + 1),
                    // A pass of the exact Hessian alone (near the minimum); the paper's
                    // trajectory always has its exact Hessian.
                    _ => {
                        let gn = run
                            .hessians(positions, HessianKind::GaussNewton, far_model)
                            .gauss_newton
                            .expect("asked for");
                        (gn, 2 * run.passes + 1)
                    }
                };
                let scale = diagonal_scale(&h);
                // The best ν changes slowly from one iteration to the next: the search
                // starts about where the last one found it, `lm_search`'s next start (at
                // 14399 vertices, exact trajectory, an earlier session: 124 factorizations
                // instead of 154 from a fixed 10⁻³ of the diagonal scale, same Hessians),
                // the first at a small ν, so that it finds the longest decreasing step.
                let start = next_nu.unwrap_or(scale * 1e-3);
                if let Some(found) = run.lm_search((&h, key), &g, positions, terms.f, start) {
                    next_nu = Some(found.next_start);
                    let (trial, gradient) = if run.correct {
                        let (trial, gt) = run.coarse_correction((&h, key), found.trial, found.nu);
                        (trial, Some(gt))
                    } else {
                        (found.trial, None)
                    };
                    step = Some((
                        trial,
                        gradient,
                        StepKind::LevenbergMarquardt,
                        Some(found.nu),
                    ));
                } else if let Some(trial) = run.steepest_descent(&g, positions, terms.f, scale) {
                    step = Some((trial, None, StepKind::SteepestDescent, None));
                }
            }
        }
        let Some((trial, gradient, kind, nu)) = step else {
            run.report.stuck = true;
            break;
        };
        let (f_before, g_before) = (terms.f, norm(&g));
        *positions = trial.positions;
        (terms, g) = match gradient {
            Some(gt) => (trial.terms, gt),
            None => functional.gradient(positions),
        };
        last_lm_decrease = (kind == StepKind::LevenbergMarquardt)
            .then(|| (f_before - terms.f) / f_before.abs().max(f64::MIN_POSITIVE));
        let flat =
            (terms.f - f_before).abs() <= ROUND_OFF * f_before.abs() && 2.0 * norm(&g) > g_before;
        stalled_steps = if kind == StepKind::Newton && flat {
            stalled_steps + 1
        } else {
            0
        };
        slow_near_steps = if near_newton && norm(&g) > SLOW_NEAR_RATE * g_before {
            slow_near_steps + 1
        } else {
            0
        };
        if slow_near_steps >= SLOW_NEAR_STEPS {
            run.sources.near = functional;
            run.report.near_hessians_raised = true;
        }
        run.forcing = forcing_term(
            run.forcing,
            g_before,
            norm(&g),
            run.report.stopping_gradient(options.relative_gradient * g0),
        );
        if loosen_kept && reusable.is_some() {
            run.forcing = kept_matrix_forcing(run.forcing, g_before, norm(&g));
        }
        run.report.iterations.push(Iteration {
            terms,
            gradient_norm: norm(&g),
            step: kind,
            nu,
        });
        if observe(run.report.iterations.last().expect("just pushed")).is_break() {
            run.report.cancelled = true;
            break;
        }
        if options.stall_steps > 0 && stalled_steps >= options.stall_steps {
            let gnorm = norm(&g);
            if gnorm > options.relative_gradient * g0 {
                let floor = run.report.at_coordinate_floor(gnorm);
                if floor && lattice_steps_left > 0 {
                    // The next iteration chooses the rounding.
                    stalled_steps = 0;
                    continue;
                }
                run.report.stalled = floor;
                run.report.stuck = !floor;
            }
            break;
        }
    }
    let mut report = run.report;
    (report.cg_iterations, report.cg_seconds) = run.solver.krylov_work();
    (
        report.fine_factorizations,
        report.fine_factorization_seconds,
    ) = run.solver.fine_factorizations();
    if !report.converged {
        report.converged = norm(&g) <= options.relative_gradient * g0;
    }
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::forcing_term;

    #[test]
    fn a_trial_gains_when_it_improves_on_the_best_by_a_percent_of_the_decrease() {
        // From F = 219 to a best of 184: 35 gained; 0.36 more is 1 %.
        assert!(super::gains(183.6, 184.0, 219.0));
        assert!(!super::gains(183.7, 184.0, 219.0));
        assert!(!super::gains(184.1, 184.0, 219.0));
    }

    #[test]
    fn a_walk_goes_on_while_a_trial_improves_by_a_ten_thousandth_of_the_decrease() {
        // From F = 24.35 to a best of 17.12 (the 14k junction's walk): 7.23 gained.
        let improves =
            |trial, best, f| super::improves_by(super::TRAJECTORY_IMPROVEMENT, trial, best, f);
        assert!(improves(17.1190, 17.1200, 24.35));
        assert!(!improves(17.1199, 17.1200, 24.35));
        assert!(!improves(17.1201, 17.1200, 24.35));
        // The traced walk's improvements (fractions of the decrease): it stops at the third
        // trial, 5.3·10⁻⁵, instead of going on for eleven more.
        let traced = [9.6e-4, 2.2e-4, 5.3e-5, 1.3e-5, 3.3e-6];
        let stop = traced
            .iter()
            .position(|&x| !improves(17.12 - 7.23 * x, 17.12, 24.35));
        assert_eq!(stop, Some(2));
    }

    #[test]
    fn forcing_term_follows_eisenstat_walker_with_its_safeguards() {
        // γ (‖g_k‖/‖g_{k−1}‖)² with γ = 0.9.
        assert!((forcing_term(0.01, 1.0, 0.1, 0.0) - 0.009).abs() < 1e-15);
        // No sudden drop from a large previous term: at least 0.9 η²_{k−1} when that is > 0.1.
        assert!((forcing_term(0.5, 1.0, 0.1, 0.0) - 0.225).abs() < 1e-15);
        // At most ½.
        assert_eq!(forcing_term(0.5, 1.0, 1.0, 0.0), 0.5);
        // No more accuracy than the gradient tolerance needs: ½ target / ‖g‖.
        assert!((forcing_term(0.01, 1.0, 1e-3, 1e-6) - 5e-4).abs() < 1e-15);
    }

    #[test]
    fn a_kept_matrix_step_is_solved_no_tighter_than_the_last_contraction() {
        // The 223k junction's first step on a kept matrix: ‖g‖ 16 021 → 970, so
        // Eisenstat–Walker asks 0.9 · (970/16 021)² = 3.3·10⁻³; the floor is 970/16 021.
        let eta = forcing_term(0.0667, 16_021.0, 970.0, 0.0);
        assert!((eta - 0.9 * (970.0f64 / 16_021.0).powi(2)).abs() < 1e-15);
        let kept = super::kept_matrix_forcing(eta, 16_021.0, 970.0);
        assert!((kept - 970.0 / 16_021.0).abs() < 1e-15);
        // A looser term stays, and the floor never passes ½.
        assert_eq!(super::kept_matrix_forcing(0.3, 10.0, 1.0), 0.3);
        assert_eq!(super::kept_matrix_forcing(0.01, 1.0, 0.9), 0.5);
    }

    #[test]
    fn a_run_stops_at_its_tolerance_or_at_twice_the_coordinates_floor_above_it() {
        use super::NewtonReport;
        let mut report = NewtonReport::new(super::Terms::default(), 1.0);
        assert_eq!(report.stopping_gradient(0.05), 0.05);
        report.coordinate_floor = Some(0.01);
        assert_eq!(report.stopping_gradient(0.05), 0.05);
        report.coordinate_floor = Some(0.1);
        assert_eq!(report.stopping_gradient(0.05), 0.2);
        // The step from ‖g‖ = 7.55 is then solved to ½ · 0.2 / 7.55, not ½ · 0.05 / 7.55.
        let eta = forcing_term(0.01, 480.0, 7.55, report.stopping_gradient(0.05));
        assert!((eta - 0.1 / 7.55).abs() < 1e-15);
    }
}
