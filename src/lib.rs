//! surfkit: the quality of surface models.
//!
//! Layers (see DESIGN.md): `mesh` (polygon soup + files) ← `halfedge` (the OpenMesh bridge)
//! ← `topology`; `subdiv` (the OpenSubdiv bridge) ← `fair`; `spline` ← `fit`; `cli` on top.
//! Only `ffi` holds `unsafe` code.

#![deny(unsafe_code)]

pub mod error;
pub mod fair;
mod ffi;
pub mod mesh;
pub mod subdiv;
pub mod tolerance;

pub use error::{Error, Result};
