//! The Galerkin product Pᵀ A P that gives each coarse level its matrix, once per Hessian.
//!
//! Formed in two stages per task of consecutive coarse rows: first the rows of A P of the
//! fine vertices those coarse rows reach, each once, then each coarse row c as the sum
//! Σᵢ P(i, c) (A P)ᵢ over them. Forming every coarse row straight from A recomputes a fine
//! vertex's row of A P for every coarse vertex whose prolongation reaches it — about 25 on
//! a quad mesh refined by Catmull–Clark (9 vertex points, 12 edge points, 4 face points),
//! here only for the fine vertices a task shares with its neighbours. At the 223 487-vertex
//! junction that product took 5.5 s of each Hessian's set-up (23 matrices, 2026-11-29, in a
//! probe run that shared the machine with a build for part of its time), and the set-ups
//! 152.6 s of a 591.7 s run against 83.2 s of 518.0 s this way
//! (docs/fairing-at-scale-log.md).

use rayon::prelude::*;

use super::block_csr::{filled_in_parallel, Block, BlockCsr, Prolongation};

/// Coarse rows per task: many, so that the fine rows a task shares with its neighbours
/// (formed in both) are few of its own, and few enough that its rows of A P stay small
/// (megabytes). Not tuned: the first value tried.
const COARSE_ROWS_PER_TASK: usize = 512;

impl BlockCsr {
    /// The Galerkin product Pᵀ A P (the coarse level's matrix), every row's blocks
    /// sorted by column.
    pub fn galerkin(&self, p: &Prolongation) -> BlockCsr {
        self.galerkin_by_tasks(p, COARSE_ROWS_PER_TASK)
    }

    /// [`Self::galerkin`] with `per_task` coarse rows per task (the tests vary it).
    fn galerkin_by_tasks(&self, p: &Prolongation, per_task: usize) -> BlockCsr {
        let coarse_count = p.coarse_count;
        let fine_count = self.size();
        let per_task = per_task.max(1);
        let tasks: Vec<(usize, usize)> = (0..coarse_count)
            .step_by(per_task)
            .map(|first| (first, (first + per_task).min(coarse_count)))
            .collect();
        let parts: Vec<Rows> = tasks
            .into_par_iter()
            .map_init(
                || Workspace::new(fine_count, coarse_count),
                |workspace, (first, end)| workspace.coarse_rows(self, p, first..end),
            )
            .collect();
        let mut row_start = Vec::with_capacity(coarse_count + 1);
        row_start.push(0);
        for part in &parts {
            for length in &part.lengths {
                row_start.push(row_start.last().expect("starts at 0") + length);
            }
        }
        let (columns, values) =
            filled_in_parallel(parts.iter().map(|part| part.columns.len()), |k, c, v| {
                c.copy_from_slice(&parts[k].columns);
                v.copy_from_slice(&parts[k].values);
            });
        BlockCsr {
            row_start,
            columns,
            values,
        }
    }
}

/// Consecutive sparse rows of blocks.
#[derive(Default)]
struct Rows {
    lengths: Vec<usize>,
    columns: Vec<u32>,
    values: Vec<Block>,
}

impl Rows {
    fn clear(&mut self) {
        self.lengths.clear();
        self.columns.clear();
        self.values.clear();
    }
}

/// A sparse row of blocks summed densely over the coarse vertices (Gustavson).
struct Accumulator {
    sums: Vec<Block>,
    seen: Vec<bool>,
    touched: Vec<u32>,
}

impl Accumulator {
    fn new(coarse_count: usize) -> Self {
        Accumulator {
            sums: vec![[[0.0; 3]; 3]; coarse_count],
            seen: vec![false; coarse_count],
            touched: Vec::new(),
        }
    }

    /// Column `c` += `w` · `block`.
    #[inline(always)]
    fn add(&mut self, c: usize, w: f64, block: &Block) {
        if !self.seen[c] {
            self.seen[c] = true;
            self.touched.push(c as u32);
        }
        let sum = &mut self.sums[c];
        for a in 0..3 {
            for b in 0..3 {
                sum[a][b] += w * block[a][b];
            }
        }
    }

    /// Appends the row summed so far to `rows`, sorted by column, and starts a new one.
    fn finish_row(&mut self, rows: &mut Rows) {
        self.touched.sort_unstable();
        rows.lengths.push(self.touched.len());
        for &c in &self.touched {
            self.seen[c as usize] = false;
            rows.columns.push(c);
            rows.values
                .push(std::mem::replace(&mut self.sums[c as usize], [[0.0; 3]; 3]));
        }
        self.touched.clear();
    }
}

/// One thread's buffers for [`BlockCsr::galerkin`].
struct Workspace {
    accumulator: Accumulator,
    /// 1 + the index among the task's fine rows of each fine vertex the task reaches, 0
    /// for the others.
    local: Vec<u32>,
    fine_rows: Vec<u32>,
    /// The task's rows of A P, in the order of `fine_rows`.
    a_p: Rows,
    a_p_start: Vec<usize>,
}

impl Workspace {
    fn new(fine_count: usize, coarse_count: usize) -> Self {
        Workspace {
            accumulator: Accumulator::new(coarse_count),
            local: vec![0; fine_count],
            fine_rows: Vec::new(),
            a_p: Rows::default(),
            a_p_start: Vec::new(),
        }
    }

    /// Rows `coarse` of Pᵀ A P: stage 1, then stage 2 (module documentation).
    fn coarse_rows(
        &mut self,
        a: &BlockCsr,
        p: &Prolongation,
        coarse: std::ops::Range<usize>,
    ) -> Rows {
        for c in coarse.clone() {
            for (i, _) in p.column(c) {
                if self.local[i] == 0 {
                    self.fine_rows.push(i as u32);
                    self.local[i] = self.fine_rows.len() as u32;
                }
            }
        }
        // Stage 1: (A P)ᵢ = Σⱼ A(i, j) Pⱼ for the fine rows reached.
        self.a_p_start.clear();
        self.a_p_start.push(0);
        for &i in &self.fine_rows {
            let i = i as usize;
            for k in a.row_start[i]..a.row_start[i + 1] {
                let block = &a.values[k];
                for (c, w) in p.row(a.columns[k] as usize) {
                    self.accumulator.add(c, w, block);
                }
            }
            self.accumulator.finish_row(&mut self.a_p);
            self.a_p_start.push(self.a_p.columns.len());
        }
        // Stage 2: (Pᵀ A P)_c = Σᵢ P(i, c) (A P)ᵢ.
        let mut out = Rows::default();
        for c in coarse {
            for (i, w) in p.column(c) {
                let row = self.local[i] as usize - 1;
                for k in self.a_p_start[row]..self.a_p_start[row + 1] {
                    self.accumulator
                        .add(self.a_p.columns[k] as usize, w, &self.a_p.values[k]);
                }
            }
            self.accumulator.finish_row(&mut out);
        }
        for &i in &self.fine_rows {
            self.local[i as usize] = 0;
        }
        self.fine_rows.clear();
        self.a_p.clear();
        // Only until the rows are joined: no room to spare meanwhile.
        out.columns.shrink_to_fit();
        out.values.shrink_to_fit();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fair::solvers::multilevel::block_csr::tests::{
        dense_product, hessian, random_hessian,
    };
    use crate::fair::solvers::multilevel::block_csr::UpperLayout;
    use crate::fair::solvers::multilevel::symmetric_csr::SymmetricCsr;

    /// Asserts `coarse` = Pᵀ A P column by column (Pᵀ A P e = restrict(A (P e))), A `dense`.
    fn assert_is_pt_a_p(coarse: &BlockCsr, p: &Prolongation, dense: &[Vec<f64>]) {
        let nc = p.coarse_count;
        for k in 0..3 * nc {
            let mut e = vec![0.0; 3 * nc];
            e[k] = 1.0;
            let mut fine = vec![0.0; dense.len()];
            p.add_prolonged(&e, &mut fine);
            let expected = p.restrict(&dense_product(dense, &fine));
            let got = coarse.multiply(&e, 0.0);
            for (g, x) in got.iter().zip(&expected) {
                assert!((g - x).abs() < 1e-14, "column {k}: {g} {x}");
            }
        }
    }

    #[test]
    fn galerkin_product_is_pt_a_p() {
        let n = 7;
        let (h, dense) = hessian(n, 11);
        let a = UpperLayout::new(&h, n).fill(&h);
        // Coarse vertex c ↦ fine 2c with weight 1 and its neighbours with ½.
        let nc = 4;
        let rows: Vec<Vec<(u32, f64)>> = (0..n)
            .map(|i| {
                if i % 2 == 0 {
                    vec![(i as u32 / 2, 1.0)]
                } else {
                    vec![(i as u32 / 2, 0.5), (i as u32 / 2 + 1, 0.5)]
                }
            })
            .collect();
        let p = Prolongation::new(nc, &rows);
        let coarse = a.galerkin(&p);
        assert_is_pt_a_p(&coarse, &p, &dense);
        // Symmetric, and its upper blocks give the same matrix back.
        let upper = SymmetricCsr::from_full(&coarse).to_upper();
        let again = UpperLayout::new(&upper, nc).fill(&upper);
        assert_eq!(again.columns, coarse.columns);
        for (x, y) in again.values.iter().zip(&coarse.values) {
            for a in 0..3 {
                for b in 0..3 {
                    assert!((x[a][b] - y[a][b]).abs() < 1e-14);
                }
            }
        }
    }

    #[test]
    fn the_product_is_the_same_however_the_coarse_rows_are_split_into_tasks() {
        // Wider stencils in no order (a coarse vertex reaches fine vertices far apart, so
        // tasks share fine rows), on a band of half-width 4.
        let n = 40;
        let nc = 13;
        let (h, dense) = random_hessian(n, 5, |i, j| j <= i + 4);
        let a = UpperLayout::new(&h, n).fill(&h);
        let rows: Vec<Vec<(u32, f64)>> = (0..n)
            .map(|i| {
                let mut row: Vec<(u32, f64)> = (0..3)
                    .map(|k| (((7 * i + 5 * k) % nc) as u32, 0.25 + 0.125 * k as f64))
                    .collect();
                row.sort_by_key(|&(c, _)| c);
                row.dedup_by_key(|&mut (c, _)| c);
                row
            })
            .collect();
        let p = Prolongation::new(nc, &rows);
        let whole = a.galerkin_by_tasks(&p, nc);
        assert_is_pt_a_p(&whole, &p, &dense);
        for per_task in [1, 2, 5, 12] {
            let split = a.galerkin_by_tasks(&p, per_task);
            assert_eq!(split.row_start, whole.row_start, "{per_task} rows per task");
            assert_eq!(split.columns, whole.columns, "{per_task} rows per task");
            // The same sums in the same order: the same bits.
            assert_eq!(split.values, whole.values, "{per_task} rows per task");
        }
    }
}
