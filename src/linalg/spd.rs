//! Sparse symmetric positive definite solves by faer's sparse Cholesky.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, LltRef};
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use faer::{Conj, Mat, Side};

use crate::error::{Error, Result, SolverFailure};
use crate::limits::MemoryBudget;

/// Solves A xₖ = bₖ for each right-hand side with one sparse Cholesky factorization of the
/// symmetric matrix A given by its (row, col, value) entries (both triangles or only the
/// lower one; duplicates are summed; only the lower triangle is read).
///
/// The factor's size is known from the symbolic analysis before any numeric work: it is
/// checked against the process's memory budget ([`MemoryBudget::default`]), so a spline
/// of a million cells is refused with the size it needs, not reported as a failed
/// factorization once the allocator gives up.
///
/// Errors: `InvalidInput` on an index out of range or a right-hand side of the wrong length
/// or a non-finite entry; `ResourceLimit` when the factor and its workspace exceed the
/// budget; `Solver { NotPositiveDefinite }` if the factorization breaks down.
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
    for &(i, j, v) in entries {
        if i >= n || j >= n || !v.is_finite() {
            return Err(Error::InvalidInput(format!(
                "matrix entry ({i}, {j}) = {v} is out of range or not finite (order {n})"
            )));
        }
    }
    let (col_ptr, row_idx, values) = lower_csc(n, entries);
    let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    let a = SparseColMat::<usize, f64>::new(symbolic, values);
    let failed = |what: &str, e: &dyn std::fmt::Debug| Error::Solver {
        failure: SolverFailure::Singular,
        detail: format!("{what} of a matrix of order {n}: {e:?}"),
    };
    let analysis = factorize_symbolic_cholesky(
        a.symbolic(),
        Side::Lower,
        Default::default(),
        Default::default(),
    )
    .map_err(|e| failed("symbolic Cholesky", &e))?;
    let par = faer::get_global_parallelism();
    let factor_scratch = analysis.factorize_numeric_llt_scratch::<f64>(par, Default::default());
    let solve_scratch = analysis.solve_in_place_scratch::<f64>(rhs.len(), par);
    let needed = (analysis.len_val() as u64)
        .saturating_mul(8)
        .saturating_add(factor_scratch.size_bytes().max(solve_scratch.size_bytes()) as u64);
    let budget = MemoryBudget::default();
    if needed > budget.get() {
        return Err(Error::ResourceLimit {
            what: format!(
                "the sparse Cholesky factor of a system of order {n} ({})",
                crate::limits::human_bytes(needed)
            ),
            limit: budget.get(),
            advice: "use fewer cells".into(),
        });
    }
    let mut factor = Vec::new();
    factor
        .try_reserve_exact(analysis.len_val())
        .map_err(|e| failed("Cholesky factor storage", &e))?;
    factor.resize(analysis.len_val(), 0.0);
    let mut scratch = MemBuffer::try_new(factor_scratch.or(solve_scratch))
        .map_err(|e| failed("Cholesky workspace", &e))?;
    analysis
        .factorize_numeric_llt(
            &mut factor,
            a.as_ref(),
            Side::Lower,
            Default::default(),
            par,
            MemStack::new(&mut scratch),
            Default::default(),
        )
        .map_err(|e| Error::Solver {
            failure: SolverFailure::NotPositiveDefinite,
            detail: format!("sparse Cholesky of a matrix of order {n}: {e:?}"),
        })?;
    let mut b = Mat::<f64>::zeros(n, rhs.len());
    for (k, col) in rhs.iter().enumerate() {
        for (i, &v) in col.iter().enumerate() {
            b[(i, k)] = v;
        }
    }
    LltRef::new(&analysis, &factor).solve_in_place_with_conj(
        Conj::No,
        b.as_mut(),
        par,
        MemStack::new(&mut scratch),
    );
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

/// The lower triangle (i ≥ j) of the matrix whose entries are the sums of `entries` at
/// each (i, j), as compressed columns with sorted rows: a counting sort by column, then
/// duplicates merged with a row marker and each column's few distinct rows sorted — linear
/// in the entries, where sorting all of them (faer's `try_new_from_triplets`) was a fixed
/// cost that dominated small fits. Precondition: indices < n (checked by the caller).
fn lower_csc(n: usize, entries: &[(usize, usize, f64)]) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    let mut start = vec![0usize; n + 1];
    for &(i, j, _) in entries {
        if i >= j {
            start[j + 1] += 1;
        }
    }
    for j in 0..n {
        start[j + 1] += start[j];
    }
    let mut next = start.clone();
    let mut rows = vec![0usize; start[n]];
    let mut vals = vec![0.0; start[n]];
    for &(i, j, v) in entries {
        if i >= j {
            rows[next[j]] = i;
            vals[next[j]] = v;
            next[j] += 1;
        }
    }
    // mark[r] = j + 1 when row r was met in column j, at output position pos[r].
    let (mut mark, mut pos) = (vec![0usize; n], vec![0usize; n]);
    let mut col_ptr = Vec::with_capacity(n + 1);
    let (mut row_idx, mut values) = (Vec::new(), Vec::new());
    let mut pairs: Vec<(usize, f64)> = Vec::new();
    col_ptr.push(0);
    for j in 0..n {
        pairs.clear();
        for k in start[j]..start[j + 1] {
            let r = rows[k];
            if mark[r] == j + 1 {
                pairs[pos[r]].1 += vals[k];
            } else {
                mark[r] = j + 1;
                pos[r] = pairs.len();
                pairs.push((r, vals[k]));
            }
        }
        pairs.sort_unstable_by_key(|p| p.0);
        row_idx.extend(pairs.iter().map(|p| p.0));
        values.extend(pairs.iter().map(|p| p.1));
        col_ptr.push(row_idx.len());
    }
    (col_ptr, row_idx, values)
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
    fn lower_csc_sums_duplicates_and_sorts_rows() {
        // [[4, 1, 0], [1, 5, 2], [0, 2, 6]] given in pieces, both triangles, shuffled.
        let e = [
            (2, 1, 1.0),
            (0, 0, 3.0),
            (1, 0, 1.0),
            (2, 2, 6.0),
            (1, 1, 5.0),
            (0, 1, 1.0),
            (2, 1, 1.0),
            (0, 0, 1.0),
            (1, 2, 2.0),
        ];
        let (p, r, v) = lower_csc(3, &e);
        assert_eq!(p, vec![0, 2, 4, 5]);
        assert_eq!(r, vec![0, 1, 1, 2, 2]);
        assert_eq!(v, vec![4.0, 1.0, 5.0, 2.0, 6.0]);
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
