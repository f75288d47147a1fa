//! The multigrid V-cycle that preconditions the conjugate gradients of the multilevel
//! solver: Galerkin coarse matrices Pᵀ A P through the Catmull–Clark prolongations,
//! Chebyshev smoothing with the 3 × 3 block diagonal or vertex patches
//! ([`super::patch_smoother`]), a Cholesky factor at the coarsest level.
//!
//! Why Chebyshev: it needs only products with A (parallel, unlike Gauss–Seidel) and an
//! upper bound of the spectrum of M⁻¹A, and it is symmetric, so the V-cycle is a
//! symmetric positive definite preconditioner for CG.

use std::sync::Arc;

use rayon::prelude::*;

use super::block_csr::{Block, BlockCsr, Prolongation};
use super::patch_smoother::{PatchSmoother, Patches};
use super::symmetric_csr::SymmetricCsr;
use crate::fair::solvers::cholesky::{Factor, Factorizer};

/// Chebyshev steps before and after each coarse correction.
const SMOOTHING_DEGREE: usize = 3;
/// The smoother damps the part of the spectrum of D⁻¹A above λ_max / this; the rest is
/// the coarse level's. Chosen by measurement: S and Q hold third derivatives, so on a mesh
/// of half the spacing the modes the coarse level cannot hold reach down to about 1/64 of
/// the largest, yet on the 56k Catmull–Clark junction (2026-11-29) /64 took 186.0 s and
/// /10 170.6 s against 126.5 s with /20 (a wider interval damps its top less: 1/T₃ gives
/// 0.77 per degree-3 sweep against 0.48, computed, not measured).
const SMOOTHED_RANGE: f64 = 20.0;
/// Power iterations for λ_max(D⁻¹A), and the safety factor on their estimate (an
/// underestimate would amplify the top of the spectrum).
const POWER_ITERATIONS: usize = 10;
const LAMBDA_SAFETY: f64 = 1.15;
/// Power iterations for λ_max(M⁻¹A) of a patch smoother, made at every set-up (its
/// factors hold the shift) from the level's last vector, and their safety factor: with
/// 1.15 and five iterations from a fixed start the bound fell short on the refined
/// junctions, the V-cycle turned indefinite and Levenberg–Marquardt stalled (2026-11-29);
/// 1.5 times the block smoother's factor did not.
const PATCH_POWER_ITERATIONS: usize = 3;
const PATCH_LAMBDA_SAFETY: f64 = 1.5 * LAMBDA_SAFETY;

/// The matrices of every level for one Hessian, before a shift: level 0 the Hessian.
pub struct LevelMatrices {
    pub matrices: Vec<Arc<SymmetricCsr>>,
    /// Upper bounds of λ_max(D⁻¹A) per smoothed level (all but the coarsest).
    pub lambda_max: Vec<f64>,
}

/// The Galerkin image of the identity on each level (level 0: I), as slots in that
/// level's matrices: the shift ν I of the finest level is ν Mₗ on level l.
pub struct Masses {
    /// Per coarse level l ≥ 1: (slot in Aₗ, weight of I₃ there).
    slots: Vec<Vec<(usize, f64)>>,
    /// λ_max(diag(Mₗ)⁻¹ Mₗ) per level (level 0: 1).
    lambda_max: Vec<f64>,
}

impl LevelMatrices {
    /// The coarse levels of `fine` through `prolongations`, each kept by its upper
    /// triangle once the next coarser one is formed from both.
    pub fn new(fine: BlockCsr, prolongations: &[Prolongation]) -> Self {
        let mut matrices = Vec::with_capacity(prolongations.len() + 1);
        let mut full = fine;
        for p in prolongations {
            let coarse = full.galerkin(p);
            matrices.push(Arc::new(SymmetricCsr::from_full(&full)));
            full = coarse;
        }
        matrices.push(Arc::new(SymmetricCsr::from_full(&full)));
        // The coarsest level is factored, not smoothed: no bound needed there.
        let smoothed = matrices.len() - 1;
        let lambda_max = matrices[..smoothed]
            .iter()
            .map(|a| block_diagonal_bound(a))
            .collect();
        LevelMatrices {
            matrices,
            lambda_max,
        }
    }
}

impl Masses {
    /// The masses of the levels of `levels` (whose patterns they are placed in).
    /// `None` if a mass entry falls outside a level's pattern (a free vertex without a
    /// diagonal Hessian block).
    pub fn new(levels: &LevelMatrices, prolongations: &[Prolongation]) -> Option<Self> {
        let mut mass = BlockCsr::scaled_identity(levels.matrices[0].size(), 1.0);
        let mut slots = vec![Vec::new()];
        let mut lambda_max = vec![1.0];
        for (p, a) in prolongations.iter().zip(&levels.matrices[1..]) {
            mass = mass.galerkin(p);
            let mut level = Vec::with_capacity(mass.values.len());
            for row in 0..mass.size() {
                for k in mass.row_start[row]..mass.row_start[row + 1] {
                    // The upper triangle's entries: the levels keep only those.
                    if mass.columns[k] as usize >= row {
                        level.push((a.slot(row, mass.columns[k])?, mass.values[k][0][0]));
                    }
                }
            }
            slots.push(level);
            lambda_max.push(block_diagonal_bound(&SymmetricCsr::from_full(&mass)));
        }
        Some(Masses { slots, lambda_max })
    }
}

/// One level of a V-cycle for a shift ν.
struct Level {
    matrix: Arc<SymmetricCsr>,
    /// ν on the finest level (its matrix is the Hessian's, unshifted); 0 below (the
    /// shift ν Mₗ is in the matrix).
    shift: f64,
    smoother: Smoother,
    lambda_max: f64,
}

/// The preconditioner M⁻¹ inside a level's Chebyshev smoothing.
enum Smoother {
    /// The 3 × 3 block diagonal's inverses.
    BlockDiagonal(Vec<Block>),
    /// Additive Schwarz over vertex patches ([`super::patch_smoother`]).
    Patches(PatchSmoother),
}

impl Smoother {
    /// s · M⁻¹ r.
    fn apply(&self, r: &[f64], s: f64) -> Vec<f64> {
        match self {
            Smoother::BlockDiagonal(blocks) => block_diagonal_product(blocks, r, s),
            Smoother::Patches(patches) => patches.apply(r, s),
        }
    }
}

/// The V-cycle preconditioner of A + ν I.
pub struct Multigrid {
    levels: Vec<Level>,
    prolongations: Arc<[Prolongation]>,
    coarsest: Factor,
}

impl Multigrid {
    /// The V-cycle of `levels`' matrices shifted by ν, smoothed by `patches` on the levels
    /// they are given for (the first ones) and by the 3 × 3 block diagonal elsewhere;
    /// `None` when a diagonal block or the coarsest matrix is not positive definite.
    pub fn new(
        levels: &LevelMatrices,
        masses: &Masses,
        prolongations: Arc<[Prolongation]>,
        patches: &[Arc<Patches>],
        nu: f64,
        factorizer: &mut Factorizer,
    ) -> Option<Self> {
        let last = levels.matrices.len() - 1;
        let mut out = Vec::with_capacity(last + 1);
        for (l, a) in levels.matrices.iter().enumerate() {
            let (matrix, shift) = if l == 0 || nu == 0.0 {
                (Arc::clone(a), if l == 0 { nu } else { 0.0 })
            } else {
                let mut shifted = SymmetricCsr::clone(a);
                for &(slot, w) in &masses.slots[l] {
                    for d in 0..3 {
                        shifted.values[slot][d][d] += nu * w;
                    }
                }
                (Arc::new(shifted), 0.0)
            };
            if l == last {
                let coarsest = factorizer.factor(&matrix.to_upper(), shift).ok()?;
                return Some(Multigrid {
                    levels: out,
                    prolongations,
                    coarsest,
                });
            }
            // A patch matrix of an indefinite Hessian may be indefinite where its 3 × 3
            // diagonal blocks are not: that level then smooths by the blocks.
            let patch_smoother = patches
                .get(l)
                .and_then(|patches| PatchSmoother::new(&matrix, shift, Arc::clone(patches)));
            let (smoother, lambda_max) = match patch_smoother {
                Some(smoother) => {
                    let bound = patch_smoother_bound(&matrix, shift, &smoother);
                    (Smoother::Patches(smoother), bound)
                }
                None => {
                    let inverse_diagonal = matrix
                        .diagonal()
                        .into_par_iter()
                        .map(|d| inverse_spd(&d, shift))
                        .collect::<Option<Vec<_>>>()?;
                    let bound = levels.lambda_max[l].max(masses.lambda_max[l]);
                    (Smoother::BlockDiagonal(inverse_diagonal), bound)
                }
            };
            out.push(Level {
                matrix,
                shift,
                smoother,
                lambda_max,
            });
        }
        unreachable!("the loop returns at the coarsest level")
    }

    /// B⁻¹ r: one V-cycle from zero.
    pub fn apply(&self, r: &[f64]) -> Vec<f64> {
        self.cycle(0, r)
    }

    /// Level `l`'s matrix and the shift its products add (ν on the finest level, 0 below:
    /// the coarse levels hold their Galerkin image of ν I), if `l` is a smoothed level.
    pub fn level_system(&self, l: usize) -> Option<(&SymmetricCsr, f64)> {
        self.levels
            .get(l)
            .map(|level| (&*level.matrix, level.shift))
    }

    /// One V-cycle from zero for level `l`'s system (`l` = 0: the fine one; below, the
    /// preconditioner of a solve in that level's subspace).
    pub fn cycle(&self, l: usize, b: &[f64]) -> Vec<f64> {
        let Some(level) = self.levels.get(l) else {
            return self.coarsest.solve(b);
        };
        let mut x = vec![0.0; b.len()];
        level.smooth(b, &mut x, true);
        let ax = level.matrix.multiply(&x, level.shift);
        let residual: Vec<f64> = b.par_iter().zip(&ax).map(|(b, a)| b - a).collect();
        let p = &self.prolongations[l];
        let correction = self.cycle(l + 1, &p.restrict(&residual));
        p.add_prolonged(&correction, &mut x);
        level.smooth(b, &mut x, false);
        x
    }
}

impl Level {
    /// `SMOOTHING_DEGREE` Chebyshev steps for A x = b from `x` (zero if `from_zero`), on
    /// [λ_max / SMOOTHED_RANGE, λ_max] of D⁻¹A (Saad, Iterative Methods, Alg. 12.1).
    fn smooth(&self, b: &[f64], x: &mut [f64], from_zero: bool) {
        let upper = self.lambda_max;
        let lower = upper / SMOOTHED_RANGE;
        let theta = 0.5 * (upper + lower);
        let delta = 0.5 * (upper - lower);
        let mut r: Vec<f64> = if from_zero {
            b.to_vec()
        } else {
            let ax = self.matrix.multiply(x, self.shift);
            b.par_iter().zip(&ax).map(|(b, a)| b - a).collect()
        };
        let mut d = self.scaled(&r, 1.0 / theta);
        let mut rho = delta / theta;
        for k in 0..SMOOTHING_DEGREE {
            x.par_iter_mut().zip(&d).for_each(|(x, d)| *x += d);
            if k + 1 == SMOOTHING_DEGREE {
                break;
            }
            let ad = self.matrix.multiply(&d, self.shift);
            r.par_iter_mut().zip(&ad).for_each(|(r, a)| *r -= a);
            let rho_next = 1.0 / (2.0 * theta / delta - rho);
            let z = self.scaled(&r, 2.0 * rho_next / delta);
            let keep = rho_next * rho;
            d.par_iter_mut()
                .zip(&z)
                .for_each(|(d, z)| *d = keep * *d + z);
            rho = rho_next;
        }
    }

    /// s · M⁻¹ r.
    fn scaled(&self, r: &[f64], s: f64) -> Vec<f64> {
        self.smoother.apply(r, s)
    }
}

/// s · M r for the block diagonal M of 3 × 3 `blocks`.
fn block_diagonal_product(blocks: &[Block], r: &[f64], s: f64) -> Vec<f64> {
    let mut out = vec![0.0; r.len()];
    out.par_chunks_mut(3)
        .zip(blocks)
        .enumerate()
        .for_each(|(i, (out, m))| {
            for a in 0..3 {
                out[a] = s * (m[a][0] * r[3 * i] + m[a][1] * r[3 * i + 1] + m[a][2] * r[3 * i + 2]);
            }
        });
    out
}

/// (D + shift · I)⁻¹ for a symmetric 3 × 3 block, `None` unless positive definite.
fn inverse_spd(d: &Block, shift: f64) -> Option<Block> {
    let m: Block = std::array::from_fn(|a| {
        std::array::from_fn(|b| d[a][b] + if a == b { shift } else { 0.0 })
    });
    // Positive definite iff the leading minors are positive (Sylvester).
    let minor2 = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let cofactor: Block = std::array::from_fn(|a| {
        std::array::from_fn(|b| {
            let (r0, r1) = ((b + 1) % 3, (b + 2) % 3);
            let (c0, c1) = ((a + 1) % 3, (a + 2) % 3);
            m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]
        })
    });
    let det = m[0][0] * cofactor[0][0] + m[0][1] * cofactor[1][0] + m[0][2] * cofactor[2][0];
    if !(m[0][0] > 0.0 && minor2 > 0.0 && det > 0.0 && det.is_finite()) {
        return None;
    }
    Some(std::array::from_fn(|a| {
        std::array::from_fn(|b| cofactor[a][b] / det)
    }))
}

/// An estimate of λ_max(D⁻¹A) (D the block diagonal) from above: the largest ‖D⁻¹A x‖ over
/// power iterations from a fixed unit start, times a safety factor (a norm, so that an
/// indefinite A still gets a finite bound; its V-cycle then fails in CG, as it should).
/// Infinite when a diagonal block is not positive definite.
fn block_diagonal_bound(a: &SymmetricCsr) -> f64 {
    let inverse: Option<Vec<Block>> = a.diagonal().iter().map(|d| inverse_spd(d, 0.0)).collect();
    let Some(inverse) = inverse else {
        return f64::INFINITY;
    };
    let m_inverse = |r: &[f64]| block_diagonal_product(&inverse, r, 1.0);
    LAMBDA_SAFETY * power_iterations(a, 0.0, &m_inverse, POWER_ITERATIONS, None).0
}

/// The bound of λ_max(M⁻¹(A + shift·I)) for a patch smoother: its power iterations from
/// the level's last vector (the matrices of one run differ little), never under the most
/// patches a vertex lies in (λ_max where A is block diagonal).
fn patch_smoother_bound(a: &SymmetricCsr, shift: f64, smoother: &PatchSmoother) -> f64 {
    let patches = &smoother.patches;
    let start = patches.power_start.lock().ok().and_then(|mut s| s.take());
    let (estimate, last) = power_iterations(
        a,
        shift,
        &|r: &[f64]| smoother.apply(r, 1.0),
        PATCH_POWER_ITERATIONS,
        start,
    );
    if let Ok(mut kept) = patches.power_start.lock() {
        *kept = Some(last);
    }
    (PATCH_LAMBDA_SAFETY * estimate).max(LAMBDA_SAFETY * patches.most_overlapping() as f64)
}

/// The largest ‖M⁻¹(A + shift·I) x‖ over power iterations on unit vectors x from `start`
/// (a fixed vector if `None`): a lower estimate of λ_max(M⁻¹(A + shift·I)) that converges
/// to it; at least 1. With the last iterate.
fn power_iterations(
    a: &SymmetricCsr,
    shift: f64,
    m_inverse: &dyn Fn(&[f64]) -> Vec<f64>,
    iterations: usize,
    start: Option<Vec<f64>>,
) -> (f64, Vec<f64>) {
    let n = 3 * a.size();
    let mut x: Vec<f64> = start.filter(|x| x.len() == n).unwrap_or_else(|| {
        (0..n)
            .map(|k| 1.0 + ((k * 7919) % 101) as f64 / 101.0)
            .collect()
    });
    let mut estimate: f64 = 1.0;
    for _ in 0..iterations {
        let norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
        if !(norm > 0.0 && norm.is_finite()) {
            break;
        }
        x.iter_mut().for_each(|v| *v /= norm);
        let y = m_inverse(&a.multiply(&x, shift));
        estimate = estimate.max(y.iter().map(|v| v * v).sum::<f64>().sqrt());
        x = y;
    }
    (estimate, x)
}
