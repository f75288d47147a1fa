//! The Euler Accompanying Test and the half-edge structure under it (OpenMesh): flaws, cracks and
//! MeshLab's reference topology.

#[path = "../common/mod.rs"]
mod common;
mod cracks;
mod flaws;
mod halfedge_bridge;
mod halfedge_direct_build;
mod reference;
mod stamp;
