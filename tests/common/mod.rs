//! Shared helpers of the integration tests: the fixture meshes and their reference values.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use serde_json::Value;

/// The folder of the real meshes (copied from the shared fixtures, with REFERENCE.json).
pub fn meshes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/meshes")
}

/// Each fixture mesh with its reference record from REFERENCE.json.
pub fn reference_meshes() -> Vec<(PathBuf, Value)> {
    let text = std::fs::read_to_string(meshes_dir().join("REFERENCE.json")).unwrap();
    let json: Value = serde_json::from_str(&text).unwrap();
    json["meshes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| (meshes_dir().join(m["file"].as_str().unwrap()), m.clone()))
        .collect()
}

/// A reference count as usize (panics with the field name if absent).
pub fn count(record: &Value, field: &str) -> usize {
    record[field]
        .as_u64()
        .unwrap_or_else(|| panic!("REFERENCE.json has no count {field} for {}", record["file"]))
        as usize
}

/// The reference meshes, read, whose only flaw is a boundary (`open`) or that have no flaw
/// of any kind (`!open`, closed), with their file names.
pub fn sound_meshes(open: bool) -> Vec<(String, surfkit::mesh::PolygonMesh)> {
    let flaws = [
        "non_manifold_edges",
        "non_manifold_vertices",
        "unreferenced_vertices",
        "duplicated_facets",
        "degenerate_facets",
        "coincident_vertex_extra",
        "inconsistent_orientation_edges",
    ];
    reference_meshes()
        .into_iter()
        .filter(|(_, r)| (count(r, "boundary_edges") > 0) == open)
        .filter(|(_, r)| flaws.iter().all(|k| count(r, k) == 0))
        .map(|(p, _)| {
            let options = surfkit::mesh::io::ReadOptions::default();
            let m = surfkit::mesh::io::read_with(&p, &options).unwrap();
            (p.file_name().unwrap().to_string_lossy().to_string(), m)
        })
        .collect()
}

/// A mesh's faces as owned corner lists (to edit and rebuild).
pub fn faces_of(m: &surfkit::mesh::PolygonMesh) -> Vec<Vec<u32>> {
    m.faces().map(<[u32]>::to_vec).collect()
}

/// Test points at the end of each stage (from the OBJ groups), with χ from the target
/// topology the paper names at each stage: a disk with two, one and no inside holes, then
/// a ball.
pub fn stamp_stages(mesh: &surfkit::mesh::PolygonMesh) -> surfkit::topology::EatOptions {
    let groups = mesh.groups.as_ref().unwrap();
    let targets = [
        "genus=0,boundaries=3",
        "genus=0,boundaries=2",
        "genus=0,boundaries=1",
        "genus=0",
    ];
    let mut test_points = Vec::new();
    for (stage, target) in targets.iter().enumerate() {
        let end = groups
            .of_face
            .iter()
            .rposition(|&g| g == stage as u32)
            .unwrap()
            + 1;
        test_points.push(surfkit::topology::TestPoint {
            label: surfkit::shapes::STAMP_STAGES[stage].0.to_string(),
            facets: end,
            expected: surfkit::topology::TargetTopology::parse(target)
                .unwrap()
                .euler_characteristic(),
        });
    }
    surfkit::topology::EatOptions {
        test_points,
        ..Default::default()
    }
}

/// The Python with the peers (pymeshlab, trimesh) that `scripts/setup.sh` installs:
/// `SURFKIT_PYTHON`, or the repository's `.venv`.
pub fn peer_python() -> PathBuf {
    if let Ok(p) = std::env::var("SURFKIT_PYTHON") {
        return PathBuf::from(p);
    }
    let venv = Path::new(env!("CARGO_MANIFEST_DIR")).join(".venv/bin/python");
    assert!(
        venv.exists(),
        "no Python with pymeshlab: run the tests through scripts/setup.sh (it makes .venv), or set SURFKIT_PYTHON"
    );
    venv
}

/// Asserts what `fair` promises about its output: the input's faces and vertex order, and
/// every vertex fewer than 3 edges from the boundary (paper §4) bit-identical to the input.
/// Returns the fixed flags.
pub fn assert_faces_and_boundary_rings_kept(
    before: &surfkit::mesh::PolygonMesh,
    after: &surfkit::mesh::PolygonMesh,
) -> Vec<bool> {
    use surfkit::fair::{fixed_vertices, MeshTopology};
    assert_eq!(after.face_offsets, before.face_offsets);
    assert_eq!(after.face_indices, before.face_indices);
    let fixed = fixed_vertices(&MeshTopology::new(before).unwrap(), 3, &[]).unwrap();
    for (v, _) in fixed.iter().enumerate().filter(|(_, &held)| held) {
        assert_eq!(
            after.positions[v].map(f64::to_bits),
            before.positions[v].map(f64::to_bits),
            "fixed vertex {v} moved"
        );
    }
    fixed
}

/// The unit cube as six quads, outward oriented: a closed quad mesh of genus 0.
pub fn unit_cube() -> surfkit::mesh::PolygonMesh {
    let p: Vec<[f64; 3]> = (0..8)
        .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
        .collect();
    surfkit::mesh::PolygonMesh::from_polygons(
        p,
        &[
            [0u32, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ],
    )
}

/// The largest coordinate difference between two meshes' vertices (same order): how far
/// two optimizations' results are apart.
pub fn largest_coordinate_difference(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .flat_map(|(p, q)| (0..3).map(move |k| (p[k] - q[k]).abs()))
        .fold(0.0f64, f64::max)
}
