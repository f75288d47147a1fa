//! The multilevel method's step solver: conjugate gradients on H + νI preconditioned by
//! one multigrid V-cycle over the un-subdivided control meshes, to the relative residual
//! the inexact Newton iteration asks for.
//!
//! Near some minima the exact Hessian is nearly singular along smooth modes (the
//! five-tube junctions: a smooth normal displacement of the whole junction), and no
//! coarse level holds such a mode to the accuracy its tiny eigenvalue needs: CG with the
//! V-cycle stagnates (the 23 997-vertex junction at its minimum: 264 iterations to a
//! residual of 10⁻¹, where the 14 399-vertex three-tube one needs 25; a two-level cycle
//! with an exact coarse solve no better). Where the memory budget holds the plain method's factor,
//! such a solve falls back to a Cholesky factor of the fine matrix, kept as the
//! preconditioner of the next solves while it serves (the Newton tail's Hessians change
//! little), the factor §5 reuses.

use std::sync::Arc;
use std::time::Instant;

use super::block_csr::{Prolongation, UpperLayout};
use super::hierarchy::Hierarchy;
use super::multigrid::{LevelMatrices, Masses, Multigrid};
use super::patch_smoother::Patches;
use super::symmetric_csr::SymmetricCsr;
use crate::fair::functional::evaluation::BlockHessian;
use crate::fair::solvers::cholesky::{Factor, Factorizer};
use crate::fair::solvers::pcg::{pcg_operator, CgOutcome, CgStop};
use crate::fair::solvers::step_solver::StepSolver;

/// Most CG iterations per step: a V-cycle-preconditioned solve that needs more has met a
/// matrix the coarse levels do not fit, and its iterate is used as it is (a CG iterate
/// is a descent direction).
const MAX_CG_ITERATIONS: usize = 200;
/// With the fine factor available: CG iterations of the V-cycle before the solve is
/// handed to it (a solve the V-cycle serves takes under 30 on the junctions measured;
/// the stagnating ones hundreds).
const V_CYCLE_ITERATIONS_BEFORE_FACTOR: usize = 40;
/// CG iterations preconditioned by a kept factor of an earlier matrix before a fresh
/// factor is made.
const KEPT_FACTOR_ITERATIONS: usize = 20;

/// The fine level's Cholesky factorizer, for the solves the V-cycle does not serve.
struct FineFactor {
    factorizer: Factorizer,
    /// The factor last made, of an earlier or the current matrix.
    kept: Option<Factor>,
    /// Whether the last solve needed the factor: the next solve tries it first.
    preferred: bool,
    factorizations: usize,
    seconds: f64,
}

/// CG iterations and their seconds so far.
#[derive(Default)]
struct KrylovWork {
    iterations: usize,
    seconds: f64,
}

impl KrylovWork {
    /// CG on `ready`'s matrix for −`g`, preconditioned by `precondition`, counted here.
    fn cg(
        &mut self,
        ready: &ReadyMultigrid,
        minus_g: &[f64],
        precondition: &dyn Fn(&[f64]) -> Vec<f64>,
        forcing: f64,
        limit: usize,
    ) -> CgOutcome {
        let clock = Instant::now();
        let cg = pcg_operator(
            &|x: &[f64]| ready.matrix.multiply(x, ready.nu),
            minus_g,
            precondition,
            forcing,
            limit,
        );
        self.iterations += cg.iterations;
        self.seconds += clock.elapsed().as_secs_f64();
        cg
    }
}

/// H + νI with its V-cycle.
pub struct ReadyMultigrid {
    matrix: Arc<SymmetricCsr>,
    nu: f64,
    multigrid: Multigrid,
}

/// See the module documentation.
pub struct MultilevelSolver {
    prolongations: Arc<[Prolongation]>,
    patches: Vec<Arc<Patches>>,
    layout: Option<UpperLayout>,
    masses: Option<Masses>,
    /// The levels of the last matrix readied, by key: a Levenberg–Marquardt search readies
    /// one matrix for many ν.
    cached: Option<(u64, Arc<LevelMatrices>)>,
    coarsest: Factorizer,
    /// `None` when the fine factor does not fit the memory budget.
    fine: Option<FineFactor>,
    krylov: KrylovWork,
}

impl MultilevelSolver {
    /// A solver over `hierarchy` (at least one coarse level); `fine_factor`: whether a
    /// Cholesky factor of the fine matrix fits the memory budget (see the module
    /// documentation).
    pub fn new(hierarchy: Hierarchy, fine_factor: bool) -> Self {
        let sizes = hierarchy.sizes();
        let coarsest = *sizes.last().expect("at least one level");
        MultilevelSolver {
            prolongations: hierarchy.prolongations.into(),
            patches: hierarchy.patches,
            layout: None,
            masses: None,
            cached: None,
            coarsest: Factorizer::new(coarsest),
            fine: fine_factor.then(|| FineFactor {
                factorizer: Factorizer::new(sizes[0]),
                kept: None,
                preferred: false,
                factorizations: 0,
                seconds: 0.0,
            }),
            krylov: KrylovWork::default(),
        }
    }

    /// The solve by the kept fine factor as preconditioner, if one is kept and preferred
    /// and it reaches `forcing` within [`KEPT_FACTOR_ITERATIONS`].
    fn solve_with_kept_factor(
        &mut self,
        ready: &ReadyMultigrid,
        minus_g: &[f64],
        forcing: f64,
    ) -> Option<Vec<f64>> {
        let fine = self.fine.as_ref().filter(|f| f.preferred)?;
        let factor = fine.kept.as_ref()?;
        let cg = self.krylov.cg(
            ready,
            minus_g,
            &|r: &[f64]| factor.solve(r),
            forcing,
            KEPT_FACTOR_ITERATIONS,
        );
        (cg.stop == CgStop::Converged).then_some(cg.x)
    }

    /// The exact solve by a fresh factor of `ready`'s matrix, kept for the next solves;
    /// `None` if it is not positive definite.
    fn solve_with_fresh_factor(&mut self, ready: &ReadyMultigrid, g: &[f64]) -> Option<Vec<f64>> {
        let fine = self.fine.as_mut()?;
        if let Some(old) = fine.kept.take() {
            fine.factorizer.recycle(old);
        }
        let clock = Instant::now();
        let factor = fine.factorizer.factor(&ready.matrix.to_upper(), ready.nu);
        fine.seconds += clock.elapsed().as_secs_f64();
        fine.factorizations += 1;
        let Ok(factor) = factor else {
            fine.preferred = false;
            return None;
        };
        let step = factor.newton_step(g);
        fine.kept = Some(factor);
        fine.preferred = true;
        Some(step)
    }

    fn levels(&mut self, h: &BlockHessian, key: u64) -> Arc<LevelMatrices> {
        if let Some((k, levels)) = &self.cached {
            if *k == key {
                return Arc::clone(levels);
            }
        }
        self.cached = None;
        let n = self.prolongations[0].fine_count();
        if !self.layout.as_ref().is_some_and(|l| l.fits(h)) {
            self.layout = Some(UpperLayout::new(h, n));
        }
        let fine = self.layout.as_ref().expect("just set").fill(h);
        let levels = Arc::new(LevelMatrices::new(fine, &self.prolongations));
        self.cached = Some((key, Arc::clone(&levels)));
        levels
    }
}

impl StepSolver for MultilevelSolver {
    type Ready = ReadyMultigrid;

    fn ready(&mut self, h: &BlockHessian, key: u64, nu: f64) -> Option<ReadyMultigrid> {
        let levels = self.levels(h, key);
        if self.masses.is_none() {
            self.masses = Some(Masses::new(&levels, &self.prolongations)?);
        }
        let multigrid = Multigrid::new(
            &levels,
            self.masses.as_ref().expect("just set"),
            Arc::clone(&self.prolongations),
            // Patch smoothing for the Newton steps only: see `patch_smoother`.
            if nu == 0.0 { &self.patches } else { &[] },
            nu,
            &mut self.coarsest,
        )?;
        Some(ReadyMultigrid {
            matrix: Arc::clone(&levels.matrices[0]),
            nu,
            multigrid,
        })
    }

    fn solve(&mut self, ready: &ReadyMultigrid, g: &[f64], forcing: f64) -> Option<Vec<f64>> {
        let minus_g: Vec<f64> = g.iter().map(|x| -x).collect();
        if let Some(step) = self.solve_with_kept_factor(ready, &minus_g, forcing) {
            return Some(step);
        }
        let limit = if self.fine.is_some() {
            V_CYCLE_ITERATIONS_BEFORE_FACTOR
        } else {
            MAX_CG_ITERATIONS
        };
        let cg = self.krylov.cg(
            ready,
            &minus_g,
            &|r: &[f64]| ready.multigrid.apply(r),
            forcing,
            limit,
        );
        match cg.stop {
            CgStop::Converged => {
                if let Some(fine) = &mut self.fine {
                    fine.preferred = false;
                }
                Some(cg.x)
            }
            CgStop::IterationLimit => self.solve_with_fresh_factor(ready, g).or(Some(cg.x)),
            CgStop::Indefinite => None,
        }
    }

    fn recycle(&mut self, _ready: ReadyMultigrid) {}

    fn has_coarse_level(&self) -> bool {
        true
    }

    /// CG on the first coarse level's matrix (its Galerkin image of H + νI) preconditioned
    /// by the V-cycle from that level, or its factor where it is the coarsest.
    fn coarse_step(&mut self, ready: &ReadyMultigrid, g: &[f64], forcing: f64) -> Option<Vec<f64>> {
        let p = &self.prolongations[0];
        let minus_g: Vec<f64> = g.iter().map(|x| -x).collect();
        let b = p.restrict(&minus_g);
        let coarse = match ready.multigrid.level_system(1) {
            Some((matrix, shift)) => {
                let clock = Instant::now();
                let cg = pcg_operator(
                    &|x: &[f64]| matrix.multiply(x, shift),
                    &b,
                    &|r: &[f64]| ready.multigrid.cycle(1, r),
                    forcing,
                    MAX_CG_ITERATIONS,
                );
                self.krylov.iterations += cg.iterations;
                self.krylov.seconds += clock.elapsed().as_secs_f64();
                if cg.stop == CgStop::Indefinite {
                    return None;
                }
                cg.x
            }
            None => ready.multigrid.cycle(1, &b),
        };
        let mut fine = vec![0.0; g.len()];
        p.add_prolonged(&coarse, &mut fine);
        Some(fine)
    }

    fn krylov_work(&self) -> (usize, f64) {
        (self.krylov.iterations, self.krylov.seconds)
    }

    fn fine_factorizations(&self) -> (usize, f64) {
        self.fine
            .as_ref()
            .map_or((0, 0.0), |f| (f.factorizations, f.seconds))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fair::functional::evaluation::Hessians;
    use crate::fair::solvers::multilevel::hierarchy::hierarchy;
    use crate::fair::solvers::step_solver::CholeskySolver;
    use crate::fair::{
        fixed_vertices, refine_surface, tubes, Functional, HessianKind, MeshTopology,
        RepresentationOptions, SurfaceKind, SurfaceRepresentation,
    };

    /// The three-tube junction refined `refinements` times, Catmull–Clark surface: its
    /// Hessians at the raw mesh, its levels and its free count.
    fn refined_junction(refinements: u32) -> (Hierarchy, Hessians, usize) {
        let mesh = refine_surface(&tubes(3, 8, 2).unwrap(), refinements).unwrap();
        let topo = MeshTopology::new(&mesh).unwrap();
        let fixed = fixed_vertices(&topo, 3, &[]).unwrap();
        let options = RepresentationOptions {
            surface: SurfaceKind::CatmullClark,
            ..RepresentationOptions::default()
        };
        let rep =
            SurfaceRepresentation::new(&mesh, &topo.boundary, &topo.special_flags(), &options)
                .unwrap();
        let functional = Functional::new(&rep, &fixed, 1.0);
        let hessians = functional.hessians(&mesh.positions, HessianKind::Both);
        let levels = hierarchy(&mesh, functional.free_index(), functional.free_count());
        (levels, hessians, functional.free_count())
    }

    /// The 3743-vertex junction's (3167 free vertices; one coarse level, the 911 internal
    /// vertices of the 1007-vertex mesh it refines).
    fn junction() -> (Hierarchy, Hessians, usize) {
        let out = refined_junction(1);
        assert_eq!(out.0.sizes(), vec![3167, 911]);
        out
    }

    fn distance(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).powi(2))
            .sum::<f64>()
            .sqrt()
    }

    #[test]
    fn coarse_step_solves_the_galerkin_system_of_the_first_coarse_level() {
        // The 3743-vertex junction (its first coarse level the coarsest, solved by its
        // factor) and the 14 399-vertex one (first coarse level 3551 vertices, solved by CG
        // with the V-cycle from there): d = P δ_c must leave Pᵀ((H + νI) d + g) = 0, the
        // Galerkin condition, checked with the fine matrix's own product and restriction.
        for refinements in [1, 2] {
            let (levels, hessians, _) = refined_junction(refinements);
            assert_eq!(
                levels.sizes().len(),
                refinements as usize + 1,
                "{:?}",
                levels.sizes()
            );
            let mut solver = MultilevelSolver::new(levels, false);
            assert!(solver.has_coarse_level());
            let g = &hessians.gradient;
            let gn = hessians.gauss_newton.as_ref().unwrap();
            let nu = 1e-3 * crate::fair::solvers::newton::diagonal_scale(gn);
            let ready = solver.ready(gn, 1, nu).expect("positive definite");
            let d = solver.coarse_step(&ready, g, 1e-10).expect("a step");
            let p = &solver.prolongations[0];
            let residual: Vec<f64> = ready
                .matrix
                .multiply(&d, nu)
                .iter()
                .zip(g)
                .map(|(hd, g)| hd + g)
                .collect();
            let restricted_residual = p.restrict(&residual);
            let restricted_gradient = p.restrict(g);
            let size = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
            assert!(
                size(&restricted_residual) <= 1e-8 * size(&restricted_gradient),
                "refinements {refinements}: {:e} of {:e}",
                size(&restricted_residual),
                size(&restricted_gradient)
            );
            // A descent direction, not zero.
            assert!(crate::linalg::dot(g, &d) < 0.0);
        }
    }

    #[test]
    fn v_cycle_conjugate_gradients_solve_as_the_cholesky_factor() {
        // The junction's Gauss–Newton part + ν I as in a Levenberg–Marquardt trial, and a
        // shifted exact Hessian, solved by CG to 1e-10 and by Cholesky.
        let (levels, hessians, free) = junction();
        let mut multilevel = MultilevelSolver::new(levels, false);
        let mut cholesky = CholeskySolver(Factorizer::new(free));
        let g = &hessians.gradient;
        let gn = hessians.gauss_newton.as_ref().unwrap();
        let exact = hessians.exact.as_ref().unwrap();
        let scale = crate::fair::solvers::newton::diagonal_scale(gn);
        // The exact Hessian of the raw mesh is indefinite: the smallest ν = 4ᵏ · scale
        // that makes it positive definite, as a Levenberg–Marquardt search would find.
        let exact_nu = (0..40)
            .map(|k| scale * 4f64.powi(k))
            .find(|&nu| cholesky.ready(exact, 0, nu).is_some())
            .expect("a shift makes it positive definite");
        for (h, key, nu) in [
            (gn, 1, 1e-3 * scale),
            (gn, 1, 1e-1 * scale),
            (exact, 0, exact_nu),
        ] {
            let direct = cholesky.ready(h, key, nu).expect("positive definite");
            let expected = cholesky.solve(&direct, g, 0.0).unwrap();
            let ready = multilevel.ready(h, key, nu).expect("positive definite");
            let before = multilevel.krylov_work().0;
            let got = multilevel.solve(&ready, g, 1e-10).unwrap();
            let iterations = multilevel.krylov_work().0 - before;
            let error = distance(&got, &expected);
            let size = expected.iter().map(|x| x * x).sum::<f64>().sqrt();
            assert!(
                error <= 1e-7 * size,
                "ν {nu:e}: error {error:e} of {size:e}"
            );
            // A V-cycle that did nothing would need hundreds of iterations here.
            assert!(iterations < 60, "ν {nu:e}: {iterations} CG iterations");
        }
    }

    #[test]
    fn newton_solves_smooth_by_patches_in_fewer_iterations_to_the_same_step() {
        // ν = 0, as in a Newton step, on the (positive definite) Gauss–Newton matrix: the
        // patch-smoothed V-cycle reaches the Cholesky step, in fewer CG iterations than
        // the same V-cycle smoothed by the 3 × 3 blocks.
        let (levels, hessians, free) = junction();
        let mut blocks_only = levels.clone();
        blocks_only.patches.clear();
        let mut cholesky = CholeskySolver(Factorizer::new(free));
        let g = &hessians.gradient;
        let gn = hessians.gauss_newton.as_ref().unwrap();
        let direct = cholesky.ready(gn, 1, 0.0).expect("positive definite");
        let expected = cholesky.solve(&direct, g, 0.0).unwrap();
        let size = expected.iter().map(|x| x * x).sum::<f64>().sqrt();
        let mut iterations = Vec::new();
        for levels in [levels, blocks_only] {
            let mut multilevel = MultilevelSolver::new(levels, false);
            let ready = multilevel.ready(gn, 1, 0.0).expect("positive definite");
            let got = multilevel.solve(&ready, g, 1e-10).unwrap();
            assert!(distance(&got, &expected) <= 1e-7 * size);
            iterations.push(multilevel.krylov_work().0);
        }
        assert!(
            iterations[0] < iterations[1],
            "CG iterations with patches, with blocks: {iterations:?}"
        );
    }

    #[test]
    fn a_solve_the_v_cycle_does_not_serve_falls_back_to_the_fine_factor() {
        // A residual of 1e-14 is beyond the 40 iterations the V-cycle is given when the
        // fine factor fits: the solve is the factor's (the plain method's step), and the
        // factor is kept: the next solve of the same matrix converges at once with it as
        // the preconditioner, with no new factor.
        let (levels, hessians, free) = junction();
        let mut multilevel = MultilevelSolver::new(levels, true);
        let mut cholesky = CholeskySolver(Factorizer::new(free));
        let g = &hessians.gradient;
        let gn = hessians.gauss_newton.as_ref().unwrap();
        let nu = 1e-3 * crate::fair::solvers::newton::diagonal_scale(gn);
        let direct = cholesky.ready(gn, 1, nu).expect("positive definite");
        let expected = cholesky.solve(&direct, g, 0.0).unwrap();
        let size = expected.iter().map(|x| x * x).sum::<f64>().sqrt();
        let ready = multilevel.ready(gn, 1, nu).expect("positive definite");
        let got = multilevel.solve(&ready, g, 1e-14).unwrap();
        assert_eq!(multilevel.krylov_work().0, V_CYCLE_ITERATIONS_BEFORE_FACTOR);
        assert_eq!(multilevel.fine_factorizations().0, 1);
        assert!(distance(&got, &expected) <= 1e-9 * size);
        let got = multilevel.solve(&ready, g, 1e-10).unwrap();
        let iterations = multilevel.krylov_work().0 - V_CYCLE_ITERATIONS_BEFORE_FACTOR;
        assert!(
            iterations <= 2,
            "{iterations} CG iterations with the exact factor"
        );
        assert_eq!(multilevel.fine_factorizations().0, 1);
        assert!(distance(&got, &expected) <= 1e-8 * size);
        // Without the fine factor the same solve is the V-cycle's, to the same answer,
        // past the 40 iterations.
        let (levels, _, _) = junction();
        let mut alone = MultilevelSolver::new(levels, false);
        let ready = alone.ready(gn, 1, nu).expect("positive definite");
        let got = alone.solve(&ready, g, 1e-14).unwrap();
        assert!(alone.krylov_work().0 > V_CYCLE_ITERATIONS_BEFORE_FACTOR);
        assert_eq!(alone.fine_factorizations().0, 0);
        assert!(distance(&got, &expected) <= 1e-9 * size);
    }
}
