//! How Newton's method solves its steps (H + νI) δ = −g: a sparse Cholesky factor (the
//! plain method, exact) or conjugate gradients with a multigrid preconditioner (the
//! multilevel method, to a relative residual the Newton iteration chooses).

use crate::fair::functional::evaluation::BlockHessian;
use crate::fair::solvers::cholesky::{Factor, Factorizer};

/// A solver of (H + νI) δ = −g.
pub trait StepSolver {
    /// H + νI made ready for solves: a Cholesky factor, a preconditioner with its matrix.
    type Ready;

    /// Readies `h` + ν I; `key` names the matrix (one key, one matrix) so that work not
    /// depending on ν is done once per matrix. `None` when the matrix is found not to be
    /// positive definite (or the set-up fails).
    fn ready(&mut self, h: &BlockHessian, key: u64, nu: f64) -> Option<Self::Ready>;

    /// δ with (H + νI) δ = −g to the relative residual `forcing` (an exact solver ignores
    /// it); `None` when the solve meets negative curvature.
    fn solve(&mut self, ready: &Self::Ready, g: &[f64], forcing: f64) -> Option<Vec<f64>>;

    /// Whether [`Self::coarse_step`] can serve (the solver has a coarse level).
    fn has_coarse_level(&self) -> bool {
        false
    }

    /// P δ_c with Pᵀ(H + νI)P δ_c = −Pᵀ g to the relative residual `forcing`, P the
    /// prolongation from the first coarse level: the step of `ready`'s matrix restricted
    /// to that level's subspace. `None` for a solver without coarse levels, or when the
    /// solve meets negative curvature.
    fn coarse_step(&mut self, _ready: &Self::Ready, _g: &[f64], _forcing: f64) -> Option<Vec<f64>> {
        None
    }

    /// Gives a readied matrix's storage back.
    fn recycle(&mut self, ready: Self::Ready);

    /// Conjugate-gradient iterations and their seconds so far (0 for a direct solver).
    fn krylov_work(&self) -> (usize, f64) {
        (0, 0.0)
    }

    /// Cholesky factors of the fine matrix an inexact solver fell back to, and their
    /// seconds (0 for a direct solver, whose factors are its readied matrices).
    fn fine_factorizations(&self) -> (usize, f64) {
        (0, 0.0)
    }
}

/// The plain method's solver: a sparse Cholesky factor of every matrix.
pub struct CholeskySolver(pub Factorizer);

impl StepSolver for CholeskySolver {
    type Ready = Factor;

    fn ready(&mut self, h: &BlockHessian, _key: u64, nu: f64) -> Option<Factor> {
        self.0.factor(h, nu).ok()
    }

    fn solve(&mut self, ready: &Factor, g: &[f64], _forcing: f64) -> Option<Vec<f64>> {
        Some(ready.newton_step(g))
    }

    fn recycle(&mut self, ready: Factor) {
        self.0.recycle(ready);
    }
}
