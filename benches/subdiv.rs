//! Uniform Catmull–Clark refinement of generated quad tori (10k and 100k faces) by 1, 2 and
//! 3 levels: surfkit (`subdiv::refine_uniform`) next to OpenSubdiv called directly from C++,
//! CGAL's `CatmullClark_subdivision` and pymeshlab's `meshing_surface_subdivision_catmull_clark`,
//! in one run.
//!
//! `cargo bench --bench subdiv`. Criterion times surfkit; the closing table gives medians
//! for all four and the ratios the issue asks for (goals: surfkit's overhead over direct
//! OpenSubdiv < 20 %, faster than CGAL at 3 levels, ≥ 15× faster than pymeshlab).
//! `SURFKIT_BENCH_QUICK=1` runs the 10k mesh only; pymeshlab is skipped (and says so) when
//! `python3 -c "import pymeshlab"` fails. The C++ reference is `tests/subdiv/cgal/bench_refine.cpp`,
//! run in a fresh process per library: timed after CGAL in the same process, direct
//! OpenSubdiv ran up to 2.5× faster at 10k faces only because CGAL's large frees had left
//! glibc's heap warm, which made surfkit's shim look 50–160 % slower than it is.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use criterion::Criterion;
use surfkit::mesh::io::{write, WriteOptions};
use surfkit::shapes::grid_torus;
use surfkit::subdiv::{refine_uniform, SubdivOptions};

fn bench_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/bench-data");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn reference_program() -> PathBuf {
    let exe = bench_dir().join("bench_refine");
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/subdiv/cgal/bench_refine.cpp");
    let out = Command::new("c++")
        .args(["-std=c++17", "-O2", "-DNDEBUG", "-o"])
        .arg(&exe)
        .arg(&src)
        .arg("-losdCPU")
        .output()
        .expect("c++");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    exe
}

fn median_seconds(repeats: usize, mut f: impl FnMut()) -> f64 {
    let mut t: Vec<Duration> = (0..repeats)
        .map(|_| {
            let a = Instant::now();
            f();
            a.elapsed()
        })
        .collect();
    t.sort();
    t[t.len() / 2].as_secs_f64()
}

/// Median seconds of `library` ("cgal" or "opensubdiv") from the C++ reference program, one
/// process per library so that neither runs on a heap the other has warmed.
fn cpp_reference(exe: &Path, off: &Path, levels: u32, repeats: usize, library: &str) -> f64 {
    let out = Command::new(exe)
        .arg(off)
        .arg(levels.to_string())
        .arg(repeats.to_string())
        .arg(library)
        .output()
        .unwrap();
    assert!(out.status.success(), "bench_refine {library} failed");
    let text = String::from_utf8(out.stdout).unwrap();
    text.lines()
        .find_map(|l| l.strip_prefix(library)?.trim().parse().ok())
        .unwrap()
}

/// pymeshlab's filter time (load excluded), or None when pymeshlab is missing.
fn pymeshlab(obj: &Path, levels: u32, repeats: usize) -> Option<f64> {
    let script = "import sys, time, pymeshlab\n\
                  t = []\n\
                  for _ in range(int(sys.argv[3])):\n    ms = pymeshlab.MeshSet(verbose=False)\n    ms.load_new_mesh(sys.argv[1])\n    a = time.perf_counter()\n    ms.meshing_surface_subdivision_catmull_clark(iterations=int(sys.argv[2]))\n    t.append(time.perf_counter() - a)\n\
                  t.sort()\n\
                  print(t[len(t) // 2])\n";
    let out = Command::new("python3")
        .arg("-c")
        .arg(script)
        .arg(obj)
        .arg(levels.to_string())
        .arg(repeats.to_string())
        .output()
        .ok()?;
    if !out.status.success() {
        return None;
    }
    String::from_utf8(out.stdout)
        .ok()?
        .lines()
        .last()?
        .trim()
        .parse()
        .ok()
}

fn main() {
    let quick = std::env::var_os("SURFKIT_BENCH_QUICK").is_some();
    let sizes: &[(u32, u32)] = if quick {
        &[(100, 100)]
    } else {
        &[(100, 100), (400, 250)]
    };
    let exe = reference_program();
    let options = SubdivOptions::default();
    let mut criterion = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3))
        .configure_from_args();
    let mut rows = Vec::new();
    for &(nu, nv) in sizes {
        let mesh = grid_torus(nu, nv, false);
        let faces = mesh.face_count();
        let off = bench_dir().join(format!("quad_torus_{faces}.off"));
        let obj = bench_dir().join(format!("quad_torus_{faces}.obj"));
        write(&off, &mesh, &WriteOptions::default()).unwrap();
        write(&obj, &mesh, &WriteOptions::default()).unwrap();
        for levels in 1..=3u32 {
            let repeats = if faces * 4usize.pow(levels) > 2_000_000 {
                3
            } else {
                7
            };
            criterion.bench_function(
                &format!("refine_uniform {faces} quads level {levels}"),
                |b| b.iter(|| refine_uniform(&mesh, levels, &options).unwrap()),
            );
            let ours = median_seconds(repeats, || {
                std::hint::black_box(refine_uniform(&mesh, levels, &options).unwrap());
            });
            let osd = cpp_reference(&exe, &off, levels, repeats, "opensubdiv");
            let cgal = cpp_reference(&exe, &off, levels, repeats, "cgal");
            let meshlab = pymeshlab(
                &obj,
                levels,
                if faces > 20_000 && levels == 3 { 1 } else { 3 },
            );
            rows.push((faces, levels, ours, osd, cgal, meshlab));
        }
    }
    println!("\nuniform Catmull–Clark, median seconds (ratios: >1 means surfkit is faster)");
    println!(
        "{:>7} {:>5} {:>10} {:>10} {:>10} {:>10}   {:>12} {:>10} {:>12}",
        "faces",
        "level",
        "surfkit",
        "OSD C++",
        "CGAL",
        "pymeshlab",
        "overhead",
        "CGAL/ours",
        "meshlab/ours"
    );
    for (faces, levels, ours, osd, cgal, meshlab) in rows {
        let ml = meshlab.map_or("missing".to_string(), |t| format!("{t:.4}"));
        let mlr = meshlab.map_or("-".to_string(), |t| format!("{:.1}×", t / ours));
        println!(
            "{faces:>7} {levels:>5} {ours:>10.4} {osd:>10.4} {cgal:>10.4} {ml:>10}   {:>11.1}% {:>9.2}× {mlr:>12}",
            100.0 * (ours / osd - 1.0),
            cgal / ours
        );
    }
}
