//! The border of the filled hole on the surface: where the hole's cells H_h meet cells
//! with data (or the rectangle's edge), traced through σ, for pictures of the fill.

use crate::error::Result;
use crate::fit::pipeline::FitOutcome;
use crate::spline::grid::Cell;

impl FitOutcome {
    /// The border of H_h as line segments on σ (point pairs), each cell side split into
    /// `pieces`; empty without a hole.
    pub fn hole_border(&self, pieces: usize) -> Result<Vec<[f64; 3]>> {
        let Some(fill) = &self.fill else {
            return Ok(Vec::new());
        };
        let grid = self.space.grid();
        let (nx, ny) = grid.shape();
        let in_hole = |i: isize, j: isize| {
            i >= 0
                && j >= 0
                && (i as usize) < nx
                && (j as usize) < ny
                && fill.hole_cells[grid.cell_index(Cell {
                    i: i as usize,
                    j: j as usize,
                })]
        };
        let pieces = pieces.max(1);
        let mut segments = Vec::new();
        for cell in grid
            .cells()
            .filter(|&c| fill.hole_cells[grid.cell_index(c)])
        {
            let ([u0, u1], [v0, v1]) = grid.cell_bounds(cell);
            let (i, j) = (cell.i as isize, cell.j as isize);
            // Each side whose neighbour is outside the hole: its two ends in (u, v).
            let sides = [
                (!in_hole(i - 1, j), [u0, v0], [u0, v1]),
                (!in_hole(i + 1, j), [u1, v0], [u1, v1]),
                (!in_hole(i, j - 1), [u0, v0], [u1, v0]),
                (!in_hole(i, j + 1), [u0, v1], [u1, v1]),
            ];
            for (_, a, b) in sides.into_iter().filter(|s| s.0) {
                let at = |k: usize| {
                    let t = k as f64 / pieces as f64;
                    self.eval(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))
                };
                for k in 0..pieces {
                    segments.push(at(k)?);
                    segments.push(at(k + 1)?);
                }
            }
        }
        Ok(segments)
    }
}
