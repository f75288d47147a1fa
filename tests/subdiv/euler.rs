//! χ = V − E + F is a topological invariant: uniform refinement must preserve it on every
//! fixture mesh, manifold or not, counted directly on the refined faces and compared with
//! the χ that `fixtures/meshes/REFERENCE.json` gives for the input.

use surfkit::mesh::io::read;
use surfkit::subdiv::{refine_uniform, SubdivOptions};

#[test]
fn refinement_preserves_the_euler_characteristic_of_every_fixture() {
    let reference: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(crate::cgal::fixture("REFERENCE.json")).unwrap(),
    )
    .unwrap();
    let meshes = reference["meshes"].as_array().unwrap();
    assert_eq!(meshes.len(), 12);
    for entry in meshes {
        let name = entry["file"].as_str().unwrap();
        let chi = entry["chi"].as_i64().unwrap();
        let mesh = read(&crate::cgal::fixture(name)).unwrap();
        assert_eq!(
            crate::cgal::euler_characteristic(&mesh),
            chi,
            "{name}: input χ"
        );
        let max_level = if mesh.face_count() > 2000 { 2 } else { 3 };
        for levels in 1..=max_level {
            let refined = refine_uniform(&mesh, levels, &SubdivOptions::default())
                .unwrap_or_else(|e| panic!("{name} level {levels}: {e}"));
            assert!(refined.faces().all(|f| f.len() == 4), "{name}: quads only");
            // Level 1 makes one quad per corner, every further level 4 per quad.
            let expected_faces = mesh.face_indices.len() * 4usize.pow(levels - 1);
            assert_eq!(
                refined.face_count(),
                expected_faces,
                "{name} level {levels}: F"
            );
            assert_eq!(
                crate::cgal::euler_characteristic(&refined),
                chi,
                "{name} level {levels}: χ"
            );
        }
    }
}
