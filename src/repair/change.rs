//! One change a repair made: the flaw kind it answers, what was done, and the facets and
//! vertices it touched, by their ids before (input ids; new elements after them) and after
//! (positions in the written mesh; null for an element taken out).

use crate::topology::FlawKind;

/// What a change did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Action {
    WeldVertex,
    DeleteFacet,
    RemoveRepeatedCorner,
    SplitEdge,
    AddFacet,
    SplitVertex,
    ReverseFacet,
    DeleteVertex,
}

#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Change {
    pub kind: FlawKind,
    pub action: Action,
    pub faces: Vec<u32>,
    pub vertices: Vec<u32>,
    pub faces_after: Vec<Option<u32>>,
    pub vertices_after: Vec<Option<u32>>,
    pub description: String,
}

impl Change {
    pub fn new(
        kind: FlawKind,
        action: Action,
        faces: Vec<u32>,
        vertices: Vec<u32>,
        description: String,
    ) -> Self {
        Change {
            kind,
            action,
            faces,
            vertices,
            faces_after: Vec::new(),
            vertices_after: Vec::new(),
            description,
        }
    }
}
