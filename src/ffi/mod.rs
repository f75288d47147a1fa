//! The only place with `unsafe`: the raw bridges to OpenMesh (cxx) and OpenSubdiv (a plain
//! C shim bound by bindgen). Only `halfedge` and `subdiv` use this module; nothing else
//! sees a raw pointer, an OpenMesh handle or a cxx type.

#![allow(unsafe_code)]

pub mod openmesh;
pub mod opensubdiv;
