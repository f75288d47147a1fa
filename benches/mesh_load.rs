//! Loading a generated 1M-triangle mesh (binary PLY and OBJ): surfkit's readers next to
//! OpenMesh's own reader and trimesh (`trimesh.load(..., process=False)`), in one run.
//!
//! `cargo bench --bench mesh_load` (trimesh from `scripts/setup-bench.sh`, which sets
//! `SURFKIT_PYTHON`; without it the trimesh column says so). Criterion times surfkit and
//! OpenMesh; the closing table gives medians of repeated loads for all three and ratios.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use criterion::Criterion;
use surfkit::halfedge::read_with_openmesh;
use surfkit::mesh::io::{read, write, WriteOptions};
use surfkit::mesh::PolygonMesh;

/// A torus of `nu × nv` vertices and `2·nu·nv` triangles.
fn torus(nu: u32, nv: u32) -> PolygonMesh {
    let mut positions = Vec::with_capacity((nu * nv) as usize);
    for i in 0..nu {
        for j in 0..nv {
            let (a, b) = (
                std::f64::consts::TAU * f64::from(i) / f64::from(nu),
                std::f64::consts::TAU * f64::from(j) / f64::from(nv),
            );
            let r = 3.0 + b.cos();
            positions.push([r * a.cos(), r * a.sin(), b.sin()]);
        }
    }
    let mut mesh = PolygonMesh {
        positions,
        ..Default::default()
    };
    let id = |i: u32, j: u32| (i % nu) * nv + (j % nv);
    for i in 0..nu {
        for j in 0..nv {
            let (p, q, r, s) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            mesh.push_face(&[p, q, r]);
            mesh.push_face(&[p, r, s]);
        }
    }
    mesh
}

fn data_files() -> (PathBuf, PathBuf) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/bench-data");
    std::fs::create_dir_all(&dir).unwrap();
    let (ply, obj) = (dir.join("torus_1m.ply"), dir.join("torus_1m.obj"));
    if !ply.exists() || !obj.exists() {
        let mesh = torus(1000, 500);
        assert_eq!(mesh.face_count(), 1_000_000);
        write(&ply, &mesh, &WriteOptions::default()).unwrap();
        write(&obj, &mesh, &WriteOptions::default()).unwrap();
    }
    (ply, obj)
}

fn median_seconds(repeats: usize, mut f: impl FnMut()) -> f64 {
    f();
    let mut t: Vec<Duration> = (0..repeats)
        .map(|_| {
            let t0 = Instant::now();
            f();
            t0.elapsed()
        })
        .collect();
    t.sort();
    t[repeats / 2].as_secs_f64()
}

fn trimesh_seconds(path: &Path, repeats: usize) -> Result<f64, String> {
    let python = std::env::var("SURFKIT_PYTHON").unwrap_or_else(|_| {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join(".venv/bin/python")
            .display()
            .to_string()
    });
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("benches/peers/trimesh_load.py");
    let out = Command::new(&python)
        .arg(script)
        .arg(path)
        .arg(repeats.to_string())
        .output()
        .map_err(|e| format!("{python}: {e} (run scripts/setup-bench.sh)"))?;
    if !out.status.success() {
        return Err(String::from_utf8_lossy(&out.stderr)
            .lines()
            .last()
            .unwrap_or("")
            .to_string());
    }
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).map_err(|e| e.to_string())?;
    Ok(v["median_s"].as_f64().unwrap())
}

fn main() {
    let (ply, obj) = data_files();
    let mut c = Criterion::default().sample_size(10).configure_from_args();
    for (name, path) in [("ply_binary_1m", &ply), ("obj_1m", &obj)] {
        let mut g = c.benchmark_group(name);
        g.bench_function("surfkit", |b| b.iter(|| read(path).unwrap()));
        g.bench_function("openmesh", |b| b.iter(|| read_with_openmesh(path).unwrap()));
        g.finish();
    }
    c.final_summary();

    println!("\nmedian load time of a 1M-triangle mesh (same files, same run)");
    println!(
        "{:<14} {:>10} {:>10} {:>10} {:>14} {:>14}",
        "file", "surfkit", "OpenMesh", "trimesh", "surfkit/trimesh", "OpenMesh/surfkit"
    );
    for (name, path, repeats) in [("binary PLY", &ply, 15), ("OBJ", &obj, 5)] {
        let ours = median_seconds(repeats, || {
            read(path).unwrap();
        });
        let om = median_seconds(repeats.min(5), || {
            read_with_openmesh(path).unwrap();
        });
        let (tm, ratio) = match trimesh_seconds(path, repeats) {
            Ok(t) => (format!("{:.1} ms", t * 1e3), format!("{:.2}", ours / t)),
            Err(e) => (format!("n/a ({e})"), "n/a".into()),
        };
        println!(
            "{:<14} {:>8.1} ms {:>7.1} ms {:>10} {:>14} {:>14.1}",
            name,
            ours * 1e3,
            om * 1e3,
            tm,
            ratio,
            om / ours
        );
    }
}
