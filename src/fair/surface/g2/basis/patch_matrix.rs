//! The special element's basis, computed once per valence: the fixed linear map from the
//! Sabin net (indexed as the domain net, 1 + 12k values, the radius-2 ones used) to the k
//! patches' 10 × 10 Bézier coefficients.
//!
//! Ritz (Kiciak's construction; the notes' "A·a = −B·b"): for each net vertex, the
//! function of V ([`super::space`]) with that vertex's ring data (1 there, 0 elsewhere) of
//! least triharmonic energy ∫_Ω ‖∇Δf‖² in Ω_k's coordinates — through δ_s with the inverse
//! chain rule and weight |det Dδ_s|, by composite 2-point Gauss–Legendre on 8 intervals per
//! direction (16 × 16 nodes per patch, as the author's optimizer). Functions linear in
//! Ω_k's coordinates have zero energy, so the basis reproduces them (linear precision)
//! and sums to one.

use std::sync::{Arc, OnceLock};

use faer::Mat;

use super::bernstein::{bernstein_derivatives, COEFFICIENTS, ORDER};
use super::disk_cache;
use super::domain_derivatives::{InverseChainRule, MapDerivatives};
use super::domain_net::DomainNet;
use super::junction::{sector_domain, SectorDomain};
use super::space::{unknowns, Conditions};
use crate::error::{Error, Result};
use crate::fair::surface::representation::DERIVATIVE_ORDERS;
use crate::linalg::constrained::minimizers_with_equalities;

/// Largest valence with a special element.
pub const MAX_SPECIAL_VALENCE: usize = 16;

/// Intervals per direction of the composite energy rule (2 Gauss nodes each).
const ENERGY_INTERVALS: usize = 8;

/// The basis of valence k's special element.
#[derive(Debug, Clone)]
pub struct PatchMatrix {
    pub k: usize,
    /// The domain patches δ_s and the junction functions, per sector.
    pub sectors: Vec<SectorDomain>,
    /// (k·100) × (1 + 12k): patch coefficients from net values.
    pub matrix: Mat<f64>,
    /// Dimension of V with the ring data zero (Kiciak's extended space: n′ + 16k).
    pub inner_dimension: usize,
}

/// Composite 2-point Gauss–Legendre rule on `intervals` equal intervals of [0, 1].
pub fn composite_gauss(intervals: usize) -> Vec<(f64, f64)> {
    let h = 1.0 / intervals as f64;
    let d = 0.5 / 3f64.sqrt();
    (0..intervals)
        .flat_map(|i| {
            let m = (i as f64 + 0.5) * h;
            [(m - d * h, 0.5 * h), (m + d * h, 0.5 * h)]
        })
        .collect()
}

/// Derivatives of orders 0–3 of a degree-(9, 9) patch with coefficients `c` at (u, v):
/// value then the nine of [`DERIVATIVE_ORDERS`].
pub fn patch_derivatives(c: &[f64], u: f64, v: f64) -> [f64; 10] {
    let (bu, bv) = (bernstein_derivatives(u), bernstein_derivatives(v));
    let mut out = [0.0; 10];
    for a in 0..ORDER {
        for b in 0..ORDER {
            let x = c[ORDER * a + b];
            if x == 0.0 {
                continue;
            }
            out[0] += bu[0][a] * bv[0][b] * x;
            for (o, (ru, rv)) in DERIVATIVE_ORDERS.iter().enumerate() {
                out[o + 1] += bu[*ru][a] * bv[*rv][b] * x;
            }
        }
    }
    out
}

/// δ_s's derivatives (orders 1–3) at (u, v).
pub fn map_derivatives(domain: &SectorDomain, u: f64, v: f64) -> MapDerivatives {
    let (x, y) = (
        patch_derivatives(&domain.patch[0], u, v),
        patch_derivatives(&domain.patch[1], u, v),
    );
    std::array::from_fn(|o| [x[o + 1], y[o + 1]])
}

/// The triharmonic energy matrix of the k patches (the auxiliary unknowns get none).
fn triharmonic(k: usize, sectors: &[SectorDomain]) -> Result<Mat<f64>> {
    let n = unknowns(k);
    let mut e = Mat::<f64>::zeros(n, n);
    let rule = composite_gauss(ENERGY_INTERVALS);
    for (s, domain) in sectors.iter().enumerate() {
        for &(u, wu) in &rule {
            for &(v, wv) in &rule {
                let chain =
                    InverseChainRule::new(map_derivatives(domain, u, v)).ok_or_else(|| {
                        Error::InvalidInput(format!(
                            "special element of valence {k}: domain patch {s} is singular \
                             at ({u}, {v})"
                        ))
                    })?;
                let (bu, bv) = (bernstein_derivatives(u), bernstein_derivatives(v));
                let mut gx = [0.0; COEFFICIENTS];
                let mut gy = [0.0; COEFFICIENTS];
                for a in 0..ORDER {
                    for b in 0..ORDER {
                        let p = DERIVATIVE_ORDERS.map(|(ru, rv)| bu[ru][a] * bv[rv][b]);
                        let f = chain.apply(&p);
                        // ∇Δf = (f_xxx + f_xyy, f_xxy + f_yyy)
                        gx[ORDER * a + b] = f[5] + f[7];
                        gy[ORDER * a + b] = f[6] + f[8];
                    }
                }
                let w = wu * wv * chain.jacobian;
                let at = s * COEFFICIENTS;
                for i in 0..COEFFICIENTS {
                    let (xi, yi) = (w * gx[i], w * gy[i]);
                    for j in 0..COEFFICIENTS {
                        e[(at + i, at + j)] += xi * gx[j] + yi * gy[j];
                    }
                }
            }
        }
    }
    Ok(e)
}

impl PatchMatrix {
    /// Computes valence k's basis (3 ≤ k ≤ 16; 4 gives the regular case, a check), on one
    /// thread: faer splits its dense factorizations by the pool's size, and the basis must
    /// not depend on it (the optimum would differ in its last bits from one machine, or
    /// RAYON_NUM_THREADS, to another; tested).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for another k, or if a solve fails (it does not for these
    /// valences: tested).
    pub fn compute(k: usize) -> Result<PatchMatrix> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .map_err(|e| Error::InvalidInput(format!("a thread for the G² basis: {e}")))?;
        pool.install(|| Self::compute_here(k))
    }

    /// [`PatchMatrix::compute`] on the current thread pool.
    fn compute_here(k: usize) -> Result<PatchMatrix> {
        if !(3..=MAX_SPECIAL_VALENCE).contains(&k) {
            return Err(Error::InvalidInput(format!(
                "special elements have valence 3 to {MAX_SPECIAL_VALENCE}, not {k}"
            )));
        }
        let net = DomainNet::new(k);
        // The domain net is k-fold rotationally symmetric: sector s is sector 0 turned by
        // 2πs/k, with the same junction functions.
        let first = sector_domain(&net, 0)?;
        let sectors: Vec<SectorDomain> = (0..k).map(|s| first.rotated(s, k)).collect();
        let conditions = Conditions::new(k, &sectors);
        let energy = triharmonic(k, &sectors)?;
        let n = unknowns(k);
        let (solution, rank) = minimizers_with_equalities(&energy, &conditions.c, &conditions.data)
            .map_err(|e| {
                Error::InvalidInput(format!("special element of valence {k}: basis: {e}"))
            })?;
        let matrix = solution.subrows(0, k * COEFFICIENTS).to_owned();
        Ok(PatchMatrix {
            k,
            sectors,
            matrix,
            inner_dimension: n - rank,
        })
    }

    /// Valence k's basis, shared by the whole process: read from the disk cache
    /// ([`disk_cache`]) or else computed on first use (and stored there).
    ///
    /// # Errors
    /// As [`PatchMatrix::compute`].
    pub fn cached(k: usize) -> Result<Arc<PatchMatrix>> {
        static CACHE: [OnceLock<Arc<PatchMatrix>>; MAX_SPECIAL_VALENCE + 1] =
            [const { OnceLock::new() }; MAX_SPECIAL_VALENCE + 1];
        let slot = CACHE.get(k).ok_or_else(|| {
            Error::InvalidInput(format!(
                "special elements have valence 3 to {MAX_SPECIAL_VALENCE}, not {k}"
            ))
        })?;
        if let Some(m) = slot.get() {
            return Ok(m.clone());
        }
        let dir = disk_cache::default_dir();
        let basis = match dir.as_deref().and_then(|d| disk_cache::load(d, k)) {
            Some(stored) => stored,
            None => {
                let computed = PatchMatrix::compute(k)?;
                if let Some(dir) = &dir {
                    // Only an optimization: a read-only or full disk costs the next run
                    // the computation, nothing else.
                    let _ = disk_cache::store(dir, &computed);
                }
                computed
            }
        };
        let basis = Arc::new(basis);
        Ok(slot.get_or_init(|| basis).clone())
    }
}
