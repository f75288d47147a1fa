//! `topology::scan`: the Euler Accompanying Test over a finished mesh — every facet
//! registered (EAT-TA), the statistics (EAT-SA) at each test point, the OpenMesh
//! half-edge structure of the accepted facets, per-component topology and every flaw.

use super::flaw::{Flaw, FlawKind};
use super::locator::{locate_with, GeometryFacts, LocatorOptions};
use super::progressive::{Checkpoint, ModelCompanion};
use super::statistics::EatStatistics;
use super::structure::Structure;
use crate::error::{Error, Result};
use crate::halfedge::{self, FaceStatus, HalfEdgeTopology};
use crate::mesh::PolygonMesh;

/// A test point: after `facets` facets, χ should be `expected`.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct TestPoint {
    pub label: String,
    pub facets: usize,
    pub expected: i64,
}

/// Options of [`scan`].
#[derive(Debug, Clone, Default)]
pub struct EatOptions {
    /// Test points in increasing facet count (the last may be the whole mesh).
    pub test_points: Vec<TestPoint>,
    pub locator: LocatorOptions,
    /// Also build the OpenMesh half-edge structure and report what it refused.
    pub halfedge: bool,
}

/// Topology of one edge-connected component.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ComponentTopology {
    pub vertices: usize,
    pub edges: usize,
    pub facets: usize,
    pub euler_characteristic: i64,
    pub boundary_loops: usize,
    /// None when an edge with three or more facets makes orientation meaningless.
    pub orientable: Option<bool>,
    /// Orientable: (2 − b − χ)/2; non-orientable: the number of cross-caps 2 − b − χ;
    /// None for a non-manifold component.
    pub genus: Option<i64>,
    pub manifold: bool,
}

/// Whole-mesh counts, with the definitions of `fixtures/meshes/REFERENCE.json`.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct TopologyCounts {
    pub vertices_in_file: usize,
    pub vertices_referenced: usize,
    pub edges: usize,
    pub facets: usize,
    pub euler_characteristic: i64,
    pub boundary_edges: usize,
    /// Connected pieces of the boundary-edge graph.
    pub boundary_loops: usize,
    /// Cycles of a half-edge walk that continues within each fan (differs at pinch
    /// vertices); None when a non-manifold edge or inconsistent orientation makes it undefined.
    pub boundary_loops_walk: Option<usize>,
    pub non_manifold_edges: usize,
    pub non_manifold_vertices: usize,
    pub components: usize,
    /// (2c − b − χ)/2 for an orientable mesh without non-manifold elements or degenerate
    /// facets (MeshLab's formula); None where a component is non-orientable.
    pub genus: Option<i64>,
    /// Cross-caps, 2c − b − χ, when every component is a non-orientable manifold (Möbius
    /// strip 1, Klein bottle 2); a mesh mixing both kinds has its genera per component.
    pub non_orientable_genus: Option<i64>,
    pub unreferenced_vertices: usize,
    pub duplicated_facets: usize,
    pub degenerate_facets: usize,
    pub inconsistent_orientation_edges: usize,
    pub coincident_vertices: usize,
}

/// What OpenMesh's half-edge structure made of the facets.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct HalfEdgeReport {
    pub accepted: usize,
    pub refused: Vec<(u32, FaceStatus)>,
    pub boundary_loops: usize,
}

/// The full result of a scan.
#[derive(Debug, Clone, serde::Serialize)]
pub struct EatReport {
    pub statistics: EatStatistics,
    pub counts: TopologyCounts,
    pub components: Vec<ComponentTopology>,
    pub checkpoints: Vec<(TestPoint, Checkpoint)>,
    /// The first failing test point, if any.
    pub first_failure: Option<usize>,
    pub flaws: Vec<Flaw>,
    pub halfedge: Option<HalfEdgeReport>,
}

impl EatReport {
    /// Number of flaws of each kind (kinds with none omitted).
    pub fn flaw_counts(&self) -> Vec<(FlawKind, usize)> {
        FlawKind::ALL
            .iter()
            .map(|&k| (k, self.flaws.iter().filter(|f| f.kind == k).count()))
            .filter(|(_, n)| *n > 0)
            .collect()
    }

    /// Whether every test point was verified.
    pub fn verified(&self) -> bool {
        self.first_failure.is_none()
    }
}

/// Runs the Euler Accompanying Test over `mesh`: registers every facet in order, checks χ
/// at each test point (Liu et al. 2020 §3.4), then locates every flaw.
///
/// # Errors
/// [`Error::InvalidInput`] when the mesh breaks its invariants, test points are not in
/// increasing order within the face count, or the weld tolerance is not a finite number
/// ≥ 0 (an infinite one makes every vertex coincident with every other); [`Error::Ffi`]
/// when OpenMesh fails.
pub fn scan(mesh: &PolygonMesh, options: &EatOptions) -> Result<EatReport> {
    mesh.validate()?;
    let weld = options.locator.weld_tolerance;
    if !(weld.is_finite() && weld >= 0.0) {
        return Err(Error::InvalidInput(format!(
            "weld tolerance {weld} must be a finite number ≥ 0"
        )));
    }
    let faces = mesh.face_count();
    if let Some(w) = options
        .test_points
        .windows(2)
        .find(|w| w[1].facets < w[0].facets)
    {
        return Err(Error::InvalidInput(format!(
            "test points must not decrease: {} after {}",
            w[1].facets, w[0].facets
        )));
    }
    if let Some(t) = options.test_points.iter().find(|t| t.facets > faces) {
        return Err(Error::InvalidInput(format!(
            "test point {} is after facet {} but the mesh has {faces} facets",
            t.label, t.facets
        )));
    }
    // OpenMesh's half-edge structure needs only the mesh: it is built on the other core
    // while the registry, the structure and the locator run here.
    let (halfedge, registry_side) = rayon::join(
        || options.halfedge.then(|| halfedge_report(mesh)).transpose(),
        || accompany(mesh, options),
    );
    let mut report = registry_side?;
    report.halfedge = halfedge?;
    Ok(report)
}

/// What OpenMesh's half-edge structure takes of the facets.
fn halfedge_report(mesh: &PolygonMesh) -> Result<HalfEdgeReport> {
    let built = halfedge::build(mesh)?;
    Ok(HalfEdgeReport {
        accepted: built.mesh.face_count(),
        refused: built.refused().map(|(f, s)| (f as u32, s)).collect(),
        boundary_loops: built.mesh.boundary_loops()?.len(),
    })
}

/// The accompanying test proper: registration with test points, then structure and flaws.
fn accompany(mesh: &PolygonMesh, options: &EatOptions) -> Result<EatReport> {
    let faces = mesh.face_count();
    let mut companion =
        ModelCompanion::with_capacity(mesh.vertex_count(), faces, mesh.face_indices.len());
    let mut checkpoints = Vec::new();
    let mut first_failure = None;
    let mut next_point = options.test_points.iter().peekable();
    let mut check = |companion: &mut ModelCompanion,
                     done: usize,
                     checkpoints: &mut Vec<(TestPoint, Checkpoint)>| {
        while let Some(t) = next_point.next_if(|t| t.facets == done) {
            let c = companion.checkpoint(t.expected);
            if !c.verified && first_failure.is_none() {
                first_failure = Some(checkpoints.len());
            }
            checkpoints.push((t.clone(), c));
        }
    };
    check(&mut companion, 0, &mut checkpoints);
    for (f, corners) in mesh.faces().enumerate() {
        companion.register(corners, f as u32)?;
        check(&mut companion, f + 1, &mut checkpoints);
    }
    let registry = companion.registry();
    // The structure and the purely geometric facts are independent: build them side by side.
    let (structure, geometry) = rayon::join(
        || Structure::of(registry),
        || GeometryFacts::of(registry, &mesh.positions, &options.locator),
    );
    let ids: Vec<u32> = (0..faces as u32).collect();
    let (flaws, walks) = locate_with(registry, &structure, &mesh.positions, &ids, &geometry);
    let counts = counts(mesh, registry, &structure, &flaws, &walks);
    let components = component_topology(registry, &structure, &walks);
    Ok(EatReport {
        statistics: companion.statistics(),
        counts,
        components,
        checkpoints,
        first_failure,
        flaws,
        halfedge: None,
    })
}

fn counts(
    mesh: &PolygonMesh,
    registry: &super::EatRegistry,
    structure: &Structure,
    flaws: &[Flaw],
    walks: &[Option<u32>],
) -> TopologyCounts {
    let count = |k: FlawKind| flaws.iter().filter(|f| f.kind == k).count();
    let stats = EatStatistics::of(registry);
    let nm_edges = registry.edges().iter().filter(|e| e.ec > 2).count();
    let inconsistent = registry.edges().iter().filter(|e| e.inconsistent()).count();
    let degenerate = count(FlawKind::DegenerateFacet);
    let boundary_edges = registry.edges().iter().filter(|e| e.ec == 1).count();
    let walk = walks.len();
    let manifold = nm_edges == 0 && structure.non_manifold_vertices.is_empty() && degenerate == 0;
    let loops = structure.boundary_loop_count as i64;
    let c = i64::from(structure.component_count);
    let orientable = &structure.component_orientable;
    TopologyCounts {
        vertices_in_file: mesh.vertex_count(),
        vertices_referenced: stats.vertices,
        edges: stats.edges,
        facets: stats.facets,
        euler_characteristic: stats.euler_characteristic,
        boundary_edges,
        boundary_loops: structure.boundary_loop_count as usize,
        // With no boundary there is nothing to walk; otherwise a non-manifold edge or an
        // inconsistent orientation leaves the next boundary half-edge ambiguous.
        boundary_loops_walk: (boundary_edges == 0 || (nm_edges == 0 && inconsistent == 0))
            .then_some(walk),
        non_manifold_edges: nm_edges,
        non_manifold_vertices: structure.non_manifold_vertices.len(),
        components: structure.component_count as usize,
        genus: (manifold && orientable.iter().all(|&o| o == Some(true)))
            .then(|| (2 * c - loops - stats.euler_characteristic) / 2),
        non_orientable_genus: (manifold
            && !orientable.is_empty()
            && orientable.iter().all(|&o| o == Some(false)))
        .then(|| 2 * c - loops - stats.euler_characteristic),
        unreferenced_vertices: count(FlawKind::UnreferencedVertex),
        duplicated_facets: count(FlawKind::DuplicatedFacet),
        degenerate_facets: degenerate,
        inconsistent_orientation_edges: inconsistent,
        coincident_vertices: count(FlawKind::CoincidentVertices),
    }
}

/// Per component: counts, loops (boundary walks lying in it), orientability and genus.
fn component_topology(
    registry: &super::EatRegistry,
    structure: &Structure,
    walks: &[Option<u32>],
) -> Vec<ComponentTopology> {
    let n = structure.component_count as usize;
    let mut out: Vec<ComponentTopology> = (0..n)
        .map(|c| ComponentTopology {
            vertices: 0,
            edges: 0,
            facets: 0,
            euler_characteristic: 0,
            boundary_loops: 0,
            orientable: structure.component_orientable[c],
            genus: None,
            manifold: true,
        })
        .collect();
    for &c in &structure.facet_component {
        out[c as usize].facets += 1;
    }
    for (e, item) in registry.edges().iter().enumerate() {
        let c = structure.facet_component[structure.first_side(e).facet as usize] as usize;
        out[c].edges += 1;
        if item.ec > 2 {
            out[c].manifold = false;
        }
    }
    for c in walks.iter().flatten() {
        out[*c as usize].boundary_loops += 1;
    }
    // Vertices per component: a pinch vertex between components counts in each. Most
    // vertices lie in one component: keep the first, and collect the rare others.
    let (_, corners) = registry.facet_arrays();
    let mut first_component =
        vec![u32::MAX; corners.iter().copied().max().map_or(0, |m| m as usize + 1)];
    let mut others: Vec<(u32, u32)> = Vec::new();
    for (&v, &f) in corners.iter().zip(&structure.corner_facet) {
        let c = structure.facet_component[f as usize];
        let first = &mut first_component[v as usize];
        if *first == u32::MAX {
            *first = c;
            out[c as usize].vertices += 1;
        } else if *first != c {
            others.push((v, c));
        }
    }
    others.sort_unstable();
    others.dedup();
    for (_, c) in others {
        out[c as usize].vertices += 1;
    }
    // A component is non-manifold where two of its own fans meet at a vertex, and where
    // one of its facets is degenerate.
    let pinched: foldhash::HashSet<u32> = structure.non_manifold_vertices.iter().copied().collect();
    let mut fans: Vec<(u32, u32, u32)> = corners
        .iter()
        .enumerate()
        .filter(|(_, v)| pinched.contains(v))
        .map(|(k, &v)| {
            (
                v,
                structure.corner_fan[k],
                structure.facet_component[structure.corner_facet[k] as usize],
            )
        })
        .collect();
    fans.sort_unstable();
    fans.dedup();
    for w in fans.windows(2) {
        if w[0].0 == w[1].0 && w[0].2 == w[1].2 {
            out[w[0].2 as usize].manifold = false;
        }
    }
    let (offsets, _) = registry.facet_arrays();
    for f in 0..registry.facet_count() {
        if crate::mesh::io::degeneracy(&corners[offsets[f] as usize..offsets[f + 1] as usize])
            .is_some()
        {
            out[structure.facet_component[f] as usize].manifold = false;
        }
    }
    for comp in out.iter_mut() {
        comp.euler_characteristic = comp.vertices as i64 - comp.edges as i64 + comp.facets as i64;
        let deficit = 2 - comp.boundary_loops as i64 - comp.euler_characteristic;
        comp.genus = match (comp.manifold, comp.orientable) {
            (true, Some(true)) => Some(deficit / 2),
            (true, Some(false)) => Some(deficit),
            _ => None,
        };
    }
    out
}
