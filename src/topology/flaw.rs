//! A located flaw: its kind, the elements (ids as in the input: 0-based positions in the
//! file's vertex and face order — OBJ `v` numbers minus one), where it is, and a fix.

/// The kinds of flaw the locator reports.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "snake_case")]
pub enum FlawKind {
    /// A boundary loop of 3 edges: a triangle left unfilled.
    MissingTriangle,
    /// A boundary loop of 4 edges: a quad left unfilled.
    MissingQuad,
    /// Any other boundary loop.
    Hole,
    /// A boundary edge running along a chain of boundary edges (a T-junction, Fig. 22).
    Crack,
    /// An edge with more than two facet sides.
    NonManifoldEdge,
    /// A vertex whose facets form more than one fan.
    NonManifoldVertex,
    /// A facet with the vertex set of an earlier facet.
    DuplicatedFacet,
    /// A facet with fewer than 3 corners or a repeated vertex.
    DegenerateFacet,
    /// Two distinct vertices at the same place (within the weld tolerance).
    CoincidentVertices,
    /// A vertex no facet uses.
    UnreferencedVertex,
    /// Two facets running their shared edge the same way.
    InconsistentOrientation,
}

impl FlawKind {
    pub const ALL: [FlawKind; 11] = [
        FlawKind::MissingTriangle,
        FlawKind::MissingQuad,
        FlawKind::Hole,
        FlawKind::Crack,
        FlawKind::NonManifoldEdge,
        FlawKind::NonManifoldVertex,
        FlawKind::DuplicatedFacet,
        FlawKind::DegenerateFacet,
        FlawKind::CoincidentVertices,
        FlawKind::UnreferencedVertex,
        FlawKind::InconsistentOrientation,
    ];

    /// The snake_case name used in JSON and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            FlawKind::MissingTriangle => "missing_triangle",
            FlawKind::MissingQuad => "missing_quad",
            FlawKind::Hole => "hole",
            FlawKind::Crack => "crack",
            FlawKind::NonManifoldEdge => "non_manifold_edge",
            FlawKind::NonManifoldVertex => "non_manifold_vertex",
            FlawKind::DuplicatedFacet => "duplicated_facet",
            FlawKind::DegenerateFacet => "degenerate_facet",
            FlawKind::CoincidentVertices => "coincident_vertices",
            FlawKind::UnreferencedVertex => "unreferenced_vertex",
            FlawKind::InconsistentOrientation => "inconsistent_orientation",
        }
    }

    /// Whether the flaw is a boundary loop (hole, missing facet or crack).
    pub fn is_boundary_loop(self) -> bool {
        matches!(
            self,
            FlawKind::Hole | FlawKind::MissingTriangle | FlawKind::MissingQuad | FlawKind::Crack
        )
    }

    /// Parses a name of [`FlawKind::name`].
    pub fn from_name(name: &str) -> Option<FlawKind> {
        FlawKind::ALL.into_iter().find(|k| k.name() == name)
    }
}

/// Measurements of a boundary loop. Finite coordinates give finite measures wherever the
/// value fits in an f64; beyond that a measure is +∞ (see `locator::loop_shape`), written
/// `"Infinity"` in JSON (where a bare number cannot say it) and `Infinity` in text.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LoopShape {
    pub edges: usize,
    #[serde(serialize_with = "measure_json")]
    pub perimeter: f64,
    /// Norm of the loop's vector area (½‖Σ pᵢ × pᵢ₊₁‖): the area of a planar loop.
    #[serde(serialize_with = "measure_json")]
    pub area: f64,
    /// Area below 1 % of the squared median edge length, or perimeter below half of it:
    /// too small to see at ordinary zoom (the paper's §4.1–4.2 flaws).
    pub tiny: bool,
}

/// One located flaw.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Flaw {
    pub kind: FlawKind,
    /// Vertex ids involved (a loop's vertices in order; an edge's two ends; …).
    pub vertices: Vec<u32>,
    /// Face ids involved.
    pub faces: Vec<u32>,
    /// A representative point (loop centroid, edge midpoint, the vertex).
    pub position: [f64; 3],
    /// Boundary-loop measurements, for holes, missing facets and cracks.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shape: Option<LoopShape>,
    /// Connected component (edge-connected facets) it lies in, where that is defined.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub component: Option<u32>,
    pub description: String,
    pub suggested_fix: String,
    /// Whether applying the suggested fix (`surfkit::repair`) removed the flaw; None when
    /// not checked (`surfkit::repair::check_fixes` sets it) or the fix is a judgment.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fix_verified: Option<bool>,
}

/// A loop measure or a coordinate in text: 6 decimals; from 1e15 on 6 significant
/// decimals with an exponent (not 300 digits); `Infinity` where it passes f64's range.
pub fn show_measure(x: f64) -> String {
    if x.is_finite() && x.abs() < 1e15 {
        format!("{x:.6}")
    } else if x.is_finite() {
        format!("{x:.6e}")
    } else {
        // Measures are non-negative; from finite coordinates the only non-finite one is +∞.
        "Infinity".into()
    }
}

/// How many ids a list in a flaw's or change's text shows before it is cut short.
pub const IDS_SHOWN: usize = 8;

/// A list of vertex or facet ids in text: all of a short list, `[a, b, …, h, … (n in all)]`
/// for a longer one, so that one flaw or change stays one readable line (a degenerate facet
/// can have thousands of corners); the JSON report keeps every id.
pub fn show_ids(ids: &[u32]) -> String {
    if ids.len() <= IDS_SHOWN {
        return format!("{ids:?}");
    }
    let head: Vec<String> = ids[..IDS_SHOWN].iter().map(u32::to_string).collect();
    format!("[{}, … ({} in all)]", head.join(", "), ids.len())
}

/// A loop measure in JSON: a number, or the string `"Infinity"` (serde_json would write
/// `null`, which reads as "not measured"). JavaScript's `Number`, Python's `float` and
/// Rust's `f64::from_str` all read that string back as +∞.
fn measure_json<S: serde::Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    if x.is_finite() {
        s.serialize_f64(*x)
    } else {
        s.serialize_str(&show_measure(*x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn id_lists_are_cut_after_eight_ids_and_say_how_many() {
        assert_eq!(show_ids(&[]), "[]");
        assert_eq!(
            show_ids(&[3, 1, 4, 1, 5, 9, 2, 6]),
            "[3, 1, 4, 1, 5, 9, 2, 6]"
        );
        let long: Vec<u32> = (0..10_000).collect();
        assert_eq!(
            show_ids(&long),
            "[0, 1, 2, 3, 4, 5, 6, 7, … (10000 in all)]"
        );
    }
}
