//! The additive Schwarz preconditioner of the block method (paper §5):
//! B⁻¹ = Σ_b P_bᵀ [A_b⁻¹ 0; 0 0] P_b, with A_b = P_b R_b H R_bᵀ P_bᵀ the principal
//! submatrix of the Hessian over the unknowns of block b, each factored by the sparse
//! Cholesky of the plain method (fill-reducing ordering in place of the paper's "narrow
//! band"). With blocks covering all unknowns and every A_b positive definite, B⁻¹ is
//! symmetric positive definite, as CG needs.

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::fair::functional::evaluation::BlockHessian;
use crate::fair::solvers::cholesky::{Factor, Factorizer};

struct Part {
    /// Free indices of the block's vertices, sorted.
    vertices: Vec<u32>,
    factorizer: Factorizer,
    factor: Option<Factor>,
}

/// The factored blocks of B⁻¹.
pub struct Schwarz {
    free_count: usize,
    parts: Vec<Part>,
}

impl Schwarz {
    /// A preconditioner over `free_count` free vertices with blocks of free indices.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for an empty block, an index out of range, or a free
    /// vertex in no block (B would be singular).
    pub fn new(free_count: usize, blocks: Vec<Vec<u32>>) -> Result<Self> {
        let mut covered = vec![false; free_count];
        let mut parts = Vec::with_capacity(blocks.len());
        for (b, mut vertices) in blocks.into_iter().enumerate() {
            vertices.sort_unstable();
            vertices.dedup();
            if vertices.is_empty() {
                return Err(Error::InvalidInput(format!("block {b} is empty")));
            }
            for &i in &vertices {
                let slot = covered.get_mut(i as usize).ok_or_else(|| {
                    Error::InvalidInput(format!(
                        "block {b} has free index {i} of only {free_count}"
                    ))
                })?;
                *slot = true;
            }
            parts.push(Part {
                factorizer: Factorizer::new(vertices.len()),
                vertices,
                factor: None,
            });
        }
        if let Some(i) = covered.iter().position(|&c| !c) {
            return Err(Error::InvalidInput(format!(
                "free vertex (free index {i}) is in no block"
            )));
        }
        Ok(Schwarz { free_count, parts })
    }

    /// Number of blocks.
    pub fn len(&self) -> usize {
        self.parts.len()
    }

    /// Whether there are no blocks.
    pub fn is_empty(&self) -> bool {
        self.parts.is_empty()
    }

    /// Extracts and factors every A_b + ν I of `h` (blocks in parallel).
    ///
    /// # Errors
    /// [`Error::Solver`] (not positive definite) when some A_b is not positive definite:
    /// the caller goes back to block iterations.
    pub fn factor(&mut self, h: &BlockHessian, nu: f64) -> Result<()> {
        let free_count = self.free_count;
        self.parts.par_iter_mut().try_for_each(|part| {
            part.factor = None;
            let mut local = vec![u32::MAX; free_count];
            for (k, &i) in part.vertices.iter().enumerate() {
                local[i as usize] = k as u32;
            }
            let mut sub = BlockHessian {
                blocks: Vec::new(),
                values: Vec::new(),
            };
            for (&(i, j), v) in h.blocks.iter().zip(&h.values) {
                let (li, lj) = (local[i as usize], local[j as usize]);
                if li != u32::MAX && lj != u32::MAX {
                    // Local indices keep the order of free indices: li ≤ lj.
                    sub.blocks.push((li, lj));
                    sub.values.push(*v);
                }
            }
            if let Some(old) = part.factor.take() {
                part.factorizer.recycle(old);
            }
            part.factor = Some(part.factorizer.factor(&sub, nu)?);
            Ok(())
        })
    }

    /// B⁻¹ r (blocks in parallel).
    ///
    /// # Panics
    /// Never: an unfactored block (after a failed [`Schwarz::factor`]) contributes nothing.
    pub fn apply(&self, r: &[f64]) -> Vec<f64> {
        let pieces: Vec<(&[u32], Vec<f64>)> = self
            .parts
            .par_iter()
            .filter_map(|part| {
                let factor = part.factor.as_ref()?;
                let block: Vec<f64> = part
                    .vertices
                    .iter()
                    .flat_map(|&i| (0..3).map(move |a| r[3 * i as usize + a]))
                    .collect();
                Some((part.vertices.as_slice(), factor.solve(&block)))
            })
            .collect();
        let mut z = vec![0.0; r.len()];
        for (vertices, x) in pieces {
            for (k, &i) in vertices.iter().enumerate() {
                for a in 0..3 {
                    z[3 * i as usize + a] += x[3 * k + a];
                }
            }
        }
        z
    }

    /// Sum of the block sizes over the number of free vertices (1: no overlap).
    pub fn coverage(&self) -> f64 {
        self.parts.iter().map(|p| p.vertices.len()).sum::<usize>() as f64
            / self.free_count.max(1) as f64
    }
}
