//! Convex quadratic programs min ½xᵀPx + qᵀx subject to Ax ≤ b, by clarabel's interior
//! point method (2024 §4: the shape-preserving filling).

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};

use crate::error::{Error, Result, SolverFailure};

/// A solved QP.
#[derive(Debug, Clone)]
pub struct QpSolution {
    /// The minimizer.
    pub x: Vec<f64>,
    /// max(0, max (Ax − b)ᵢ): the worst constraint violation.
    pub max_violation: f64,
    /// The solver's own status, for reports.
    pub status: String,
    /// The violation the solver's stopping rule allows: ‖Ax + s − b‖ ≤ tol_feas ·
    /// max(1, ‖b‖∞ + ‖x‖₂ + ‖s‖₂) with the slack s = max(0, b − Ax) (clarabel's primal
    /// residual test, without its internal equilibration scaling).
    pub violation_tolerance: f64,
}

/// clarabel's primal feasibility tolerance tol_feas (its default, set explicitly so the
/// reported tolerance is the one used).
pub const QP_FEASIBILITY: f64 = 1e-8;

/// The violation a QP solution with constraint data `b`, unknowns `x` and constraint
/// values `ax` = Ax may have by the solver's own stopping rule (see
/// [`QpSolution::violation_tolerance`]).
pub fn violation_tolerance(b: &[f64], x: &[f64], ax: &[f64]) -> f64 {
    let two = |v: &mut dyn Iterator<Item = f64>| v.map(|t| t * t).sum::<f64>().sqrt();
    let nb = b.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    let nx = two(&mut x.iter().copied());
    let ns = two(&mut ax.iter().zip(b).map(|(l, r)| (r - l).max(0.0)));
    QP_FEASIBILITY * 1f64.max(nb + nx + ns)
}

/// Solves min ½xᵀPx + qᵀx s.t. Ax ≤ b. `p` holds P's entries (either triangle or both; the
/// upper triangle is built from them), `a` the entries of the m × n matrix A.
///
/// Preconditions: P symmetric positive semi-definite, the problem bounded.
/// Errors: `InvalidInput` on out-of-range indices, wrong lengths or non-finite numbers;
/// `Solver { Infeasible }` if the constraints have no solution; `Solver { NotConverged }`
/// for any other non-solved status.
pub fn solve_qp(
    n: usize,
    p: &[(usize, usize, f64)],
    q: &[f64],
    m: usize,
    a: &[(usize, usize, f64)],
    b: &[f64],
) -> Result<QpSolution> {
    if q.len() != n || b.len() != m {
        return Err(Error::InvalidInput(format!(
            "QP: q has {} entries for {n} unknowns, b has {} for {m} constraints",
            q.len(),
            b.len()
        )));
    }
    let bad = |&(i, j, v): &(usize, usize, f64), r: usize| i >= r || j >= n || !v.is_finite();
    if p.iter().any(|e| bad(e, n))
        || a.iter().any(|e| bad(e, m))
        || q.iter().chain(b).any(|v| !v.is_finite())
    {
        return Err(Error::InvalidInput(
            "QP: entry out of range or not finite".into(),
        ));
    }
    // Upper triangle of P: (min, max) of each entry's indices; a both-triangle input
    // contributes each off-diagonal twice, so take only i ≤ j entries when both exist.
    let both = p.iter().any(|&(i, j, _)| i > j) && p.iter().any(|&(i, j, _)| i < j);
    let mut pi = vec![];
    let mut pj = vec![];
    let mut pv = vec![];
    for &(i, j, v) in p {
        if both && i > j {
            continue;
        }
        pi.push(i.min(j));
        pj.push(i.max(j));
        pv.push(v);
    }
    let pm = CscMatrix::new_from_triplets(n, n, pi, pj, pv);
    let (ai, aj, av) = a
        .iter()
        .fold((vec![], vec![], vec![]), |mut t, &(i, j, v)| {
            t.0.push(i);
            t.1.push(j);
            t.2.push(v);
            t
        });
    let am = CscMatrix::new_from_triplets(m, n, ai, aj, av);
    let cones = [SupportedConeT::NonnegativeConeT(m)];
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_feas(QP_FEASIBILITY)
        .build()
        .map_err(|e| Error::Solver {
            failure: SolverFailure::NotConverged,
            detail: format!("clarabel settings: {e:?}"),
        })?;
    let mut solver =
        DefaultSolver::new(&pm, q, &am, b, &cones, settings).map_err(|e| Error::Solver {
            failure: SolverFailure::NotConverged,
            detail: format!("clarabel setup: {e:?}"),
        })?;
    solver.solve();
    let status = solver.solution.status;
    match status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {}
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
            return Err(Error::Solver {
                failure: SolverFailure::Infeasible,
                detail: format!("clarabel: {status:?}"),
            })
        }
        other => {
            return Err(Error::Solver {
                failure: SolverFailure::NotConverged,
                detail: format!("clarabel: {other:?}"),
            })
        }
    }
    let x = solver.solution.x.clone();
    let mut ax = vec![0.0; m];
    for &(i, j, v) in a {
        ax[i] += v * x[j];
    }
    let max_violation = ax.iter().zip(b).fold(0.0f64, |w, (l, r)| w.max(l - r));
    Ok(QpSolution {
        violation_tolerance: violation_tolerance(b, &x, &ax),
        x,
        max_violation,
        status: format!("{status:?}"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::tolerance::FINITE_DIFFERENCE;

    #[test]
    fn projection_onto_a_half_plane() {
        // min ½‖x − (1, 1)‖² s.t. x₀ + x₁ ≤ 1 ⇒ x = (½, ½) (closed form).
        let p = [(0, 0, 1.0), (1, 1, 1.0)];
        let a = [(0, 0, 1.0), (0, 1, 1.0)];
        let s = solve_qp(2, &p, &[-1.0, -1.0], 1, &a, &[1.0]).unwrap();
        // Interior-point accuracy (clarabel's default 1e-8 gaps) is of the order of a
        // finite-difference comparison, not of round-off.
        assert_near!(s.x[0], 0.5, FINITE_DIFFERENCE);
        assert_near!(s.x[1], 0.5, FINITE_DIFFERENCE);
    }

    #[test]
    fn infeasible_is_an_error() {
        // x ≤ −1 and −x ≤ −1 (x ≥ 1).
        let a = [(0, 0, 1.0), (1, 0, -1.0)];
        let r = solve_qp(1, &[(0, 0, 1.0)], &[0.0], 2, &a, &[-1.0, -1.0]);
        assert!(matches!(
            r,
            Err(Error::Solver {
                failure: SolverFailure::Infeasible,
                ..
            })
        ));
    }
}
