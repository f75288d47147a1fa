//! Mesh repair and the spline fill of its holes.

#[path = "../common/mod.rs"]
mod common;
mod mesh_repair;
mod spline_fill;
