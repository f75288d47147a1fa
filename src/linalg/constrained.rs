//! min ½βᵀKβ − βᵀr subject to Cβ = d — the saddle-point system (14) of the 2022 paper —
//! solved by the null-space method so that linearly dependent constraints (a hole that is
//! a rectangle of cells) do not break it: β is unique, λ is not, and we return the λ of
//! minimum norm.

use faer::linalg::solvers::Llt;
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};

use crate::error::{Error, Result, SolverFailure};
use crate::tolerance::SOLVE;

/// The solution of an equality-constrained quadratic minimization.
#[derive(Debug, Clone)]
pub struct ConstrainedSolution {
    /// One β per right-hand side.
    pub beta: Vec<Vec<f64>>,
    /// The Lagrange multipliers of minimum norm, one vector per right-hand side.
    pub lambda: Vec<Vec<f64>>,
    /// Rank of C.
    pub rank: usize,
    /// Number of constraints (rows of C); `rows − rank` of them are redundant.
    pub rows: usize,
    /// max over right-hand sides of ‖Cβ − d‖∞.
    pub constraint_residual: f64,
}

/// Solves, for each pair (rₖ, dₖ), the KKT system  [K Cᵀ; C 0] [β; λ] = [r; d]  (2022 (14)).
///
/// β = β_p + Zγ with β_p the minimum-norm solution of Cβ = d and Z an orthonormal basis of
/// ker C (both from the SVD of C, rank by the usual max(p, n)·ε·σ_max threshold); then
/// (ZᵀKZ)γ = Zᵀ(r − Kβ_p) by dense Cholesky; λ = (Cᵀ)⁺(r − Kβ).
///
/// Preconditions: K (n × n) symmetric, positive definite on ker C; C is p × n (p may be 0).
/// Errors: `InvalidInput` on mismatched shapes or non-finite entries; `Solver { Infeasible }`
/// if Cβ = d has no solution (d outside the range of C, relative residual above `SOLVE`);
/// `Solver { NotPositiveDefinite }` if K is not positive definite on ker C.
pub fn minimize_with_equalities(
    k: &Mat<f64>,
    c: &Mat<f64>,
    rhs: &[Vec<f64>],
    d: &[Vec<f64>],
) -> Result<ConstrainedSolution> {
    let n = k.nrows();
    let p = c.nrows();
    if k.ncols() != n || c.ncols() != n || rhs.len() != d.len() {
        return Err(Error::InvalidInput(format!(
            "constrained solve: K is {}×{}, C is {}×{}, {} and {} right-hand sides",
            k.nrows(),
            k.ncols(),
            c.nrows(),
            c.ncols(),
            rhs.len(),
            d.len()
        )));
    }
    if rhs.iter().any(|r| r.len() != n) || d.iter().any(|x| x.len() != p) {
        return Err(Error::InvalidInput(
            "constrained solve: right-hand side of wrong length".into(),
        ));
    }
    if rhs.iter().chain(d).flatten().any(|v| !v.is_finite()) {
        return Err(Error::InvalidInput(
            "constrained solve: non-finite entry".into(),
        ));
    }

    let NullSpace {
        rank,
        u,
        s,
        v,
        z,
        llt,
    } = null_space(k, c)?;

    let mut beta = Vec::with_capacity(rhs.len());
    let mut lambda = Vec::with_capacity(rhs.len());
    let mut worst = 0.0f64;
    for (r, dk) in rhs.iter().zip(d) {
        // β_p = V_r S_r⁻¹ U_rᵀ d.
        let mut bp = Mat::<f64>::zeros(n, 1);
        for q in 0..rank {
            let coef: f64 = (0..p).map(|i| u[(i, q)] * dk[i]).sum::<f64>() / s[q];
            for i in 0..n {
                bp[(i, 0)] += v[(i, q)] * coef;
            }
        }
        let res = c * &bp;
        let dnorm = dk.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let rnorm = (0..p).fold(0.0f64, |m, i| m.max((res[(i, 0)] - dk[i]).abs()));
        if rnorm > SOLVE * dnorm.max(1.0) {
            return Err(Error::Solver {
                failure: SolverFailure::Infeasible,
                detail: format!("equality constraints are inconsistent: residual {rnorm:e}"),
            });
        }
        worst = worst.max(rnorm);
        let mut rv = Mat::<f64>::zeros(n, 1);
        for i in 0..n {
            rv[(i, 0)] = r[i];
        }
        let mut b = bp.clone();
        if let Some(llt) = &llt {
            let g = llt.solve(z.transpose() * (&rv - k * &bp));
            b = &bp + &z * g;
        }
        // λ = (Cᵀ)⁺ (r − Kβ) = U_r S_r⁻¹ V_rᵀ (r − Kβ).
        let w = &rv - k * &b;
        let mut lam = vec![0.0; p];
        for q in 0..rank {
            let coef: f64 = (0..n).map(|i| v[(i, q)] * w[(i, 0)]).sum::<f64>() / s[q];
            for (i, l) in lam.iter_mut().enumerate() {
                *l += u[(i, q)] * coef;
            }
        }
        beta.push((0..n).map(|i| b[(i, 0)]).collect());
        lambda.push(lam);
    }
    Ok(ConstrainedSolution {
        beta,
        lambda,
        rank,
        rows: p,
        constraint_residual: worst,
    })
}

/// C = U S Vᵀ with its numerical rank, Z = V[:, rank..] an orthonormal basis of ker C, and
/// the Cholesky factor of ZᵀKZ (none when ker C = {0}).
struct NullSpace {
    rank: usize,
    u: Mat<f64>,
    s: Vec<f64>,
    v: Mat<f64>,
    z: Mat<f64>,
    llt: Option<Llt<f64>>,
}

fn null_space(k: &Mat<f64>, c: &Mat<f64>) -> Result<NullSpace> {
    let (n, p) = (k.nrows(), c.nrows());
    if !finite(k) || !finite(c) {
        return Err(Error::InvalidInput(
            "constrained solve: non-finite entry".into(),
        ));
    }
    // SVD of C: C = U S Vᵀ. Row space = V[:, ..rank], null space = V[:, rank..].
    let (rank, u, s, v) = if p == 0 {
        (
            0,
            Mat::<f64>::zeros(0, 0),
            vec![],
            Mat::<f64>::identity(n, n),
        )
    } else {
        let failed = |e| Error::Solver {
            failure: SolverFailure::NotConverged,
            detail: format!("SVD of the {p}×{n} constraint matrix: {e:?}"),
        };
        // With at least as many rows as columns the thin SVD has all of V (the null space
        // needs it) and an n-column U instead of a p × p one.
        let (u, sv, v) = if p >= n {
            let svd = c.thin_svd().map_err(failed)?;
            let sv: Vec<f64> = svd.S().column_vector().iter().copied().collect();
            (svd.U().to_owned(), sv, svd.V().to_owned())
        } else {
            let svd = c.svd().map_err(failed)?;
            let sv: Vec<f64> = svd.S().column_vector().iter().copied().collect();
            (svd.U().to_owned(), sv, svd.V().to_owned())
        };
        let smax = sv.iter().copied().fold(0.0, f64::max);
        let thresh = p.max(n) as f64 * f64::EPSILON * smax;
        let rank = sv.iter().filter(|&&x| x > thresh).count();
        (rank, u, sv, v)
    };
    let z = v.subcols(rank, n - rank).to_owned();
    let ztkz = z.transpose() * k * &z;
    let llt = if n > rank {
        Some(ztkz.llt(Side::Lower).map_err(|e| Error::Solver {
            failure: SolverFailure::NotPositiveDefinite,
            detail: format!("reduced matrix ZᵀKZ of order {}: {e:?}", n - rank),
        })?)
    } else {
        None
    };

    Ok(NullSpace {
        rank,
        u,
        s,
        v,
        z,
        llt,
    })
}

/// The minimizers of ½βᵀKβ subject to Cβ = d for every column d of `d` at once (the
/// problem of [`minimize_with_equalities`] with r = 0, without multipliers): the columns
/// of B_p + Z (ZᵀKZ)⁻¹ Zᵀ(−K B_p), B_p = V_r S_r⁻¹ U_rᵀ D, by matrix products. Returns the
/// minimizers (n × columns of d) and the rank of C.
///
/// # Errors
/// As [`minimize_with_equalities`].
pub fn minimizers_with_equalities(
    k: &Mat<f64>,
    c: &Mat<f64>,
    d: &Mat<f64>,
) -> Result<(Mat<f64>, usize)> {
    let (n, p) = (k.nrows(), c.nrows());
    if k.ncols() != n || c.ncols() != n || d.nrows() != p {
        return Err(Error::InvalidInput(format!(
            "constrained solve: K is {}×{}, C is {}×{}, D is {}×{}",
            k.nrows(),
            k.ncols(),
            c.nrows(),
            c.ncols(),
            d.nrows(),
            d.ncols()
        )));
    }
    if !finite(d) {
        return Err(Error::InvalidInput(
            "constrained solve: non-finite entry".into(),
        ));
    }
    let space = null_space(k, c)?;
    let rank = space.rank;
    let mut scaled = space.u.subcols(0, rank).transpose() * d;
    for (q, sq) in space.s.iter().take(rank).enumerate() {
        for j in 0..scaled.ncols() {
            scaled[(q, j)] /= sq;
        }
    }
    let particular = space.v.subcols(0, rank) * &scaled;
    let residual = c * &particular - d;
    for j in 0..d.ncols() {
        let dnorm = (0..p).fold(0.0f64, |m, i| m.max(d[(i, j)].abs()));
        let rnorm = (0..p).fold(0.0f64, |m, i| m.max(residual[(i, j)].abs()));
        if rnorm > SOLVE * dnorm.max(1.0) {
            return Err(Error::Solver {
                failure: SolverFailure::Infeasible,
                detail: format!(
                    "equality constraints are inconsistent for column {j}: residual {rnorm:e}"
                ),
            });
        }
    }
    let beta = match &space.llt {
        Some(llt) => {
            let gamma = llt.solve(space.z.transpose() * (k * &particular));
            &particular - &space.z * gamma
        }
        None => particular,
    };
    Ok((beta, rank))
}

fn finite(m: &Mat<f64>) -> bool {
    (0..m.ncols()).all(|j| (0..m.nrows()).all(|i| m[(i, j)].is_finite()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    #[test]
    fn dependent_constraints_give_the_unique_beta() {
        // min ½‖β‖² − (1,1,1)·β s.t. β₀ + β₁ = 1 written twice (and scaled): the
        // KKT matrix is singular. Exact: β₂ = 1, β₀ = β₁ = ½, and Kβ + Cᵀλ = r holds.
        let k = Mat::<f64>::identity(3, 3);
        let mut c = Mat::<f64>::zeros(2, 3);
        c[(0, 0)] = 1.0;
        c[(0, 1)] = 1.0;
        c[(1, 0)] = 2.0;
        c[(1, 1)] = 2.0;
        let sol = minimize_with_equalities(&k, &c, &[vec![1.0; 3]], &[vec![1.0, 2.0]]).unwrap();
        assert_eq!(sol.rank, 1);
        let b = &sol.beta[0];
        assert_near!(b[0], 0.5, SOLVE);
        assert_near!(b[1], 0.5, SOLVE);
        assert_near!(b[2], 1.0, SOLVE);
        // Stationarity: β + Cᵀλ = r.
        let l = &sol.lambda[0];
        assert_near!(b[0] + l[0] + 2.0 * l[1], 1.0, SOLVE);
        assert_near!(b[2], 1.0, SOLVE);
    }

    #[test]
    fn inconsistent_constraints_are_infeasible() {
        let k = Mat::<f64>::identity(2, 2);
        let mut c = Mat::<f64>::zeros(2, 2);
        c[(0, 0)] = 1.0;
        c[(1, 0)] = 1.0;
        let r = minimize_with_equalities(&k, &c, &[vec![0.0; 2]], &[vec![1.0, 2.0]]);
        assert!(matches!(
            r,
            Err(Error::Solver {
                failure: SolverFailure::Infeasible,
                ..
            })
        ));
    }
}
