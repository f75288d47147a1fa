//! `surfkit eat` as a user runs it — a whole process, default options (OpenMesh half-edge
//! structure included) — next to pymeshlab as a user runs it (a Python process: load +
//! `get_topological_measures`), in one run: one binary PLY torus of 100k, 1M and 4M
//! triangles, then a folder of 200 meshes (`surfkit eat DIR --jsonl` against a pymeshlab
//! loop over the same files).
//!
//! `cargo bench --bench eat_process` (pymeshlab from the .venv of `scripts/setup.sh`).

mod support;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use surfkit::mesh::io::{write, WriteOptions};
use surfkit::shapes::grid_torus;

/// Median wall time of `repeats` runs of a whole process (after one warm-up).
fn process_seconds(repeats: usize, mut command: impl FnMut() -> Command) -> f64 {
    support::median_seconds(repeats, || {
        let status = command()
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .unwrap();
        assert!(status.code().is_some(), "the process was killed");
    })
}

fn python() -> String {
    std::env::var("SURFKIT_PYTHON").unwrap_or_else(|_| {
        support::repo_root()
            .join(".venv/bin/python")
            .display()
            .to_string()
    })
}

fn pymeshlab(files: &[PathBuf]) -> Command {
    let mut c = Command::new(python());
    c.arg(support::repo_root().join("benches/peers/pymeshlab_files.py"))
        .args(files);
    c
}

fn surfkit_eat(inputs: &[&Path], extra: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_surfkit"));
    c.arg("eat").args(inputs).args(extra);
    c
}

/// 200 meshes of 1k–17k triangles (tori of varied sizes, some with a facet removed),
/// a third each as binary PLY, OBJ and OFF.
fn folder() -> (PathBuf, Vec<PathBuf>) {
    let dir = support::data_dir().join("eat_folder_200");
    std::fs::create_dir_all(&dir).unwrap();
    let mut files = Vec::new();
    for i in 0..200u32 {
        let (nu, nv) = (20 + (i * 7) % 100, 12 + (i * 13) % 60);
        let ext = ["ply", "obj", "off"][i as usize % 3];
        let path = dir.join(format!("mesh_{i:03}.{ext}"));
        if !path.exists() {
            let mut mesh = grid_torus(nu, nv, true);
            if i % 4 == 0 {
                let faces: Vec<Vec<u32>> = mesh.faces().skip(1).map(<[u32]>::to_vec).collect();
                mesh = surfkit::mesh::PolygonMesh::from_polygons(mesh.positions.clone(), &faces);
            }
            write(&path, &mesh, &WriteOptions::default()).unwrap();
        }
        files.push(path);
    }
    (dir, files)
}

fn main() {
    println!("surfkit eat vs pymeshlab load + get_topological_measures, whole processes, same run");
    println!(
        "{:>12} {:>14} {:>14} {:>10}",
        "triangles", "surfkit eat", "pymeshlab", "ratio"
    );
    for (nu, nv, repeats) in [(250u32, 200u32, 5usize), (1000, 500, 3), (2000, 1000, 3)] {
        let mesh = grid_torus(nu, nv, true);
        let path = support::data_dir().join(format!("torus_{}.ply", mesh.face_count()));
        if !path.exists() {
            write(&path, &mesh, &WriteOptions::default()).unwrap();
        }
        drop(mesh);
        let ours = process_seconds(repeats, || surfkit_eat(&[&path], &[]));
        let peer = process_seconds(repeats, || pymeshlab(std::slice::from_ref(&path)));
        println!(
            "{:>12} {:>11.3} s {:>11.3} s {:>9.1}×",
            2 * nu * nv,
            ours,
            peer,
            peer / ours
        );
    }
    let (dir, files) = folder();
    let t = Instant::now();
    let ours = process_seconds(3, || surfkit_eat(&[&dir], &["--jsonl"]));
    let peer = process_seconds(1, || pymeshlab(&files));
    println!(
        "folder of {} files: surfkit eat DIR --jsonl {:.2} s ({:.0} files/s), pymeshlab loop {:.2} s ({:.0} files/s): {:.1}× (bench {:.0} s)",
        files.len(),
        ours,
        files.len() as f64 / ours,
        peer,
        files.len() as f64 / peer,
        peer / ours,
        t.elapsed().as_secs_f64()
    );
}
