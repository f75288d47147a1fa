//! Gram matrices of the Sobolev semi-norm |·|ₘ over a union of cells:
//! (u, v)ₘ,ω = Σ_{|β| = m} ∫_ω ∂^β u ∂^β v (2022 §2, 2024 §2, 2004 §2: the sum runs over
//! multi-indices β = (β₁, β₂), so the mixed derivative counts once, without a binomial
//! weight — the papers' definition).

use super::grid::Cell;
use super::quadrature::GaussLegendre;
use super::space::Space;
use crate::error::{Error, Result};

/// A symmetric sparse matrix as (row, col, value) entries, both triangles stored. Entries
/// are appended (cheap in assembly loops) and merged when read.
#[derive(Debug, Clone, Default)]
pub struct SparseSym {
    /// Order of the matrix.
    pub n: usize,
    entries: Vec<(usize, usize, f64)>,
}

impl SparseSym {
    /// The zero matrix of order n.
    pub fn new(n: usize) -> Self {
        Self {
            n,
            entries: Vec::new(),
        }
    }

    /// Room for `additional` more entries (one allocation instead of repeated growth).
    pub fn reserve(&mut self, additional: usize) {
        self.entries.reserve(additional);
    }

    /// Adds v to entry (i, j) only (callers add both triangles).
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        self.entries.push((i, j, v));
    }

    /// The entries as added, unsorted, with duplicates (their sum is the matrix): for
    /// consumers that sum duplicates themselves (`solve_spd`), without a sort.
    pub fn entries(&self) -> &[(usize, usize, f64)] {
        &self.entries
    }

    /// Entry (i, j) (a linear scan: for checks, not for loops).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.entries
            .iter()
            .filter(|&&(a, b, _)| a == i && b == j)
            .map(|e| e.2)
            .sum()
    }

    /// The entries merged and sorted by (row, col).
    pub fn triplets(&self) -> Vec<(usize, usize, f64)> {
        let mut v = self.entries.clone();
        v.sort_unstable_by_key(|&(i, j, _)| (i, j));
        let mut out: Vec<(usize, usize, f64)> = Vec::with_capacity(v.len());
        for (i, j, x) in v {
            match out.last_mut() {
                Some(last) if last.0 == i && last.1 == j => last.2 += x,
                _ => out.push((i, j, x)),
            }
        }
        out
    }

    /// cᵀ A c.
    pub fn quadratic_form(&self, c: &[f64]) -> f64 {
        self.entries.iter().map(|&(i, j, x)| c[i] * x * c[j]).sum()
    }
}

/// The Gram matrix Gᵢⱼ = (φᵢ, φⱼ)ₘ,ω of the semi-norm |·|ₘ over ω = ∪ `cells`
/// (the matrix 𝓡 of (8) and (14) in the 2022 paper). Exact: each cell is integrated with
/// degree + 1 Gauss points per variable.
///
/// Errors: `InvalidInput` if `m` exceeds the space's degree or a cell is outside the grid.
pub fn seminorm_gram(space: &dyn Space, m: usize, cells: &[Cell]) -> Result<SparseSym> {
    if m > space.degree() {
        return Err(Error::InvalidInput(format!(
            "semi-norm order {m} exceeds the space's degree {}",
            space.degree()
        )));
    }
    let (nx, ny) = space.grid().shape();
    let rule = GaussLegendre::new(space.degree() + 1)?;
    let mut g = SparseSym::new(space.dim());
    if let Some(c) = cells.first() {
        g.reserve(cells.len() * space.cell_functions(*c).len().pow(2));
    }
    for &cell in cells {
        if cell.i >= nx || cell.j >= ny {
            return Err(Error::InvalidInput(format!(
                "cell ({}, {}) outside a {nx} × {ny} grid",
                cell.i, cell.j
            )));
        }
        let idx = space.cell_functions(cell);
        let nl = idx.len();
        let local = space.cell_seminorm_gram(cell, m, &rule);
        for p in 0..nl {
            for q in 0..nl {
                g.add(idx[p], idx[q], local[p * nl + q]);
            }
        }
    }
    Ok(g)
}
