//! Holes: the region H where data are missing, and its cell hull H_h = ∪{K ∈ 𝒯_h : K ∩ H ≠ ∅}
//! (2022 §2, 2024 §2).

use crate::error::{Error, Result};
use crate::mesh::planar::{point_in_polygon, segments_meet};
use crate::spline::{Cell, Grid};

/// One component of a hole.
#[derive(Debug, Clone, PartialEq)]
pub enum HoleShape {
    /// The closed ellipse a(x − cx)² + b(y − cy)² ≤ level with a, b, level > 0 (the papers'
    /// holes are written this way).
    Ellipse {
        center: [f64; 2],
        coeffs: [f64; 2],
        level: f64,
    },
    /// A closed simple polygon (vertices in order, not repeated).
    Polygon(Vec<[f64; 2]>),
    /// Whole cells, given by index (for holes read off the data: the cells without points).
    Cells(Vec<Cell>),
}

/// A hole: a union of shapes.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Hole {
    pub shapes: Vec<HoleShape>,
}

impl HoleShape {
    fn validate(&self) -> Result<()> {
        match self {
            HoleShape::Ellipse {
                center,
                coeffs,
                level,
            } => {
                if !(center.iter().all(|x| x.is_finite())
                    && coeffs.iter().all(|&a| a > 0.0 && a.is_finite())
                    && *level > 0.0
                    && level.is_finite())
                {
                    return Err(Error::InvalidInput(format!(
                        "ellipse hole {coeffs:?}·(p − {center:?})² ≤ {level}: coefficients and level must be positive and finite"
                    )));
                }
            }
            HoleShape::Polygon(v) => {
                if v.len() < 3 || v.iter().flatten().any(|x| !x.is_finite()) {
                    return Err(Error::InvalidInput(format!(
                        "polygon hole needs at least 3 finite vertices, got {}",
                        v.len()
                    )));
                }
            }
            HoleShape::Cells(_) => {}
        }
        Ok(())
    }

    /// Whether the closed shape holds (x, y).
    pub fn contains(&self, grid: &Grid, x: f64, y: f64) -> bool {
        match self {
            HoleShape::Ellipse {
                center,
                coeffs,
                level,
            } => {
                coeffs[0] * (x - center[0]).powi(2) + coeffs[1] * (y - center[1]).powi(2) <= *level
            }
            HoleShape::Polygon(v) => point_in_polygon([x, y], v),
            HoleShape::Cells(cells) => grid.locate(x, y).is_some_and(|c| cells.contains(&c)),
        }
    }

    /// Whether the closed shape meets the closed cell.
    fn meets(&self, grid: &Grid, cell: Cell) -> bool {
        let ([x0, x1], [y0, y1]) = grid.cell_bounds(cell);
        match self {
            HoleShape::Ellipse {
                center,
                coeffs,
                level,
            } => {
                // The axis-aligned quadratic is separable: its minimum over the box is at
                // the clamped centre.
                let x = center[0].clamp(x0, x1);
                let y = center[1].clamp(y0, y1);
                coeffs[0] * (x - center[0]).powi(2) + coeffs[1] * (y - center[1]).powi(2) <= *level
            }
            HoleShape::Polygon(v) => {
                let corners = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]];
                v.iter()
                    .any(|p| p[0] >= x0 && p[0] <= x1 && p[1] >= y0 && p[1] <= y1)
                    || corners.iter().any(|&c| point_in_polygon(c, v))
                    || (0..v.len()).any(|i| {
                        let (a, b) = (v[i], v[(i + 1) % v.len()]);
                        (0..4).any(|k| segments_meet(a, b, corners[k], corners[(k + 1) % 4]))
                    })
            }
            HoleShape::Cells(cells) => cells.contains(&cell),
        }
    }
}

impl Hole {
    /// Whether (x, y) is in the closed hole H.
    pub fn contains(&self, grid: &Grid, x: f64, y: f64) -> bool {
        self.shapes.iter().any(|s| s.contains(grid, x, y))
    }

    /// H_h as a mask over the grid's cells (by linear index).
    ///
    /// Errors: `InvalidInput` for a malformed shape, an empty H_h (nothing to fill) or an
    /// H_h that swallows every cell (no data left to fill from).
    pub fn cells(&self, grid: &Grid) -> Result<Vec<bool>> {
        for s in &self.shapes {
            s.validate()?;
        }
        let mask: Vec<bool> = grid
            .cells()
            .map(|c| self.shapes.iter().any(|s| s.meets(grid, c)))
            .collect();
        let k = mask.iter().filter(|&&b| b).count();
        if k == 0 {
            return Err(Error::InvalidInput(
                "the hole meets no cell of the partition".into(),
            ));
        }
        if k == mask.len() {
            return Err(Error::InvalidInput(format!(
                "the hole meets all {k} cells of the partition: there is no data around it to fill from"
            )));
        }
        Ok(mask)
    }
}

/// The cells holding none of the points: the hole read off the data.
pub fn cells_without_data(grid: &Grid, points: &[[f64; 2]]) -> Vec<Cell> {
    let mut seen = vec![false; grid.cell_count()];
    for p in points {
        if let Some(c) = grid.locate(p[0], p[1]) {
            seen[grid.cell_index(c)] = true;
        }
    }
    grid.cells()
        .filter(|&c| !seen[grid.cell_index(c)])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ellipse_and_polygon_cells() {
        let g = Grid::uniform(0.0, 1.0, 0.0, 1.0, 4, 4).unwrap();
        // A small circle around (0.375, 0.375) lies in cell (1, 1) only.
        let h = Hole {
            shapes: vec![HoleShape::Ellipse {
                center: [0.375, 0.375],
                coeffs: [1.0, 1.0],
                level: 0.01,
            }],
        };
        let m = h.cells(&g).unwrap();
        assert_eq!(m.iter().filter(|&&b| b).count(), 1);
        assert!(m[g.cell_index(Cell { i: 1, j: 1 })]);
        // A triangle crossing cells (0,0), (1,0), (0,1)… without a vertex inside (1, 1).
        let t = Hole {
            shapes: vec![HoleShape::Polygon(vec![[0.1, 0.1], [0.6, 0.1], [0.1, 0.6]])],
        };
        let m = t.cells(&g).unwrap();
        let on: Vec<Cell> = g.cells().filter(|&c| m[g.cell_index(c)]).collect();
        assert_eq!(
            on,
            vec![
                Cell { i: 0, j: 0 },
                Cell { i: 0, j: 1 },
                Cell { i: 0, j: 2 },
                Cell { i: 1, j: 0 },
                Cell { i: 1, j: 1 },
                Cell { i: 2, j: 0 }
            ]
        );
    }

    #[test]
    fn swallowing_or_empty_holes_are_errors() {
        let g = Grid::uniform(0.0, 1.0, 0.0, 1.0, 2, 2).unwrap();
        let big = Hole {
            shapes: vec![HoleShape::Ellipse {
                center: [0.5, 0.5],
                coeffs: [1.0, 1.0],
                level: 4.0,
            }],
        };
        assert!(big.cells(&g).is_err());
        let outside = Hole {
            shapes: vec![HoleShape::Ellipse {
                center: [5.0, 5.0],
                coeffs: [1.0, 1.0],
                level: 1.0,
            }],
        };
        assert!(outside.cells(&g).is_err());
        let bad = Hole {
            shapes: vec![HoleShape::Ellipse {
                center: [0.5, 0.5],
                coeffs: [-1.0, 1.0],
                level: 1.0,
            }],
        };
        assert!(bad.cells(&g).is_err());
    }
}
