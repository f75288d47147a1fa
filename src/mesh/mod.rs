//! Polygon meshes as surfkit holds them (`PolygonMesh`, a soup that never refuses input)
//! and their files (`io`: OBJ, PLY, OFF, STL); vector and plane-polygon geometry.

pub mod io;
pub mod planar;
mod polygon_mesh;
mod sharp_features;
pub mod vector;

pub use polygon_mesh::{CornerUvs, FaceLabels, PolygonMesh, NO_LABEL};
pub use sharp_features::SharpFeatures;
