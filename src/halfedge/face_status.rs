//! What the half-edge structure did with each face of a soup.

/// Why OpenMesh took or refused a face (the codes of `cpp/openmesh/bridge.cpp`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FaceStatus {
    Added,
    /// An edge of the face already has a face on the side this one needs (a third face on
    /// an edge, or a neighbour with the opposite orientation).
    ComplexEdge,
    /// A vertex of the face cannot take another fan of faces there.
    ComplexVertex,
    /// OpenMesh could not re-link the boundary around a vertex.
    RelinkFailed,
    /// Fewer than 3 corners or a repeated vertex: never given to OpenMesh.
    Degenerate,
    /// Refused for a reason OpenMesh did not name.
    Other,
}

impl FaceStatus {
    pub(crate) fn from_code(code: u8) -> FaceStatus {
        match code {
            0 => FaceStatus::Added,
            1 => FaceStatus::ComplexEdge,
            2 => FaceStatus::ComplexVertex,
            3 => FaceStatus::RelinkFailed,
            4 => FaceStatus::Degenerate,
            _ => FaceStatus::Other,
        }
    }

    /// A short human description.
    pub fn describe(self) -> &'static str {
        match self {
            FaceStatus::Added => "added",
            FaceStatus::ComplexEdge => {
                "complex edge (an edge would get a third face or an inconsistent orientation)"
            }
            FaceStatus::ComplexVertex => "complex vertex (no room in the vertex's fan of faces)",
            FaceStatus::RelinkFailed => "boundary re-linking failed",
            FaceStatus::Degenerate => "degenerate (fewer than 3 corners or a repeated vertex)",
            FaceStatus::Other => "refused",
        }
    }
}
