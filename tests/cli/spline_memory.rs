//! `surfkit fit` and `fill` under `--max-memory`: the sampled mesh and the spline's
//! Cholesky factor are sized before they are made, and a size beyond the limit is refused
//! with the option to change, with nothing written.

use std::path::Path;
use std::process::Command;

/// `surfkit --max-memory MEMORY COMMAND DATA ARGS…`: its exit status and stderr.
fn run(memory: &str, command: &str, data: &Path, args: &[&str]) -> (Option<i32>, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_surfkit"))
        .args(["--max-memory", memory, command])
        .arg(data)
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `n` × `n` points of the plane z = u + v on [0, 1]², one at the centre of each cell of an
/// `n` × `n` grid.
fn plane(dir: &Path, n: usize) -> std::path::PathBuf {
    let mut text = String::from("u,v,x,y,z\n");
    for i in 0..n {
        for j in 0..n {
            let (u, v) = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
            text.push_str(&format!("{u},{v},{u},{v},{}\n", u + v));
        }
    }
    let path = dir.join("plane.csv");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_sampled_mesh_beyond_the_limit_is_refused_before_the_solve() {
    let dir = tempfile::tempdir().unwrap();
    let data = plane(dir.path(), 10);
    let output = dir.path().join("fit.ply");
    let output_arg = output.to_str().unwrap();
    for command in ["fit", "fill"] {
        let args = |resolution| {
            [
                "--cells",
                "4,4",
                "--resolution",
                resolution,
                "--output",
                output_arg,
            ]
        };
        let (status, stderr) = run("64M", command, &data, &args("4096"));
        assert_eq!(status, Some(1), "{command}: {stderr}");
        // 4096² samples of 72 bytes: 1.1 GiB.
        assert!(
            stderr.contains("--resolution 4096") && stderr.contains("1.1 GiB"),
            "{command}: {stderr}"
        );
        assert!(
            stderr.contains("memory limit of 64 MiB"),
            "{command}: {stderr}"
        );
        assert!(!output.exists(), "{command}: nothing written");
        // Within the limit the same command writes its mesh.
        let (status, stderr) = run("64M", command, &data, &args("256"));
        assert_eq!(status, Some(0), "{command}: {stderr}");
        assert!(output.exists());
        std::fs::remove_file(&output).unwrap();
    }
}

#[test]
fn a_cholesky_factor_beyond_the_limit_is_refused_with_its_size() {
    // 300 × 300 biquadratic cells: 302² unknowns, whose factor does not fit 4 MiB; the same
    // data on 30 × 30 cells does.
    let dir = tempfile::tempdir().unwrap();
    let data = plane(dir.path(), 300);
    let (status, stderr) = run("4M", "fit", &data, &["--cells", "300,300"]);
    assert_eq!(status, Some(1), "{stderr}");
    assert!(
        stderr.contains("sparse Cholesky factor of a system of order")
            && stderr.contains("memory limit of 4.0 MiB")
            && stderr.contains("fewer cells"),
        "{stderr}"
    );
    let (status, stderr) = run("4M", "fit", &data, &["--cells", "30,30"]);
    assert_eq!(status, Some(0), "{stderr}");
}
