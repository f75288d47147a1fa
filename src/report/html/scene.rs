//! Meshes and overlays as the compact arrays the viewer uploads to the GPU: little-endian
//! `f32`/`u32` arrays in base64 (a third of the size of JSON numbers, and decoded without
//! parsing). Positions are stored relative to the view's origin (its bounding box centre),
//! so that `f32` keeps the detail of CAD coordinates far from 0.

use base64::engine::general_purpose::STANDARD;
use base64::Engine as _;
use serde::Serialize;

use crate::mesh::PolygonMesh;

/// A mesh as the viewer takes it. Polygons are given by `arity` when they all have the same
/// number of corners, else by `offsets` (polygon f is `indices[offsets[f]..offsets[f+1]]`);
/// the viewer fans them into triangles.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeshData {
    pub vertices: usize,
    pub faces: usize,
    /// base64 `f32` x, y, z per vertex, less `origin`.
    pub positions: String,
    pub arity: Option<u32>,
    /// base64 `u32`, faces + 1 entries (only without `arity`).
    pub offsets: Option<String>,
    /// base64 `u32` corner vertex ids.
    pub indices: String,
    /// base64 `f32` per-vertex quality (NaN where undefined, drawn grey).
    pub quality: Option<String>,
}

/// Faces drawn over the mesh in one colour (a flaw kind).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Highlight {
    pub name: String,
    pub colour: [u8; 3],
    /// base64 `u32` face ids.
    pub faces: String,
}

/// Line segments (boundary loops, a hole's border): base64 `f32` point pairs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Lines {
    pub name: String,
    pub colour: [u8; 3],
    pub segments: String,
}

/// Points drawn as dots (flawed vertices, data points): base64 `f32` x, y, z.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Points {
    pub name: String,
    pub colour: [u8; 3],
    pub positions: String,
    /// Dot diameter in CSS pixels.
    pub size: f32,
}

/// One panel of the page: a mesh and what is drawn over it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct View {
    pub name: String,
    /// Subtracted from every position of the view (and of its overlays).
    pub origin: [f64; 3],
    /// Half the bounding box diagonal (what the camera frames at first).
    pub radius: f64,
    pub mesh: MeshData,
    pub highlights: Vec<Highlight>,
    pub lines: Vec<Lines>,
    pub points: Vec<Points>,
}

/// `f32` values as base64 of their little-endian bytes.
pub(super) fn f32_base64(values: impl Iterator<Item = f32>) -> String {
    let bytes: Vec<u8> = values.flat_map(f32::to_le_bytes).collect();
    STANDARD.encode(bytes)
}

/// `u32` values as base64 of their little-endian bytes.
pub(super) fn u32_base64(values: impl Iterator<Item = u32>) -> String {
    let bytes: Vec<u8> = values.flat_map(u32::to_le_bytes).collect();
    STANDARD.encode(bytes)
}

/// Points less `origin`, as base64 `f32`.
fn relative_positions<'a>(points: impl Iterator<Item = &'a [f64; 3]>, origin: [f64; 3]) -> String {
    f32_base64(points.flat_map(|p| [0, 1, 2].map(|i| (p[i] - origin[i]) as f32)))
}

impl View {
    /// The view of `mesh` (its quality, when it has one, colours it), with no overlay yet.
    pub fn new(name: &str, mesh: &PolygonMesh) -> Self {
        let (origin, radius) = match mesh.bounding_box() {
            Some((lo, hi)) => {
                let origin = [0, 1, 2].map(|i| 0.5 * (lo[i] + hi[i]));
                let radius = 0.5 * (0..3).map(|i| (hi[i] - lo[i]).powi(2)).sum::<f64>().sqrt();
                (origin, radius)
            }
            None => ([0.0; 3], 1.0),
        };
        // one arity for all faces (an empty mesh counts as triangles): no offsets needed
        let mut arities = mesh.face_offsets.windows(2).map(|w| w[1] - w[0]);
        let uniform = match arities.next() {
            Some(first) => arities.all(|a| a == first).then_some(first),
            None => Some(3),
        };
        View {
            name: name.to_string(),
            origin,
            radius: if radius > 0.0 { radius } else { 1.0 },
            mesh: MeshData {
                vertices: mesh.vertex_count(),
                faces: mesh.face_count(),
                positions: relative_positions(mesh.positions.iter(), origin),
                arity: uniform,
                offsets: uniform
                    .is_none()
                    .then(|| u32_base64(mesh.face_offsets.iter().copied())),
                indices: u32_base64(mesh.face_indices.iter().copied()),
                quality: mesh
                    .quality
                    .as_ref()
                    .map(|q| f32_base64(q.iter().map(|&v| v as f32))),
            },
            highlights: Vec::new(),
            lines: Vec::new(),
            points: Vec::new(),
        }
    }

    /// Points in the view's coordinates (less its origin), as base64 `f32`.
    pub fn local_positions<'a>(&self, points: impl Iterator<Item = &'a [f64; 3]>) -> String {
        relative_positions(points, self.origin)
    }

    /// A point in the view's coordinates.
    pub fn local(&self, p: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|i| p[i] - self.origin[i])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decode_f32(s: &str) -> Vec<f32> {
        STANDARD
            .decode(s)
            .unwrap()
            .chunks(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
            .collect()
    }

    #[test]
    fn positions_are_relative_to_the_box_centre() {
        let mesh = PolygonMesh::from_polygons(
            vec![[1e6, 0.0, 0.0], [1e6 + 2.0, 0.0, 0.0], [1e6, 2.0, 0.0]],
            &[[0u32, 1, 2]],
        );
        let view = View::new("m", &mesh);
        assert_eq!(view.origin, [1e6 + 1.0, 1.0, 0.0]);
        assert_eq!(
            decode_f32(&view.mesh.positions),
            vec![-1.0, -1.0, 0.0, 1.0, -1.0, 0.0, -1.0, 1.0, 0.0]
        );
        assert_eq!(view.mesh.arity, Some(3));
        assert!(view.mesh.offsets.is_none());
    }

    #[test]
    fn mixed_polygons_carry_their_offsets() {
        let mesh = PolygonMesh::from_polygons(
            vec![
                [0.0; 3],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
                [2.0, 0.0, 0.0],
            ],
            &[vec![0u32, 1, 2, 3], vec![1, 4, 2]],
        );
        let view = View::new("m", &mesh);
        assert_eq!(view.mesh.arity, None);
        let offsets = STANDARD.decode(view.mesh.offsets.unwrap()).unwrap();
        assert_eq!(offsets.len(), 3 * 4);
        assert_eq!(u32::from_le_bytes(offsets[8..12].try_into().unwrap()), 7);
    }
}
