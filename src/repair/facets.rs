//! Fixes on single facets and vertices: weld coincident vertices, clean degenerate facets,
//! delete duplicated ones, delete unreferenced vertices.

use foldhash::{HashMap as FxHashMap, HashMapExt};

use super::change::{Action, Change};
use super::editable::Editable;
use crate::topology::{show_ids, Flaw, FlawKind};

/// Welds each `coincident_vertices` flaw's vertex into the earlier one it lies on.
pub fn weld(mesh: &mut Editable, flaws: &[Flaw], changes: &mut Vec<Change>) {
    let mut into: FxHashMap<u32, u32> = FxHashMap::new();
    for f in flaws
        .iter()
        .filter(|f| f.kind == FlawKind::CoincidentVertices)
    {
        into.insert(f.vertices[0], f.vertices[1]);
    }
    if into.is_empty() {
        return;
    }
    for corners in mesh.faces.iter_mut().flatten() {
        for v in corners.iter_mut() {
            if let Some(&u) = into.get(v) {
                *v = u;
            }
        }
    }
    let mut pairs: Vec<(u32, u32)> = into.into_iter().collect();
    pairs.sort_unstable();
    for (v, u) in pairs {
        mesh.removed_vertex[v as usize] = true;
        changes.push(Change::new(
            FlawKind::CoincidentVertices,
            Action::WeldVertex,
            Vec::new(),
            vec![v, u],
            welded_where(mesh, v, u),
        ));
    }
}

/// The description of welding `v` into `u`: at the same place, or how far apart (a weld
/// within a tolerance moves the facets of `v`).
fn welded_where(mesh: &Editable, v: u32, u: u32) -> String {
    let (p, q) = (mesh.positions[v as usize], mesh.positions[u as usize]);
    if p == q {
        format!("vertex {v} welded into vertex {u} at the same place")
    } else {
        format!(
            "vertex {v} welded into vertex {u}, {:.3e} away (within the weld tolerance)",
            crate::mesh::vector::distance(p, q)
        )
    }
}

/// Removes repeated consecutive corners (a welded edge, a doubled corner); a facet left
/// with fewer than 3 corners, or with a vertex repeated apart, is deleted.
pub fn clean_degenerate(mesh: &mut Editable, changes: &mut Vec<Change>) {
    for f in 0..mesh.faces.len() {
        let Some(corners) = mesh.faces[f].as_ref() else {
            continue;
        };
        if crate::mesh::io::degeneracy(corners).is_none() {
            continue;
        }
        let mut kept: Vec<u32> = Vec::with_capacity(corners.len());
        for &v in corners {
            if kept.last() != Some(&v) {
                kept.push(v);
            }
        }
        while kept.len() > 1 && kept.first() == kept.last() {
            kept.pop();
        }
        let before = corners.clone();
        if kept.len() >= 3 && crate::mesh::io::degeneracy(&kept).is_none() {
            changes.push(Change::new(
                FlawKind::DegenerateFacet,
                Action::RemoveRepeatedCorner,
                vec![f as u32],
                kept.clone(),
                format!(
                    "facet {f}: corners {} become {}",
                    show_ids(&before),
                    show_ids(&kept)
                ),
            ));
            mesh.faces[f] = Some(kept);
        } else {
            changes.push(Change::new(
                FlawKind::DegenerateFacet,
                Action::DeleteFacet,
                vec![f as u32],
                before.clone(),
                format!(
                    "facet {f} with corners {} has no area left: deleted",
                    show_ids(&before)
                ),
            ));
            mesh.faces[f] = None;
        }
    }
}

/// Deletes each facet whose vertex set an earlier facet already has.
pub fn delete_duplicates(mesh: &mut Editable, changes: &mut Vec<Change>) {
    let mut first: FxHashMap<Vec<u32>, u32> = FxHashMap::new();
    for f in mesh.output_order() {
        let Some(corners) = mesh.faces[f as usize].as_ref() else {
            continue;
        };
        let mut key = corners.clone();
        key.sort_unstable();
        match first.get(&key) {
            Some(&g) => {
                changes.push(Change::new(
                    FlawKind::DuplicatedFacet,
                    Action::DeleteFacet,
                    vec![f, g],
                    corners.clone(),
                    format!("facet {f} has the vertices of facet {g}: deleted"),
                ));
                mesh.faces[f as usize] = None;
            }
            None => {
                first.insert(key, f);
            }
        }
    }
}

/// Deletes the input vertices no facet uses.
pub fn delete_unreferenced(mesh: &mut Editable, changes: &mut Vec<Change>) {
    let mut used = vec![false; mesh.positions.len()];
    for corners in mesh.faces.iter().flatten() {
        for &v in corners {
            used[v as usize] = true;
        }
    }
    for (v, &is_used) in used.iter().enumerate() {
        if !is_used && !mesh.removed_vertex[v] {
            mesh.removed_vertex[v] = true;
            changes.push(Change::new(
                FlawKind::UnreferencedVertex,
                Action::DeleteVertex,
                Vec::new(),
                vec![v as u32],
                format!("vertex {v} is used by no facet: deleted"),
            ));
        }
    }
}
