//! The mesh with its flaws coloured, for MeshLab: vertex colour by flaw kind and the kind's
//! number as vertex quality (0 where there is no flaw).

use super::flaw::{Flaw, FlawKind};
use crate::mesh::PolygonMesh;

/// The colour of a flaw kind (RGBA) in the marked mesh.
pub fn flaw_color(kind: FlawKind) -> [u8; 4] {
    match kind {
        FlawKind::MissingTriangle | FlawKind::MissingQuad => [255, 0, 255, 255],
        FlawKind::Hole => [255, 140, 0, 255],
        FlawKind::Crack => [255, 0, 0, 255],
        FlawKind::NonManifoldEdge => [200, 0, 0, 255],
        FlawKind::NonManifoldVertex => [0, 0, 255, 255],
        FlawKind::DuplicatedFacet => [255, 220, 0, 255],
        FlawKind::DegenerateFacet => [0, 200, 200, 255],
        FlawKind::CoincidentVertices => [0, 160, 0, 255],
        FlawKind::UnreferencedVertex => [0, 0, 0, 255],
        FlawKind::InconsistentOrientation => [128, 0, 160, 255],
    }
}

/// Colour of vertices with no flaw.
pub const SOUND: [u8; 4] = [200, 200, 200, 255];

/// A copy of `mesh` whose vertices carry the colour of the first flaw listed at them and,
/// as quality, that flaw kind's number in [`FlawKind::ALL`] plus one.
pub fn mark_flaws(mesh: &PolygonMesh, flaws: &[Flaw]) -> PolygonMesh {
    let mut marked = mesh.clone();
    let n = mesh.vertex_count();
    let mut colors = vec![SOUND; n];
    let mut quality = vec![0.0; n];
    // Most specific kinds last so they win over holes.
    let mut order: Vec<&Flaw> = flaws.iter().collect();
    order.sort_by_key(|f| std::cmp::Reverse(f.kind == FlawKind::Hole));
    for flaw in order {
        let number = FlawKind::ALL.iter().position(|&k| k == flaw.kind).unwrap() as f64 + 1.0;
        let mut vertices = flaw.vertices.clone();
        for &f in &flaw.faces {
            if (f as usize) < mesh.face_count() {
                vertices.extend_from_slice(mesh.face(f as usize));
            }
        }
        for v in vertices {
            if (v as usize) < n {
                colors[v as usize] = flaw_color(flaw.kind);
                quality[v as usize] = number;
            }
        }
    }
    marked.colors = Some(colors);
    marked.quality = Some(quality);
    marked
}
