//! The page of `surfkit eat --html`: the mesh, its flaws highlighted by kind, boundary
//! loops as lines, and the flaw list that centres the camera on a flaw when clicked.

use super::page::{FlawEntry, HtmlPage, LegendEntry, Shading};
use super::scene::{u32_base64, Highlight, Lines, Points, View};
use crate::mesh::vector::distance;
use crate::mesh::PolygonMesh;
use crate::report::RenderOptions;
use crate::topology::{EatReport, Flaw, FlawKind};

/// One colour per flaw kind, in [`FlawKind::ALL`]'s order: saturated, distinct from the
/// grey mesh and from each other.
const KIND_COLOURS: [[u8; 3]; 11] = [
    [255, 140, 0],   // missing triangle
    [255, 200, 0],   // missing quad
    [255, 60, 60],   // hole
    [255, 0, 200],   // crack
    [0, 200, 255],   // non-manifold edge
    [60, 120, 255],  // non-manifold vertex
    [160, 90, 255],  // duplicated facet
    [120, 255, 80],  // degenerate facet
    [0, 255, 190],   // coincident vertices
    [255, 255, 255], // unreferenced vertex
    [255, 110, 150], // inconsistent orientation
];

/// The colour of a flaw kind on the page.
pub fn kind_colour(kind: FlawKind) -> [u8; 3] {
    let i = FlawKind::ALL.iter().position(|&k| k == kind).unwrap_or(0);
    KIND_COLOURS[i]
}

/// How far a flaw's elements reach from its representative point (what the camera frames
/// when the flaw is clicked); a flaw at one point gets a hundredth of the mesh's size.
fn flaw_radius(mesh: &PolygonMesh, flaw: &Flaw, mesh_radius: f64) -> f64 {
    let vertex_ids = flaw.vertices.iter().copied().chain(
        flaw.faces
            .iter()
            .filter(|&&f| (f as usize) < mesh.face_count())
            .flat_map(|&f| mesh.face(f as usize).iter().copied()),
    );
    let reach = vertex_ids
        .filter_map(|v| mesh.positions.get(v as usize))
        .map(|p| distance(*p, flaw.position))
        .fold(0.0, f64::max);
    reach.max(0.01 * mesh_radius)
}

/// The segments a flaw draws: a boundary loop closed, an edge's two ends joined.
fn flaw_segments(mesh: &PolygonMesh, flaw: &Flaw) -> Vec<[f64; 3]> {
    let points: Vec<[f64; 3]> = flaw
        .vertices
        .iter()
        .filter_map(|&v| mesh.positions.get(v as usize).copied())
        .collect();
    let closed = flaw.kind.is_boundary_loop() && points.len() > 2;
    let pairs = if closed {
        points.len()
    } else if points.len() == 2 && flaw.kind == FlawKind::NonManifoldEdge {
        1
    } else {
        0
    };
    (0..pairs)
        .flat_map(|i| [points[i], points[(i + 1) % points.len()]])
        .collect()
}

/// The page of an EAT report on `mesh` (the file `name`), with `text` the command's text
/// summary.
pub fn eat_page(name: &str, mesh: &PolygonMesh, report: &EatReport, text: &str) -> HtmlPage {
    let mut view = View::new("mesh", mesh);
    let mut legend = Vec::new();
    for (kind, count) in report.flaw_counts() {
        let colour = kind_colour(kind);
        let of_kind = || report.flaws.iter().filter(move |f| f.kind == kind);
        let faces: Vec<u32> = of_kind().flat_map(|f| f.faces.iter().copied()).collect();
        if !faces.is_empty() {
            view.highlights.push(Highlight {
                name: kind.name().into(),
                colour,
                faces: u32_base64(faces.into_iter()),
            });
        }
        let segments: Vec<[f64; 3]> = of_kind().flat_map(|f| flaw_segments(mesh, f)).collect();
        if !segments.is_empty() {
            let segments = view.local_positions(segments.iter());
            view.lines.push(Lines {
                name: kind.name().into(),
                colour,
                segments,
            });
        }
        let points: Vec<[f64; 3]> = of_kind()
            .filter(|f| !f.kind.is_boundary_loop())
            .flat_map(|f| f.vertices.iter())
            .filter_map(|&v| mesh.positions.get(v as usize).copied())
            .collect();
        if !points.is_empty() {
            let positions = view.local_positions(points.iter());
            view.points.push(Points {
                name: kind.name().into(),
                colour,
                positions,
                size: 7.0,
            });
        }
        legend.push(LegendEntry {
            name: kind.name().into(),
            colour,
            count,
        });
    }
    let flaws = report
        .flaws
        .iter()
        .enumerate()
        .map(|(index, f)| FlawEntry {
            index,
            kind: f.kind.name().into(),
            description: f.description.clone(),
            fix: f.suggested_fix.clone(),
            fix_verified: f.fix_verified,
            position: view.local(f.position),
            radius: flaw_radius(mesh, f, view.radius),
            faces: f.faces.clone(),
            vertices: f.vertices.clone(),
            closed_loop: f.kind.is_boundary_loop(),
        })
        .collect();
    let s = &report.statistics;
    let c = &report.counts;
    let summary = vec![
        ("file".into(), name.to_string()),
        ("vertices".into(), s.vertices.to_string()),
        ("edges".into(), s.edges.to_string()),
        ("facets".into(), s.facets.to_string()),
        (
            "Euler characteristic".into(),
            s.euler_characteristic.to_string(),
        ),
        ("components".into(), c.components.to_string()),
        ("boundary loops".into(), c.boundary_loops.to_string()),
        (
            "test points".into(),
            if report.checkpoints.is_empty() {
                "none".into()
            } else if report.verified() {
                format!("{} verified", report.checkpoints.len())
            } else {
                format!(
                    "FAILED at {} of {}",
                    report.first_failure.map_or(0, |i| i + 1),
                    report.checkpoints.len()
                )
            },
        ),
        ("flaws".into(), report.flaws.len().to_string()),
    ];
    HtmlPage {
        title: format!("EAT of {name}"),
        summary,
        text: Some(text.to_string()),
        shading: Shading::Flat,
        initial_view: {
            let d = RenderOptions::default();
            (d.azimuth, d.elevation)
        },
        views: vec![view],
        legend,
        flaws,
        colour_bar: None,
        plot: None,
    }
}
