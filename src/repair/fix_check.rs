//! Every suggested fix checked by applying it: the EAT's flaws are repaired (the kinds
//! found, holes as large as found), the result is scanned again, and each flaw is marked
//! `fix_verified` when a change touched it (a change of another kind may be the fix: a
//! duplicated facet deleted is what mends the non-manifold edges it made) and no flaw of
//! the repaired kinds is left on its vertices. A flaw whose fix is a judgment the repair does not make (the
//! border of an isolated facet: debris, or the surface?) stays unchecked.

use foldhash::{HashSet, HashSetExt};

use super::{repair_located, HoleFill, RepairOptions};
use crate::error::Result;
use crate::mesh::PolygonMesh;
use crate::topology::{scan, EatOptions, Flaw, FlawKind, LocatorOptions};

/// Whether the repair has an automatic fix for `flaw` at all.
fn has_automatic_fix(flaw: &Flaw) -> bool {
    flaw.kind != FlawKind::Hole || flaw.faces.is_empty()
}

/// Applies every flaw's fix to a copy of `mesh`, scans the result and sets each flaw's
/// `fix_verified`. `flaws` are those the EAT found on `mesh` with `locator`.
///
/// # Errors
/// What [`repair_located`] and [`scan`] return on a mesh that breaks its invariants.
pub fn check_fixes(mesh: &PolygonMesh, flaws: &mut [Flaw], locator: LocatorOptions) -> Result<()> {
    for flaw in flaws.iter_mut() {
        flaw.fix_verified = None;
    }
    // Only the kinds found, and holes only as large as the largest one with a fix: the
    // repair's passes are whole-mesh work, and an isolated facet's border (a face of 400 000
    // corners) is not filled just to be left unchecked.
    let fixable = || flaws.iter().filter(|f| has_automatic_fix(f));
    let kinds: Vec<FlawKind> = FlawKind::ALL
        .iter()
        .copied()
        .filter(|&k| fixable().any(|f| f.kind == k))
        .collect();
    if kinds.is_empty() {
        return Ok(());
    }
    let largest_hole = fixable()
        .filter(|f| f.kind == FlawKind::Hole)
        .map(|f| f.vertices.len())
        .max()
        .unwrap_or(0);
    let options = RepairOptions {
        kinds,
        max_hole_edges: largest_hole,
        // The check is about topology, which a fan and a spline fill change alike.
        hole_fill: HoleFill::Fan,
        locator,
    };
    let repaired = repair_located(mesh, flaws, &options)?;
    let after = scan(
        &repaired.mesh,
        &EatOptions {
            locator,
            halfedge: false,
            ..Default::default()
        },
    )?;
    let left: HashSet<u32> = repaired
        .remaining(&after, &options)
        .iter()
        .flat_map(|f| f.vertices.iter().copied())
        .collect();
    let mut touched_vertices = HashSet::new();
    let mut touched_faces = HashSet::new();
    for c in &repaired.changes {
        touched_vertices.extend(c.vertices.iter().copied());
        touched_faces.extend(c.faces.iter().copied());
    }
    for flaw in flaws.iter_mut() {
        if !has_automatic_fix(flaw) {
            continue;
        }
        let acted = flaw.vertices.iter().any(|v| touched_vertices.contains(v))
            || flaw.faces.iter().any(|f| touched_faces.contains(f));
        let clear = flaw
            .vertices
            .iter()
            .filter_map(|&v| repaired.vertex_after.get(v as usize).copied().flatten())
            .all(|v| !left.contains(&v));
        flaw.fix_verified = Some(acted && clear);
    }
    Ok(())
}
