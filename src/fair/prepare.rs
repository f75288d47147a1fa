//! Preparation of a mesh for optimization (paper §2 and §4): uniform Catmull–Clark
//! refinement until the paper's conditions hold, with χ checked unchanged, and the choice
//! of fixed vertices.

use crate::error::{Error, Result};
use crate::fair::topology::{condition_violation, MeshTopology};
use crate::mesh::PolygonMesh;
use crate::subdiv::{refine_uniform, SubdivOptions};

/// The mesh refined (uniformly, by OpenSubdiv) the fewest times, at most `max_levels`, that
/// makes every face a quad and keeps special vertices two edges apart from each other and
/// from the boundary (§2); and the number of levels used.
///
/// # Errors
/// [`Error::Topology`] if the mesh is not manifold, if refinement changed V − E + F (it
/// must not), or if `max_levels` refinements do not meet the conditions; errors of
/// [`refine_uniform`].
pub fn prepare(mesh: &PolygonMesh, max_levels: u32) -> Result<(PolygonMesh, u32)> {
    let topo = MeshTopology::new(mesh)?;
    let chi = topo.euler_characteristic();
    let mut current = mesh.clone();
    let mut current_topo = topo;
    for level in 0..=max_levels {
        let violation = condition_violation(&current, &current_topo);
        match violation {
            None => return Ok((current, level)),
            Some(why) if level == max_levels => {
                return Err(Error::Topology(format!(
                    "after {max_levels} refinements the mesh still fails the optimizer's \
                     conditions: {why}"
                )))
            }
            Some(_) => {}
        }
        current = refine_uniform(&current, 1, &SubdivOptions::default())?;
        current_topo = MeshTopology::new(&current)?;
        let refined_chi = current_topo.euler_characteristic();
        if refined_chi != chi {
            return Err(Error::Topology(format!(
                "refinement changed the Euler characteristic from {chi} to {refined_chi}"
            )));
        }
    }
    unreachable!("the loop returns at level max_levels")
}

/// Fixed vertices (§4): every vertex fewer than `rings` edges from the boundary (boundary,
/// tangent plane and curvature kept for `rings` = 3), plus `extra`.
///
/// # Errors
/// [`Error::InvalidInput`] if an id in `extra` is not a vertex, or if nothing is fixed
/// (a closed mesh without user-given vertices: F would have no unique minimum and the
/// surface could shrink or drift freely).
pub fn fixed_vertices(topo: &MeshTopology, rings: u32, extra: &[u32]) -> Result<Vec<bool>> {
    let nv = topo.neighbours.len();
    let dist = topo.distances(topo.boundary_vertices());
    let mut fixed: Vec<bool> = dist.iter().map(|&d| d < rings).collect();
    for &v in extra {
        if v as usize >= nv {
            return Err(Error::InvalidInput(format!(
                "fixed vertex id {v} does not exist (the mesh has {nv} vertices)"
            )));
        }
        fixed[v as usize] = true;
    }
    if !fixed.iter().any(|&f| f) {
        return Err(Error::InvalidInput(
            "the mesh is closed and no vertex is fixed: give vertex ids to hold (the \
             optimization needs a boundary or soft constraints)"
                .into(),
        ));
    }
    Ok(fixed)
}
