//! Sparse symmetric positive definite solves by faer's sparse Cholesky.

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};

use crate::error::{Error, Result, SolverFailure};

/// Solves A xₖ = bₖ for each right-hand side with one sparse Cholesky factorization of the
/// symmetric matrix A given by its (row, col, value) entries (both triangles or only the
/// lower one; duplicates are summed; only the lower triangle is read).
///
/// Errors: `InvalidInput` on an index out of range or a right-hand side of the wrong length
/// or a non-finite entry; `Solver { NotPositiveDefinite }` if the factorization breaks down.
pub fn solve_spd(
    n: usize,
    entries: &[(usize, usize, f64)],
    rhs: &[Vec<f64>],
) -> Result<Vec<Vec<f64>>> {
    if let Some(b) = rhs.iter().find(|b| b.len() != n) {
        return Err(Error::InvalidInput(format!(
            "right-hand side of length {} for a system of order {n}",
            b.len()
        )));
    }
    let mut trip = Vec::with_capacity(entries.len());
    for &(i, j, v) in entries {
        if i >= n || j >= n || !v.is_finite() {
            return Err(Error::InvalidInput(format!(
                "matrix entry ({i}, {j}) = {v} is out of range or not finite (order {n})"
            )));
        }
        if i >= j {
            trip.push(Triplet::new(i, j, v));
        }
    }
    let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &trip).map_err(|e| {
        Error::Solver {
            failure: SolverFailure::Singular,
            detail: format!("building the sparse matrix: {e:?}"),
        }
    })?;
    let llt = a.sp_cholesky(Side::Lower).map_err(|e| Error::Solver {
        failure: SolverFailure::NotPositiveDefinite,
        detail: format!("sparse Cholesky of a matrix of order {n}: {e}"),
    })?;
    let mut b = Mat::<f64>::zeros(n, rhs.len());
    for (k, col) in rhs.iter().enumerate() {
        for (i, &v) in col.iter().enumerate() {
            b[(i, k)] = v;
        }
    }
    llt.solve_in_place(&mut b);
    let out: Vec<Vec<f64>> = (0..rhs.len())
        .map(|k| (0..n).map(|i| b[(i, k)]).collect())
        .collect();
    if out.iter().flatten().any(|v| !v.is_finite()) {
        return Err(Error::Solver {
            failure: SolverFailure::NotPositiveDefinite,
            detail: format!("sparse Cholesky of order {n} produced a non-finite solution"),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::tolerance::SOLVE;

    #[test]
    fn solves_a_tridiagonal_system_with_two_right_hand_sides() {
        // A = tridiag(−1, 2, −1), x = (1, 2, 3, 4) ⇒ b = (0, 0, 0, 5); and x = 1 ⇒ b = (1,0,0,1).
        let n = 4;
        let mut e = vec![];
        for i in 0..n {
            e.push((i, i, 2.0));
            if i + 1 < n {
                e.push((i + 1, i, -1.0));
                e.push((i, i + 1, -1.0));
            }
        }
        let x = solve_spd(n, &e, &[vec![0.0, 0.0, 0.0, 5.0], vec![1.0, 0.0, 0.0, 1.0]]).unwrap();
        for (i, (a, b)) in x[0].iter().zip(&x[1]).enumerate() {
            assert_near!(*a, (i + 1) as f64, SOLVE);
            assert_near!(*b, 1.0, SOLVE);
        }
    }

    #[test]
    fn indefinite_and_bad_input_are_errors() {
        let e = vec![(0, 0, 1.0), (1, 1, -1.0)];
        assert!(matches!(
            solve_spd(2, &e, &[vec![1.0, 1.0]]),
            Err(Error::Solver { .. })
        ));
        assert!(solve_spd(2, &[(2, 0, 1.0)], &[vec![1.0, 1.0]]).is_err());
        assert!(solve_spd(2, &[(0, 0, f64::NAN)], &[vec![1.0, 1.0]]).is_err());
        assert!(solve_spd(2, &[(0, 0, 1.0)], &[vec![1.0]]).is_err());
    }
}
