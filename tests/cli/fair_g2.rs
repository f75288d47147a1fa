//! `surfkit fair` on Kiciak's G² surface (the default) against the author's program and
//! against the surface's own continuity: on his mesh kiciak_trojnik3 (359 vertices, two
//! special vertices of valence 6) BSTools' optimizer — C = 0.01, boundary and two rings
//! fixed, F at 8 × 8 nodes — ends at F = 6.657508816, S = 2.612291562 (its driver built
//! beside the project and run 2026-11-26). The Bézier export is checked against
//! OpenSubdiv's limit (the ordinary patches are the Catmull–Clark limit there), the
//! curvature samples for one mean curvature on both sides of every face border.

use std::collections::HashMap;
use std::path::Path;
use std::process::Command;

use surfkit::mesh::io::read;
use surfkit::subdiv::{
    limit_surface, BoundaryInterpolation, PatchOptions, SubdivOptions, SurfacePoint,
};

fn surfkit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_surfkit"))
}

const MESH: &str = "fixtures/meshes/kiciak_trojnik3.obj";

/// de Casteljau in one variable over `n + 1` points of a row.
fn bernstein(n: usize, t: f64) -> Vec<f64> {
    let mut b = vec![0.0; n + 1];
    b[0] = 1.0;
    for level in 1..=n {
        for i in (0..=level).rev() {
            let left = if i > 0 { b[i - 1] * t } else { 0.0 };
            b[i] = b[i] * (1.0 - t) + left;
        }
    }
    b
}

fn patch_point(degree: usize, points: &[[f64; 3]], u: f64, v: f64) -> [f64; 3] {
    let (bu, bv) = (bernstein(degree, u), bernstein(degree, v));
    let mut p = [0.0; 3];
    for i in 0..=degree {
        for j in 0..=degree {
            for c in 0..3 {
                p[c] += bu[i] * bv[j] * points[(degree + 1) * i + j][c];
            }
        }
    }
    p
}

#[test]
fn fair_on_the_g2_surface_reaches_the_authors_optimum_and_exports_it() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("faired.obj");
    let samples = dir.path().join("samples.ply");
    let bezier = dir.path().join("patches.json");
    let run = surfkit()
        .args(["fair", MESH, "--nodes", "8", "--json", "--quiet", "-o"])
        .arg(&output)
        .arg("--samples")
        .arg(&samples)
        .arg("--bezier")
        .arg(&bezier)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    let r = &report["report"];
    assert_eq!(r["surface"], "g2");
    assert_eq!(r["regularization"], 0.01);
    assert!(r["newton"]["converged"].as_bool().unwrap());
    let (f, s) = (
        r["final_terms"]["f"].as_f64().unwrap(),
        r["final_terms"]["s"].as_f64().unwrap(),
    );
    println!("F = {f:.6} (BSTools 6.657509), S = {s:.6} (BSTools 2.612292)");
    assert!((f - 6.657508816).abs() < 1e-4, "F = {f}");
    assert!((s - 2.612291562).abs() < 1e-4, "S = {s}");

    // The Bézier patches: one per internal face; the bicubic ones are OpenSubdiv's limit
    // of the optimized mesh at the face's (u, v); each special patch's corner opposite
    // the special vertex is the limit point of that (valence-4) corner.
    let out = read(&output).unwrap();
    let limit = limit_surface(
        &out,
        &SubdivOptions {
            boundary: BoundaryInterpolation::None,
            ..Default::default()
        },
        &PatchOptions::default(),
    )
    .unwrap();
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&bezier).unwrap()).unwrap();
    assert_eq!(doc["format"], "surfkit-bezier-patches");
    let patches = doc["patches"].as_array().unwrap();
    let (mut bicubic, mut special) = (0, 0);
    for patch in patches {
        let face = patch["face"].as_u64().unwrap() as u32;
        let degree = patch["degree"][0].as_u64().unwrap() as usize;
        let points: Vec<[f64; 3]> = patch["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| [0, 1, 2].map(|c| p[c].as_f64().unwrap()))
            .collect();
        assert_eq!(points.len(), (degree + 1) * (degree + 1));
        let checks: &[(f64, f64)] = match patch["kind"].as_str().unwrap() {
            "bicubic" => {
                bicubic += 1;
                assert_eq!(degree, 3);
                &[(0.0, 0.0), (0.3, 0.8), (1.0, 0.5)]
            }
            _ => {
                special += 1;
                assert_eq!(degree, 9);
                &[]
            }
        };
        for &(u, v) in checks {
            let want = limit
                .evaluate(&[SurfacePoint {
                    ptex_face: face,
                    u,
                    v,
                }])
                .unwrap()[0]
                .position;
            let have = patch_point(degree, &points, u, v);
            for c in 0..3 {
                assert!((have[c] - want[c]).abs() < 1e-9, "face {face} ({u}, {v})");
            }
        }
        if degree == 9 {
            // the corner (1, 1): the face's corner two edges from the special vertex
            let corners = out.face(face as usize);
            let centre_at = corners
                .iter()
                .position(|&v| out.faces().filter(|f| f.contains(&v)).count() == 6)
                .unwrap();
            let opposite = (centre_at + 2) % 4;
            let (u, v) = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)][opposite];
            let want = limit
                .evaluate(&[SurfacePoint {
                    ptex_face: face,
                    u,
                    v,
                }])
                .unwrap()[0]
                .position;
            let have = points[99];
            for c in 0..3 {
                assert!((have[c] - want[c]).abs() < 1e-9, "special face {face}");
            }
        }
    }
    assert_eq!((bicubic + special, special), (288, 12));

    // The samples: mean curvature (vertex quality) the same on both sides of every face
    // border, special patches included — curvature continuity, sampled.
    let sampled = read(&samples).unwrap();
    let quality = sampled.quality.as_ref().unwrap();
    let key = |p: [f64; 3]| p.map(|x| (x * 1e7).round() as i64);
    let mut seen: HashMap<[i64; 3], f64> = HashMap::new();
    let (mut shared, mut worst) = (0, 0.0f64);
    for (p, &h) in sampled.positions.iter().zip(quality) {
        if let Some(&other) = seen.get(&key(*p)) {
            shared += 1;
            worst = worst.max((h - other).abs() / (1.0 + h.abs()));
        } else {
            seen.insert(key(*p), h);
        }
    }
    println!("{shared} samples on face borders, largest relative jump of H {worst:.1e}");
    assert!(shared > 1000);
    assert!(worst < 1e-7, "{worst}");
}

#[test]
fn bezier_export_needs_the_g2_surface() {
    let dir = tempfile::tempdir().unwrap();
    let run = surfkit()
        .args(["fair", MESH, "--surface", "catmull-clark", "-o"])
        .arg(dir.path().join("out.obj"))
        .arg("--bezier")
        .arg(dir.path().join("p.json"))
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(1));
    let said = String::from_utf8_lossy(&run.stderr);
    assert!(
        said.contains("--bezier") && said.contains("--surface g2"),
        "{said}"
    );
    assert!(!Path::new(&dir.path().join("out.obj")).exists());
}
