//! Uniform Catmull–Clark refinement against CGAL's (`Subdivision_method_3`), the Euler
//! characteristic under refinement, the boundary rules and refined UVs.

#[path = "cgal/mod.rs"]
mod cgal;

use surfkit::mesh::io::read;
use surfkit::mesh::PolygonMesh;
use surfkit::subdiv::{refine_uniform, SubdivOptions};
use surfkit::tolerance::ROUND_OFF;

/// Refines with OpenSubdiv and CGAL and checks: same vertex count, every CGAL vertex has an
/// OpenSubdiv vertex within ROUND_OFF · bbox diagonal, and the same faces. Returns the
/// largest deviation relative to the diagonal.
fn assert_matches_cgal(
    name: &str,
    mesh: &PolygonMesh,
    levels: u32,
    options: &SubdivOptions,
) -> f64 {
    let ours = refine_uniform(mesh, levels, options).unwrap();
    let theirs = cgal::catmull_clark(mesh, levels);
    let diag = cgal::diagonal(mesh);
    assert_eq!(
        ours.vertex_count(),
        theirs.vertex_count(),
        "{name} level {levels}: vertex count"
    );
    assert_eq!(
        ours.face_count(),
        theirs.face_count(),
        "{name} level {levels}: face count"
    );
    let m = cgal::match_vertices(&ours, &theirs, ROUND_OFF * diag);
    assert!(
        m.unmatched_theirs.is_empty() && m.unmatched_ours.is_empty(),
        "{name} level {levels}: {} CGAL vertices have no OpenSubdiv vertex within {:e}",
        m.unmatched_theirs.len(),
        ROUND_OFF * diag
    );
    let our_faces = cgal::face_cycles(
        ours.faces()
            .map(|f| f.iter().map(|&v| v as usize).collect()),
    );
    assert_eq!(
        Some(our_faces),
        cgal::faces_in_our_ids(&theirs, &m),
        "{name} level {levels}: faces differ"
    );
    let rel = m.max_distance / diag;
    eprintln!("{name} level {levels}: max deviation from CGAL {rel:e} of the bbox diagonal");
    rel
}

#[test]
fn closed_quads_match_cgal_at_levels_1_to_3() {
    for name in ["catmark_torus.obj", "quadknot.obj", "comments.off"] {
        let mesh = read(&cgal::fixture(name)).unwrap();
        for levels in 1..=3 {
            assert_matches_cgal(name, &mesh, levels, &SubdivOptions::default());
        }
    }
}

#[test]
fn closed_mixed_polygons_match_cgal_at_levels_1_to_3() {
    // rabbit: triangles, quads and n-gons up to 16 corners; spot and fixed_top: triangles.
    for (name, max_level) in [("rabbit.obj", 3), ("spot.obj", 2), ("fixed_top.ply", 2)] {
        let mesh = read(&cgal::fixture(name)).unwrap();
        for levels in 1..=max_level {
            assert_matches_cgal(name, &mesh, levels, &SubdivOptions::default());
        }
    }
}
