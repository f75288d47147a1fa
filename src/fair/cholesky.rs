//! Sparse Cholesky factorization of the Hessian (paper §5: "renumbering of variables …
//! decomposed using the Cholesky method"): faer's supernodal/simplicial LLᵀ with its
//! approximate-minimum-degree fill-reducing ordering; the symbolic analysis is done once
//! per sparsity pattern and reused by every numeric factorization.

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};
use faer::{Mat, Side};

use crate::error::{Error, Result, SolverFailure};
use crate::fair::functional::BlockHessian;

/// The symbolic analysis of a block Hessian's pattern (upper triangle).
pub struct Factorizer {
    n: usize,
    symbolic: Option<SymbolicLlt<usize>>,
    /// The compressed-column pattern and the order of the entries in it, computed for the
    /// first Hessian: every later one has the same blocks, so its values are placed
    /// without sorting again.
    pattern: Option<(SymbolicSparseColMat<usize>, Argsort<usize>)>,
}

/// A numeric factor of H + νI.
pub struct Factor {
    llt: Llt<usize, f64>,
}

impl Factorizer {
    /// A factorizer for `free_count` free vertices (3 unknowns each).
    pub fn new(free_count: usize) -> Self {
        Factorizer {
            n: 3 * free_count,
            symbolic: None,
            pattern: None,
        }
    }

    /// Factors `H + ν I`.
    ///
    /// # Errors
    /// [`Error::Solver`] with [`SolverFailure::NotPositiveDefinite`] when a pivot is not
    /// positive; [`SolverFailure::Singular`] when faer fails otherwise (out of memory).
    pub fn factor(&mut self, h: &BlockHessian, nu: f64) -> Result<Factor> {
        let failed = |e: &dyn std::fmt::Debug| Error::Solver {
            failure: SolverFailure::Singular,
            detail: format!("assembling the Hessian: {e:?}"),
        };
        let mut values = Vec::with_capacity(9 * h.blocks.len() + self.n);
        for (&(i, j), v) in h.blocks.iter().zip(&h.values) {
            for (a, row) in v.iter().enumerate() {
                for (b, &x) in row.iter().enumerate() {
                    if i != j || a <= b {
                        values.push(x);
                    }
                }
            }
        }
        // The diagonal is always in the pattern, so that every ν shares one analysis.
        values.extend(std::iter::repeat_n(nu, self.n));
        if self.pattern.is_none() {
            let mut indices = Vec::with_capacity(values.len());
            for &(i, j) in &h.blocks {
                let (i, j) = (3 * i as usize, 3 * j as usize);
                for a in 0..3 {
                    for b in 0..3 {
                        // The upper triangle only (same order as `values`).
                        if i != j || a <= b {
                            indices.push(Pair::new(i + a, j + b));
                        }
                    }
                }
            }
            indices.extend((0..self.n).map(|k| Pair::new(k, k)));
            self.pattern = Some(
                SymbolicSparseColMat::try_new_from_indices(self.n, self.n, &indices)
                    .map_err(|e| failed(&e))?,
            );
        }
        let (pattern, order) = self.pattern.as_ref().expect("just set");
        let matrix = SparseColMat::new_from_argsort(pattern.clone(), order, &values)
            .map_err(|e| failed(&e))?;
        let symbolic = match &self.symbolic {
            Some(s) => s.clone(),
            None => {
                let s = SymbolicLlt::try_new(matrix.symbolic(), Side::Upper).map_err(|e| {
                    Error::Solver {
                        failure: SolverFailure::Singular,
                        detail: format!("symbolic Cholesky: {e:?}"),
                    }
                })?;
                self.symbolic = Some(s.clone());
                s
            }
        };
        let llt =
            Llt::try_new_with_symbolic(symbolic, matrix.as_ref(), Side::Upper).map_err(|e| {
                Error::Solver {
                    failure: match e {
                        faer::sparse::linalg::LltError::Numeric(_) => {
                            SolverFailure::NotPositiveDefinite
                        }
                        _ => SolverFailure::Singular,
                    },
                    detail: format!("Cholesky of the Hessian + {nu:e} I: {e:?}"),
                }
            })?;
        Ok(Factor { llt })
    }
}

impl Factor {
    /// Solves `(H + ν I) δ = −g` (eq. 7 and 9).
    pub fn newton_step(&self, g: &[f64]) -> Vec<f64> {
        let mut rhs = Mat::from_fn(g.len(), 1, |i, _| -g[i]);
        self.llt.solve_in_place(rhs.as_mut());
        (0..g.len()).map(|i| rhs[(i, 0)]).collect()
    }
}
