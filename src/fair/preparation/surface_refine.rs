//! Refinement of the *surface* of a mesh with a boundary, as Kiciak refines his meshes (§2):
//! Catmull–Clark refinement that loses the outermost ring of vertices at each level.
//!
//! Why: in the paper's refinement (doubling followed by averagings) an averaging makes a
//! facet only for each *internal* vertex, so every level drops the ring along the boundary.
//! The surface the optimizer sees is made of the complete patches only (facets without a
//! boundary vertex), and that surface is unchanged by the drop: the kept vertices are face
//! points, edge points of internal edges and vertex points of internal vertices, none of
//! which depends on a boundary rule. This reproduces the author's sizes: his 359-vertex
//! three-tube mesh refines to 1295 and 4895 vertices (plain Catmull–Clark: 1391 and 5087,
//! i.e. 3 · 32 and 3 · 64 boundary vertices more).

use crate::error::{Error, Result};
use crate::mesh::PolygonMesh;
use crate::subdiv::{refine_uniform, SubdivOptions};

/// `mesh` refined `levels` times: each level is one uniform Catmull–Clark refinement by
/// OpenSubdiv followed by removing every boundary vertex and every face touching one;
/// the remaining vertices keep their relative order and are numbered compactly.
///
/// A closed mesh has no boundary ring: it is refined as by [`refine_uniform`].
///
/// # Errors
/// [`Error::InvalidInput`] when a level leaves no face (the mesh is only one ring wide);
/// errors of [`refine_uniform`].
pub fn refine_surface(mesh: &PolygonMesh, levels: u32) -> Result<PolygonMesh> {
    // All the levels at once, before the first: refined one at a time, a request far
    // beyond the budget was refused only at the level that passed it, after the others.
    // (An upper bound: each level drops its boundary ring.)
    crate::subdiv::check_refinement_memory(mesh, levels, crate::limits::MemoryBudget::default())?;
    let mut current = mesh.clone();
    for level in 1..=levels {
        let refined = refine_uniform(&current, 1, &SubdivOptions::default())?;
        current = drop_boundary_ring(&refined);
        if current.face_count() == 0 {
            return Err(Error::InvalidInput(format!(
                "refinement level {level} leaves no face after dropping the boundary ring \
                 (the mesh is too thin: every face touches the boundary)"
            )));
        }
    }
    Ok(current)
}

/// Whether each of `vertex_count` vertices lies on an edge of only one of `faces`.
pub(crate) fn boundary_flags<'a>(
    faces: impl Iterator<Item = &'a [u32]>,
    vertex_count: usize,
) -> Vec<bool> {
    let mut uses: foldhash::HashMap<(u32, u32), u32> = Default::default();
    for f in faces {
        for (i, &a) in f.iter().enumerate() {
            let b = f[(i + 1) % f.len()];
            *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let mut boundary = vec![false; vertex_count];
    for (&(a, b), &n) in &uses {
        if n == 1 {
            boundary[a as usize] = true;
            boundary[b as usize] = true;
        }
    }
    boundary
}

/// `mesh` without its boundary vertices (those on an edge of one face) and the faces that
/// touch them; unused vertices are dropped too, the others renumbered in order.
pub fn drop_boundary_ring(mesh: &PolygonMesh) -> PolygonMesh {
    let boundary = boundary_flags(mesh.faces(), mesh.vertex_count());
    let kept: Vec<&[u32]> = mesh
        .faces()
        .filter(|f| f.iter().all(|&v| !boundary[v as usize]))
        .collect();
    let mut used = vec![false; mesh.vertex_count()];
    for f in &kept {
        for &v in *f {
            used[v as usize] = true;
        }
    }
    let mut id = vec![u32::MAX; mesh.vertex_count()];
    let mut positions = Vec::new();
    for v in 0..mesh.vertex_count() {
        if used[v] {
            id[v] = positions.len() as u32;
            positions.push(mesh.positions[v]);
        }
    }
    let mut out = PolygonMesh {
        positions,
        ..Default::default()
    };
    for f in kept {
        let renumbered: Vec<u32> = f.iter().map(|&v| id[v as usize]).collect();
        out.push_face(&renumbered);
    }
    out
}
