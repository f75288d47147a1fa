//! The OpenMesh side of the seam: a PolyMesh owned from Rust.

use std::path::Path;

use cxx::UniquePtr;

use super::{Components, EdgeTable, FaceNeighbours, FaceStatus, HalfEdgeTopology, Loops};
use crate::error::{Error, Result};
use crate::ffi::openmesh::bridge;
use crate::mesh::PolygonMesh;

/// An OpenMesh `PolyMesh` (double-precision points) built by surfkit.
pub struct OpenMeshHalfEdge {
    inner: UniquePtr<bridge::HalfEdgeMesh>,
}

/// The result of [`build`]: the half-edge mesh, what happened to each input face, and
/// everything OpenMesh said (captured, never printed).
pub struct Built {
    pub mesh: OpenMeshHalfEdge,
    pub face_status: Vec<FaceStatus>,
    pub messages: String,
    /// The structure was built directly (an oriented 2-manifold), not face by face.
    pub built_directly: bool,
}

impl Built {
    /// Input ids and reasons of the faces OpenMesh refused.
    pub fn refused(&self) -> impl Iterator<Item = (usize, FaceStatus)> + '_ {
        self.face_status
            .iter()
            .enumerate()
            .filter(|(_, s)| **s != FaceStatus::Added)
            .map(|(f, s)| (f, *s))
    }
}

fn ffi_error(e: cxx::Exception) -> Error {
    Error::Ffi {
        library: "OpenMesh",
        message: e.what().to_string(),
    }
}

/// Builds an OpenMesh PolyMesh from `mesh` in one call: every vertex (referenced or not)
/// in input order, then every face in input order. Degenerate faces (fewer than 3 corners,
/// a repeated vertex) are not given to OpenMesh; the others are added with
/// `PolyConnectivity::add_face`, and refused faces are classified by OpenMesh's message.
///
/// # Errors
/// [`Error::InvalidInput`] when the mesh breaks its invariants (index out of range,
/// non-finite coordinate); [`Error::Ffi`] if OpenMesh throws.
pub fn build(mesh: &PolygonMesh) -> Result<Built> {
    mesh.validate()?;
    let mut log = bridge::BuildLog {
        face_status: Vec::new(),
        all_added: false,
        messages: String::new(),
    };
    let inner = bridge::build(
        mesh.positions_flat(),
        &mesh.face_offsets,
        &mesh.face_indices,
        &mut log,
    )
    .map_err(ffi_error)?;
    Ok(Built {
        mesh: OpenMeshHalfEdge { inner },
        face_status: if log.all_added {
            vec![FaceStatus::Added; mesh.face_count()]
        } else {
            log.face_status
                .into_iter()
                .map(FaceStatus::from_code)
                .collect()
        },
        messages: log.messages,
        built_directly: log.all_added,
    })
}

/// Reads a file with OpenMesh's own importer. For benchmarks and cross-checks only:
/// OpenMesh re-adds refused faces on duplicated vertices, which changes V and χ, so
/// surfkit never uses it to measure topology.
///
/// # Errors
/// [`Error::Ffi`] with OpenMesh's message when it cannot read the file.
pub fn read_with_openmesh(path: &Path) -> Result<OpenMeshHalfEdge> {
    let p = path
        .to_str()
        .ok_or_else(|| Error::InvalidInput(format!("{}: path is not UTF-8", path.display())))?;
    let inner = bridge::read_with_openmesh(p).map_err(ffi_error)?;
    Ok(OpenMeshHalfEdge { inner })
}

/// The version of the OpenMesh library surfkit was built against.
pub fn openmesh_version() -> String {
    bridge::openmesh_version()
}

impl OpenMeshHalfEdge {
    /// Vertex positions as a flat `[x0, y0, z0, …]` array.
    pub fn positions(&self) -> Vec<f64> {
        let mut out = Vec::new();
        self.inner.positions(&mut out);
        out
    }

    /// Moves every vertex (topology unchanged).
    ///
    /// # Errors
    /// [`Error::Ffi`] when `positions` does not hold 3 coordinates per vertex.
    pub fn set_positions(&mut self, positions: &[[f64; 3]]) -> Result<()> {
        self.inner
            .pin_mut()
            .set_positions(positions.as_flattened())
            .map_err(ffi_error)
    }

    /// Adds one face (input id `input_id`) to the mesh, as a modelling program adding
    /// facets one by one would; returns what OpenMesh did and what it said.
    ///
    /// # Errors
    /// [`Error::Ffi`] when a corner names no vertex of the mesh.
    pub fn add_face(&mut self, corners: &[u32], input_id: u32) -> Result<(FaceStatus, String)> {
        let mut message = String::new();
        let code = self
            .inner
            .pin_mut()
            .add_face(corners, input_id, &mut message)
            .map_err(ffi_error)?;
        Ok((FaceStatus::from_code(code), message))
    }

    /// Adds faces in one call (offsets + corners, ids `first_input_id`, `first_input_id + 1`,
    /// …): what happened to each and what OpenMesh said.
    ///
    /// # Errors
    /// [`Error::Ffi`] when the offsets are malformed or a corner names no vertex.
    pub fn add_faces(
        &mut self,
        offsets: &[u32],
        corners: &[u32],
        first_input_id: u32,
    ) -> Result<(Vec<FaceStatus>, String)> {
        let (mut codes, mut messages) = (Vec::new(), String::new());
        self.inner
            .pin_mut()
            .add_faces(offsets, corners, first_input_id, &mut codes, &mut messages)
            .map_err(ffi_error)?;
        Ok((
            codes.into_iter().map(FaceStatus::from_code).collect(),
            messages,
        ))
    }

    /// Appends vertices (ids continue after the existing ones).
    ///
    /// # Errors
    /// [`Error::Ffi`] when `positions` is not made of triples.
    pub fn add_vertices(&mut self, positions: &[[f64; 3]]) -> Result<()> {
        self.inner
            .pin_mut()
            .add_vertices(positions.as_flattened())
            .map_err(ffi_error)
    }

    /// Writes the mesh with OpenMesh's own exporter (a cross-check of surfkit's writers).
    ///
    /// # Errors
    /// [`Error::Ffi`] with OpenMesh's message.
    pub fn write_with_openmesh(&self, path: &Path) -> Result<()> {
        let p = path
            .to_str()
            .ok_or_else(|| Error::InvalidInput(format!("{}: path is not UTF-8", path.display())))?;
        self.inner.write_with_openmesh(p).map_err(ffi_error)
    }
}

impl HalfEdgeTopology for OpenMeshHalfEdge {
    fn vertex_count(&self) -> usize {
        self.inner.n_vertices()
    }

    fn edge_count(&self) -> usize {
        self.inner.n_edges()
    }

    fn face_count(&self) -> usize {
        self.inner.n_faces()
    }

    fn boundary_loops(&self) -> Result<Loops> {
        let mut loops = Loops::default();
        self.inner
            .boundary_loops(&mut loops.offsets, &mut loops.vertices)
            .map_err(ffi_error)?;
        Ok(loops)
    }

    fn vertex_valences(&self) -> Vec<u32> {
        let mut out = Vec::new();
        self.inner.vertex_valences(&mut out);
        out
    }

    fn edges(&self) -> EdgeTable {
        let (mut vertices, mut faces) = (Vec::new(), Vec::new());
        self.inner.edges(&mut vertices, &mut faces);
        EdgeTable {
            vertices: vertices.chunks_exact(2).map(|c| [c[0], c[1]]).collect(),
            faces: faces.chunks_exact(2).map(|c| [c[0], c[1]]).collect(),
        }
    }

    fn face_neighbours(&self) -> FaceNeighbours {
        let mut n = FaceNeighbours::default();
        self.inner
            .face_neighbours(&mut n.offsets, &mut n.neighbours);
        n.faces = self.accepted_faces();
        n
    }

    fn connected_components(&self) -> Components {
        let mut c = Components::default();
        c.count = self.inner.connected_components(&mut c.of_face);
        c.faces = self.accepted_faces();
        c
    }
}

impl OpenMeshHalfEdge {
    /// Input ids of the faces OpenMesh holds, in its own order.
    fn accepted_faces(&self) -> Vec<u32> {
        let mut faces = Vec::new();
        self.inner.face_ids(&mut faces);
        faces
    }
}
