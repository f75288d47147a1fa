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
        .arg(dir.path().join("x.3mf"))
        .output()
        .unwrap();
    assert_eq!(unknown.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&unknown.stderr).contains("unknown mesh format"));
    assert!(!dir.path().join("x.3mf").exists());
    // No temporary file is left behind by a failed or a finished write.
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().starts_with(".surfkit-"))
        .collect();
    assert!(leftovers.is_empty());
}

/// A mesh through STL and back: `eat` finds the triangulated mesh's topology (the same χ,
/// components and boundary loops as the polygons'), and a cut binary STL is refused with
/// its file, the header's count and where it ends.
#[test]
fn stl_round_trip_keeps_the_topology_and_a_cut_file_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let input = crate::common::meshes_dir().join("rabbit.obj");
    let eat = |path: &std::path::Path| {
        let out = surfkit()
            .arg("eat")
            .arg(path)
            .arg("--json")
            .output()
            .unwrap();
        assert!(out.status.code().is_some_and(|c| c == 0 || c == 3));
        serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap()["report"]["counts"]
            .clone()
    };
    let before = eat(&input);
    for ascii in [false, true] {
        let stl = dir
            .path()
            .join(format!("rabbit{}.stl", if ascii { "_a" } else { "" }));
        let mut convert = surfkit();
        convert.arg("convert").arg(&input).arg(&stl);
        if ascii {
            convert.arg("--ascii");
        }
        let ok = convert.output().unwrap();
        assert!(
            ok.status.success(),
            "{}",
            String::from_utf8_lossy(&ok.stderr)
        );
        // 176 triangles, 496 quads and 6 16-gons as fans: 176 + 2 × 496 + 14 × 6.
        let said = String::from_utf8_lossy(&ok.stdout);
        assert!(
            said.contains("678 faces (written as 1252 triangles)"),
            "{said}"
        );
        assert_eq!(std::fs::read(&stl).unwrap().starts_with(b"solid"), ascii);
        let after = eat(&stl);
        for key in [
            "euler_characteristic",
            "components",
            "boundary_loops",
            "vertices_referenced",
        ] {
            assert_eq!(after[key], before[key], "{key}");
        }
    }
    let bytes = std::fs::read(dir.path().join("rabbit.stl")).unwrap();
    let cut = dir.path().join("cut.stl");
    std::fs::write(&cut, &bytes[..bytes.len() - 70]).unwrap();
    let out = surfkit().arg("eat").arg(&cut).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("cut.stl: header: binary STL: the header gives")
            && stderr.contains("the file is truncated: it ends inside facet"),
        "{stderr}"
    );
}
