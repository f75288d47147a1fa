//! The Python door against the Rust library and against pymeshlab, in one run:
//! - `surfkit.eat` on a 100k- and a 1M-triangle torus already in memory, against the same
//!   scan called in Rust (`topology::scan` + `repair::check_fixes`, the defaults of both;
//!   and "counts": without the OpenMesh structure and the fix check): the binding's
//!   overhead (goal under 10 % at 100k);
//! - two scans on a `ThreadPoolExecutor` of 2 threads against one (the GIL is released: on
//!   2 cores about the time of one);
//! - corpus throughput: `surfkit.batch.scan` on a 2-worker local Dask cluster and on a
//!   2-process spawn `ProcessPoolExecutor` against a
//!   pymeshlab loop (load + `get_topological_measures`) over the same files (goal ≥ 5×),
//!   with the default options and without the OpenMesh structure and the fix check (the
//!   counts and flaws pymeshlab's measures compare with); the cluster's start apart.
//!
//! `cargo bench --bench python_door` (the package built into the .venv by scripts/test.sh).

mod support;

use std::path::Path;

use surfkit::mesh::io::{read, write, WriteOptions};
use surfkit::shapes::grid_torus;
use surfkit::topology::{scan, EatOptions};

/// The library's time for what `surfkit.eat(mesh)` does: by default (`full`) with the
/// OpenMesh structure and the fix check, else without both.
fn library_seconds(path: &Path, repeats: usize, full: bool) -> f64 {
    let mesh = read(path).unwrap();
    let options = EatOptions {
        halfedge: full,
        ..EatOptions::default()
    };
    support::median_seconds(repeats, || {
        let mut report = scan(&mesh, &options).unwrap();
        if full {
            surfkit::repair::check_fixes(&mesh, &mut report.flaws, options.locator).unwrap();
        }
    })
}

/// The 200-file folder of `eat_process` (made there or here the same way) repeated under
/// five names: 1000 files of 1k–17k triangles.
fn corpus() -> Vec<String> {
    let dir = support::data_dir().join("python_corpus_1000");
    std::fs::create_dir_all(&dir).unwrap();
    let mut files = Vec::new();
    for copy in 0..5u32 {
        for i in 0..200u32 {
            let (nu, nv) = (20 + (i * 7) % 100, 12 + (i * 13) % 60);
            let ext = ["ply", "obj", "off"][i as usize % 3];
            let path = dir.join(format!("mesh_{copy}_{i:03}.{ext}"));
            if !path.exists() {
                let mut mesh = grid_torus(nu + copy, nv, true);
                if i % 4 == 0 {
                    let faces: Vec<Vec<u32>> = mesh.faces().skip(1).map(<[u32]>::to_vec).collect();
                    mesh =
                        surfkit::mesh::PolygonMesh::from_polygons(mesh.positions.clone(), &faces);
                }
                write(&path, &mesh, &WriteOptions::default()).unwrap();
            }
            files.push(path.display().to_string());
        }
    }
    files
}

fn main() {
    println!("surfkit.eat (Python) vs the Rust library, mesh in memory, same run");
    println!(
        "{:>10} {:<10} {:>10} {:>10} {:>9} {:>20}",
        "triangles", "options", "Rust", "Python", "overhead", "2 threads / 1 scan"
    );
    for (nu, nv, repeats) in [(250u32, 200u32, 9usize), (1000, 500, 5)] {
        let mesh = grid_torus(nu, nv, true);
        let path = support::data_dir().join(format!("torus_{}.ply", mesh.face_count()));
        if !path.exists() {
            write(&path, &mesh, &WriteOptions::default()).unwrap();
        }
        drop(mesh);
        let py = support::python_peer(
            "surfkit_python.py",
            &[
                "eat".into(),
                path.display().to_string(),
                repeats.to_string(),
            ],
        )
        .expect("surfkit's Python package (scripts/test.sh builds it)");
        for (options, key, full) in [("default", "eat", true), ("counts", "counts", false)] {
            let rust = library_seconds(&path, repeats, full);
            let python = py[key].as_f64().unwrap();
            println!(
                "{:>10} {:<10} {:>8.4} s {:>8.4} s {:>8.1} % {:>19.2}×",
                2 * nu * nv,
                options,
                rust,
                python,
                100.0 * (python / rust - 1.0),
                py[format!("{key}_threads")].as_f64().unwrap()
            );
        }
    }
    let files = corpus();
    let mut args = vec!["scan".to_string(), "2".to_string()];
    args.extend(files.iter().cloned());
    let ours = support::python_peer("surfkit_python.py", &args).expect("surfkit.batch");
    let peer = support::python_peer("pymeshlab_files.py", &files).expect("pymeshlab");
    let peer_seconds = peer["seconds"].as_f64().unwrap();
    let n = files.len() as f64;
    println!(
        "corpus of {} files, pymeshlab loop {:.2} s ({:.0} files/s); surfkit.batch.scan with \
         2 workers:",
        files.len(),
        peer_seconds,
        n / peer_seconds
    );
    for (engine, key) in [
        ("Dask local cluster", "dask"),
        ("spawn process pool", "pool"),
    ] {
        let start = ours[format!("{key}_start")].as_f64().unwrap();
        for (what, suffix) in [
            ("default options", ""),
            ("halfedge=False, check_fixes=False", "_counts"),
        ] {
            let seconds = ours[format!("{key}{suffix}")].as_f64().unwrap();
            println!(
                "  {engine:<19} {what:<34} {seconds:.2} s ({:.0} files/s): {:.1}× \
                 ({:.1}× with its {start:.2} s start)",
                n / seconds,
                peer_seconds / seconds,
                peer_seconds / (seconds + start)
            );
        }
    }
    assert_eq!(ours["errors"].as_u64(), Some(0));
    assert_eq!(peer["errors"].as_u64(), Some(0));
}
