//! The optimized surface as Bézier patches, for another CAD tool: one JSON file, format
//! `surfkit-bezier-patches` version 1 —
//!
//! ```json
//! { "format": "surfkit-bezier-patches", "version": 1, "surface": "g2",
//!   "patches": [ { "face": 17, "kind": "bicubic", "degree": [3, 3],
//!                  "points": [[x, y, z], …] }, … ] }
//! ```
//!
//! One patch per internal face of the control mesh, in face order: `kind` is `bicubic`
//! (an ordinary element) or `special` (one of the k degree-(9, 9) patches round a special
//! vertex, u running from the special vertex along the face's edge to its next corner).
//! `points` holds the (d+1)² control points P_ij, index (d+1)·i + j, and the patch is
//! p(u, v) = Σ_ij B_i^d(u) B_j^d(v) P_ij on [0, 1]², u along the face's first edge (from its
//! first corner for a bicubic patch), v along its last edge reversed. Neighbouring patches
//! join with continuous tangent plane and curvature (G²).

use std::path::Path;

use serde::Serialize;

use super::surface::{FacePatch, G2Surface};
use crate::error::Result;
use crate::mesh::io::write_atomically;

#[derive(Serialize)]
struct Patch {
    face: usize,
    kind: &'static str,
    degree: [usize; 2],
    points: Vec<[f64; 3]>,
}

#[derive(Serialize)]
struct Document {
    format: &'static str,
    version: u32,
    surface: &'static str,
    patches: Vec<Patch>,
}

/// Writes `surface` at `positions` to `path` (atomically).
///
/// # Errors
/// [`crate::Error::Io`] naming `path`.
pub fn write_bezier_patches(
    path: &Path,
    surface: &G2Surface,
    positions: &[[f64; 3]],
) -> Result<()> {
    let patches = (0..surface.faces.len())
        .filter_map(|f| {
            let kind = match surface.faces[f].as_ref()? {
                FacePatch::Bicubic(_) => "bicubic",
                FacePatch::Special { .. } => "special",
            };
            let (degree, points) = surface.bezier(f, positions)?;
            Some(Patch {
                face: f,
                kind,
                degree: [degree, degree],
                points,
            })
        })
        .collect();
    let document = Document {
        format: "surfkit-bezier-patches",
        version: 1,
        surface: "g2",
        patches,
    };
    write_atomically(path, |out| {
        serde_json::to_writer(&mut *out, &document).map_err(std::io::Error::other)?;
        out.write_all(b"\n")
    })
}
