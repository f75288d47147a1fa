//! Symmetric sparse matrices of 3 × 3 blocks stored by their upper triangle: the form in
//! which the multilevel solver keeps its levels and multiplies by them.
//!
//! Why half the matrix: a product reads every stored block once, and on the 2-core machine
//! its time is the memory traffic, not the arithmetic. In a probe the size of the 223k
//! junction's Hessian (8.9 million blocks both triangles, 2026-11-28), a product took
//! 0.034 to 0.037 s from the upper triangle against 0.054 to 0.064 s from both, while
//! compiling the both-triangle product for AVX2 and FMA changed nothing. The price is a
//! per-task partial result, summed after: the transposed blocks scatter across rows.

use rayon::prelude::*;

use super::block_csr::{filled_in_parallel, Block, BlockCsr};
use crate::fair::functional::evaluation::BlockHessian;

/// At most this many partial results per product (each up to the length of the result):
/// on many cores more tasks would cost more in summing than they gain.
const MAX_TASKS: usize = 16;
/// Result rows per parallel task when the partial results are summed.
const SUM_CHUNK_ROWS: usize = 4096;

/// A symmetric matrix of 3 × 3 blocks: the blocks (i, j) with i ≤ j, every row's sorted
/// by column; a diagonal block is stored whole (symmetric).
#[derive(Debug, Clone, PartialEq)]
pub struct SymmetricCsr {
    row_start: Vec<usize>,
    columns: Vec<u32>,
    pub values: Vec<Block>,
}

impl SymmetricCsr {
    /// The upper triangle of `full` (both triangles stored, as [`BlockCsr`]).
    pub fn from_full(full: &BlockCsr) -> Self {
        let n = full.size();
        // Each row's upper blocks are a tail of it (columns sorted): its first slot ≥ i.
        let first_upper: Vec<usize> = (0..n)
            .into_par_iter()
            .map(|i| {
                let range = full.row_start[i]..full.row_start[i + 1];
                range.start + full.columns[range].partition_point(|&c| (c as usize) < i)
            })
            .collect();
        let mut row_start = Vec::with_capacity(n + 1);
        row_start.push(0);
        for (i, &first) in first_upper.iter().enumerate() {
            row_start.push(row_start[i] + full.row_start[i + 1] - first);
        }
        let (columns, values) = filled_in_parallel(
            row_start.windows(2).map(|w| w[1] - w[0]),
            |i, columns, values| {
                let source = first_upper[i]..full.row_start[i + 1];
                columns.copy_from_slice(&full.columns[source.clone()]);
                values.copy_from_slice(&full.values[source]);
            },
        );
        SymmetricCsr {
            row_start,
            columns,
            values,
        }
    }

    /// Block rows (vertices).
    pub fn size(&self) -> usize {
        self.row_start.len() - 1
    }

    /// The slot of block (`row`, `column`), `row` ≤ `column`, if it is in the pattern.
    pub fn slot(&self, row: usize, column: u32) -> Option<usize> {
        debug_assert!(row <= column as usize);
        let range = self.row_start[row]..self.row_start[row + 1];
        self.columns[range.clone()]
            .binary_search(&column)
            .ok()
            .map(|k| range.start + k)
    }

    /// Block (`row`, `column`) of the symmetric matrix, either side of the diagonal (the
    /// stored block transposed below it), if it is in the pattern.
    pub fn block(&self, row: u32, column: u32) -> Option<Block> {
        if row <= column {
            self.slot(row as usize, column).map(|s| self.values[s])
        } else {
            let upper = self.values[self.slot(column as usize, row)?];
            Some(std::array::from_fn(|a| {
                std::array::from_fn(|b| upper[b][a])
            }))
        }
    }

    /// The diagonal blocks (zero where one is not in the pattern).
    pub fn diagonal(&self) -> Vec<Block> {
        (0..self.size())
            .into_par_iter()
            .map(|i| {
                let k = self.row_start[i];
                let here = k < self.row_start[i + 1] && self.columns[k] as usize == i;
                if here {
                    self.values[k]
                } else {
                    [[0.0; 3]; 3]
                }
            })
            .collect()
    }

    /// The stored blocks as a [`BlockHessian`], for the Cholesky factorizer.
    pub fn to_upper(&self) -> BlockHessian {
        let blocks = (0..self.size())
            .flat_map(|i| {
                let range = self.row_start[i]..self.row_start[i + 1];
                self.columns[range].iter().map(move |&j| (i as u32, j))
            })
            .collect();
        BlockHessian {
            blocks,
            values: self.values.clone(),
        }
    }

    /// y = (A + `shift` I) x: row ranges of about equal block counts in parallel, each
    /// into its own partial result from its first row on (a block (i, j) adds to rows i
    /// and j ≥ i), summed after.
    pub fn multiply(&self, x: &[f64], shift: f64) -> Vec<f64> {
        let n = self.size();
        let tasks = rayon::current_num_threads().clamp(1, MAX_TASKS);
        let blocks = self.values.len();
        let bounds: Vec<usize> = (0..=tasks)
            .map(|t| {
                let target = blocks * t / tasks;
                self.row_start.partition_point(|&s| s < target).min(n)
            })
            .collect();
        let mut parts: Vec<(usize, Vec<f64>)> = bounds
            .par_windows(2)
            .map(|w| (w[0], self.rows_product(x, shift, w[0]..w[1])))
            .collect();
        // The first range starts at row 0: its partial result is whole, and the others are
        // added into it.
        let (_, mut y) = parts.remove(0);
        y.par_chunks_mut(3 * SUM_CHUNK_ROWS)
            .enumerate()
            .for_each(|(chunk, out)| {
                let first = chunk * 3 * SUM_CHUNK_ROWS;
                for (start_row, part) in &parts {
                    let offset = 3 * start_row;
                    let from = first.max(offset);
                    for k in from..first + out.len() {
                        out[k - first] += part[k - offset];
                    }
                }
            });
        y
    }

    /// The contributions of the blocks of `rows` to (A + `shift` I) x, from row
    /// `rows.start` to the last.
    fn rows_product(&self, x: &[f64], shift: f64, rows: std::ops::Range<usize>) -> Vec<f64> {
        let first = rows.start;
        let mut y = vec![0.0; 3 * (self.size() - first)];
        for i in rows {
            let xi = [x[3 * i], x[3 * i + 1], x[3 * i + 2]];
            let mut sum = xi.map(|v| shift * v);
            for k in self.row_start[i]..self.row_start[i + 1] {
                let j = self.columns[k] as usize;
                let v = &self.values[k];
                let xj = &x[3 * j..3 * j + 3];
                for (s, row) in sum.iter_mut().zip(v) {
                    *s += row[0] * xj[0] + row[1] * xj[1] + row[2] * xj[2];
                }
                if j != i {
                    let out = &mut y[3 * (j - first)..3 * (j - first) + 3];
                    for (b, o) in out.iter_mut().enumerate() {
                        *o += v[0][b] * xi[0] + v[1][b] * xi[1] + v[2][b] * xi[2];
                    }
                }
            }
            for (o, s) in y[3 * (i - first)..3 * (i - first) + 3].iter_mut().zip(sum) {
                *o += s;
            }
        }
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fair::solvers::multilevel::block_csr::tests::random_hessian;
    use crate::fair::solvers::multilevel::block_csr::UpperLayout;

    /// A symmetric matrix over `n` vertices with blocks (i, j) for |i − j| ≤ 2 and
    /// (i, n − 1 − i), pseudo-random entries, as upper blocks.
    fn hessian(n: usize, seed: u64) -> BlockHessian {
        random_hessian(n, seed, |i, j| j <= i + 2 || j == n - 1 - i).0
    }

    /// [`hessian`] as given, with both triangles, and by its upper one.
    fn forms(n: usize, seed: u64) -> (BlockHessian, BlockCsr, SymmetricCsr) {
        let h = hessian(n, seed);
        let full = UpperLayout::new(&h, n).fill(&h);
        let upper = SymmetricCsr::from_full(&full);
        (h, full, upper)
    }

    #[test]
    fn multiplies_as_both_triangles_on_any_number_of_threads() {
        // The second implementation: the both-triangle product of the same matrix.
        let n = 23;
        let (h, full, upper) = forms(n, 5);
        assert_eq!(upper.values.len(), h.blocks.len());
        let x: Vec<f64> = (0..3 * n).map(|k| (k as f64 * 0.37).sin()).collect();
        let expected = full.multiply(&x, 0.25);
        for threads in [1, 2, 3, 7] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let got = pool.install(|| upper.multiply(&x, 0.25));
            for (g, e) in got.iter().zip(&expected) {
                assert!((g - e).abs() < 1e-14, "{threads} threads: {g} against {e}");
            }
        }
    }

    /// The slot of diagonal block `i` in `full`.
    fn full_slot(full: &BlockCsr, i: u32) -> usize {
        let range = full.row_start[i as usize]..full.row_start[i as usize + 1];
        range.start + full.columns[range].binary_search(&i).unwrap()
    }

    #[test]
    fn keeps_the_upper_blocks_diagonal_and_slots() {
        let (h, full, upper) = forms(9, 8);
        assert_eq!(upper.to_upper().blocks, h.blocks);
        let diagonal = upper.diagonal();
        for (k, &(i, j)) in h.blocks.iter().enumerate() {
            assert_eq!(upper.slot(i as usize, j), Some(k));
            if i == j {
                assert_eq!(diagonal[i as usize], full.values[full_slot(&full, i)]);
            }
        }
        assert_eq!(upper.slot(0, 5), None);
        // Every block of the full matrix, above and below the diagonal.
        for i in 0..9u32 {
            let range = full.row_start[i as usize]..full.row_start[i as usize + 1];
            for k in range {
                assert_eq!(upper.block(i, full.columns[k]), Some(full.values[k]));
            }
        }
        assert_eq!(upper.block(5, 0), None);
    }
}
