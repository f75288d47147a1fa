//! Catmull–Clark refinement and limit surfaces (OpenSubdiv) against CGAL, MeshLab and exact values.

mod cgal;
#[path = "../common/mod.rs"]
mod common;
mod euler;
mod high_valence;
mod limit;
mod meshlab;
mod uniform;
