//! Discrete smoothing variational splines with parallelism conditions (2004 paper §4):
//! minimize J(y) = Σ_{a∈A} ‖y(a) − pₐ‖² + τ Π(y, y) + ε|y|²ₘ (4.3) over V_h = (X_h)³, with
//! Π(y, z) = Σ_{b∈B} Σ_{i=1,2} ⟨Dᵢy(b), N(b)⟩⟨Dᵢz(b), N(b)⟩ measuring how far the tangent
//! planes of y are from those of the reference surface x₀ (unit normals N). Π couples the
//! three coordinates, so the system M α = b of §4 has order 3·dim X_h (1323 for BFS C² on
//! 6 × 6 cells).

use crate::error::{Error, Result};
use crate::linalg::solve_spd;
use crate::spline::{seminorm_gram, Space, SparseSym};

use super::surface::VectorSpline;

/// Options of [`parallel_fit`].
#[derive(Debug, Clone, Copy)]
pub struct ParallelOptions {
    /// ε > 0.
    pub epsilon: f64,
    /// τ ≥ 0 (τ = 0 is the plain discrete smoothing Dᵐ-spline, Remark 4.2).
    pub tau: f64,
    /// The semi-norm order m (3 in the paper, with BFS C²).
    pub m: usize,
}

/// The solved spline and its report.
#[derive(Debug, Clone)]
pub struct ParallelFit {
    /// s_ετ.
    pub spline: VectorSpline,
    /// Order of the linear system (3 · dim X_h).
    pub system_dimension: usize,
    /// Π(s, s) / |B|: mean squared normal component of the tangent vectors.
    pub pi_per_point: f64,
    /// Σ_{a∈A} ‖s(a) − pₐ‖².
    pub data_misfit: f64,
}

/// Solves (4.6) of the 2004 paper, M α = b with
/// m_ij = Σₐ⟨vᵢ(a), vⱼ(a)⟩ + τΠ(vᵢ, vⱼ) + ε(vᵢ, vⱼ)ₘ and bᵢ = Σₐ⟨pₐ, vᵢ(a)⟩, by sparse
/// Cholesky. The unknown of (basis k, coordinate ℓ) has index 3k + ℓ (the paper's vⱼ).
///
/// Preconditions (`InvalidInput` otherwise): ε > 0 and τ ≥ 0 finite; 1 ≤ m ≤ degree;
/// finite data; `values` aligned with `a_points`, `normals` with `b_points`; all points in
/// the rectangle; A unisolvent for ℙ_{m−1} (3.2) — checked through the factorization, a
/// failure is `Solver { NotPositiveDefinite }`.
pub fn parallel_fit(
    space: &dyn Space,
    a_points: &[[f64; 2]],
    values: &[[f64; 3]],
    b_points: &[[f64; 2]],
    normals: &[[f64; 3]],
    opts: &ParallelOptions,
) -> Result<ParallelFit> {
    if !(opts.epsilon > 0.0 && opts.epsilon.is_finite() && opts.tau >= 0.0 && opts.tau.is_finite())
    {
        return Err(Error::InvalidInput(format!(
            "need ε > 0 and τ ≥ 0, finite; got ε = {}, τ = {}",
            opts.epsilon, opts.tau
        )));
    }
    if opts.m == 0 || opts.m > space.degree() {
        return Err(Error::InvalidInput(format!(
            "semi-norm order m = {} out of range",
            opts.m
        )));
    }
    if a_points.len() != values.len() || b_points.len() != normals.len() {
        return Err(Error::InvalidInput(format!(
            "{} points A with {} values, {} points B with {} normals",
            a_points.len(),
            values.len(),
            b_points.len(),
            normals.len()
        )));
    }
    if a_points
        .iter()
        .flatten()
        .chain(values.iter().flatten())
        .chain(b_points.iter().flatten())
        .chain(normals.iter().flatten())
        .any(|x| !x.is_finite())
    {
        return Err(Error::InvalidInput(
            "parallel fit: a datum is not finite".into(),
        ));
    }
    let n = 3 * space.dim();
    let mut sys = SparseSym::new(n);
    let mut rhs = vec![0.0; n];
    for (p, v) in a_points.iter().zip(values) {
        let lb = space.eval(p[0], p[1], 0)?;
        for (l, &k) in lb.indices.iter().enumerate() {
            let dl = lb.d(l, 0, 0);
            for c in 0..3 {
                rhs[3 * k + c] += dl * v[c];
            }
            for (q, &kq) in lb.indices.iter().enumerate() {
                for c in 0..3 {
                    sys.add(3 * k + c, 3 * kq + c, dl * lb.d(q, 0, 0));
                }
            }
        }
    }
    // Π: for each b and i, the row r = (Dᵢφ_k N_ℓ)_{k,ℓ} contributes τ rᵀr; rows are
    // accumulated per cell in a dense local block, then scattered once.
    if opts.tau > 0.0 {
        let g = space.grid();
        let mut blocks: Vec<Option<(Vec<usize>, Vec<f64>)>> = vec![None; g.cell_count()];
        for (p, nb) in b_points.iter().zip(normals) {
            let lb = space.eval(p[0], p[1], 1)?;
            let nl = 3 * lb.indices.len();
            let block = blocks[g.cell_index(lb.cell)]
                .get_or_insert_with(|| (lb.indices.clone(), vec![0.0; nl * nl]));
            for (da, db) in [(1, 0), (0, 1)] {
                let mut row = Vec::with_capacity(nl);
                for l in 0..lb.indices.len() {
                    let d = lb.d(l, da, db);
                    row.extend((0..3).map(|c| d * nb[c]));
                }
                for (i, &x) in row.iter().enumerate() {
                    for (j, &y) in row.iter().enumerate() {
                        block.1[i * nl + j] += opts.tau * x * y;
                    }
                }
            }
        }
        for (idx, m) in blocks.into_iter().flatten() {
            let nl = 3 * idx.len();
            for i in 0..nl {
                for j in 0..nl {
                    let v = m[i * nl + j];
                    if v != 0.0 {
                        sys.add(3 * idx[i / 3] + i % 3, 3 * idx[j / 3] + j % 3, v);
                    }
                }
            }
        }
    }
    let gram = seminorm_gram(space, opts.m, &space.grid().cells().collect::<Vec<_>>())?;
    for (i, j, v) in gram.triplets() {
        for c in 0..3 {
            sys.add(3 * i + c, 3 * j + c, opts.epsilon * v);
        }
    }
    let sol = solve_spd(n, &sys.triplets(), &[rhs])?;
    let mut spline = VectorSpline::zeros(space.dim());
    for k in 0..space.dim() {
        for c in 0..3 {
            spline.coeffs[c][k] = sol[0][3 * k + c];
        }
    }
    let mut pi = 0.0;
    for (p, nb) in b_points.iter().zip(normals) {
        for (da, db) in [(1, 0), (0, 1)] {
            let d = spline.eval(space, p[0], p[1], da, db)?;
            pi += (d[0] * nb[0] + d[1] * nb[1] + d[2] * nb[2]).powi(2);
        }
    }
    let mut misfit = 0.0;
    for (p, v) in a_points.iter().zip(values) {
        let s = spline.eval(space, p[0], p[1], 0, 0)?;
        misfit += (0..3).map(|c| (s[c] - v[c]).powi(2)).sum::<f64>();
    }
    Ok(ParallelFit {
        spline,
        system_dimension: n,
        pi_per_point: pi / b_points.len().max(1) as f64,
        data_misfit: misfit,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::fit::smoothing::{smoothing_spline, SmoothingOptions};
    use crate::spline::{Partition, TensorSpace};
    use crate::tolerance::SOLVE;

    fn data() -> (Vec<[f64; 2]>, Vec<[f64; 3]>) {
        let pts: Vec<[f64; 2]> = (0..64)
            .map(|k| [((k / 8) as f64 + 0.5) / 8.0, ((k % 8) as f64 + 0.25) / 8.0])
            .collect();
        let vals = pts
            .iter()
            .map(|p| [p[0], p[1], (3.0 * p[0]).sin() * p[1]])
            .collect();
        (pts, vals)
    }

    #[test]
    fn tau_zero_is_the_smoothing_spline() {
        // Remark 4.2: τ = 0 gives the discrete smoothing Dᵐ-spline, solved independently
        // by the per-component solver.
        let u = Partition::uniform(0.0, 1.0, 3).unwrap();
        let s = TensorSpace::bfs_c2(u.clone(), u).unwrap();
        let (a, v) = data();
        let b = vec![[0.5, 0.5]];
        let n = vec![[0.0, 0.0, 1.0]];
        let opts = ParallelOptions {
            epsilon: 1e-6,
            tau: 0.0,
            m: 3,
        };
        let par = parallel_fit(&s, &a, &v, &b, &n, &opts).unwrap();
        let sm = smoothing_spline(
            &s,
            &a,
            &v,
            &[],
            &SmoothingOptions {
                epsilon: 1e-6,
                m: 3,
                domain: None,
            },
        )
        .unwrap();
        for p in [[0.1, 0.2], [0.6, 0.9]] {
            let x = par.spline.eval(&s, p[0], p[1], 0, 0).unwrap();
            let y = sm.spline.eval(&s, p[0], p[1], 0, 0).unwrap();
            for c in 0..3 {
                assert_near!(x[c], y[c], SOLVE);
            }
        }
    }

    #[test]
    fn parallel_to_a_plane_flattens_the_height() {
        // x₀ the plane z = 0 (N = e₃): Π = Σ (∂z/∂u)² + (∂z/∂v)² at B, so a large τ makes
        // the height flatter while x and y, untouched by Π, do not change at all.
        let u = Partition::uniform(0.0, 1.0, 3).unwrap();
        let s = TensorSpace::bfs_c2(u.clone(), u).unwrap();
        let (a, v) = data();
        let b: Vec<[f64; 2]> = (0..100)
            .map(|k| {
                [
                    ((k / 10) as f64 + 0.5) / 10.0,
                    ((k % 10) as f64 + 0.5) / 10.0,
                ]
            })
            .collect();
        let n = vec![[0.0, 0.0, 1.0]; b.len()];
        let lo = parallel_fit(
            &s,
            &a,
            &v,
            &b,
            &n,
            &ParallelOptions {
                epsilon: 1e-6,
                tau: 1e-3,
                m: 3,
            },
        )
        .unwrap();
        let hi = parallel_fit(
            &s,
            &a,
            &v,
            &b,
            &n,
            &ParallelOptions {
                epsilon: 1e-6,
                tau: 1e3,
                m: 3,
            },
        )
        .unwrap();
        assert!(hi.pi_per_point < lo.pi_per_point);
        for p in [[0.3, 0.7], [0.8, 0.1]] {
            let (x, y) = (
                hi.spline.eval(&s, p[0], p[1], 0, 0).unwrap(),
                lo.spline.eval(&s, p[0], p[1], 0, 0).unwrap(),
            );
            assert_near!(x[0], y[0], SOLVE);
            assert_near!(x[1], y[1], SOLVE);
            let (gx, gy) = (
                hi.spline.eval(&s, p[0], p[1], 1, 0).unwrap(),
                lo.spline.eval(&s, p[0], p[1], 1, 0).unwrap(),
            );
            assert!(gx[2].abs() < gy[2].abs(), "∂z/∂u: {} vs {}", gx[2], gy[2]);
        }
    }

    #[test]
    fn bad_input_is_an_error() {
        let u = Partition::uniform(0.0, 1.0, 2).unwrap();
        let s = TensorSpace::bfs_c2(u.clone(), u).unwrap();
        let (a, v) = data();
        let ok = ParallelOptions {
            epsilon: 1e-6,
            tau: 1.0,
            m: 3,
        };
        assert!(parallel_fit(&s, &a, &v, &[[0.5, 0.5]], &[], &ok).is_err());
        assert!(parallel_fit(&s, &a, &v, &[], &[], &ParallelOptions { tau: -1.0, ..ok }).is_err());
        assert!(parallel_fit(
            &s,
            &a,
            &v,
            &[],
            &[],
            &ParallelOptions { epsilon: 0.0, ..ok }
        )
        .is_err());
        assert!(parallel_fit(&s, &a[..3], &v[..3], &[], &[], &ok).is_err());
    }
}
