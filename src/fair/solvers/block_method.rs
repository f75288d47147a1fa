//! The block (domain-decomposition) optimizer of paper §5 for large meshes, where the
//! Cholesky factor of the whole Hessian gets too costly:
//!
//! 1. blocks: a discrete Voronoi diagram of seed vertices, extended to overlap
//!    ([`voronoi_blocks`]);
//! 2. block iterations: the plain method ([`newton`], Newton / Levenberg–Marquardt with
//!    factor reuse) on one block at a time, the other vertices held, over only the
//!    quadrature points that meet the block ([`SubRepresentation`]); sweeps over the
//!    blocks "until the Newton method step for each block is effective" (it decreases F and
//!    cuts the block's gradient by the reuse factor, 4);
//! 3. final phase: Newton for all unknowns, eq. 7 solved by CG ([`pcg`]) with the additive
//!    Schwarz preconditioner ([`Schwarz`]); the Hessian and the preconditioner are reused
//!    while steps are effective, as in the plain method. When CG meets indefiniteness, an
//!    A_b is not positive definite, or a fresh step does not decrease F, "a number of
//!    additional iterations for the blocks are made" (back to 2).
//!
//! Measured (2 shared cores, release): on the 359-vertex junction with isolation 2 and
//! 3 nodes the method reaches the plain optimum in 10 sweeps and 2 global Hessians
//! (tests/fair/blocks.rs). At the default isolation 4 the sweeps converge only linearly:
//! 359 vertices, 4 blocks, tolerance 1e-8: 154 sweeps and 8 global Hessians in 261 s,
//! where the plain method needs 30 Hessians (measured before the same session made each
//! Hessian about 2.5× cheaper, which speeds both up); 1295 vertices, tolerance 1e-7:
//! plain 61 s and 64 Hessians,
//! while neither this loop (8 blocks, stopped after 12 min) nor `global_lm` (200 global
//! steps at ν ≈ 1e7–1e10, F still 12× the optimum) converged. One-level Schwarz on this
//! problem (third derivatives squared: an order-6 Euler–Lagrange operator) probably needs
//! a coarse level (the paper's planned multilevel method) to pay; not tried.

use std::ops::ControlFlow;
use std::time::Instant;

use crate::error::{Error, Result};
use crate::fair::functional::evaluation::{BlockHessian, Functional, Terms};
use crate::fair::preparation::topology::MeshTopology;
use crate::fair::solvers::blocks::voronoi_blocks;
use crate::fair::solvers::newton::{
    decreases, diagonal_scale, finite_start, moved, newton, Iteration, NewtonOptions, NewtonReport,
    StepKind,
};
use crate::fair::solvers::pcg::{pcg, CgStop};
use crate::fair::solvers::schwarz::Schwarz;
use crate::fair::surface::representation::Representation;
use crate::fair::surface::sub_representation::SubRepresentation;
use crate::linalg::norm;

/// Options of the block method.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockOptions {
    /// Number of blocks (Voronoi seeds).
    pub count: usize,
    /// Rings of edges each Voronoi region is extended by.
    pub overlap: u32,
    /// Most iterations of the plain method per block visit.
    pub block_iterations: usize,
    /// Most sweeps over the blocks before trying the final phase anyway.
    pub max_sweeps: usize,
    /// Most returns from the final phase to block iterations.
    pub max_rounds: usize,
    /// Largest relative CG residual; CG is asked for min(this, ‖g‖/‖g₀‖) (an inexact
    /// Newton forcing term: loose far away, tight near the optimum).
    pub cg_tolerance: f64,
    pub cg_max_iterations: usize,
    /// Halvings of a global step that does not decrease F before going back to block
    /// iterations (a safeguard beyond the paper, which goes back at once).
    pub step_halvings: usize,
    /// When the global Newton system fails (an A_b or H not positive definite, no
    /// decrease), search the Levenberg–Marquardt trajectory (eq. 8–9) with PCG on
    /// H + νI before going back to block iterations. Not in the paper's block method
    /// (which goes back at once); measured to be needed far from the optimum here.
    pub global_lm: bool,
}

impl Default for BlockOptions {
    fn default() -> Self {
        BlockOptions {
            count: 8,
            overlap: 2,
            block_iterations: 3,
            max_sweeps: 30,
            max_rounds: 100,
            cg_tolerance: 1e-2,
            cg_max_iterations: 2000,
            step_halvings: 6,
            global_lm: false,
        }
    }
}

/// One entry of the block method's log.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(tag = "phase", rename_all = "snake_case")]
pub enum BlockPhase {
    /// A sweep of block iterations; F and ‖g‖ of the whole problem after it.
    Sweep {
        terms: Terms,
        gradient_norm: f64,
        effective_blocks: usize,
        skipped_blocks: usize,
    },
    /// A global Newton step solved by preconditioned CG.
    Global {
        terms: Terms,
        gradient_norm: f64,
        cg_iterations: usize,
        cg_relative_residual: f64,
        reused_hessian: bool,
        /// 1 for the Newton step; less when it was halved to decrease F.
        step_length: f64,
        /// ν of eq. 9 (0: Newton).
        nu: f64,
    },
    /// The final phase gave up and went back to block iterations.
    BackToBlocks { reason: String },
}

/// What the block method did (beside the [`NewtonReport`] of its global steps).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct BlockReport {
    pub blocks: usize,
    pub smallest_block: usize,
    pub largest_block: usize,
    /// Sum of block sizes / free vertices.
    pub coverage: f64,
    pub sweeps: usize,
    pub rounds: usize,
    pub block_newton_iterations: usize,
    pub block_hessian_evaluations: usize,
    /// Block Hessians weighted by their share of the quadrature points: their cost in
    /// whole-surface Hessians.
    pub block_hessians_equivalent: f64,
    pub global_hessian_evaluations: usize,
    pub cg_iterations: usize,
    pub block_seconds: f64,
    pub preconditioner_seconds: f64,
    pub cg_seconds: f64,
    pub log: Vec<BlockPhase>,
}

/// The block method's state across its phases.
struct Run<'a, 'r, R: Representation> {
    rep: &'r R,
    global: &'a Functional<'r, R>,
    c: f64,
    /// Vertex ids of each block.
    blocks: Vec<Vec<u32>>,
    newton: NewtonOptions,
    options: BlockOptions,
    /// ‖g‖ target of the whole problem.
    target: f64,
    report: NewtonReport,
    blocks_report: BlockReport,
}

/// How the final phase ended.
enum Final {
    Converged,
    IterationLimit,
    BackToBlocks,
    /// The observer asked to stop.
    Cancelled,
}

impl<R: Representation> Run<'_, '_, R> {
    /// One sweep over the blocks; whether every block's step was effective (or its gradient
    /// already below the target).
    fn sweep(&mut self, positions: &mut Vec<[f64; 3]>) -> Result<(usize, usize)> {
        let clock = Instant::now();
        let n = self.rep.vertex_count();
        let total_points = self.rep.points().len().max(1) as f64;
        let (mut effective, mut skipped) = (0, 0);
        // Each block's sub-representation is rebuilt per sweep rather than kept: together
        // the blocks copy every quadrature point about `coverage` times, too much memory
        // for the meshes this method is for, while the copy costs far less than the
        // block's Hessians.
        for block in &self.blocks {
            let mut in_block = vec![false; n];
            for &v in block {
                in_block[v as usize] = true;
            }
            let sub = SubRepresentation::new(self.rep, &in_block);
            let held: Vec<bool> = in_block.iter().map(|&b| !b).collect();
            let functional = Functional::new(&sub, &held, self.c);
            let g = norm(&functional.gradient(positions).1);
            if g <= self.target {
                skipped += 1;
                effective += 1;
                continue;
            }
            let options = NewtonOptions {
                max_iterations: self.options.block_iterations,
                ..self.newton.clone()
            };
            match newton(&functional, positions, &options) {
                Ok(r) => {
                    self.blocks_report.block_newton_iterations += r.iterations.len();
                    self.blocks_report.block_hessian_evaluations += r.hessian_evaluations;
                    self.blocks_report.block_hessians_equivalent +=
                        r.hessian_evaluations as f64 * sub.points().len() as f64 / total_points;
                    if r.iterations.first().is_some_and(|it| {
                        it.step == StepKind::Newton
                            && it.gradient_norm * self.newton.reuse_factor
                                <= r.initial_gradient_norm
                    }) {
                        effective += 1;
                    }
                }
                // No decrease of F in this block (round-off level): not effective; the
                // positions reached are kept.
                Err(Error::Solver { .. }) => {}
                Err(e) => return Err(e),
            }
        }
        self.blocks_report.sweeps += 1;
        self.blocks_report.block_seconds += clock.elapsed().as_secs_f64();
        Ok((effective, skipped))
    }

    /// Global Newton steps with PCG until convergence, the iteration limit, or a failure.
    fn final_phase(
        &mut self,
        schwarz: &mut Schwarz,
        positions: &mut Vec<[f64; 3]>,
        terms: &mut Terms,
        g: &mut Vec<f64>,
        observe: &mut dyn FnMut(&Iteration) -> ControlFlow<()>,
    ) -> Final {
        let free = self.global.free_index().to_vec();
        let g0 = self.report.initial_gradient_norm;
        let mut kept: Option<BlockHessian> = None;
        loop {
            let gnorm = norm(g);
            if gnorm <= self.target {
                return Final::Converged;
            }
            if self.report.cancelled {
                return Final::Cancelled;
            }
            if self.report.iterations.len() >= self.newton.max_iterations {
                return Final::IterationLimit;
            }
            let reused = kept.is_some();
            let h = match kept.take() {
                Some(h) => h,
                None => {
                    let clock = Instant::now();
                    let (t, gh, h) = self.global.hessian(positions);
                    self.report.hessian_evaluations += 1;
                    self.blocks_report.global_hessian_evaluations += 1;
                    self.report.hessian_seconds += clock.elapsed().as_secs_f64();
                    (*terms, *g) = (t, gh);
                    h
                }
            };
            let gnorm = norm(g);
            let scale = diagonal_scale(&h);
            // ν = 0 (Newton, eq. 7); with `global_lm`, then ν growing by 4 from 1e-3 of
            // the diagonal's scale (the Levenberg–Marquardt trajectory, eq. 9).
            let trials = if self.options.global_lm && !reused {
                40
            } else {
                1
            };
            let mut reason = String::new();
            let mut accepted = false;
            for trial in 0..trials {
                let nu = if trial == 0 {
                    0.0
                } else {
                    scale * 1e-3 * 4f64.powi(trial - 1)
                };
                if !reused {
                    let clock = Instant::now();
                    let factored = schwarz.factor(&h, nu);
                    self.report.factorizations += schwarz.len();
                    let seconds = clock.elapsed().as_secs_f64();
                    self.report.factorization_seconds += seconds;
                    self.blocks_report.preconditioner_seconds += seconds;
                    if let Err(e) = factored {
                        reason = format!("a block of the Hessian + {nu:e} I: {e}");
                        continue;
                    }
                }
                let tolerance = (gnorm / g0).clamp(1e-10, self.options.cg_tolerance);
                let minus_g: Vec<f64> = g.iter().map(|x| -x).collect();
                let clock = Instant::now();
                let cg = pcg(
                    &h,
                    nu,
                    &minus_g,
                    &|r| schwarz.apply(r),
                    tolerance,
                    self.options.cg_max_iterations,
                );
                self.blocks_report.cg_seconds += clock.elapsed().as_secs_f64();
                self.blocks_report.cg_iterations += cg.iterations;
                reason = match cg.stop {
                    CgStop::Converged => {
                        "neither the Newton step nor its halvings decrease F".to_string()
                    }
                    CgStop::Indefinite => "CG met a direction with pᵀHp ≤ 0".to_string(),
                    CgStop::IterationLimit => format!(
                        "CG reached {} iterations (relative residual {:e})",
                        cg.iterations, cg.relative_residual
                    ),
                };
                if cg.stop != CgStop::Converged {
                    continue;
                }
                // The full step, then (a safeguard, not in the paper) halved steps: a CG
                // iterate with positive curvatures throughout is a descent direction.
                let mut length = 1.0;
                for _ in 0..=self.options.step_halvings {
                    let trial = moved(positions, &free, &cg.x, length);
                    let (t, gt) = self.global.gradient(&trial);
                    let gt_norm = norm(&gt);
                    if decreases(t.f, terms.f) && gt_norm.is_finite() {
                        accepted = true;
                        if length == 1.0 && nu == 0.0 && gt_norm * self.newton.reuse_factor <= gnorm
                        {
                            kept = Some(h.clone());
                        }
                        (*positions, *terms, *g) = (trial, t, gt);
                        let it = Iteration {
                            terms: *terms,
                            gradient_norm: gt_norm,
                            step: if nu > 0.0 {
                                StepKind::LevenbergMarquardt
                            } else if reused {
                                StepKind::ReusedNewton
                            } else {
                                StepKind::Newton
                            },
                            nu: (nu > 0.0).then_some(nu),
                        };
                        self.report.iterations.push(it);
                        let flow = observe(&it);
                        self.blocks_report.log.push(BlockPhase::Global {
                            terms: *terms,
                            gradient_norm: gt_norm,
                            cg_iterations: cg.iterations,
                            cg_relative_residual: cg.relative_residual,
                            reused_hessian: reused,
                            step_length: length,
                            nu,
                        });
                        self.report.cancelled = flow.is_break();
                        break;
                    }
                    if reused {
                        break; // retry with a fresh Hessian first
                    }
                    length *= 0.5;
                }
                if accepted {
                    break;
                }
            }
            if !accepted && !reused {
                self.back(reason);
                return Final::BackToBlocks;
            }
            // A failed step with a kept Hessian retries with a fresh one (`kept` is None).
        }
    }

    fn back(&mut self, reason: String) {
        self.blocks_report
            .log
            .push(BlockPhase::BackToBlocks { reason });
    }
}

/// Minimizes F̃ (eq. 6) over the free vertices of `positions` by the block method (§5).
///
/// `observe` is called after each global step and after each sweep (with the whole
/// problem's F and ‖g‖; a sweep is reported as a [`StepKind::Newton`] line, for progress
/// display only); `ControlFlow::Break` stops the run there ([`NewtonReport::cancelled`]). The returned [`NewtonReport`] lists the global steps; Hessian counts
/// of both phases are in the [`BlockReport`].
///
/// # Errors
/// [`Error::InvalidInput`] for bad block options (see [`voronoi_blocks`]);
/// [`Error::Solver`] when F or its gradient is not finite at the start.
#[allow(clippy::too_many_arguments)]
pub fn block_newton<R: Representation>(
    rep: &R,
    topo: &MeshTopology,
    fixed: &[bool],
    c: f64,
    positions: &mut Vec<[f64; 3]>,
    newton_options: &NewtonOptions,
    options: &BlockOptions,
    observe: &mut dyn FnMut(&Iteration) -> ControlFlow<()>,
) -> Result<(NewtonReport, BlockReport)> {
    if !(options.cg_tolerance > 0.0 && options.cg_tolerance < 1.0) {
        return Err(Error::InvalidInput(format!(
            "the CG tolerance must lie in (0, 1), not {}",
            options.cg_tolerance
        )));
    }
    if options.block_iterations == 0 || options.max_sweeps == 0 {
        return Err(Error::InvalidInput(
            "the block method needs at least one iteration per block and one sweep".into(),
        ));
    }
    let global = Functional::new(rep, fixed, c);
    let blocks = voronoi_blocks(topo, fixed, options.count, options.overlap)?;
    let free_blocks: Vec<Vec<u32>> = blocks
        .iter()
        .map(|b| b.iter().map(|&v| global.free_index()[v as usize]).collect())
        .collect();
    let mut schwarz = Schwarz::new(global.free_count(), free_blocks)?;
    let (mut terms, mut g) = {
        let (terms, g) = global.gradient(positions);
        finite_start(terms, g, positions)?
    };
    let g0 = norm(&g);
    let mut run = Run {
        rep,
        global: &global,
        c,
        newton: newton_options.clone(),
        options: options.clone(),
        target: newton_options.relative_gradient * g0,
        report: NewtonReport::new(terms, g0),
        blocks_report: BlockReport {
            blocks: blocks.len(),
            smallest_block: blocks.iter().map(Vec::len).min().unwrap_or(0),
            largest_block: blocks.iter().map(Vec::len).max().unwrap_or(0),
            coverage: schwarz.coverage(),
            sweeps: 0,
            rounds: 0,
            block_newton_iterations: 0,
            block_hessian_evaluations: 0,
            block_hessians_equivalent: 0.0,
            global_hessian_evaluations: 0,
            cg_iterations: 0,
            block_seconds: 0.0,
            preconditioner_seconds: 0.0,
            cg_seconds: 0.0,
            log: Vec::new(),
        },
        blocks,
    };
    if g0 == 0.0 {
        run.report.converged = true;
        return Ok((run.report, run.blocks_report));
    }
    'rounds: for _ in 0..options.max_rounds.max(1) {
        run.blocks_report.rounds += 1;
        for _ in 0..options.max_sweeps {
            let (effective, skipped) = run.sweep(positions)?;
            (terms, g) = global.gradient(positions);
            let gradient_norm = norm(&g);
            run.blocks_report.log.push(BlockPhase::Sweep {
                terms,
                gradient_norm,
                effective_blocks: effective,
                skipped_blocks: skipped,
            });
            let flow = observe(&Iteration {
                terms,
                gradient_norm,
                step: StepKind::Newton,
                nu: None,
            });
            if gradient_norm <= run.target {
                run.report.converged = true;
                break 'rounds;
            }
            if flow.is_break() {
                run.report.cancelled = true;
                break 'rounds;
            }
            if effective == run.blocks.len() {
                break;
            }
        }
        match run.final_phase(&mut schwarz, positions, &mut terms, &mut g, observe) {
            Final::Converged => {
                run.report.converged = true;
                break;
            }
            Final::IterationLimit | Final::Cancelled => break,
            Final::BackToBlocks => {}
        }
    }
    Ok((run.report, run.blocks_report))
}
