//! Creases and corners on the command line and in OBJ files (OpenSubdiv's `t crease`,
//! `t corner`, `t creasemethod` tags): tags read and written back, bad tags named by line,
//! and `subdivide` against OpenSubdiv's documented semantics — an infinitely sharp crease
//! refines as a cubic B-spline curve of its vertices, an infinitely sharp corner stays
//! put, and Chaikin's rule differs from the uniform one only where sharpness varies along
//! a crease.

use std::path::{Path, PathBuf};
use std::process::Command;

use surfkit::mesh::io::read;

fn surfkit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_surfkit"))
}

const N: usize = 7;

/// A 7 × 7 grid of vertices (0-based id j·7 + i) over a bumpy height field, as OBJ text,
/// with `tags` appended.
fn grid_obj(tags: &str) -> String {
    let mut s = String::new();
    for j in 0..N {
        for i in 0..N {
            let (x, y) = (i as f64, j as f64);
            let z = 0.3 * (0.9 * x).sin() * (0.7 * y).cos() + 0.05 * x * y;
            s += &format!("v {x} {y} {z}\n");
        }
    }
    for j in 0..N - 1 {
        for i in 0..N - 1 {
            let v = |i: usize, j: usize| j * N + i + 1;
            s += &format!(
                "f {} {} {} {}\n",
                v(i, j),
                v(i + 1, j),
                v(i + 1, j + 1),
                v(i, j + 1)
            );
        }
    }
    s + tags
}

/// Tags for the mesh line j = 3 from boundary to boundary, sharpness per edge.
fn row_crease(sharpness: impl Fn(usize) -> f32) -> String {
    (0..N - 1)
        .map(|i| {
            format!(
                "t crease 2/1/0 {} {} {}\n",
                3 * N + i,
                3 * N + i + 1,
                sharpness(i)
            )
        })
        .collect()
}

fn write_file(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn subdivide(input: &Path, output: &Path, extra: &[&str]) -> Vec<[f64; 3]> {
    let out = surfkit()
        .arg("subdivide")
        .arg(input)
        .args(["-l", "3", "-o"])
        .arg(output)
        .args(extra)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    read(output).unwrap().positions
}

fn contains(points: &[[f64; 3]], p: [f64; 3]) -> bool {
    points
        .iter()
        .any(|q| (0..3).all(|c| (q[c] - p[c]).abs() < 1e-12))
}

#[test]
fn tags_are_read_and_written_back() {
    let dir = tempfile::tempdir().unwrap();
    let tags = "t crease 2/1/0 21 22 2.5\nt crease 4/2/0 22 23 23 24 1 10\n\
                t corner 1/1/0 0 3.5\nt creasemethod 0/0/1 chaikin\nt interpolateboundary 1/0/0 2\n";
    let input = write_file(dir.path(), "tagged.obj", &grid_obj(tags));
    let mesh = read(&input).unwrap();
    let sharp = mesh.sharp_features.clone().unwrap();
    assert_eq!(
        sharp.creases,
        vec![([21, 22], 2.5), ([22, 23], 1.0), ([23, 24], 10.0)]
    );
    assert_eq!(sharp.corners, vec![(0, 3.5)]);
    assert!(sharp.chaikin);
    let copy = dir.path().join("copy.obj");
    let out = surfkit()
        .arg("convert")
        .arg(&input)
        .arg(&copy)
        .output()
        .unwrap();
    assert!(out.status.success());
    assert_eq!(read(&copy).unwrap().sharp_features, Some(sharp));
}

#[test]
fn bad_tags_are_named_by_line() {
    let dir = tempfile::tempdir().unwrap();
    let faces_end = N * N + (N - 1) * (N - 1);
    for (tag, said) in [
        ("t crease 2/1/0 21 22\n", "fewer values"),
        ("t crease 2/1/0 21 99 1\n", "tag vertex 99 is out of range"),
        ("t crease 3/1/0 21 22 23 1\n", "pairs of vertices"),
        ("t corner 1/1/0 4 -1\n", "must be a finite number ≥ 0"),
        ("t creasemethod 0/0/1 bumpy\n", "chaikin or normal"),
        ("t crease 2/1 21 22 1\n", "counts"),
    ] {
        let path = write_file(dir.path(), "bad.obj", &grid_obj(tag));
        let out = surfkit().arg("info").arg(&path).output().unwrap();
        assert_eq!(out.status.code(), Some(1), "{tag}");
        let err = String::from_utf8_lossy(&out.stderr);
        let line = format!("bad.obj: line {}:", faces_end + 1);
        assert!(err.contains(&line) && err.contains(said), "{tag}: {err}");
    }
}

#[test]
fn an_infinitely_sharp_crease_refines_as_a_cubic_bspline_curve() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_file(dir.path(), "crease.obj", &grid_obj(&row_crease(|_| 10.0)));
    let refined = subdivide(&input, &dir.path().join("r.obj"), &[]);
    // The crease polygon refined three times by the curve rules: new points at edge
    // midpoints, old ones to (1, 6, 1)/8 of themselves and their crease neighbours; its
    // ends (where the crease meets the sharp boundary: corners) stay.
    let mesh = read(&input).unwrap();
    let mut curve: Vec<[f64; 3]> = (0..N).map(|i| mesh.positions[3 * N + i]).collect();
    for _ in 0..3 {
        let mut next = vec![curve[0]];
        for i in 0..curve.len() - 1 {
            if i > 0 {
                next.push(std::array::from_fn(|c| {
                    (curve[i - 1][c] + 6.0 * curve[i][c] + curve[i + 1][c]) / 8.0
                }));
            }
            next.push(std::array::from_fn(|c| {
                (curve[i][c] + curve[i + 1][c]) / 2.0
            }));
        }
        next.push(*curve.last().unwrap());
        curve = next;
    }
    assert_eq!(curve.len(), 8 * (N - 1) + 1);
    for p in &curve {
        assert!(
            contains(&refined, *p),
            "crease point {p:?} is not a refined vertex"
        );
    }
    // Without the crease the same line is smoothed away from that curve.
    let smooth = subdivide(
        &write_file(dir.path(), "smooth.obj", &grid_obj("")),
        &dir.path().join("s.obj"),
        &[],
    );
    assert!(curve[1..curve.len() - 1]
        .iter()
        .any(|p| !contains(&smooth, *p)));
}

#[test]
fn an_infinitely_sharp_corner_stays_where_it_is() {
    let dir = tempfile::tempdir().unwrap();
    let centre = 3 * N + 3;
    let input = write_file(dir.path(), "plain.obj", &grid_obj(""));
    let p = read(&input).unwrap().positions[centre];
    let corner = format!("{centre},10");
    let cornered = subdivide(&input, &dir.path().join("c.obj"), &["--corner", &corner]);
    assert!(contains(&cornered, p));
    let smooth = subdivide(&input, &dir.path().join("s.obj"), &[]);
    assert!(
        !contains(&smooth, p),
        "a smooth vertex moves (the height field is curved)"
    );
}

#[test]
fn chaikin_differs_from_uniform_only_where_sharpness_varies() {
    let dir = tempfile::tempdir().unwrap();
    let run = |name: &str, tags: &str, method: &str| {
        let input = write_file(dir.path(), &format!("{name}.obj"), &grid_obj(tags));
        let out = dir.path().join(format!("{name}_{method}.obj"));
        subdivide(&input, &out, &["--crease-method", method])
    };
    let constant = row_crease(|_| 2.0);
    assert_eq!(
        run("constant", &constant, "uniform"),
        run("constant", &constant, "chaikin")
    );
    let varying = row_crease(|i| if i % 2 == 0 { 1.0 } else { 3.0 });
    assert_ne!(
        run("varying", &varying, "uniform"),
        run("varying", &varying, "chaikin")
    );
}

#[test]
fn command_line_creases_equal_the_files_tags() {
    let dir = tempfile::tempdir().unwrap();
    let tagged = write_file(
        dir.path(),
        "tagged.obj",
        &grid_obj(&row_crease(|i| 1.0 + i as f32)),
    );
    let plain = write_file(dir.path(), "plain.obj", &grid_obj(""));
    let flags: Vec<String> = (0..N - 1)
        .flat_map(|i| {
            [
                "--crease".to_string(),
                format!("{},{},{}", 3 * N + i, 3 * N + i + 1, 1.0 + i as f32),
            ]
        })
        .collect();
    let flags: Vec<&str> = flags.iter().map(String::as_str).collect();
    assert_eq!(
        subdivide(&tagged, &dir.path().join("a.obj"), &[]),
        subdivide(&plain, &dir.path().join("b.obj"), &flags)
    );
    // A vertex that is not one is refused, naming it.
    let out = surfkit()
        .arg("subdivide")
        .arg(&plain)
        .args(["-o", "/tmp/unused.obj", "--corner", "4900,2"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("vertex 4900"));
}
