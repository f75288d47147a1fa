//! `surfkit eat` as a pipeline uses it: exit status, JSON report, marked mesh.

mod common;

use std::process::Command;

use surfkit::mesh::io::write;

fn surfkit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_surfkit"))
}

#[test]
fn stages_from_groups_with_targets_pass_and_fail_with_status_3() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("stamp.obj");
    write(&good, &surfkit::shapes::stamp(&[]), &Default::default()).unwrap();
    let bad = dir.path().join("stamp_crack.obj");
    write(
        &bad,
        &surfkit::shapes::stamp(&[surfkit::shapes::StampFlaw::Crack]),
        &Default::default(),
    )
    .unwrap();
    let targets = "genus=0,boundaries=3;genus=0,boundaries=2;genus=0,boundaries=1;genus=0";
    let ok = surfkit()
        .args(["eat", "--stages", "groups", "--target", targets])
        .arg(&good)
        .output()
        .unwrap();
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stdout)
    );
    let text = String::from_utf8_lossy(&ok.stdout);
    assert_eq!(text.matches("verified").count(), 4, "{text}");

    let marked = dir.path().join("marked.ply");
    let out = surfkit()
        .args([
            "eat", "--stages", "groups", "--json", "--target", targets, "--mark",
        ])
        .arg(&marked)
        .arg(&bad)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(3));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["verified"], false);
    assert_eq!(json["report"]["first_failure"], 1);
    assert_eq!(json["report"]["flaws"][0]["kind"], "crack");
    let m = surfkit::mesh::io::read(&marked).unwrap();
    let crack_vertices: Vec<u64> = json["report"]["flaws"][0]["vertices"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap())
        .collect();
    let colors = m.colors.unwrap();
    for v in crack_vertices {
        assert_eq!(
            colors[v as usize],
            surfkit::topology::flaw_color(surfkit::topology::FlawKind::Crack)
        );
    }
}

#[test]
fn fail_on_kinds_and_expectations() {
    let tetra = common::meshes_dir().join("joined_tetrahedra.obj");
    let out = surfkit()
        .args(["eat", "--fail-on", "non_manifold_edge"])
        .arg(&tetra)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(3));
    let out = surfkit()
        .args(["eat", "--fail-on", "hole"])
        .arg(&tetra)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let out = surfkit()
        .args(["eat", "--expect", "4"])
        .arg(&tetra)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let out = surfkit()
        .args(["eat", "--fail-on", "holes"])
        .arg(&tetra)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown flaw kind \"holes\""));
    let torus = common::meshes_dir().join("catmark_torus.obj");
    let out = surfkit()
        .args(["eat", "--reference"])
        .arg(&torus)
        .arg(common::meshes_dir().join("quadknot.obj"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "both are tori");
    let out = surfkit()
        .args(["eat", "--reference"])
        .arg(&torus)
        .arg(common::meshes_dir().join("spot.obj"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(3), "a sphere is not a torus");
}
