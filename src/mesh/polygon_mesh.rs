//! `PolygonMesh`: the polygon soup every surfkit capability reads and writes.

use super::SharpFeatures;
use crate::error::{Error, Result};

/// Marks a face that carries no object or group label.
pub const NO_LABEL: u32 = u32::MAX;

/// Named labels on faces (OBJ `o` objects or `g` groups): a name table and, per face, an
/// index into it (or [`NO_LABEL`]). Kept per face so that non-contiguous runs of the same
/// group survive a round trip.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct FaceLabels {
    pub names: Vec<String>,
    pub of_face: Vec<u32>,
}

impl FaceLabels {
    /// The name of face `f`'s label, if it has one.
    pub fn name_of(&self, f: usize) -> Option<&str> {
        let id = *self.of_face.get(f)?;
        if id == NO_LABEL {
            None
        } else {
            self.names.get(id as usize).map(String::as_str)
        }
    }

    /// The id of `name`, added to the table if new.
    pub fn intern(&mut self, name: &str) -> u32 {
        match self.names.iter().position(|n| n == name) {
            Some(i) => i as u32,
            None => {
                self.names.push(name.to_string());
                (self.names.len() - 1) as u32
            }
        }
    }
}

/// Texture coordinates per face corner (face-varying, as OBJ `vt` and MeshLab's wedge
/// texcoords are): `corner_indices` runs parallel to [`PolygonMesh::face_indices`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CornerUvs {
    pub coords: Vec<[f64; 2]>,
    pub corner_indices: Vec<u32>,
    /// The coordinate (0, 0) that the corners of faces without texture coordinates point
    /// to, when some faces have them and some not (an OBJ that joins a textured and an
    /// untextured part): those faces are written back without, and fitting refuses them,
    /// instead of every face's UVs being dropped or the stand-in being taken as a real one.
    pub untextured: Option<u32>,
}

impl CornerUvs {
    /// The value that stands for "no texture coordinate" (what a face-varying channel,
    /// which holds a value at every corner, keeps there).
    pub const UNTEXTURED_VALUE: [f64; 2] = [0.0, 0.0];

    /// Whether the corner at `corner` (an index into the face corners) has a coordinate of
    /// its own; every corner of a face has one or none.
    pub fn is_textured(&self, corner: usize) -> bool {
        self.untextured != Some(self.corner_indices[corner])
    }

    /// How many of the faces (given by their corner offsets) have texture coordinates (a
    /// face without corners, kept for a flaw report, counts as textured: it lacks nothing).
    pub fn textured_faces(&self, face_offsets: &[u32]) -> usize {
        face_offsets
            .windows(2)
            .filter(|w| w[0] == w[1] || self.is_textured(w[0] as usize))
            .count()
    }
}

/// A polygon soup that never refuses input: any arity, any topology, any vertex order.
///
/// Faces are stored as offsets + indices: face `f` is
/// `face_indices[face_offsets[f]..face_offsets[f + 1]]`. Validation against the file a mesh
/// came from is the readers' job; [`PolygonMesh::validate`] checks the invariants that make
/// indexing safe.
#[derive(Debug, Clone, PartialEq)]
pub struct PolygonMesh {
    pub positions: Vec<[f64; 3]>,
    pub face_offsets: Vec<u32>,
    pub face_indices: Vec<u32>,
    /// OBJ `o` records.
    pub objects: Option<FaceLabels>,
    /// OBJ `g` records.
    pub groups: Option<FaceLabels>,
    pub uvs: Option<CornerUvs>,
    /// Per-vertex scalar written as PLY `quality` (MeshLab colours by it).
    pub quality: Option<Vec<f64>>,
    /// Per-vertex RGBA colour.
    pub colors: Option<Vec<[u8; 4]>>,
    /// OBJ `t crease` / `t corner` / `t creasemethod` tags (subdivision sharpness).
    pub sharp_features: Option<SharpFeatures>,
}

impl Default for PolygonMesh {
    fn default() -> Self {
        PolygonMesh {
            positions: Vec::new(),
            face_offsets: vec![0],
            face_indices: Vec::new(),
            objects: None,
            groups: None,
            uvs: None,
            quality: None,
            colors: None,
            sharp_features: None,
        }
    }
}

impl PolygonMesh {
    /// A mesh from positions and a list of polygons.
    pub fn from_polygons<F: AsRef<[u32]>>(positions: Vec<[f64; 3]>, faces: &[F]) -> Self {
        let mut mesh = PolygonMesh {
            positions,
            ..Default::default()
        };
        for f in faces {
            mesh.push_face(f.as_ref());
        }
        mesh
    }

    /// Appends a face (no checks: a soup keeps what it is given).
    pub fn push_face(&mut self, corners: &[u32]) {
        self.face_indices.extend_from_slice(corners);
        self.face_offsets.push(self.face_indices.len() as u32);
    }

    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    pub fn face_count(&self) -> usize {
        self.face_offsets.len().saturating_sub(1)
    }

    /// The corners of face `f`.
    pub fn face(&self, f: usize) -> &[u32] {
        let (a, b) = (
            self.face_offsets[f] as usize,
            self.face_offsets[f + 1] as usize,
        );
        &self.face_indices[a..b]
    }

    /// All faces in order.
    pub fn faces(&self) -> impl ExactSizeIterator<Item = &[u32]> + '_ {
        self.face_offsets
            .windows(2)
            .map(move |w| &self.face_indices[w[0] as usize..w[1] as usize])
    }

    /// Positions as one flat `[x0, y0, z0, x1, …]` slice, for bulk transfer across FFI.
    pub fn positions_flat(&self) -> &[f64] {
        self.positions.as_flattened()
    }

    /// Number of faces with `n` corners, for n = 0.. up to the largest arity.
    pub fn arity_histogram(&self) -> Vec<usize> {
        let mut hist = Vec::new();
        for w in self.face_offsets.windows(2) {
            let n = (w[1] - w[0]) as usize;
            if hist.len() <= n {
                hist.resize(n + 1, 0);
            }
            hist[n] += 1;
        }
        hist
    }

    /// Axis-aligned bounding box `(min, max)` of the positions; `None` for no vertices.
    pub fn bounding_box(&self) -> Option<([f64; 3], [f64; 3])> {
        let first = *self.positions.first()?;
        Some(self.positions.iter().fold((first, first), |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1]), lo[2].min(p[2])],
                [hi[0].max(p[0]), hi[1].max(p[1]), hi[2].max(p[2])],
            )
        }))
    }

    /// Checks the invariants that make indexing safe: offsets start at 0, never decrease and
    /// end at the index count; every index names a vertex; every coordinate is finite;
    /// optional per-face and per-vertex arrays have the right length.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the first offending face, vertex or array.
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(Error::InvalidInput(m));
        if self.face_offsets.first() != Some(&0) {
            return bad("face_offsets must start with 0".into());
        }
        if *self.face_offsets.last().unwrap() as usize != self.face_indices.len() {
            return bad(format!(
                "face_offsets end at {} but there are {} face indices",
                self.face_offsets.last().unwrap(),
                self.face_indices.len()
            ));
        }
        if let Some(f) = self.face_offsets.windows(2).position(|w| w[1] < w[0]) {
            return bad(format!("face_offsets decrease at face {f}"));
        }
        let n = self.positions.len() as u32;
        if let Some(k) = self.face_indices.iter().position(|&i| i >= n) {
            let f = self.face_offsets.partition_point(|&o| o as usize <= k) - 1;
            return bad(format!(
                "face {f} refers to vertex {} but the mesh has {n} vertices",
                self.face_indices[k]
            ));
        }
        if let Some(v) = self
            .positions
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return bad(format!(
                "vertex {v} has a non-finite coordinate {:?}",
                self.positions[v]
            ));
        }
        let faces = self.face_count();
        for (what, labels) in [("objects", &self.objects), ("groups", &self.groups)] {
            if let Some(l) = labels {
                if l.of_face.len() != faces {
                    return bad(format!(
                        "{what} label {} faces, mesh has {faces}",
                        l.of_face.len()
                    ));
                }
                if let Some(f) = l
                    .of_face
                    .iter()
                    .position(|&i| i != NO_LABEL && i as usize >= l.names.len())
                {
                    return bad(format!(
                        "{what}: face {f} names a label that does not exist"
                    ));
                }
            }
        }
        if let Some(uv) = &self.uvs {
            if uv.corner_indices.len() != self.face_indices.len() {
                return bad("uv corner indices do not match the face corners".into());
            }
            if uv
                .corner_indices
                .iter()
                .any(|&i| i as usize >= uv.coords.len())
            {
                return bad("a uv corner index is out of range".into());
            }
        }
        if self
            .quality
            .as_ref()
            .is_some_and(|q| q.len() != self.positions.len())
        {
            return bad("quality must have one value per vertex".into());
        }
        if self
            .colors
            .as_ref()
            .is_some_and(|c| c.len() != self.positions.len())
        {
            return bad("colors must have one value per vertex".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn histogram_and_faces() {
        let m = PolygonMesh::from_polygons(
            vec![[0.0; 3]; 5],
            &[vec![0u32, 1, 2], vec![0, 1, 2, 3], vec![0, 1, 2, 3, 4]],
        );
        assert_eq!(m.face_count(), 3);
        assert_eq!(m.arity_histogram(), vec![0, 0, 0, 1, 1, 1]);
        assert_eq!(m.face(1), &[0, 1, 2, 3]);
        m.validate().unwrap();
    }

    #[test]
    fn validate_names_the_face_with_a_bad_index() {
        let m = PolygonMesh::from_polygons(vec![[0.0; 3]; 3], &[vec![0u32, 1, 2], vec![0, 1, 7]]);
        let e = m.validate().unwrap_err().to_string();
        assert!(e.contains("face 1") && e.contains("vertex 7"), "{e}");
    }
}
