//! Facets that repeat a vertex (`f 1 2 3 1`, `f 1 1 2`), alone or beside sound ones: they
//! are counted as degenerate, never handed to OpenMesh (whose walks abort on a self-loop
//! half-edge), and they do not invent other flaws. The expected counts follow
//! `fixtures/meshes/REFERENCE.json`'s definitions: E counts pairs {a, b} with a ≠ b, and a
//! vertex's fans are of facets, so one facet is one fan however often it repeats the vertex.

use std::path::Path;
use std::process::{Command, Output};

fn surfkit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_surfkit"))
}

fn json(out: &Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "status {:?}: {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON on stdout")
}

/// (file name, OBJ text, edges, degenerate facets, facets OpenMesh holds, flaw kinds).
type Case = (
    &'static str,
    &'static str,
    u64,
    u64,
    u64,
    &'static [&'static str],
);

const CASES: &[Case] = &[
    (
        "consecutive.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 2\n",
        1,
        1,
        0,
        &["degenerate_facet", "unreferenced_vertex"],
    ),
    (
        "closing.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 1\n",
        3,
        1,
        0,
        // The facet's border is its three distinct edges: a lone facet's hole, as for
        // `f 1 2 3`, not a missing triangle to add on top of it.
        &["degenerate_facet", "hole"],
    ),
    (
        "apart.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 1 3\n",
        2,
        1,
        0,
        &["degenerate_facet", "unreferenced_vertex"],
    ),
    (
        "beside_a_triangle.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 4 3\n",
        5,
        1,
        1,
        &["degenerate_facet", "missing_quad"],
    ),
];

fn write_cases(dir: &Path) {
    for (name, text, ..) in CASES {
        std::fs::write(dir.join(name), text).unwrap();
    }
}

#[test]
fn a_repeated_vertex_is_a_degenerate_facet_and_nothing_else() {
    let dir = tempfile::tempdir().unwrap();
    write_cases(dir.path());
    for &(name, _, edges, degenerate, in_openmesh, kinds) in CASES {
        let path = dir.path().join(name);
        let info = json(
            &surfkit()
                .arg("info")
                .arg(&path)
                .arg("--json")
                .output()
                .unwrap(),
        );
        assert_eq!(info["halfedge"]["faces"], in_openmesh, "{name}: info");

        let eat = json(
            &surfkit()
                .arg("eat")
                .arg(&path)
                .arg("--json")
                .output()
                .unwrap(),
        );
        let report = &eat["report"];
        assert_eq!(report["counts"]["edges"], edges, "{name}");
        assert_eq!(report["counts"]["degenerate_facets"], degenerate, "{name}");
        assert_eq!(report["counts"]["non_manifold_vertices"], 0, "{name}");
        assert_eq!(report["halfedge"]["accepted"], in_openmesh, "{name}");
        let refused = report["halfedge"]["refused"].as_array().unwrap();
        assert!(
            refused.iter().all(|r| r[1] == "degenerate"),
            "{name}: {refused:?}"
        );
        let mut found: Vec<&str> = report["flaws"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f["kind"].as_str().unwrap())
            .collect();
        found.sort_unstable();
        assert_eq!(found, kinds, "{name}");
    }
}

#[test]
fn a_folder_of_degenerate_facets_is_scanned_whole() {
    // Built into OpenMesh, such facets left half-edges unset: a folder scan read them and
    // ended by a segmentation fault part-way through its JSON lines.
    let dir = tempfile::tempdir().unwrap();
    write_cases(dir.path());
    for jobs in ["1", "2"] {
        let out = surfkit()
            .arg("eat")
            .arg(dir.path())
            .args(["--jsonl", "--jobs", jobs])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(0), "jobs {jobs}");
        let lines: Vec<serde_json::Value> = out
            .stdout
            .split(|&b| b == b'\n')
            .filter(|l| !l.is_empty())
            .map(|l| serde_json::from_slice(l).unwrap())
            .collect();
        assert_eq!(
            lines.len(),
            CASES.len() + 1,
            "a line per file and a summary"
        );
        assert_eq!(
            lines.last().unwrap()["summary"]["files"],
            CASES.len() as u64
        );
    }
}
