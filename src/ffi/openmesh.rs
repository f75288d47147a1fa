//! cxx bridge to `cpp/openmesh/bridge.{h,cpp}`: an OpenMesh PolyMesh (double points) built
//! from a soup in one call and queried through flat arrays. C++ exceptions arrive as
//! `Err(cxx::Exception)`.

#[cxx::bridge(namespace = "surfkit::om")]
pub mod bridge {
    /// What happened to each input face, and everything OpenMesh said about it.
    struct BuildLog {
        /// One `halfedge::FaceStatus` code per input face, or none when `all_added`.
        face_status: Vec<u8>,
        /// Every face was added (the direct build of an oriented 2-manifold).
        all_added: bool,
        messages: String,
    }

    unsafe extern "C++" {
        include!("surfkit/cpp/openmesh/bridge.h");

        type HalfEdgeMesh;

        fn build(
            positions: &[f64],
            offsets: &[u32],
            indices: &[u32],
            log: &mut BuildLog,
        ) -> Result<UniquePtr<HalfEdgeMesh>>;
        fn read_with_openmesh(path: &str) -> Result<UniquePtr<HalfEdgeMesh>>;
        fn openmesh_version() -> String;

        fn n_vertices(self: &HalfEdgeMesh) -> usize;
        fn n_edges(self: &HalfEdgeMesh) -> usize;
        fn n_faces(self: &HalfEdgeMesh) -> usize;
        fn face_ids(self: &HalfEdgeMesh, out: &mut Vec<u32>);
        fn boundary_loops(
            self: &HalfEdgeMesh,
            offsets: &mut Vec<u32>,
            vertices: &mut Vec<u32>,
        ) -> Result<()>;
        fn vertex_valences(self: &HalfEdgeMesh, out: &mut Vec<u32>);
        fn edges(self: &HalfEdgeMesh, vertices: &mut Vec<u32>, faces: &mut Vec<u32>);
        fn face_neighbours(self: &HalfEdgeMesh, offsets: &mut Vec<u32>, neighbours: &mut Vec<u32>);
        fn connected_components(self: &HalfEdgeMesh, face_component: &mut Vec<u32>) -> u32;
        fn positions(self: &HalfEdgeMesh, out: &mut Vec<f64>);
        fn set_positions(self: Pin<&mut HalfEdgeMesh>, positions: &[f64]) -> Result<()>;
        fn add_face(
            self: Pin<&mut HalfEdgeMesh>,
            corners: &[u32],
            input_id: u32,
            message: &mut String,
        ) -> Result<u8>;
        fn add_faces(
            self: Pin<&mut HalfEdgeMesh>,
            offsets: &[u32],
            indices: &[u32],
            first_input_id: u32,
            status: &mut Vec<u8>,
            messages: &mut String,
        ) -> Result<()>;
        fn add_vertices(self: Pin<&mut HalfEdgeMesh>, positions: &[f64]) -> Result<()>;
        fn write_with_openmesh(self: &HalfEdgeMesh, path: &str) -> Result<()>;
    }
}

// SAFETY: a HalfEdgeMesh owns its OpenMesh PolyMesh outright and keeps no thread-local or
// shared state (omerr's capture is set up per call, under a lock), so it may be moved to
// and dropped on another thread: a modelling program's companion may live on any thread.
unsafe impl Send for bridge::HalfEdgeMesh {}
