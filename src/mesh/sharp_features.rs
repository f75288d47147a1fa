//! Sharp features of a subdivision control mesh as OpenSubdiv's OBJ files tag them
//! (`t crease 2/1/0 v0 v1 s`, `t corner 1/1/0 v s`, `t creasemethod 0/0/1 chaikin`):
//! plain data kept with the mesh so that they survive reading and writing; the subdivision
//! layer turns them into its own options.

/// Creases, corners and the crease rule of a control mesh (vertex ids 0-based, as in the
/// tags). Sharpness: 0 smooth, k sharp for k levels, ≥ 10 infinitely sharp.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SharpFeatures {
    /// Edges (their two vertices) and their sharpness.
    pub creases: Vec<([u32; 2], f32)>,
    /// Vertices and their sharpness.
    pub corners: Vec<(u32, f32)>,
    /// Chaikin's rule (`t creasemethod 0/0/1 chaikin`) instead of the uniform one.
    pub chaikin: bool,
}

impl SharpFeatures {
    pub fn is_empty(&self) -> bool {
        self.creases.is_empty() && self.corners.is_empty() && !self.chaikin
    }
}
