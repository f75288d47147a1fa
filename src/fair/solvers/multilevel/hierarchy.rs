//! The levels of the multilevel solver: the prolongations from each coarser control mesh
//! to the next finer one's unknowns, found by un-subdividing the mesh level by level.

use std::sync::Arc;

use super::block_csr::Prolongation;
use super::patch_smoother::Patches;
use super::unsubdivision::{coarsen, FaceList};
use crate::mesh::PolygonMesh;

/// Coarsening stops at this many unknown vertices or fewer: the coarsest level is
/// factored directly, which costs little below a few thousand vertices.
pub const COARSEST_VERTICES: usize = 2000;

/// At most this many coarse levels.
const MAX_LEVELS: usize = 8;

/// The prolongations P_l from level l + 1's unknowns to level l's (level 0: the free
/// vertices, numbered by the functional's free index).
#[derive(Debug, Clone)]
pub struct Hierarchy {
    pub prolongations: Vec<Prolongation>,
    /// The smoother's patches of every smoothed level (all but the coarsest).
    pub patches: Vec<Arc<Patches>>,
}

impl Hierarchy {
    /// Unknown vertices per level, finest first.
    pub fn sizes(&self) -> Vec<usize> {
        let mut out: Vec<usize> = self.prolongations.iter().map(|p| p.fine_count()).collect();
        if let Some(last) = self.prolongations.last() {
            out.push(last.coarse_count);
        }
        out
    }
}

/// The hierarchy of `mesh` for the unknowns `free_index` (vertex → unknown, `u32::MAX`
/// for a fixed vertex): as many levels as un-subdivision finds, until the coarsest has at
/// most [`COARSEST_VERTICES`] unknowns or a level does not cut them by a third. No levels
/// when the mesh is not a Catmull–Clark refinement.
pub fn hierarchy(mesh: &PolygonMesh, free_index: &[u32], free_count: usize) -> Hierarchy {
    let mut faces = FaceList {
        vertex_count: mesh.vertex_count(),
        faces: mesh.faces().map(<[u32]>::to_vec).collect(),
    };
    let mut unknown_of = free_index.to_vec();
    let mut count = free_count;
    let mut prolongations = Vec::new();
    while count > COARSEST_VERTICES && prolongations.len() < MAX_LEVELS {
        let Some(coarsening) = coarsen(&faces) else {
            break;
        };
        let mut coarse_unknown = vec![u32::MAX; coarsening.coarse.vertex_count];
        for (v, &u) in unknown_of.iter().enumerate() {
            if u != u32::MAX {
                for &(c, _) in &coarsening.stencils[v] {
                    coarse_unknown[c as usize] = 0;
                }
            }
        }
        let mut coarse_count = 0u32;
        for u in coarse_unknown.iter_mut().filter(|u| **u == 0) {
            *u = coarse_count;
            coarse_count += 1;
        }
        let coarse_count = coarse_count as usize;
        if 3 * coarse_count > 2 * count {
            break;
        }
        let mut rows = vec![Vec::new(); count];
        for (v, &u) in unknown_of.iter().enumerate() {
            if u != u32::MAX {
                rows[u as usize] = coarsening.stencils[v]
                    .iter()
                    .map(|&(c, w)| (coarse_unknown[c as usize], w))
                    .collect();
            }
        }
        prolongations.push(Prolongation::new(coarse_count, &rows));
        faces = coarsening.coarse;
        unknown_of = coarse_unknown;
        count = coarse_count;
    }
    let patches = if prolongations.is_empty() {
        Vec::new()
    } else {
        std::iter::once(Patches::of_mesh(mesh, free_index, free_count))
            .chain(
                prolongations[..prolongations.len() - 1]
                    .iter()
                    .map(Patches::of_prolongation),
            )
            .map(Arc::new)
            .collect()
    };
    Hierarchy {
        prolongations,
        patches,
    }
}
