//! The EAT of a 1M-triangle mesh through the C++ layer (surfkit::eat on an OpenMesh
//! TriMesh), next to the same scan from Rust and to pymeshlab's get_topological_measures,
//! in one run; prints the C++ layer's overhead (flattening + mapping handles back) as a
//! fraction of the scan. The goal is under 15 %.
//!
//! `bash scripts/setup.sh cargo bench -p surfkit-capi --bench eat_openmesh`

#[path = "../../benches/support/mod.rs"]
mod support;

use std::path::Path;
use std::process::Command;

use surfkit::mesh::io::{read, write, WriteOptions};
use surfkit::shapes::grid_torus;
use surfkit::topology::{scan, EatOptions};

fn main() {
    let repeats = 5;
    let mesh = grid_torus(1000, 500, true);
    let path = support::data_dir().join(format!("torus_{}.ply", mesh.face_count()));
    if !path.exists() {
        write(&path, &mesh, &WriteOptions::default()).unwrap();
    }
    // The library's own scan of the same file (default options of the C++ layer: with
    // OpenMesh's half-edge structure).
    let loaded = read(&path).unwrap();
    let options = EatOptions {
        halfedge: true,
        ..Default::default()
    };
    let rust = support::median_seconds(repeats, || {
        scan(&loaded, &options).unwrap();
    });

    // The C++ layer, from an install of this build.
    let root = support::repo_root();
    let libs = std::env::current_exe()
        .unwrap()
        .parent()
        .unwrap()
        .parent()
        .unwrap()
        .to_path_buf();
    let prefix = support::data_dir().join("cpp-prefix");
    let status = Command::new("bash")
        .arg(root.join("scripts/install-cpp.sh"))
        .arg(&prefix)
        .env("SURFKIT_BUILT_LIBS", &libs)
        .status()
        .unwrap();
    assert!(
        status.success(),
        "install-cpp.sh failed (is libsurfkit.so built in {}?)",
        libs.display()
    );
    let exe = support::data_dir().join("eat_bench");
    let flags = Command::new("pkg-config")
        .args(["--cflags", "--libs", "surfkit"])
        .env("PKG_CONFIG_PATH", prefix.join("lib/pkgconfig"))
        .output()
        .unwrap();
    let flags = String::from_utf8(flags.stdout).unwrap();
    // A release build as CMake's Release configuration makes it (-DNDEBUG): without it
    // OpenMesh's inline handle asserts run on every access and the flattening takes 3× as
    // long (58 against 19 ms at 1M triangles, 2026-11-26).
    let status = Command::new("g++")
        .args(["-std=c++17", "-O2", "-DNDEBUG", "-Wno-maybe-uninitialized"])
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("benches/native/eat_bench.cc"))
        .arg("-o")
        .arg(&exe)
        .args(flags.split_whitespace())
        .status()
        .unwrap();
    assert!(status.success());
    let out = Command::new(&exe)
        .arg(&path)
        .arg(repeats.to_string())
        .env("LD_LIBRARY_PATH", prefix.join("lib"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let cpp: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let (eat, flatten, c_scan) = (
        cpp["eat"].as_f64().unwrap(),
        cpp["flatten"].as_f64().unwrap(),
        cpp["scan"].as_f64().unwrap(),
    );
    assert_eq!(cpp["faces"].as_u64().unwrap() as usize, mesh.face_count());

    let peer = support::python_peer(
        "pymeshlab_topology.py",
        &[path.display().to_string(), repeats.to_string()],
    );
    let pymeshlab = match &peer {
        Ok(v) => format!("{:.0} ms", v["median_s"].as_f64().unwrap() * 1e3),
        Err(e) => format!("n/a ({e})"),
    };
    println!(
        "EAT of a {}-triangle torus (median of {repeats}; file loading excluded)",
        mesh.face_count()
    );
    println!(
        "  Rust library scan (with OpenMesh)          {:>8.0} ms",
        rust * 1e3
    );
    println!(
        "  C ABI scan of a flattened mesh              {:>8.0} ms",
        c_scan * 1e3
    );
    println!(
        "  C++ surfkit::eat(TriMesh) whole             {:>8.0} ms",
        eat * 1e3
    );
    println!(
        "    of which flattening the OpenMesh mesh     {:>8.0} ms",
        flatten * 1e3
    );
    println!(
        "  pymeshlab get_topological_measures          {:>11}",
        pymeshlab
    );
    println!(
        "  C++ layer overhead (eat − scan) / scan: {:.1} % (goal < 15 %); flattening alone {:.1} %",
        100.0 * (eat - c_scan) / c_scan,
        100.0 * flatten / c_scan
    );
}
