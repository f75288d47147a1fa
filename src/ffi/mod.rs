//! The only place with `unsafe`: the raw bridges to OpenMesh (cxx) and OpenSubdiv (a plain
//! C shim bound by bindgen), and the global allocator (its large blocks on huge pages).
//! Only `halfedge` and `subdiv` use the bridges; nothing else sees a raw pointer, an
//! OpenMesh handle or a cxx type.

#![allow(unsafe_code)]

#[cfg(target_os = "linux")]
pub mod huge_pages;
pub mod openmesh;
pub mod opensubdiv;
