//! The part of a representation a block sees (paper §5, block iterations): only the
//! quadrature points with a control vertex in the block. With the other vertices held,
//! F̃ restricted to the block differs from the full F̃ by a constant (the points that do
//! not meet the block), so its gradient and Hessian over the block are exact while costing
//! only the block's patches.

use crate::fair::surface::representation::{QuadraturePoint, Representation};

/// A filtered copy of a [`Representation`]'s quadrature points.
pub struct SubRepresentation {
    vertex_count: usize,
    element_count: usize,
    points: Vec<QuadraturePoint>,
}

impl SubRepresentation {
    /// The points of `rep` with at least one vertex flagged in `in_block` (one flag per
    /// vertex of `rep`; missing flags count as false). Vertex ids and the element count
    /// (for c, §4) stay those of `rep`.
    pub fn new<R: Representation>(rep: &R, in_block: &[bool]) -> Self {
        let points = rep
            .points()
            .iter()
            .filter(|p| {
                p.vertices
                    .iter()
                    .any(|&v| in_block.get(v as usize).copied().unwrap_or(false))
            })
            .cloned()
            .collect();
        SubRepresentation {
            vertex_count: rep.vertex_count(),
            element_count: rep.element_count(),
            points,
        }
    }
}

impl Representation for SubRepresentation {
    fn vertex_count(&self) -> usize {
        self.vertex_count
    }
    fn points(&self) -> &[QuadraturePoint] {
        &self.points
    }
    fn element_count(&self) -> usize {
        self.element_count
    }
}
