//! Repair: the fixes the EAT's flaw list suggests, applied (the paper's workflow ends with
//! the flaw "found and modified"). Each fix works on the facets the EAT located, records
//! what it changed, and the result is checked by the EAT again by the caller.
//!
//! - `editable`: the mesh under repair, facets by id, written back in input order.
//! - `change`: the record of one change (kind, action, ids before and after).
//! - `facets`: weld, degenerate and duplicated facets, unreferenced vertices.
//! - `boundary`: cracks split, missing facets and small holes closed.
//! - `manifold`: non-manifold edges and vertices split into one vertex per fan.
//! - `orientation`: facets reversed to agree with their neighbours.
//! - `fix_check`: the EAT's suggested fixes checked by applying them.

mod boundary;
mod change;
mod editable;
mod facets;
mod fix_check;
mod manifold;
mod orientation;
mod spline_fill;

pub use change::{Action, Change};
pub use fix_check::check_fixes;

use crate::error::Result;
use crate::mesh::PolygonMesh;
use crate::topology::{scan, EatOptions, EatReport, Flaw, FlawKind, LocatorOptions};

/// What to repair.
#[derive(Debug, Clone, PartialEq)]
pub struct RepairOptions {
    /// The flaw kinds to repair (holes only up to `max_hole_edges`).
    pub kinds: Vec<FlawKind>,
    /// Holes of up to this many edges are closed (0: none).
    pub max_hole_edges: usize,
    /// How those holes are closed.
    pub hole_fill: HoleFill,
    pub locator: LocatorOptions,
}

impl Default for RepairOptions {
    fn default() -> Self {
        RepairOptions {
            kinds: FlawKind::ALL
                .into_iter()
                .filter(|&k| k != FlawKind::Hole)
                .collect(),
            max_hole_edges: 0,
            hole_fill: HoleFill::default(),
            locator: LocatorOptions::default(),
        }
    }
}

/// How `repair` closes a hole.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum HoleFill {
    /// Triangles around a new vertex at the border's centroid.
    Fan,
    /// The 2022 paper's filled spline over the hole's least-squares plane where its
    /// surroundings are a height field there (a fan elsewhere, saying why).
    #[default]
    Spline,
}

impl RepairOptions {
    /// Whether flaws of `kind` are repaired.
    pub fn wants(&self, kind: FlawKind) -> bool {
        self.kinds.contains(&kind)
    }
}

/// The repaired mesh and what was changed.
#[derive(Debug, Clone)]
pub struct Repaired {
    pub mesh: PolygonMesh,
    pub changes: Vec<Change>,
    /// Texture coordinates were dropped because facets changed.
    pub uvs_dropped: bool,
    /// Input vertex id → its id in `mesh` (None: deleted).
    pub vertex_after: Vec<Option<u32>>,
}

impl Repaired {
    /// The flaws of `after` (the EAT of the repaired mesh) that the repair should have
    /// removed: those of the repaired kinds (holes up to the size asked for, not the
    /// border of an isolated facet), except the coincidence of a split vertex with its
    /// copies, which is the repair itself — unless a weld made that vertex: then the split
    /// undid the weld (two parts touching at a point, welded into a vertex of two fans,
    /// come apart again), and the coincidence the weld was asked to remove is left.
    pub fn remaining<'a>(&self, after: &'a EatReport, options: &RepairOptions) -> Vec<&'a Flaw> {
        let welded: std::collections::HashSet<u32> = self
            .changes
            .iter()
            .filter(|c| c.action == Action::WeldVertex)
            .filter_map(|c| c.vertices_after.last().copied().flatten())
            .collect();
        let split: std::collections::HashSet<(u32, u32)> = self
            .changes
            .iter()
            .filter(|c| c.action == Action::SplitVertex)
            .filter_map(|c| match c.vertices_after[..] {
                [Some(v), Some(copy)] if !welded.contains(&v) => Some((v.min(copy), v.max(copy))),
                _ => None,
            })
            .collect();
        after
            .flaws
            .iter()
            .filter(|f| options.wants(f.kind))
            // The border of an isolated facet is no hole to close: it would add the reverse.
            .filter(|f| {
                f.kind != FlawKind::Hole
                    || (f.faces.is_empty() && f.vertices.len() <= options.max_hole_edges)
            })
            .filter(|f| {
                f.kind != FlawKind::CoincidentVertices
                    || !split.contains(&(
                        f.vertices[0].min(f.vertices[1]),
                        f.vertices[0].max(f.vertices[1]),
                    ))
            })
            .collect()
    }
}

fn flaws_of(mesh: &PolygonMesh, options: &RepairOptions) -> Result<Vec<Flaw>> {
    let report = scan(
        mesh,
        &EatOptions {
            locator: options.locator,
            halfedge: false,
            ..Default::default()
        },
    )?;
    Ok(report.flaws)
}

/// Repairs the flaws of the chosen kinds, in an order where each fix sees the mesh the
/// earlier ones left: weld, degenerate and duplicated facets, cracks and missing facets
/// (and small holes), non-manifold edges and vertices, orientation, unreferenced vertices.
/// A mesh with nothing to repair comes back unchanged.
///
/// # Errors
/// [`crate::Error::InvalidInput`] when the mesh breaks its invariants.
pub fn repair(mesh: &PolygonMesh, options: &RepairOptions) -> Result<Repaired> {
    repair_located(mesh, &flaws_of(mesh, options)?, options)
}

/// [`repair`] for a caller that has already run the EAT on `mesh` with
/// `options.locator`: `flaws` are its flaws, so the input is not scanned again.
///
/// # Errors
/// [`crate::Error::InvalidInput`] when the mesh breaks its invariants.
pub fn repair_located(
    mesh: &PolygonMesh,
    flaws: &[Flaw],
    options: &RepairOptions,
) -> Result<Repaired> {
    let mut edit = editable::Editable::new(mesh);
    let mut changes = Vec::new();
    if options.wants(FlawKind::CoincidentVertices) {
        facets::weld(&mut edit, flaws, &mut changes);
    }
    if options.wants(FlawKind::DegenerateFacet) || !changes.is_empty() {
        // Welding can fold a facet onto itself: cleaning it is part of the weld.
        facets::clean_degenerate(&mut edit, &mut changes);
    }
    if options.wants(FlawKind::DuplicatedFacet) {
        facets::delete_duplicates(&mut edit, &mut changes);
    }
    // The boundary fixes need the flaws of the mesh these facet fixes left: the input's
    // when they changed nothing.
    let (later, facet_ids) = if changes.is_empty() {
        (flaws.to_vec(), edit.output_order())
    } else {
        let live = edit.live();
        (flaws_of(&live.mesh, options)?, live.facet_ids)
    };
    let flaws: Vec<Flaw> = later
        .into_iter()
        .filter(|f| options.wants(f.kind))
        .collect();
    boundary::split_cracks(&mut edit, &facet_ids, &flaws, &mut changes);
    boundary::close_loops(
        &mut edit,
        &flaws,
        options.max_hole_edges,
        options.hole_fill,
        &mut changes,
    );
    let (edges, vertices) = (
        options.wants(FlawKind::NonManifoldEdge),
        options.wants(FlawKind::NonManifoldVertex),
    );
    if edges || vertices {
        let before = changes.len();
        manifold::split_fans(&mut edit, edges, vertices, &mut changes);
        if changes.len() > before {
            // Taking facets apart can open loops the flaws above did not have (two solids
            // glued on a duplicated facet lose that facet's copy on one side): close the
            // ones of the kinds asked for.
            let live = edit.live();
            let opened: Vec<Flaw> = flaws_of(&live.mesh, options)?
                .into_iter()
                .filter(|f| f.kind.is_boundary_loop() && options.wants(f.kind))
                .collect();
            boundary::close_loops(
                &mut edit,
                &opened,
                options.max_hole_edges,
                options.hole_fill,
                &mut changes,
            );
        }
    }
    if options.wants(FlawKind::InconsistentOrientation) {
        orientation::orient(&mut edit, &mut changes);
    }
    if options.wants(FlawKind::UnreferencedVertex) {
        facets::delete_unreferenced(&mut edit, &mut changes);
    }
    if changes.is_empty() {
        return Ok(Repaired {
            mesh: mesh.clone(),
            changes,
            uvs_dropped: false,
            vertex_after: (0..mesh.positions.len() as u32).map(Some).collect(),
        });
    }
    let mut finished = edit.finish(mesh, &mut changes);
    finished.vertex_after.truncate(mesh.positions.len());
    Ok(Repaired {
        mesh: finished.mesh,
        changes,
        uvs_dropped: finished.uvs_dropped,
        vertex_after: finished.vertex_after,
    })
}
