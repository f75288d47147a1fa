//! The Sabin net of a special vertex in a mesh: its k faces in turn and the radius-2 net
//! (centre, then per sector the six vertices at lattice (a, b) ∈ {1, 2} × {0, 1, 2}),
//! indexed like the domain net so that the patch matrix applies to it directly.

use std::collections::HashMap;

use super::basis::domain_net::PER_SECTOR;
use crate::error::{Error, Result};
use crate::mesh::PolygonMesh;

/// Directed edge (from, to) → (face, position of `from` in the face).
pub type DirectedEdges = HashMap<(u32, u32), (usize, usize)>;

/// The directed edges of all faces.
pub fn directed_edges(mesh: &PolygonMesh) -> DirectedEdges {
    let mut out = HashMap::with_capacity(4 * mesh.face_count());
    for (f, face) in mesh.faces().enumerate() {
        for i in 0..face.len() {
            out.insert((face[i], face[(i + 1) % face.len()]), (f, i));
        }
    }
    out
}

/// Per vertex, the first face that holds it (`usize::MAX` if none) and the number of faces
/// that do (the valence of an interior vertex): where a special vertex's net starts.
pub fn first_faces(mesh: &PolygonMesh) -> (Vec<usize>, Vec<usize>) {
    let mut first = vec![usize::MAX; mesh.vertex_count()];
    let mut count = vec![0usize; mesh.vertex_count()];
    for (f, face) in mesh.faces().enumerate() {
        for &v in face {
            count[v as usize] += 1;
            if first[v as usize] == usize::MAX {
                first[v as usize] = f;
            }
        }
    }
    (first, count)
}

/// A special vertex's element: its faces (sector s = `faces[s]`) and net.
#[derive(Debug, Clone, PartialEq)]
pub struct SabinNet {
    pub centre: u32,
    pub faces: Vec<usize>,
    /// Mesh vertex per domain-net index (1 + 12k); `None` for the radius-3 positions,
    /// which the surface does not depend on.
    pub vertices: Vec<Option<u32>>,
}

/// Face `f` of `mesh` rotated to start at vertex `v`.
fn rotated(mesh: &PolygonMesh, f: usize, v: u32) -> Option<[u32; 4]> {
    let face = mesh.face(f);
    if face.len() != 4 {
        return None;
    }
    let at = face.iter().position(|&x| x == v)?;
    Some(std::array::from_fn(|i| face[(at + i) % 4]))
}

impl SabinNet {
    /// The net of special vertex `centre` of valence `k`, starting from one of its faces.
    ///
    /// # Errors
    /// [`Error::Topology`] if the faces round it do not form the quad net the construction
    /// needs (a boundary, a non-quad or an irregular vertex within two rings — what the
    /// preparation rules out).
    pub fn new(
        mesh: &PolygonMesh,
        edges: &DirectedEdges,
        centre: u32,
        first_face: usize,
        k: usize,
    ) -> Result<SabinNet> {
        let fail = |what: &str| {
            Error::Topology(format!(
                "special vertex {centre} (valence {k}): {what}; Kiciak's special element needs \
                 quads round it and valence-4 vertices within two rings"
            ))
        };
        let across = |from: u32, to: u32, start: u32| -> Result<[u32; 4]> {
            let &(f, _) = edges
                .get(&(from, to))
                .ok_or_else(|| fail(&format!("no face across edge {to}–{from}")))?;
            rotated(mesh, f, start).ok_or_else(|| fail(&format!("face {f} is not a quad")))
        };
        let mut faces = Vec::with_capacity(k);
        let mut vertices = vec![None; 1 + PER_SECTOR * k];
        vertices[0] = Some(centre);
        let mut face = first_face;
        for s in 0..k {
            let [c, x, d, y] = rotated(mesh, face, centre)
                .ok_or_else(|| fail(&format!("face {face} is not a quad")))?;
            debug_assert_eq!(c, centre);
            faces.push(face);
            let [_, n20, n21, _] = across(d, x, x)?;
            let [_, n12, _, _] = across(y, d, d)?;
            let [_, _, n22, last] = across(d, n21, d)?;
            if last != n12 {
                return Err(fail(&format!("vertex {d} does not have valence 4")));
            }
            let slot = |a: usize, b: usize| 1 + s * PER_SECTOR + (a - 1) * 4 + b;
            for (a, b, v) in [
                (1, 0, x),
                (1, 1, d),
                (1, 2, n12),
                (2, 0, n20),
                (2, 1, n21),
                (2, 2, n22),
            ] {
                vertices[slot(a, b)] = Some(v);
            }
            // next sector: the face across edge (y, c), which holds c → y
            let &(next, _) = edges
                .get(&(centre, y))
                .ok_or_else(|| fail(&format!("no face across edge {centre}–{y}")))?;
            face = next;
            if s + 1 < k && face == first_face {
                return Err(fail(&format!("only {} faces round it", s + 1)));
            }
        }
        if face != first_face {
            return Err(fail("its faces do not close up into a fan"));
        }
        let mut used: Vec<u32> = vertices.iter().flatten().copied().collect();
        used.sort_unstable();
        used.dedup();
        if used.len() != 1 + 6 * k {
            return Err(fail("its net's vertices are not distinct"));
        }
        Ok(SabinNet {
            centre,
            faces,
            vertices,
        })
    }
}
