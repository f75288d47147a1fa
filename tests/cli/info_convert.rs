//! `surfkit info` and `surfkit convert` as users call them.

use std::process::Command;

fn surfkit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_surfkit"))
}

#[test]
fn info_json_lists_what_openmesh_refused() {
    let out = surfkit()
        .args(["info", "--json"])
        .arg(crate::common::meshes_dir().join("joined_tetrahedra.obj"))
        .output()
        .unwrap();
    assert!(out.status.success());
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["vertices"], 5);
    assert_eq!(json["faces"], 8);
    assert_eq!(json["objects"], 1, "the file has one `o` record");
    let refused = json["refused"].as_array().unwrap();
    assert_eq!(
        refused.len() + json["halfedge"]["faces"].as_u64().unwrap() as usize,
        8
    );
    assert!(refused
        .iter()
        .all(|r| r["reason"] == "complex_vertex" || r["reason"] == "complex_edge"));
    assert_eq!(
        json["openmesh_messages"].as_array().unwrap().len(),
        refused.len()
    );
}

#[test]
fn convert_writes_the_other_format_and_never_over_its_input() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("torus.obj");
    std::fs::copy(
        crate::common::meshes_dir().join("catmark_torus.obj"),
        &input,
    )
    .unwrap();
    let before = std::fs::read(&input).unwrap();
    let out_ply = dir.path().join("torus.ply");
    let ok = surfkit()
        .arg("convert")
        .arg(&input)
        .arg(&out_ply)
        .output()
        .unwrap();
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    let a = surfkit::mesh::io::read(&input).unwrap();
    let b = surfkit::mesh::io::read(&out_ply).unwrap();
    assert_eq!(a.positions, b.positions);
    assert_eq!(a.face_indices, b.face_indices);
    assert!(std::fs::read(&out_ply)
        .unwrap()
        .windows(20)
        .any(|w| w == b"binary_little_endian"));

    let refused = surfkit()
        .arg("convert")
        .arg(&input)
        .arg(&input)
        .output()
        .unwrap();
    assert_eq!(refused.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("refusing to write over the input"));
    assert_eq!(
        std::fs::read(&input).unwrap(),
        before,
        "the input is untouched"
    );

    let unknown = surfkit()
        .arg("convert")
        .arg(&input)
        .arg(dir.path().join("x.stl"))
        .output()
        .unwrap();
    assert_eq!(unknown.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&unknown.stderr).contains("unknown mesh format"));
    assert!(!dir.path().join("x.stl").exists());
    // No temporary file is left behind by a failed or a finished write.
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().starts_with(".surfkit-"))
        .collect();
    assert!(leftovers.is_empty());
}
