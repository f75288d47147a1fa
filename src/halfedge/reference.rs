//! A small pure-Rust implementation of [`HalfEdgeTopology`], computed straight from the
//! face list with a map of directed edges. It exists to check the OpenMesh bridge (and to
//! be checked by it): given the faces OpenMesh accepted, both must answer alike.

use std::collections::HashMap;

use super::{Components, EdgeTable, FaceNeighbours, HalfEdgeTopology, Loops, NO_FACE};
use crate::error::{Error, Result};
use crate::mesh::PolygonMesh;

/// Topology of a set of faces whose directed edges are all distinct (as in any half-edge
/// structure).
pub struct ReferenceTopology {
    vertex_count: usize,
    /// Input id and corners of each face.
    faces: Vec<(u32, Vec<u32>)>,
    /// Directed edge (from, to) → (face slot, corner of `from`).
    directed: HashMap<(u32, u32), (usize, usize)>,
}

impl ReferenceTopology {
    /// The topology of the faces of `mesh` whose ids are in `face_ids`.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when two faces run the same directed edge (such a set is
    /// not a half-edge structure) or an id names no face.
    pub fn new(mesh: &PolygonMesh, face_ids: &[u32]) -> Result<Self> {
        let mut faces = Vec::with_capacity(face_ids.len());
        let mut directed = HashMap::new();
        for (slot, &f) in face_ids.iter().enumerate() {
            if f as usize >= mesh.face_count() {
                return Err(Error::InvalidInput(format!("face {f} does not exist")));
            }
            let corners = mesh.face(f as usize).to_vec();
            let n = corners.len();
            for k in 0..n {
                let e = (corners[k], corners[(k + 1) % n]);
                if directed.insert(e, (slot, k)).is_some() {
                    return Err(Error::InvalidInput(format!(
                        "face {f} runs the directed edge {e:?} that another face runs already"
                    )));
                }
            }
            faces.push((f, corners));
        }
        Ok(ReferenceTopology {
            vertex_count: mesh.vertex_count(),
            faces,
            directed,
        })
    }

    fn is_boundary(&self, from: u32, to: u32) -> bool {
        !self.directed.contains_key(&(from, to)) && self.directed.contains_key(&(to, from))
    }

    /// The directed edge before `(from, to)` in its face.
    fn prev(&self, from: u32, to: u32) -> (u32, u32) {
        let (slot, k) = self.directed[&(from, to)];
        let corners = &self.faces[slot].1;
        let p = corners[(k + corners.len() - 1) % corners.len()];
        (p, from)
    }
}

impl HalfEdgeTopology for ReferenceTopology {
    fn vertex_count(&self) -> usize {
        self.vertex_count
    }

    fn edge_count(&self) -> usize {
        self.directed
            .keys()
            .filter(|&&(a, b)| a < b || !self.directed.contains_key(&(b, a)))
            .count()
    }

    fn face_count(&self) -> usize {
        self.faces.len()
    }

    fn boundary_loops(&self) -> Result<Loops> {
        let mut starts: Vec<(u32, u32)> = self
            .directed
            .keys()
            .filter(|&&(a, b)| !self.directed.contains_key(&(b, a)))
            .map(|&(a, b)| (b, a))
            .collect();
        starts.sort_unstable();
        let mut seen = std::collections::HashSet::new();
        let mut loops = Loops {
            offsets: vec![0],
            vertices: Vec::new(),
        };
        for start in starts {
            if seen.contains(&start) {
                continue;
            }
            let mut cur = start;
            while seen.insert(cur) {
                loops.vertices.push(cur.0);
                // From the face half-edge opposite `cur`, rotate within the fan at cur.1.
                let mut g = (cur.1, cur.0);
                let mut guard = 0;
                while !self.is_boundary(g.0, g.1) {
                    let p = self.prev(g.0, g.1);
                    g = (p.1, p.0);
                    guard += 1;
                    if guard > self.directed.len() {
                        return Err(Error::Topology("boundary walk did not close".into()));
                    }
                }
                cur = g;
            }
            loops.offsets.push(loops.vertices.len() as u32);
        }
        Ok(loops)
    }

    fn vertex_valences(&self) -> Vec<u32> {
        let mut valence = vec![0u32; self.vertex_count];
        for &(a, b) in self.directed.keys() {
            if a < b || !self.directed.contains_key(&(b, a)) {
                valence[a as usize] += 1;
                valence[b as usize] += 1;
            }
        }
        valence
    }

    fn edges(&self) -> EdgeTable {
        let mut table = EdgeTable::default();
        let face_of = |e: &(u32, u32)| {
            self.directed
                .get(e)
                .map_or(NO_FACE, |&(s, _)| self.faces[s].0)
        };
        for &(a, b) in self.directed.keys() {
            if a < b || !self.directed.contains_key(&(b, a)) {
                table.vertices.push([a, b]);
                table.faces.push([face_of(&(a, b)), face_of(&(b, a))]);
            }
        }
        table
    }

    fn face_neighbours(&self) -> FaceNeighbours {
        let mut n = FaceNeighbours {
            offsets: vec![0],
            ..Default::default()
        };
        for (f, corners) in &self.faces {
            n.faces.push(*f);
            let len = corners.len();
            for k in 0..len {
                let (a, b) = (corners[k], corners[(k + 1) % len]);
                n.neighbours.push(
                    self.directed
                        .get(&(b, a))
                        .map_or(NO_FACE, |&(s, _)| self.faces[s].0),
                );
            }
            n.offsets.push(n.neighbours.len() as u32);
        }
        n
    }

    fn connected_components(&self) -> Components {
        let n = self.faces.len();
        let mut parent: Vec<usize> = (0..n).collect();
        fn root(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        for (&(a, b), &(s, _)) in &self.directed {
            if let Some(&(t, _)) = self.directed.get(&(b, a)) {
                let (ra, rb) = (root(&mut parent, s), root(&mut parent, t));
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
        let mut label = vec![u32::MAX; n];
        let mut c = Components::default();
        for slot in 0..n {
            let r = root(&mut parent, slot);
            if label[r] == u32::MAX {
                label[r] = c.count;
                c.count += 1;
            }
            c.faces.push(self.faces[slot].0);
            c.of_face.push(label[r]);
        }
        c
    }
}
