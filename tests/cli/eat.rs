//! `surfkit eat` as a pipeline uses it: exit status, JSON report, marked mesh.

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
    let tetra = crate::common::meshes_dir().join("joined_tetrahedra.obj");
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
    let torus = crate::common::meshes_dir().join("catmark_torus.obj");
    let out = surfkit()
        .args(["eat", "--reference"])
        .arg(&torus)
        .arg(crate::common::meshes_dir().join("quadknot.obj"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "both are tori");
    let out = surfkit()
        .args(["eat", "--reference"])
        .arg(&torus)
        .arg(crate::common::meshes_dir().join("spot.obj"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(3), "a sphere is not a torus");
}

/// Two triangles on edge 0–1 from one side and a quad 0–3–1–2 on the other: vertex 3 is
/// 0.4 % of the edge's length off the edge (a float export of a T-junction).
#[test]
fn crack_tolerance_decides_whether_a_vertex_off_the_edge_is_a_t_vertex() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.obj");
    std::fs::write(
        &path,
        "v 0 0 0\nv 1 0 0\nv 0.5 -1 0\nv 0.5 0.004 0\nv 0.5 1 0\nf 1 3 2\nf 1 4 5\nf 4 2 5\n",
    )
    .unwrap();
    let run = |extra: &[&str]| {
        let out = surfkit()
            .arg("eat")
            .arg(&path)
            .arg("--json")
            .args(extra)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let kinds: Vec<String> = json["report"]["flaws"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f["kind"].as_str().unwrap().to_string())
            .collect();
        (kinds, json)
    };
    let (kinds, json) = run(&[]);
    assert!(kinds.contains(&"crack".to_string()), "{kinds:?}");
    let crack = json["report"]["flaws"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["kind"] == "crack")
        .unwrap();
    let mut edge: Vec<u64> = crack["vertices"].as_array().unwrap()[..2]
        .iter()
        .map(|v| v.as_u64().unwrap())
        .collect();
    edge.sort_unstable();
    assert_eq!(edge, vec![0, 1]);
    assert_eq!(crack["vertices"][2], 3);
    assert_eq!(crack["faces"], serde_json::json!([0]));
    let (kinds, _) = run(&["--crack-tolerance", "0.001"]);
    assert!(!kinds.contains(&"crack".to_string()), "{kinds:?}");
    let out = surfkit()
        .args(["eat", path.to_str().unwrap(), "--crack-tolerance", "2"])
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(2),
        "clap refuses a tolerance outside (0, 1)"
    );
}

/// Every fix `eat` suggests for the stamp's three flaws is checked by applying it and
/// found to work; `--no-fix-check` leaves them unchecked.
#[test]
fn suggested_fixes_are_checked_by_applying_them() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("stamp_flaws.obj");
    let flaws = [
        surfkit::shapes::StampFlaw::TinyTriangle,
        surfkit::shapes::StampFlaw::NarrowQuad,
        surfkit::shapes::StampFlaw::Crack,
    ];
    write(&bad, &surfkit::shapes::stamp(&flaws), &Default::default()).unwrap();
    for (extra, expected) in [(None, Some(true)), (Some("--no-fix-check"), None)] {
        let mut cmd = surfkit();
        cmd.args(["eat", "--json"]).arg(&bad);
        cmd.args(extra);
        let out = cmd.output().unwrap();
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let list = v["report"]["flaws"].as_array().unwrap();
        assert_eq!(list.len(), 3);
        for f in list {
            assert_eq!(f["fix_verified"].as_bool(), expected, "{f}");
        }
    }
}

/// Test points without a χ to check at them were dropped in silence: `eat --every 100`
/// printed no test point and passed. Each way of placing them is refused, naming the
/// option (in text and in JSON lines); `repair --stages` alike, writing nothing.
#[test]
fn test_points_without_an_expected_chi_are_refused_not_dropped() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("stamp.obj");
    write(&mesh, &surfkit::shapes::stamp(&[]), &Default::default()).unwrap();
    let repaired = dir.path().join("repaired.obj");
    let run = |args: &[&str]| {
        let out = surfkit()
            .arg(args[0])
            .arg(&mesh)
            .args(&args[1..])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        (out.status.code(), stderr, out.stdout)
    };
    let refusal = "places test points but no χ is given to check at them";
    let cases: [&[&str]; 4] = [
        &["eat", "--stages", "groups"],
        &["eat", "--test-points", "5,3"],
        &["eat", "--every", "10"],
        &["eat", "--stages", "objects", "--jsonl"],
    ];
    for args in cases {
        let (code, err, _) = run(args);
        assert_eq!(code, Some(1), "{args:?}: {err}");
        assert!(
            err.contains(&format!("{} {refusal}", args[1])),
            "{args:?}: {err}"
        );
    }
    // With an expected χ the same test points are checked and shown.
    let (_, _, out) = run(&["eat", "--every", "10", "--expect", "1"]);
    assert!(String::from_utf8_lossy(&out).contains("test point 1"));

    let (code, err, _) = run(&["repair", repaired.to_str().unwrap(), "--stages", "groups"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains(&format!("--stages {refusal}")), "{err}");
    assert!(
        !repaired.exists(),
        "nothing is written when the command is refused"
    );
}
