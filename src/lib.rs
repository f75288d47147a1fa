//! surfkit: the quality of surface models.
//!
//! Layers (see DESIGN.md): `mesh` (polygon soup + files) ← `halfedge` (the OpenMesh bridge)
//! ← `topology`; `subdiv` (the OpenSubdiv bridge) ← `fair`; `spline` ← `fit`; `cli` on top.
//! Only `ffi` holds `unsafe` code.

#![deny(unsafe_code)]

pub mod cli;
pub mod error;
pub mod fair;
mod ffi;
pub mod fit;
pub mod halfedge;
pub mod limits;
pub mod linalg;
pub mod mesh;
pub mod repair;
pub mod report;
pub mod shapes;
pub mod spline;
pub mod subdiv;
pub mod tolerance;
pub mod topology;

pub use error::{Error, Result};

/// Large blocks on transparent huge pages (`ffi::huge_pages` says why); in every artifact
/// built on this crate: the CLI, the C ABI and the Python module.
#[cfg(target_os = "linux")]
#[global_allocator]
static ALLOCATOR: ffi::huge_pages::HugePageAllocator = ffi::huge_pages::HugePageAllocator;
