//! The hostile-input matrix, generated here: every subcommand that reads a mesh × malformed
//! files of each format it reads, and every subcommand with its standard output on a full
//! disk. Each case asserts the exit status, a one-line message naming the file, that no
//! output is left behind and that the input is unmodified. (Time bounds are measured in
//! `benches/hostile_inputs.rs`, not here.)

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

fn surfkit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_surfkit"))
}

/// Malformed meshes: (file name, bytes, what the message must say besides the file name).
fn malformed() -> Vec<(&'static str, Vec<u8>, &'static str)> {
    let garbage: Vec<u8> = (0..4096u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
        .collect();
    let mut ply_truncated = b"ply\nformat binary_little_endian 1.0\nelement vertex 4\n\
property double x\nproperty double y\nproperty double z\nelement face 1\n\
property list uchar int vertex_indices\nend_header\n"
        .to_vec();
    ply_truncated.extend([0u8; 40]);
    vec![
        ("empty.obj", vec![], "empty"),
        ("garbage.obj", garbage.clone(), "OBJ"),
        ("garbage.ply", garbage.clone(), "ply"),
        ("garbage.off", garbage, "OFF"),
        (
            "nan.obj",
            b"v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n".to_vec(),
            "line 2",
        ),
        (
            "index.obj",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n".to_vec(),
            "line 4",
        ),
        (
            "index.off",
            b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n".to_vec(),
            "9",
        ),
        ("truncated.ply", ply_truncated, "vertex"),
        ("lying.off", b"OFF\n1000000000 1 0\n0 0 0\n".to_vec(), "OFF"),
        (
            "lying.stl",
            [&[b' '; 80][..], &1_000_000_000u32.to_le_bytes()].concat(),
            "the header gives 1000000000 facets",
        ),
        (
            "cut.stl",
            b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n".to_vec(),
            "line 4: the file ends inside a solid",
        ),
        ("mesh.3mf", b"PK\x03\x04".to_vec(), "unknown mesh format"),
    ]
}

/// Subcommand arguments with `{in}` for the mesh and `{out}` for an output in the folder.
fn mesh_commands() -> Vec<Vec<&'static str>> {
    vec![
        vec!["info", "{in}"],
        vec!["info", "--json", "{in}"],
        vec!["convert", "{in}", "{out}.ply"],
        vec!["eat", "{in}"],
        vec!["eat", "--json", "--mark", "{out}.ply", "{in}"],
        vec!["repair", "{in}", "{out}.obj"],
        vec![
            "repair",
            "--json",
            "{in}",
            "{out}.ply",
            "--mark",
            "{out}_marked.ply",
        ],
        vec!["subdivide", "{in}", "-o", "{out}.obj"],
        vec!["limit", "{in}", "-o", "{out}.ply"],
        vec!["fair", "{in}", "-o", "{out}.obj"],
        vec!["fit", "{in}", "--output", "{out}.ply"],
        vec!["fill", "{in}", "--hole-from-data", "--output", "{out}.ply"],
    ]
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    names.sort();
    names
}

fn expand(args: &[&str], input: &Path, out: &Path) -> Vec<String> {
    args.iter()
        .map(|a| {
            a.replace("{in}", input.to_str().unwrap())
                .replace("{out}", out.to_str().unwrap())
        })
        .collect()
}

#[test]
fn every_mesh_command_refuses_every_malformed_file_cleanly() {
    let mut cases = 0;
    for (name, bytes, says) in malformed() {
        for command in mesh_commands() {
            let dir = tempfile::tempdir().unwrap();
            let input = dir.path().join(name);
            std::fs::write(&input, &bytes).unwrap();
            let args = expand(&command, &input, &dir.path().join("out"));
            let run = surfkit().args(&args).output().unwrap();
            let err = String::from_utf8_lossy(&run.stderr);
            assert_eq!(run.status.code(), Some(1), "{args:?}: {err}");
            assert_eq!(err.lines().count(), 1, "{args:?}: one line, got {err}");
            assert!(
                err.contains(name),
                "{args:?}: the message names no file: {err}"
            );
            assert!(
                err.to_lowercase().contains(&says.to_lowercase()),
                "{args:?}: expected {says:?} in {err}"
            );
            assert!(!err.contains("panicked"), "{args:?}: {err}");
            assert_eq!(files_in(dir.path()), [name], "{args:?} left files behind");
            assert_eq!(
                std::fs::read(&input).unwrap(),
                bytes,
                "{args:?} changed its input"
            );
            cases += 1;
        }
    }
    assert_eq!(cases, 12 * 12, "12 malformed files × 12 commands");
}

/// A small valid mesh: a 16 × 16 quad grid lifted into a bump (open, so `fair` holds its
/// boundary), with UVs so that `fit`/`fill` can read it as data.
fn bump(dir: &Path) -> PathBuf {
    let mut text = String::new();
    let n = 16;
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
            text.push_str(&format!(
                "v {x} {y} {}\nvt {x} {y}\n",
                x * (1.0 - x) * y * (1.0 - y)
            ));
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i + 1;
            let (b, c, d) = (a + 1, a + n + 2, a + n + 1);
            text.push_str(&format!("f {a}/{a} {b}/{b} {c}/{c} {d}/{d}\n"));
        }
    }
    let path = dir.join("bump.obj");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn every_command_with_its_output_on_a_full_disk_says_so_in_one_line() {
    for command in mesh_commands().into_iter().chain([
        vec!["paper", "kp2022-table1"],
        vec!["demo", "--out", "{out}"],
    ]) {
        let dir = tempfile::tempdir().unwrap();
        let input = bump(dir.path());
        let args = expand(&command, &input, &dir.path().join("out"));
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let run = surfkit()
            .args(&args)
            .stdout(Stdio::from(full))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{args:?}: {err}");
        let last = err.lines().last().unwrap_or("");
        assert!(
            last.contains("cannot write to standard output") && last.contains("No space left"),
            "{args:?}: {err}"
        );
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}
