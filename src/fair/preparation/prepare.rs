//! Preparation of a mesh for optimization (paper §2 and §4): uniform Catmull–Clark
//! refinement until the paper's conditions hold, with χ checked unchanged, and the choice
//! of fixed vertices.

use crate::error::{Error, Result};
use crate::fair::preparation::topology::{condition_violation, MeshTopology};
use crate::fair::SurfaceKind;
use crate::mesh::PolygonMesh;
use crate::subdiv::{refine_uniform, SubdivOptions};

/// The mesh refined (uniformly, by OpenSubdiv) the fewest times, at most `max_levels`, that
/// makes every face a quad and keeps special vertices two edges apart from each other and
/// from the boundary (§2) — and, for the G² surface, gives each a proper Sabin net (see
/// [`condition_violation`]); and the number of levels used.
///
/// # Errors
/// [`Error::Topology`] if the mesh is not manifold, if refinement changed V − E + F (it
/// must not), or if `max_levels` refinements do not meet the conditions; errors of
/// [`refine_uniform`].
pub fn prepare(
    mesh: &PolygonMesh,
    max_levels: u32,
    surface: SurfaceKind,
) -> Result<(PolygonMesh, u32)> {
    check_valence(mesh)?;
    let topo = MeshTopology::new(mesh)?;
    let chi = topo.euler_characteristic();
    let mut current = mesh.clone();
    let mut current_topo = topo;
    for level in 0..=max_levels {
        let violation = condition_violation(&current, &current_topo, surface);
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

/// The highest vertex valence (faces around a vertex) the optimizer accepts. Every
/// quadrature point near a vertex of valence n depends on its 2n + 1 neighbours, so the
/// Hessian's work there grows as n³ (measured, 2 cores: valence 64 in 6.7 s, 256 past a
/// minute and 3.6 GB); Kiciak's special vertices have valence 3 to 8 or so.
pub const MAX_FAIR_VALENCE: usize = 64;

/// Refuses a vertex of more than [`MAX_FAIR_VALENCE`] faces (refinement keeps valences).
fn check_valence(mesh: &PolygonMesh) -> Result<()> {
    let mut faces_at = vec![0usize; mesh.vertex_count()];
    for f in mesh.faces() {
        for &v in f {
            if let Some(count) = faces_at.get_mut(v as usize) {
                *count += 1;
            }
        }
    }
    match faces_at.iter().enumerate().max_by_key(|&(_, &n)| n) {
        Some((v, &n)) if n > MAX_FAIR_VALENCE => Err(Error::Topology(format!(
            "vertex {v} lies in {n} faces; fairing supports vertices of at most \
             {MAX_FAIR_VALENCE} (its work grows as the cube of the valence)"
        ))),
        _ => Ok(()),
    }
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
