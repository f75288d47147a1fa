//! The mesh being repaired: facets kept by id (input ids first, new facets after) so that
//! every change can name the facets and vertices it touched, and written out at the end
//! in the input's order with each new facet right after the facet it was made beside
//! (so it stays in that facet's OBJ group, and stage test points still fall where they did).

use crate::mesh::PolygonMesh;

use super::change::Change;

pub struct Editable {
    pub positions: Vec<[f64; 3]>,
    /// The input vertex each vertex copies (itself for input vertices; None for new points).
    pub vertex_source: Vec<Option<u32>>,
    /// Vertices taken out (welded into another, or unreferenced and deleted).
    pub removed_vertex: Vec<bool>,
    /// Corners of each facet by id; None once deleted.
    pub faces: Vec<Option<Vec<u32>>>,
    /// The input facet each facet is written after (itself for input facets).
    pub anchor: Vec<u32>,
    pub input_faces: usize,
}

/// One edge of a facet: from its corner `corner` to the next one.
pub struct FacetEdge {
    pub facet: u32,
    pub corner: usize,
    pub next_corner: usize,
    pub from: u32,
    pub to: u32,
}

/// The live facets as a mesh (all vertices, ids unchanged) and, per position in it, the
/// facet id.
pub struct Live {
    pub mesh: PolygonMesh,
    pub facet_ids: Vec<u32>,
}

impl Editable {
    pub fn new(mesh: &PolygonMesh) -> Self {
        let n = mesh.vertex_count();
        Editable {
            positions: mesh.positions.clone(),
            vertex_source: (0..n as u32).map(Some).collect(),
            removed_vertex: vec![false; n],
            faces: mesh.faces().map(|f| Some(f.to_vec())).collect(),
            anchor: (0..mesh.face_count() as u32).collect(),
            input_faces: mesh.face_count(),
        }
    }

    /// Facet ids in output order: input facets in order, each followed by the new facets
    /// made beside it, in the order they were made.
    pub fn output_order(&self) -> Vec<u32> {
        let mut after: Vec<Vec<u32>> = vec![Vec::new(); self.input_faces];
        for f in self.input_faces..self.faces.len() {
            after[self.anchor[f] as usize].push(f as u32);
        }
        let mut order = Vec::with_capacity(self.faces.len());
        for (f, extra) in after.into_iter().enumerate() {
            order.push(f as u32);
            order.extend(extra);
        }
        order.retain(|&f| self.faces[f as usize].is_some());
        order
    }

    /// Every edge of the live facets, in corner order.
    pub fn edges(&self) -> impl Iterator<Item = FacetEdge> + '_ {
        self.faces
            .iter()
            .enumerate()
            .filter_map(|(f, c)| c.as_ref().map(|c| (f as u32, c)))
            .flat_map(|(facet, c)| {
                (0..c.len()).map(move |corner| {
                    let next_corner = (corner + 1) % c.len();
                    FacetEdge {
                        facet,
                        corner,
                        next_corner,
                        from: c[corner],
                        to: c[next_corner],
                    }
                })
            })
    }

    pub fn live(&self) -> Live {
        let order = self.output_order();
        let faces: Vec<&[u32]> = order
            .iter()
            .map(|&f| self.faces[f as usize].as_deref().unwrap_or(&[]))
            .collect();
        Live {
            mesh: PolygonMesh::from_polygons(self.positions.clone(), &faces),
            facet_ids: order,
        }
    }

    /// Adds a facet written after `beside` (or after its anchor, for a new facet).
    pub fn add_facet(&mut self, corners: Vec<u32>, beside: u32) -> u32 {
        let anchor = self.anchor[beside as usize];
        self.faces.push(Some(corners));
        self.anchor.push(anchor);
        (self.faces.len() - 1) as u32
    }

    /// A new vertex at `position`, copying the attributes of `source` if given.
    pub fn add_vertex(&mut self, position: [f64; 3], source: Option<u32>) -> u32 {
        self.positions.push(position);
        self.vertex_source
            .push(source.and_then(|s| self.vertex_source[s as usize]));
        self.removed_vertex.push(false);
        (self.positions.len() - 1) as u32
    }

    /// Writes the repaired mesh; fills each change's ids after. Vertex attributes (quality,
    /// colour) follow the vertex each one copies; face labels follow the anchor; texture
    /// coordinates are kept when every written facet is an input facet with its corners
    /// unchanged, and dropped otherwise (the returned flag says so).
    pub fn finish(&self, input: &PolygonMesh, changes: &mut [Change]) -> Finished {
        let order = self.output_order();
        let mut vertex_after = vec![None; self.positions.len()];
        let mut kept_vertices = Vec::new();
        for (v, after) in vertex_after.iter_mut().enumerate() {
            if !self.removed_vertex[v] {
                *after = Some(kept_vertices.len() as u32);
                kept_vertices.push(v);
            }
        }
        let mut facet_after = vec![None; self.faces.len()];
        for (i, &f) in order.iter().enumerate() {
            facet_after[f as usize] = Some(i as u32);
        }
        let mut mesh = PolygonMesh {
            positions: kept_vertices.iter().map(|&v| self.positions[v]).collect(),
            ..Default::default()
        };
        for &f in &order {
            let corners: Vec<u32> = self.faces[f as usize]
                .as_ref()
                .map(|c| c.iter().filter_map(|&v| vertex_after[v as usize]).collect())
                .unwrap_or_default();
            mesh.push_face(&corners);
        }
        let labels = |l: &Option<crate::mesh::FaceLabels>| {
            l.as_ref().map(|l| crate::mesh::FaceLabels {
                names: l.names.clone(),
                of_face: order
                    .iter()
                    .map(|&f| l.of_face[self.anchor[f as usize] as usize])
                    .collect(),
            })
        };
        mesh.objects = labels(&input.objects);
        mesh.groups = labels(&input.groups);
        let per_vertex = |source: Option<u32>| source.map(|s| s as usize);
        mesh.quality = input.quality.as_ref().map(|q| {
            kept_vertices
                .iter()
                .map(|&v| per_vertex(self.vertex_source[v]).map_or(0.0, |s| q[s]))
                .collect()
        });
        mesh.colors = input.colors.as_ref().map(|c| {
            kept_vertices
                .iter()
                .map(|&v| per_vertex(self.vertex_source[v]).map_or([255; 4], |s| c[s]))
                .collect()
        });
        let untouched = order.iter().all(|&f| {
            (f as usize) < self.input_faces
                && self.faces[f as usize].as_deref() == Some(input.face(f as usize))
        });
        let mut uvs_dropped = false;
        if let Some(uvs) = &input.uvs {
            if untouched && self.removed_vertex.iter().all(|&r| !r) {
                let corner_indices = order
                    .iter()
                    .flat_map(|&f| {
                        let (a, b) = (
                            input.face_offsets[f as usize] as usize,
                            input.face_offsets[f as usize + 1] as usize,
                        );
                        uvs.corner_indices[a..b].iter().copied()
                    })
                    .collect();
                mesh.uvs = Some(crate::mesh::CornerUvs {
                    coords: uvs.coords.clone(),
                    corner_indices,
                    untextured: uvs.untextured,
                });
            } else {
                uvs_dropped = true;
            }
        }
        for c in changes.iter_mut() {
            c.faces_after = c.faces.iter().map(|&f| facet_after[f as usize]).collect();
            c.vertices_after = c
                .vertices
                .iter()
                .map(|&v| vertex_after[v as usize])
                .collect();
        }
        Finished {
            mesh,
            uvs_dropped,
            vertex_after,
        }
    }
}

/// The written mesh and where each vertex went.
pub struct Finished {
    pub mesh: PolygonMesh,
    pub uvs_dropped: bool,
    /// Vertex id (input ids, then new vertices) → id in `mesh`; None if deleted.
    pub vertex_after: Vec<Option<u32>>,
}
