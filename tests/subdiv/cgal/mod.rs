//! Test helpers around CGAL's Catmull–Clark (`catmull_clark.cpp`, header-only CGAL from
//! Debian's libcgal-dev): compiled once per test binary with `c++`, run on a mesh written
//! as OFF, its result read back; plus matching of two refined meshes by vertex position.

#![allow(dead_code)]

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use surfkit::mesh::io::{read, write, WriteOptions};
use surfkit::mesh::PolygonMesh;

/// The compiled CGAL program (built into Cargo's per-target temp dir).
pub fn program() -> &'static Path {
    static PROGRAM: OnceLock<PathBuf> = OnceLock::new();
    PROGRAM.get_or_init(|| {
        let source =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/subdiv/cgal/catmull_clark.cpp");
        let exe = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cgal_catmull_clark");
        let out = Command::new("c++")
            .args(["-std=c++17", "-O2", "-DNDEBUG", "-o"])
            .arg(&exe)
            .arg(&source)
            .output()
            .expect("running c++ (install g++ and libcgal-dev)");
        assert!(
            out.status.success(),
            "compiling {} failed (needs libcgal-dev):\n{}",
            source.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        exe
    })
}

/// CGAL's Catmull–Clark of `mesh` by `levels`.
pub fn catmull_clark(mesh: &PolygonMesh, levels: u32) -> PolygonMesh {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.off");
    let output = dir.path().join("out.off");
    let plain = PolygonMesh {
        positions: mesh.positions.clone(),
        face_offsets: mesh.face_offsets.clone(),
        face_indices: mesh.face_indices.clone(),
        ..Default::default()
    };
    write(&input, &plain, &WriteOptions::default()).unwrap();
    let out = Command::new(program())
        .arg(&input)
        .arg(levels.to_string())
        .arg(&output)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "CGAL failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    read(&output).unwrap()
}

/// Diagonal of the bounding box: the scale of "relative to the bounding box".
pub fn diagonal(mesh: &PolygonMesh) -> f64 {
    let (lo, hi) = mesh.bounding_box().unwrap();
    (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
}

/// Result of matching the vertices of `ours` and `theirs` by position.
pub struct Matching {
    /// For each vertex of `theirs`, the vertex of `ours` within `tol` (nearest), if any.
    pub ours_of_theirs: Vec<Option<usize>>,
    /// Largest distance over the matched pairs.
    pub max_distance: f64,
    /// Vertices of `ours` that no vertex of `theirs` matched.
    pub unmatched_ours: Vec<usize>,
    pub unmatched_theirs: Vec<usize>,
}

/// Matches vertices by position within `tol` (absolute), with a hash grid of cell `tol`.
pub fn match_vertices(ours: &PolygonMesh, theirs: &PolygonMesh, tol: f64) -> Matching {
    let cell = |p: [f64; 3]| p.map(|c| (c / tol).floor() as i64);
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, &p) in ours.positions.iter().enumerate() {
        grid.entry(cell(p)).or_default().push(i);
    }
    let mut used = vec![false; ours.positions.len()];
    let mut max_distance: f64 = 0.0;
    let mut ours_of_theirs = Vec::with_capacity(theirs.positions.len());
    let mut unmatched_theirs = Vec::new();
    for (j, &q) in theirs.positions.iter().enumerate() {
        let c = cell(q);
        let mut best: Option<(f64, usize)> = None;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(list) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) {
                        for &i in list {
                            let d = dist(ours.positions[i], q);
                            if d <= tol && best.is_none_or(|(bd, _)| d < bd) {
                                best = Some((d, i));
                            }
                        }
                    }
                }
            }
        }
        match best {
            Some((d, i)) => {
                used[i] = true;
                max_distance = max_distance.max(d);
                ours_of_theirs.push(Some(i));
            }
            None => {
                unmatched_theirs.push(j);
                ours_of_theirs.push(None);
            }
        }
    }
    let unmatched_ours = (0..used.len()).filter(|&i| !used[i]).collect();
    Matching {
        ours_of_theirs,
        max_distance,
        unmatched_ours,
        unmatched_theirs,
    }
}

/// The faces of a mesh as rotation-normalised vertex cycles (smallest index first).
pub fn face_cycles(faces: impl Iterator<Item = Vec<usize>>) -> Vec<Vec<usize>> {
    let mut out: Vec<Vec<usize>> = faces
        .map(|f| {
            let k = (0..f.len()).min_by_key(|&i| f[i]).unwrap();
            f[k..].iter().chain(&f[..k]).copied().collect()
        })
        .collect();
    out.sort();
    out
}

/// `theirs`' faces expressed in `ours`' vertex ids (None if a vertex is unmatched).
pub fn faces_in_our_ids(theirs: &PolygonMesh, m: &Matching) -> Option<Vec<Vec<usize>>> {
    let faces: Option<Vec<Vec<usize>>> = theirs
        .faces()
        .map(|f| f.iter().map(|&v| m.ours_of_theirs[v as usize]).collect())
        .collect();
    faces.map(|f| face_cycles(f.into_iter()))
}

/// χ = V_referenced − E + F with E the distinct unordered index pairs of consecutive
/// corners (the fixtures' REFERENCE.json definition), counted directly on the faces.
pub fn euler_characteristic(mesh: &PolygonMesh) -> i64 {
    let mut referenced = vec![false; mesh.vertex_count()];
    let mut edges = std::collections::HashSet::new();
    for f in mesh.faces() {
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            referenced[a as usize] = true;
            if a != b {
                edges.insert((a.min(b), a.max(b)));
            }
        }
    }
    referenced.iter().filter(|&&r| r).count() as i64 - edges.len() as i64 + mesh.face_count() as i64
}

pub fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures/meshes")
        .join(name)
}
