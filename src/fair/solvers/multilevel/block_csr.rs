//! Symmetric sparse matrices of 3 × 3 blocks stored by rows, both triangles: the form in
//! which the multilevel solver forms the coarse levels' Galerkin products Pᵀ A P (every
//! row whole, [`super::galerkin`]) before it keeps each level by its upper triangle
//! ([`super::symmetric_csr`]); and the prolongations.

use rayon::prelude::*;

use crate::fair::functional::evaluation::BlockHessian;

/// A 3 × 3 block.
pub type Block = [[f64; 3]; 3];

/// The columns and blocks of consecutive pieces of a sparse matrix, piece k `lengths[k]`
/// entries long and written by `fill(k, its columns, its blocks)`, the pieces in parallel:
/// one pass over fresh memory, where appending them in turn is one thread's (the 223k
/// junction's fine upper triangle, 2026-11-30: 0.44 s against 1.0 s).
pub fn filled_in_parallel(
    lengths: impl Iterator<Item = usize>,
    fill: impl Fn(usize, &mut [u32], &mut [Block]) + Sync,
) -> (Vec<u32>, Vec<Block>) {
    let lengths: Vec<usize> = lengths.collect();
    let total = lengths.iter().sum();
    let mut columns = vec![0u32; total];
    let mut values = vec![[[0.0; 3]; 3]; total];
    let mut pieces = Vec::with_capacity(lengths.len());
    let (mut column_rest, mut value_rest) = (&mut columns[..], &mut values[..]);
    for length in lengths {
        let (c, c_rest) = std::mem::take(&mut column_rest).split_at_mut(length);
        let (v, v_rest) = std::mem::take(&mut value_rest).split_at_mut(length);
        pieces.push((c, v));
        (column_rest, value_rest) = (c_rest, v_rest);
    }
    pieces
        .into_par_iter()
        .enumerate()
        .for_each(|(k, (c, v))| fill(k, c, v));
    (columns, values)
}

/// A symmetric matrix of 3 × 3 blocks, every row's blocks sorted by column.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockCsr {
    pub row_start: Vec<usize>,
    pub columns: Vec<u32>,
    pub values: Vec<Block>,
}

/// A prolongation P (fine unknown vertex × coarse unknown vertex, scalar weights acting on
/// each coordinate alike) by rows, and its transpose.
#[derive(Debug, Clone, PartialEq)]
pub struct Prolongation {
    pub coarse_count: usize,
    rows: Csr,
    transposed: Csr,
}

/// A scalar sparse matrix by rows.
#[derive(Debug, Clone, PartialEq)]
struct Csr {
    start: Vec<usize>,
    columns: Vec<u32>,
    weights: Vec<f64>,
}

impl Csr {
    fn row(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let range = self.start[i]..self.start[i + 1];
        self.columns[range.clone()]
            .iter()
            .zip(&self.weights[range])
            .map(|(&c, &w)| (c as usize, w))
    }

    fn transpose(&self, column_count: usize) -> Csr {
        let mut count = vec![0usize; column_count + 1];
        for &c in &self.columns {
            count[c as usize + 1] += 1;
        }
        for k in 0..column_count {
            count[k + 1] += count[k];
        }
        let mut next = count.clone();
        let mut columns = vec![0u32; self.columns.len()];
        let mut weights = vec![0.0; self.columns.len()];
        for row in 0..self.start.len() - 1 {
            for (c, w) in self.row(row) {
                columns[next[c]] = row as u32;
                weights[next[c]] = w;
                next[c] += 1;
            }
        }
        Csr {
            start: count,
            columns,
            weights,
        }
    }
}

impl Prolongation {
    /// P from its rows: `rows[i]` lists (coarse index, weight) of fine unknown vertex i.
    pub fn new(coarse_count: usize, rows: &[Vec<(u32, f64)>]) -> Self {
        let mut start = Vec::with_capacity(rows.len() + 1);
        start.push(0);
        let mut columns = Vec::new();
        let mut weights = Vec::new();
        for row in rows {
            for &(c, w) in row {
                debug_assert!((c as usize) < coarse_count);
                columns.push(c);
                weights.push(w);
            }
            start.push(columns.len());
        }
        let rows = Csr {
            start,
            columns,
            weights,
        };
        let transposed = rows.transpose(coarse_count);
        Prolongation {
            coarse_count,
            rows,
            transposed,
        }
    }

    /// Fine unknown vertices (rows).
    pub fn fine_count(&self) -> usize {
        self.rows.start.len() - 1
    }

    /// Row `i` of P: (coarse index, weight).
    pub fn row(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.rows.row(i)
    }

    /// Column `c` of P: (fine index, weight).
    pub fn column(&self, c: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.transposed.row(c)
    }

    /// x_fine += P x_coarse (3 coordinates per vertex).
    pub fn add_prolonged(&self, coarse: &[f64], fine: &mut [f64]) {
        fine.par_chunks_mut(3).enumerate().for_each(|(i, out)| {
            for (c, w) in self.rows.row(i) {
                for a in 0..3 {
                    out[a] += w * coarse[3 * c + a];
                }
            }
        });
    }

    /// Pᵀ x_fine.
    pub fn restrict(&self, fine: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; 3 * self.coarse_count];
        out.par_chunks_mut(3).enumerate().for_each(|(c, out)| {
            for (i, w) in self.transposed.row(c) {
                for a in 0..3 {
                    out[a] += w * fine[3 * i + a];
                }
            }
        });
        out
    }
}

/// Where each block of a [`BlockCsr`] comes from in a [`BlockHessian`] of a fixed pattern:
/// computed once, since every Hessian of a run has the same blocks.
#[derive(Debug, Clone)]
pub struct UpperLayout {
    row_start: Vec<usize>,
    columns: Vec<u32>,
    /// Index into the Hessian's blocks, with [`TRANSPOSED`] set for a block of the lower
    /// triangle (the transpose of an upper one).
    source: Vec<u32>,
    block_count: usize,
}

const TRANSPOSED: u32 = 1 << 31;

impl UpperLayout {
    /// The layout of the full symmetric matrix of `h` (upper blocks, row ≤ column) over
    /// `n` vertices.
    pub fn new(h: &BlockHessian, n: usize) -> Self {
        assert!(h.blocks.len() < TRANSPOSED as usize, "Hessian too large");
        let mut count = vec![0usize; n + 1];
        for &(i, j) in &h.blocks {
            count[i as usize + 1] += 1;
            if i != j {
                count[j as usize + 1] += 1;
            }
        }
        for k in 0..n {
            count[k + 1] += count[k];
        }
        let mut next = count.clone();
        let mut entries = vec![(0u32, 0u32); count[n]];
        for (k, &(i, j)) in h.blocks.iter().enumerate() {
            entries[next[i as usize]] = (j, k as u32);
            next[i as usize] += 1;
            if i != j {
                entries[next[j as usize]] = (i, k as u32 | TRANSPOSED);
                next[j as usize] += 1;
            }
        }
        for row in 0..n {
            entries[count[row]..count[row + 1]].sort_unstable_by_key(|e| e.0);
        }
        UpperLayout {
            row_start: count,
            columns: entries.iter().map(|e| e.0).collect(),
            source: entries.iter().map(|e| e.1).collect(),
            block_count: h.blocks.len(),
        }
    }

    /// Whether `h` has the pattern this layout was made for (by its number of blocks: the
    /// Hessians of one functional differ only in values).
    pub fn fits(&self, h: &BlockHessian) -> bool {
        h.blocks.len() == self.block_count
    }

    /// The entries of block row `row` (a vertex): indices for [`Self::column`] and
    /// [`Self::block`], by increasing column.
    pub fn row(&self, row: usize) -> std::ops::Range<usize> {
        self.row_start[row]..self.row_start[row + 1]
    }

    /// The block column (vertex) of entry `k`.
    pub fn column(&self, k: usize) -> u32 {
        self.columns[k]
    }

    /// Entry `k`'s block of the full symmetric matrix of `h`; a diagonal block is read from
    /// its upper triangle (the lower one of a Hessian's diagonal block need not be filled).
    pub fn block(&self, h: &BlockHessian, k: usize) -> Block {
        let s = self.source[k];
        let v = &h.values[(s & !TRANSPOSED) as usize];
        let (i, j) = h.blocks[(s & !TRANSPOSED) as usize];
        if i == j {
            std::array::from_fn(|a| std::array::from_fn(|b| v[a.min(b)][a.max(b)]))
        } else if s & TRANSPOSED != 0 {
            std::array::from_fn(|a| std::array::from_fn(|b| v[b][a]))
        } else {
            *v
        }
    }

    /// The full symmetric matrix of `h` ([`Self::block`] for every entry).
    pub fn fill(&self, h: &BlockHessian) -> BlockCsr {
        let values = (0..self.source.len())
            .into_par_iter()
            .map(|k| self.block(h, k))
            .collect();
        BlockCsr {
            row_start: self.row_start.clone(),
            columns: self.columns.clone(),
            values,
        }
    }
}

impl BlockCsr {
    /// Block rows (vertices).
    pub fn size(&self) -> usize {
        self.row_start.len() - 1
    }

    /// `shift` · I as a block matrix over `n` vertices.
    pub fn scaled_identity(n: usize, shift: f64) -> Self {
        BlockCsr {
            row_start: (0..=n).collect(),
            columns: (0..n as u32).collect(),
            values: vec![diagonal_block(shift); n],
        }
    }

    /// y = (A + `shift` I) x: the reference product of the tests (the solver multiplies
    /// by the upper triangle, [`super::symmetric_csr::SymmetricCsr`]).
    #[cfg(test)]
    pub fn multiply(&self, x: &[f64], shift: f64) -> Vec<f64> {
        let mut y = vec![0.0; x.len()];
        y.par_chunks_mut(3).enumerate().for_each(|(i, out)| {
            let mut sum = [shift * x[3 * i], shift * x[3 * i + 1], shift * x[3 * i + 2]];
            for k in self.row_start[i]..self.row_start[i + 1] {
                let j = 3 * self.columns[k] as usize;
                let v = &self.values[k];
                for (a, s) in sum.iter_mut().enumerate() {
                    *s += v[a][0] * x[j] + v[a][1] * x[j + 1] + v[a][2] * x[j + 2];
                }
            }
            out.copy_from_slice(&sum);
        });
        y
    }
}

/// s · I₃.
pub fn diagonal_block(s: f64) -> Block {
    [[s, 0.0, 0.0], [0.0, s, 0.0], [0.0, 0.0, s]]
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// A dense symmetric 3n × 3n matrix as upper blocks (i, j), |i − j| ≤ 2.
    pub fn hessian(n: usize, seed: u64) -> (BlockHessian, Vec<Vec<f64>>) {
        random_hessian(n, seed, |i, j| j <= i + 2)
    }

    /// A dense symmetric 3n × 3n matrix of pseudo-random entries as upper blocks, with the
    /// blocks (i, j), i ≤ j, that `linked` accepts.
    pub fn random_hessian(
        n: usize,
        seed: u64,
        linked: impl Fn(usize, usize) -> bool,
    ) -> (BlockHessian, Vec<Vec<f64>>) {
        let mut dense = vec![vec![0.0; 3 * n]; 3 * n];
        let mut state = seed;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let mut blocks = Vec::new();
        let mut values = Vec::new();
        for i in 0..n {
            for j in i..n {
                if !linked(i, j) {
                    continue;
                }
                let mut v: Block = std::array::from_fn(|_| std::array::from_fn(|_| next()));
                if i == j {
                    // Symmetric: the lower triangle mirrors the upper one.
                    v = std::array::from_fn(|a| std::array::from_fn(|b| v[a.min(b)][a.max(b)]));
                }
                for a in 0..3 {
                    for b in 0..3 {
                        dense[3 * i + a][3 * j + b] = v[a][b];
                        dense[3 * j + b][3 * i + a] = v[a][b];
                    }
                }
                if i == j {
                    // Only the upper triangle is meaningful in a Hessian's diagonal block.
                    v[2][0] = f64::NAN;
                }
                blocks.push((i as u32, j as u32));
                values.push(v);
            }
        }
        (BlockHessian { blocks, values }, dense)
    }

    pub fn dense_product(m: &[Vec<f64>], x: &[f64]) -> Vec<f64> {
        m.iter()
            .map(|row| row.iter().zip(x).map(|(a, b)| a * b).sum())
            .collect()
    }

    #[test]
    fn the_full_matrix_multiplies_as_the_dense_one() {
        let (h, dense) = hessian(7, 3);
        let a = UpperLayout::new(&h, 7).fill(&h);
        let x: Vec<f64> = (0..21).map(|k| (k as f64 * 0.7).cos()).collect();
        let mut expected = dense_product(&dense, &x);
        for (y, x) in expected.iter_mut().zip(&x) {
            *y += 0.5 * x;
        }
        for (y, e) in a.multiply(&x, 0.5).iter().zip(&expected) {
            assert!((y - e).abs() < 1e-14, "{y} {e}");
        }
    }
}
