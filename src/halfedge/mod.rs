//! The half-edge view of a polygon mesh: the only safe door to OpenMesh.
//!
//! [`build`] hands a `PolygonMesh` to OpenMesh in one batched call and returns, per face,
//! whether OpenMesh took it or why it refused it. What topology needs from a half-edge
//! structure is the [`HalfEdgeTopology`] trait, implemented by the OpenMesh bridge
//! ([`OpenMeshHalfEdge`]) and by a small pure-Rust reference ([`ReferenceTopology`]) so each
//! side of the bridge can be checked against the other.
//!
//! Face ids in every query are input face ids (positions in the `PolygonMesh`); vertex ids
//! are input vertex ids (every input vertex is added, referenced or not).

mod face_status;
mod openmesh_mesh;
mod reference;
mod summary;

pub use face_status::FaceStatus;
pub use openmesh_mesh::{build, openmesh_version, read_with_openmesh, Built, OpenMeshHalfEdge};
pub use reference::ReferenceTopology;
pub use summary::{HalfEdgeCounts, MeshSummary, RefusedFace};

use crate::error::Result;

/// Marks "no face" in edge and neighbour tables (a boundary side); `NONE` in bridge.cpp.
pub const NO_FACE: u32 = u32::MAX;

/// Cycles of vertices as offsets + vertices: loop `k` is `vertices[offsets[k]..offsets[k+1]]`.
#[derive(Debug, Clone, Default, PartialEq, Eq, serde::Serialize)]
pub struct Loops {
    pub offsets: Vec<u32>,
    pub vertices: Vec<u32>,
}

impl Loops {
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn get(&self, k: usize) -> &[u32] {
        &self.vertices[self.offsets[k] as usize..self.offsets[k + 1] as usize]
    }

    pub fn iter(&self) -> impl Iterator<Item = &[u32]> + '_ {
        (0..self.len()).map(move |k| self.get(k))
    }
}

/// Every edge with its two vertices and the face on each side (`NO_FACE` for a boundary
/// side). Side 0 is the face that runs the edge from `vertices[e][0]` to `vertices[e][1]`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct EdgeTable {
    pub vertices: Vec<[u32; 2]>,
    pub faces: Vec<[u32; 2]>,
}

/// Per face (in the order the faces were accepted), the face across each of its edges,
/// in corner order, or `NO_FACE`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct FaceNeighbours {
    /// Input id of each accepted face.
    pub faces: Vec<u32>,
    pub offsets: Vec<u32>,
    pub neighbours: Vec<u32>,
}

/// Connected components of faces linked through shared edges.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Components {
    pub count: u32,
    /// Input id of each accepted face and its component.
    pub faces: Vec<u32>,
    pub of_face: Vec<u32>,
}

/// What topology needs from a half-edge structure (manifold by construction: a face that
/// would break the structure is refused when it is built).
pub trait HalfEdgeTopology {
    fn vertex_count(&self) -> usize;
    fn edge_count(&self) -> usize;
    fn face_count(&self) -> usize;
    /// Boundary loops as vertex cycles, found by walking boundary half-edges and continuing
    /// at each vertex within the same fan of faces (so a pinch vertex closes one loop per fan).
    fn boundary_loops(&self) -> Result<Loops>;
    /// Number of edges at each vertex.
    fn vertex_valences(&self) -> Vec<u32>;
    fn edges(&self) -> EdgeTable;
    fn face_neighbours(&self) -> FaceNeighbours;
    fn connected_components(&self) -> Components;
}
