//! Mesh files and report images read back: every format's round trip, the PNG reports.

#[path = "../common/mod.rs"]
mod common;
mod mesh_roundtrip;
mod report_png;
