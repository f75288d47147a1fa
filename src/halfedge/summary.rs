//! A summary of a polygon soup and of what OpenMesh made of it: the report behind
//! `surfkit info` (human text and JSON).

use super::{build, FaceStatus, HalfEdgeTopology};
use crate::error::Result;
use crate::mesh::PolygonMesh;

/// A refused face: input id, corners, and why.
#[derive(Debug, Clone, serde::Serialize)]
pub struct RefusedFace {
    pub face: usize,
    pub vertices: Vec<u32>,
    pub reason: FaceStatus,
}

/// Counts of the soup and of the half-edge structure built from it.
#[derive(Debug, Clone, serde::Serialize)]
pub struct MeshSummary {
    pub vertices: usize,
    pub faces: usize,
    /// Faces per number of corners: `[(corners, faces)]`, non-zero entries only.
    pub arity_histogram: Vec<(usize, usize)>,
    pub bounding_box: Option<[[f64; 3]; 2]>,
    pub objects: usize,
    pub groups: usize,
    pub has_uvs: bool,
    /// Faces with texture coordinates (all of them, or fewer in an OBJ that gives some
    /// faces none; 0 without UVs).
    pub textured_faces: usize,
    pub has_quality: bool,
    pub has_colors: bool,
    /// The OpenMesh half-edge structure.
    pub halfedge: HalfEdgeCounts,
    /// Faces OpenMesh refused (all of them).
    pub refused: Vec<RefusedFace>,
    /// OpenMesh's own messages, captured.
    pub openmesh_messages: Vec<String>,
}

/// Counts of the half-edge structure (accepted faces only).
#[derive(Debug, Clone, serde::Serialize)]
pub struct HalfEdgeCounts {
    pub vertices: usize,
    pub edges: usize,
    pub faces: usize,
    pub boundary_loops: usize,
    pub components: u32,
    /// V − E + F of the structure, counting only vertices that some accepted face uses.
    pub euler_characteristic: i64,
}

impl MeshSummary {
    /// Builds the half-edge structure of `mesh` and summarizes both.
    ///
    /// # Errors
    /// Those of [`build`].
    pub fn of(mesh: &PolygonMesh) -> Result<MeshSummary> {
        let built = build(mesh)?;
        let he = &built.mesh;
        let valences = he.vertex_valences();
        let used = valences.iter().filter(|&&v| v > 0).count();
        let halfedge = HalfEdgeCounts {
            vertices: he.vertex_count(),
            edges: he.edge_count(),
            faces: he.face_count(),
            boundary_loops: he.boundary_loops()?.len(),
            components: he.connected_components().count,
            euler_characteristic: used as i64 - he.edge_count() as i64 + he.face_count() as i64,
        };
        let refused = built
            .refused()
            .map(|(f, reason)| RefusedFace {
                face: f,
                vertices: mesh.face(f).to_vec(),
                reason,
            })
            .collect();
        Ok(MeshSummary {
            vertices: mesh.vertex_count(),
            faces: mesh.face_count(),
            arity_histogram: mesh
                .arity_histogram()
                .into_iter()
                .enumerate()
                .filter(|(_, n)| *n > 0)
                .collect(),
            bounding_box: mesh.bounding_box().map(|(lo, hi)| [lo, hi]),
            objects: mesh.objects.as_ref().map_or(0, |l| l.names.len()),
            groups: mesh.groups.as_ref().map_or(0, |l| l.names.len()),
            has_uvs: mesh.uvs.is_some(),
            textured_faces: mesh
                .uvs
                .as_ref()
                .map_or(0, |uv| uv.textured_faces(&mesh.face_offsets)),
            has_quality: mesh.quality.is_some(),
            has_colors: mesh.colors.is_some(),
            halfedge,
            refused,
            openmesh_messages: built.messages.lines().map(str::to_string).collect(),
        })
    }
}
