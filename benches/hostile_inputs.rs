//! Small inputs that imply huge work (issue: hostile input), timed as whole `surfkit`
//! processes next to the 10 s bound and, where it has the operation, pymeshlab (load +
//! topological measures) in the same run. Inputs are generated into target/bench-data:
//! one face of 400 000 corners (9 MB of OBJ), a cone fan of valence 1000 and one of a million
//! triangles (every edge and vertex set at one vertex: 50 MB), a UV sphere of 256
//! segments (poles of valence 256, 16 384 faces), connected grids of 100 352 and 320 000
//! triangles (every vertex extraordinary for Catmull–Clark) and piles of 10 000 and 50 000
//! degenerate triangles on one line, each with its own vertices (all coincident).
//!
//! `cargo bench --bench hostile_inputs`

#[path = "support/mod.rs"]
mod support;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

fn write_once(name: &str, make: impl FnOnce() -> String) -> PathBuf {
    let path = support::data_dir().join(name);
    if !path.exists() {
        std::fs::write(&path, make()).unwrap();
    }
    path
}

fn big_face(n: usize) -> String {
    let mut s = String::new();
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        writeln!(s, "v {:.5} {:.5} 0", a.cos(), a.sin()).unwrap();
    }
    s.push('f');
    for i in 1..=n {
        write!(s, " {i}").unwrap();
    }
    s.push('\n');
    s
}

fn fan(n: usize) -> String {
    let mut s = String::from("v 0 0 1\n");
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        writeln!(s, "v {} {} 0", a.cos(), a.sin()).unwrap();
    }
    for i in 0..n {
        writeln!(s, "f 1 {} {}", i + 2, (i + 1) % n + 2).unwrap();
    }
    s
}

fn uv_sphere(segments: usize, rings: usize) -> String {
    let mut s = String::from("v 0 0 1\n");
    for r in 1..rings {
        let t = std::f64::consts::PI * r as f64 / rings as f64;
        for k in 0..segments {
            let p = std::f64::consts::TAU * k as f64 / segments as f64;
            writeln!(
                s,
                "v {} {} {}",
                t.sin() * p.cos(),
                t.sin() * p.sin(),
                t.cos()
            )
            .unwrap();
        }
    }
    s.push_str("v 0 0 -1\n");
    let id = |r: usize, k: usize| 2 + (r - 1) * segments + k % segments;
    for k in 0..segments {
        writeln!(s, "f 1 {} {}", id(1, k), id(1, k + 1)).unwrap();
    }
    for r in 1..rings - 1 {
        for k in 0..segments {
            let (a, b, c, d) = (id(r, k), id(r + 1, k), id(r + 1, k + 1), id(r, k + 1));
            writeln!(s, "f {a} {b} {c} {d}").unwrap();
        }
    }
    let south = 2 + (rings - 1) * segments;
    for k in 0..segments {
        writeln!(s, "f {} {} {south}", id(rings - 1, k + 1), id(rings - 1, k)).unwrap();
    }
    s
}

/// `n` degenerate triangles on one line, each with its own three vertices at x = 0, 1, 2:
/// a pile of coincident boundary vertices on coincident edges (the crack search once listed
/// every vertex of the pile on every edge of it).
fn collinear_pile(n: usize) -> String {
    let mut s = "v 0 0 0\nv 1 0 0\nv 2 0 0\n".repeat(n);
    for i in 0..n {
        writeln!(s, "f {} {} {}", 3 * i + 1, 3 * i + 2, 3 * i + 3).unwrap();
    }
    s
}

fn triangle_grid(m: usize) -> String {
    let mut s = String::new();
    for j in 0..=m {
        for i in 0..=m {
            writeln!(s, "v {i} {j} 0").unwrap();
        }
    }
    for j in 0..m {
        for i in 0..m {
            let a = j * (m + 1) + i + 1;
            let (b, c, d) = (a + 1, a + m + 1, a + m + 2);
            writeln!(s, "f {a} {b} {d}\nf {a} {d} {c}").unwrap();
        }
    }
    s
}

/// Runs surfkit with `args`; wall seconds, exit status and the last line of stderr.
fn run(args: &[&str]) -> (f64, Option<i32>, String) {
    let t0 = Instant::now();
    let out = Command::new(env!("CARGO_BIN_EXE_surfkit"))
        .args(args)
        .output()
        .unwrap();
    let seconds = t0.elapsed().as_secs_f64();
    let err = String::from_utf8_lossy(&out.stderr);
    (
        seconds,
        out.status.code(),
        err.lines().last().unwrap_or("").chars().take(110).collect(),
    )
}

fn pymeshlab(path: &Path) -> String {
    match support::python_peer(
        "pymeshlab_topology.py",
        &[path.display().to_string(), "1".into()],
    ) {
        Ok(v) => {
            let load = v["load_s"].as_f64().unwrap_or(f64::NAN);
            let measure = v["median_s"].as_f64().unwrap_or(f64::NAN);
            format!("pymeshlab load + measures {:.2} s", load + measure)
        }
        Err(e) => format!("pymeshlab: {e}"),
    }
}

fn main() {
    let face = write_once("hostile_face_400k.obj", || big_face(400_000));
    let hub = write_once("hostile_fan_1m.obj", || fan(1_000_000));
    let fan = write_once("hostile_fan_1000.obj", || fan(1000));
    let sphere = write_once("hostile_uv_sphere_256.obj", || uv_sphere(256, 64));
    let grid = write_once("hostile_grid_100k_triangles.obj", || triangle_grid(224));
    let big_grid = write_once("hostile_grid_320k_triangles.obj", || triangle_grid(400));
    let pile = write_once("hostile_collinear_pile_10k.obj", || collinear_pile(10_000));
    let big_pile = write_once("hostile_collinear_pile_50k.obj", || collinear_pile(50_000));
    let out = support::data_dir().join("hostile_out.ply");
    let o = out.to_str().unwrap();
    println!("hostile inputs, whole surfkit processes (bound: 10 s on inputs under 10 MB)");
    let mb = |p: &Path| std::fs::metadata(p).unwrap().len() as f64 / 1e6;
    let cases: Vec<(String, Vec<&str>, Option<&Path>)> = vec![
        (
            "info, one face of 400k corners".into(),
            vec!["info", face.to_str().unwrap()],
            Some(&face),
        ),
        (
            "eat, one face of 400k corners".into(),
            vec!["eat", face.to_str().unwrap()],
            None,
        ),
        (
            "eat, fan of 1M triangles round one vertex".into(),
            vec!["eat", hub.to_str().unwrap()],
            Some(&hub),
        ),
        (
            "limit, fan of valence 1000".into(),
            vec!["limit", fan.to_str().unwrap(), "-o", o],
            None,
        ),
        (
            "fair, fan of valence 1000 (refused)".into(),
            vec!["fair", fan.to_str().unwrap(), "-o", o],
            None,
        ),
        (
            "limit, UV sphere 256 segments".into(),
            vec!["limit", sphere.to_str().unwrap(), "-o", o],
            None,
        ),
        (
            "eat, pile of 10k collinear triangles".into(),
            vec!["eat", pile.to_str().unwrap()],
            Some(&pile),
        ),
        (
            "eat, pile of 50k collinear triangles".into(),
            vec!["eat", big_pile.to_str().unwrap()],
            None,
        ),
        (
            "eat, grid of 100k triangles".into(),
            vec!["eat", grid.to_str().unwrap()],
            Some(&grid),
        ),
        (
            "limit, grid of 100k triangles".into(),
            vec!["limit", grid.to_str().unwrap(), "-o", o],
            None,
        ),
        (
            "limit, grid of 320k triangles".into(),
            vec!["limit", big_grid.to_str().unwrap(), "-o", o],
            None,
        ),
    ];
    for (what, args, peer) in cases {
        let (s, status, err) = run(&args);
        let input = Path::new(args[1]);
        print!(
            "  {what:<38} {:>5.1} MB in  {s:>6.2} s  status {}",
            mb(input),
            status.map_or("signal".into(), |c| c.to_string())
        );
        if let Some(p) = peer {
            print!("  | {}", pymeshlab(p));
        }
        println!();
        if !err.is_empty() {
            println!("      {err}");
        }
    }
    let _ = std::fs::remove_file(&out);
    let _ = std::fs::remove_file(out.with_extension("png"));
}
