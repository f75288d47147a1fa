//! Loading a generated 1M-triangle mesh (binary PLY, OBJ and binary STL): surfkit's readers
//! next to OpenMesh's own reader and trimesh (`trimesh.load(..., process=False)`, and for
//! STL `merge_vertices()` after it, as surfkit and OpenMesh weld STL corners), in one run.
//!
//! `cargo bench --bench mesh_load` (trimesh from `scripts/setup.sh`, which sets
//! `SURFKIT_PYTHON`; without it the trimesh column says so). Criterion times surfkit and
//! OpenMesh; the closing table gives medians of repeated loads for all three and ratios.

mod support;

use std::path::{Path, PathBuf};

use criterion::Criterion;
use surfkit::halfedge::read_with_openmesh;
use surfkit::mesh::io::{read, write, WriteOptions};
use surfkit::shapes::grid_torus;

fn data_files() -> [PathBuf; 3] {
    let dir = support::data_dir();
    let files = ["ply", "obj", "stl"].map(|ext| dir.join(format!("torus_1m.{ext}")));
    if !files.iter().all(|f| f.exists()) {
        let mesh = grid_torus(1000, 500, true);
        assert_eq!(mesh.face_count(), 1_000_000);
        for f in &files {
            write(f, &mesh, &WriteOptions::default()).unwrap();
        }
    }
    files
}

fn trimesh_seconds(path: &Path, repeats: usize) -> Result<f64, String> {
    let v = support::python_peer(
        "trimesh_load.py",
        &[path.display().to_string(), repeats.to_string()],
    )?;
    Ok(v["median_s"].as_f64().unwrap())
}

fn main() {
    let [ply, obj, stl] = data_files();
    // The STL's 3 million corners weld back into the torus's 500 000 vertices.
    assert_eq!(read(&stl).unwrap().vertex_count(), 500_000);
    let mut c = Criterion::default().sample_size(10).configure_from_args();
    for (name, path) in [
        ("ply_binary_1m", &ply),
        ("obj_1m", &obj),
        ("stl_binary_1m", &stl),
    ] {
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
    for (name, path, repeats) in [
        ("binary PLY", &ply, 15),
        ("OBJ", &obj, 5),
        ("binary STL", &stl, 5),
    ] {
        let ours = support::median_seconds(repeats, || {
            read(path).unwrap();
        });
        let om = support::median_seconds(repeats.min(5), || {
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
