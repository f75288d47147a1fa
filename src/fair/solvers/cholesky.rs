//! Sparse Cholesky factorization of the Hessian (paper §5: "renumbering of variables …
//! decomposed using the Cholesky method"): faer's supernodal/simplicial LLᵀ with its
//! approximate-minimum-degree fill-reducing ordering. The symbolic analysis is done once
//! per sparsity pattern; the factor's storage and faer's workspace are kept and reused by
//! every numeric factorization, because a Levenberg–Marquardt search factors H + νI many
//! times and fresh buffers of hundreds of megabytes are paid for in page faults
//! (measured in an earlier session at 14399 vertices: 154 factorizations took 92 s with
//! fresh buffers, 68 s reusing them). A nested-dissection ordering (METIS) was measured
//! then too: 17 % less fill than AMD on these meshes but no faster, so AMD stays.

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};
use faer::{Conj, Mat, Side};

use crate::error::{Error, Result, SolverFailure};
use crate::fair::functional::evaluation::BlockHessian;

/// The symbolic analysis of a block Hessian's pattern (upper triangle) and the buffers
/// its numeric factorizations reuse.
pub struct Factorizer {
    n: usize,
    symbolic: Option<Arc<SymbolicCholesky<usize>>>,
    /// The compressed-column pattern and the order of the entries in it, computed for the
    /// first Hessian: every later one has the same blocks, so its values are placed
    /// without sorting again.
    pattern: Option<(SymbolicSparseColMat<usize>, Argsort<usize>)>,
    /// faer's workspace for a numeric factorization.
    scratch: Option<MemBuffer>,
    /// Factor storage given back by [`Factorizer::recycle`].
    spare: Option<Vec<f64>>,
}

/// A numeric factor of H + νI.
pub struct Factor {
    symbolic: Arc<SymbolicCholesky<usize>>,
    values: Vec<f64>,
}

impl Factorizer {
    /// A factorizer for `free_count` free vertices (3 unknowns each).
    pub fn new(free_count: usize) -> Self {
        Factorizer {
            n: 3 * free_count,
            symbolic: None,
            pattern: None,
            scratch: None,
            spare: None,
        }
    }

    /// Factors `H + ν I`.
    ///
    /// # Errors
    /// [`Error::Solver`] with [`SolverFailure::NotPositiveDefinite`] when a pivot is not
    /// positive; [`SolverFailure::Singular`] when faer fails otherwise (out of memory).
    pub fn factor(&mut self, h: &BlockHessian, nu: f64) -> Result<Factor> {
        let matrix = self.assemble(h, nu)?;
        let symbolic = match &self.symbolic {
            Some(s) => Arc::clone(s),
            None => {
                let s = factorize_symbolic_cholesky(
                    matrix.symbolic(),
                    Side::Upper,
                    Default::default(),
                    Default::default(),
                )
                .map_err(|e| failed("symbolic Cholesky", &e))?;
                let s = Arc::new(s);
                self.symbolic = Some(Arc::clone(&s));
                s
            }
        };
        let par = faer::get_global_parallelism();
        let mut scratch = match self.scratch.take() {
            Some(buffer) => buffer,
            None => MemBuffer::try_new(
                symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
            )
            .map_err(|e| failed("Cholesky workspace", &e))?,
        };
        let mut values = match self.spare.take() {
            Some(v) => v,
            None => {
                let mut v = Vec::new();
                v.try_reserve_exact(symbolic.len_val())
                    .map_err(|e| failed("Cholesky factor storage", &e))?;
                v.resize(symbolic.len_val(), 0.0);
                v
            }
        };
        // The supernodal factorization clears its storage itself; the simplicial one
        // relies on starting from zeros.
        if matches!(symbolic.raw(), SymbolicCholeskyRaw::Simplicial(_)) {
            values.fill(0.0);
        }
        let outcome = symbolic.factorize_numeric_llt(
            &mut values,
            matrix.as_ref(),
            Side::Upper,
            Default::default(),
            par,
            MemStack::new(&mut scratch),
            Default::default(),
        );
        self.scratch = Some(scratch);
        match outcome {
            Ok(_) => Ok(Factor { symbolic, values }),
            Err(e) => {
                self.spare = Some(values);
                Err(Error::Solver {
                    failure: SolverFailure::NotPositiveDefinite,
                    detail: format!("Cholesky of the Hessian + {nu:e} I: {e:?}"),
                })
            }
        }
    }

    /// Gives a factor's storage back for the next factorization.
    pub fn recycle(&mut self, factor: Factor) {
        self.spare = Some(factor.values);
    }

    /// The upper triangle of `H + ν I` in compressed columns.
    fn assemble(&mut self, h: &BlockHessian, nu: f64) -> Result<SparseColMat<usize, f64>> {
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
                    .map_err(|e| failed("assembling the Hessian", &e))?,
            );
        }
        let (pattern, order) = self.pattern.as_ref().expect("just set");
        SparseColMat::new_from_argsort(pattern.clone(), order, &values)
            .map_err(|e| failed("assembling the Hessian", &e))
    }
}

/// A failure of faer other than a non-positive pivot (out of memory, a malformed pattern).
fn failed(what: &str, e: &dyn std::fmt::Debug) -> Error {
    Error::Solver {
        failure: SolverFailure::Singular,
        detail: format!("{what}: {e:?}"),
    }
}

impl Factor {
    /// Solves `(H + ν I) δ = −g` (eq. 7 and 9).
    pub fn newton_step(&self, g: &[f64]) -> Vec<f64> {
        self.solve_scaled(g, -1.0)
    }

    /// `(H + ν I)⁻¹ b`: the factor as a preconditioner or a block solve.
    pub fn solve(&self, b: &[f64]) -> Vec<f64> {
        self.solve_scaled(b, 1.0)
    }

    /// `(H + ν I)⁻¹ (sign · b)`.
    fn solve_scaled(&self, b: &[f64], sign: f64) -> Vec<f64> {
        let mut rhs = Mat::from_fn(b.len(), 1, |i, _| sign * b[i]);
        let par = faer::get_global_parallelism();
        let mut scratch = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(1, par));
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            rhs.as_mut(),
            par,
            MemStack::new(&mut scratch),
        );
        (0..b.len()).map(|i| rhs[(i, 0)]).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A block tridiagonal Hessian over `n` vertices: diagonal blocks `d·I + e·E` (E all
    /// ones), off-diagonal blocks `o·I` between neighbours.
    fn chain(n: u32, d: f64, e: f64, o: f64) -> BlockHessian {
        let mut blocks = Vec::new();
        let mut values = Vec::new();
        for i in 0..n {
            blocks.push((i, i));
            values.push(std::array::from_fn(|a| {
                std::array::from_fn(|b| e + if a == b { d } else { 0.0 })
            }));
            if i + 1 < n {
                blocks.push((i, i + 1));
                values.push(std::array::from_fn(|a| {
                    std::array::from_fn(|b| if a == b { o } else { 0.0 })
                }));
            }
        }
        BlockHessian { blocks, values }
    }

    /// (H + νI) x for the full symmetric matrix of `h`.
    fn apply(h: &BlockHessian, nu: f64, x: &[f64]) -> Vec<f64> {
        let mut y: Vec<f64> = x.iter().map(|v| nu * v).collect();
        for (&(i, j), v) in h.blocks.iter().zip(&h.values) {
            let (i, j) = (3 * i as usize, 3 * j as usize);
            for a in 0..3 {
                for b in 0..3 {
                    y[i + a] += v[a][b] * x[j + b];
                    if i != j {
                        y[j + b] += v[a][b] * x[i + a];
                    }
                }
            }
        }
        y
    }

    fn residual(h: &BlockHessian, nu: f64, factor: &Factor, g: &[f64]) -> f64 {
        let x = factor.newton_step(g);
        apply(h, nu, &x)
            .iter()
            .zip(g)
            .map(|(y, g)| (y + g).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn reused_storage_gives_each_matrix_its_own_factor() {
        let n = 40;
        let g: Vec<f64> = (0..3 * n).map(|k| (k as f64 * 0.37).sin()).collect();
        let first = chain(n as u32, 4.0, 0.5, -1.0);
        let second = chain(n as u32, 9.0, -0.25, 2.0);
        // Indefinite: diagonal −1 with unit coupling.
        let indefinite = chain(n as u32, -1.0, 0.0, 1.0);
        let mut factorizer = Factorizer::new(n);
        let f1 = factorizer.factor(&first, 0.0).expect("positive definite");
        assert!(residual(&first, 0.0, &f1, &g) < 1e-12);
        factorizer.recycle(f1);
        let refused = factorizer.factor(&indefinite, 0.0);
        assert!(matches!(
            refused,
            Err(Error::Solver {
                failure: SolverFailure::NotPositiveDefinite,
                ..
            })
        ));
        // The storage the refused factorization wrote into serves the next one.
        let f2 = factorizer.factor(&second, 0.5).expect("positive definite");
        assert!(residual(&second, 0.5, &f2, &g) < 1e-12);
        // A kept factor is not disturbed by later factorizations.
        let f3 = factorizer
            .factor(&indefinite, 4.0)
            .expect("shifted: definite");
        assert!(residual(&second, 0.5, &f2, &g) < 1e-12);
        assert!(residual(&indefinite, 4.0, &f3, &g) < 1e-12);
    }
}
