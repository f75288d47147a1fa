//! The control mesh as OpenSubdiv takes it: a `PolygonMesh` and `SubdivOptions` checked and
//! converted once into the flat `i32`/`f32` arrays of the shim's topology descriptor.

use std::collections::{HashMap, HashSet};

use crate::error::{Error, Result};
use crate::ffi::opensubdiv as ffi;
use crate::mesh::{CornerUvs, PolygonMesh};
use crate::subdiv::SubdivOptions;

/// Owned descriptor arrays; [`ControlMesh::topology`] lends them to the shim.
pub(crate) struct ControlMesh {
    pub num_vertices: usize,
    pub verts_per_face: Vec<i32>,
    pub face_vertices: Vec<i32>,
    crease_pairs: Vec<i32>,
    crease_sharpness: Vec<f32>,
    corner_vertices: Vec<i32>,
    corner_sharpness: Vec<f32>,
    pub num_uvs: usize,
    uv_indices: Vec<i32>,
    options: [i32; 4],
}

fn invalid(message: String) -> Error {
    Error::InvalidInput(message)
}

fn check_sharpness(s: f32, what: &str) -> Result<()> {
    if s.is_finite() && s >= 0.0 {
        Ok(())
    } else {
        Err(invalid(format!(
            "{what}: sharpness {s} must be finite and ≥ 0"
        )))
    }
}

/// The face-varying channel's value count and corner indices. Corners of faces without
/// texture coordinates get one value per vertex after the mesh's (the stand-in (0, 0)
/// each; [`ControlMesh::num_uvs`] counts them): OpenSubdiv ties each face-varying value
/// to one vertex, so the one shared stand-in would not be a valid channel.
fn uv_channel(mesh: &PolygonMesh, uv: &CornerUvs) -> Result<(usize, Vec<i32>)> {
    let mut count = uv.coords.len();
    let mut of_vertex: HashMap<u32, i32> = HashMap::new();
    let mut indices = Vec::with_capacity(uv.corner_indices.len());
    for (k, (&t, &v)) in uv.corner_indices.iter().zip(&mesh.face_indices).enumerate() {
        indices.push(if uv.is_textured(k) {
            t as i32
        } else {
            *of_vertex.entry(v).or_insert_with(|| {
                count += 1;
                (count - 1) as i32
            })
        });
    }
    if count > i32::MAX as usize {
        return Err(invalid(
            "the mesh has too many texture coordinates for OpenSubdiv's 32-bit indices".into(),
        ));
    }
    Ok((count, indices))
}

impl ControlMesh {
    /// Checks `mesh` and `options` and converts them.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when the mesh breaks its invariants, has no face, a face with
    /// fewer than 3 corners, more than `i32::MAX` elements, when a crease names a pair of
    /// vertices that is not an edge, a corner names no vertex, or a sharpness is negative or
    /// not finite.
    pub fn new(mesh: &PolygonMesh, options: &SubdivOptions, with_uvs: bool) -> Result<Self> {
        mesh.validate()?;
        if mesh.face_count() == 0 {
            return Err(invalid("the mesh has no faces to subdivide".into()));
        }
        if mesh.face_indices.len() > i32::MAX as usize || mesh.vertex_count() > i32::MAX as usize {
            return Err(invalid(
                "the mesh is too large for OpenSubdiv's 32-bit indices".into(),
            ));
        }
        let mut verts_per_face = Vec::with_capacity(mesh.face_count());
        let mut edges = HashSet::new();
        for (f, face) in mesh.faces().enumerate() {
            if face.len() < 3 {
                return Err(invalid(format!(
                    "face {f} has {} corners; at least 3 are needed",
                    face.len()
                )));
            }
            // OpenSubdiv's end-cap construction recurses without end on such a face (a
            // stack overflow found by fuzzing): refuse it here.
            if let Some(problem) = crate::mesh::io::degeneracy(face) {
                return Err(invalid(format!(
                    "face {f}: {problem}; OpenSubdiv cannot refine it (surfkit repair removes it)"
                )));
            }
            verts_per_face.push(face.len() as i32);
            if !options.creases.is_empty() {
                for k in 0..face.len() {
                    let (a, b) = (face[k], face[(k + 1) % face.len()]);
                    edges.insert((a.min(b), a.max(b)));
                }
            }
        }
        let mut crease_pairs = Vec::with_capacity(2 * options.creases.len());
        let mut crease_sharpness = Vec::with_capacity(options.creases.len());
        for (i, c) in options.creases.iter().enumerate() {
            let [a, b] = c.vertices;
            if !edges.contains(&(a.min(b), a.max(b))) {
                return Err(invalid(format!(
                    "crease {i}: vertices {a} and {b} do not form an edge of the mesh"
                )));
            }
            check_sharpness(c.sharpness, &format!("crease {i}"))?;
            crease_pairs.extend([a as i32, b as i32]);
            crease_sharpness.push(c.sharpness);
        }
        let mut corner_vertices = Vec::with_capacity(options.corners.len());
        let mut corner_sharpness = Vec::with_capacity(options.corners.len());
        for (i, c) in options.corners.iter().enumerate() {
            if c.vertex as usize >= mesh.vertex_count() {
                return Err(invalid(format!(
                    "corner {i}: vertex {} does not exist",
                    c.vertex
                )));
            }
            check_sharpness(c.sharpness, &format!("corner {i}"))?;
            corner_vertices.push(c.vertex as i32);
            corner_sharpness.push(c.sharpness);
        }
        let (num_uvs, uv_indices) = match (&mesh.uvs, with_uvs) {
            (Some(uv), true) if !uv.coords.is_empty() => uv_channel(mesh, uv)?,
            _ => (0, Vec::new()),
        };
        Ok(ControlMesh {
            num_vertices: mesh.vertex_count(),
            verts_per_face,
            face_vertices: mesh.face_indices.iter().map(|&i| i as i32).collect(),
            crease_pairs,
            crease_sharpness,
            corner_vertices,
            corner_sharpness,
            num_uvs,
            uv_indices,
            options: [
                options.boundary.sdc(),
                options.face_varying.sdc(),
                match options.creasing {
                    crate::subdiv::CreasingMethod::Uniform => 0,
                    crate::subdiv::CreasingMethod::Chaikin => 1,
                },
                match options.triangles {
                    crate::subdiv::TriangleSubdivision::CatmullClark => 0,
                    crate::subdiv::TriangleSubdivision::Smooth => 1,
                },
            ],
        })
    }

    pub fn face_count(&self) -> usize {
        self.verts_per_face.len()
    }

    /// The shim's view of these arrays.
    pub fn topology(&self) -> ffi::Topology<'_> {
        ffi::Topology {
            num_vertices: self.num_vertices as i32,
            verts_per_face: &self.verts_per_face,
            face_vertices: &self.face_vertices,
            crease_vertex_pairs: &self.crease_pairs,
            crease_sharpness: &self.crease_sharpness,
            corner_vertices: &self.corner_vertices,
            corner_sharpness: &self.corner_sharpness,
            num_fvar_values: self.num_uvs as i32,
            fvar_indices: &self.uv_indices,
            vtx_boundary_interpolation: self.options[0],
            fvar_linear_interpolation: self.options[1],
            creasing_method: self.options[2],
            triangle_subdivision: self.options[3],
        }
    }
}
