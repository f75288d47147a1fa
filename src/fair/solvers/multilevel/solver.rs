//! The multilevel method's step solver: conjugate gradients on H + νI preconditioned by
//! one multigrid V-cycle over the un-subdivided control meshes, to the relative residual
//! the inexact Newton iteration asks for.

use std::sync::Arc;
use std::time::Instant;

use super::block_csr::{BlockCsr, Prolongation, UpperLayout};
use super::hierarchy::Hierarchy;
use super::multigrid::{LevelMatrices, Masses, Multigrid};
use crate::fair::functional::evaluation::BlockHessian;
use crate::fair::solvers::cholesky::Factorizer;
use crate::fair::solvers::pcg::{pcg_operator, CgStop};
use crate::fair::solvers::step_solver::StepSolver;

/// Most CG iterations per step: a V-cycle-preconditioned solve that needs more has met a
/// matrix the coarse levels do not fit, and its iterate is used as it is (a CG iterate
/// is a descent direction).
const MAX_CG_ITERATIONS: usize = 200;

/// H + νI with its V-cycle.
pub struct ReadyMultigrid {
    matrix: Arc<BlockCsr>,
    nu: f64,
    multigrid: Multigrid,
}

/// See the module documentation.
pub struct MultilevelSolver {
    prolongations: Arc<[Prolongation]>,
    layout: Option<UpperLayout>,
    masses: Option<Masses>,
    /// The levels of the last matrix readied, by key: a Levenberg–Marquardt search readies
    /// one matrix for many ν.
    cached: Option<(u64, Arc<LevelMatrices>)>,
    coarsest: Factorizer,
    cg_iterations: usize,
    cg_seconds: f64,
}

impl MultilevelSolver {
    /// A solver over `hierarchy` (at least one coarse level).
    pub fn new(hierarchy: Hierarchy) -> Self {
        let coarsest = *hierarchy.sizes().last().expect("at least one level");
        MultilevelSolver {
            prolongations: hierarchy.prolongations.into(),
            layout: None,
            masses: None,
            cached: None,
            coarsest: Factorizer::new(coarsest),
            cg_iterations: 0,
            cg_seconds: 0.0,
        }
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
        let levels = Arc::new(LevelMatrices::new(Arc::new(fine), &self.prolongations));
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
        let clock = Instant::now();
        let minus_g: Vec<f64> = g.iter().map(|x| -x).collect();
        let cg = pcg_operator(
            &|x: &[f64]| ready.matrix.multiply(x, ready.nu),
            &minus_g,
            &|r: &[f64]| ready.multigrid.apply(r),
            forcing,
            MAX_CG_ITERATIONS,
        );
        self.cg_iterations += cg.iterations;
        self.cg_seconds += clock.elapsed().as_secs_f64();
        match cg.stop {
            CgStop::Converged | CgStop::IterationLimit => Some(cg.x),
            CgStop::Indefinite => None,
        }
    }

    fn recycle(&mut self, _ready: ReadyMultigrid) {}

    fn krylov_work(&self) -> (usize, f64) {
        (self.cg_iterations, self.cg_seconds)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fair::solvers::multilevel::hierarchy::hierarchy;
    use crate::fair::solvers::step_solver::CholeskySolver;
    use crate::fair::{
        fixed_vertices, refine_surface, tubes, Functional, HessianKind, MeshTopology,
        RepresentationOptions, SurfaceKind, SurfaceRepresentation,
    };

    #[test]
    fn v_cycle_conjugate_gradients_solve_as_the_cholesky_factor() {
        // The 3743-vertex junction's Hessians at the raw mesh (3167 free vertices; one
        // coarse level, the 911 internal vertices of the 1007-vertex mesh it refines): the
        // Gauss–Newton part + ν I as in a Levenberg–Marquardt trial, and a shifted exact
        // Hessian, solved by CG to 1e-10 and by Cholesky.
        let mesh = refine_surface(&tubes(3, 8, 2).unwrap(), 1).unwrap();
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
        assert_eq!(levels.sizes(), vec![3167, 911]);
        let mut multilevel = MultilevelSolver::new(levels);
        let mut cholesky = CholeskySolver(Factorizer::new(functional.free_count()));
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
            let error = got
                .iter()
                .zip(&expected)
                .map(|(a, b)| (a - b).powi(2))
                .sum::<f64>()
                .sqrt();
            let size = expected.iter().map(|x| x * x).sum::<f64>().sqrt();
            assert!(
                error <= 1e-7 * size,
                "ν {nu:e}: error {error:e} of {size:e}"
            );
            // A V-cycle that did nothing would need hundreds of iterations here.
            assert!(iterations < 60, "ν {nu:e}: {iterations} CG iterations");
        }
    }
}
