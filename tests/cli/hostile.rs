//! The command line under a hostile environment and hostile input (generated here, not
//! fixture files): a reader that closes the pipe, a full disk, outputs that name inputs or
//! each other or a missing folder, outputs that are FIFOs or devices (mknod: root only), and
//! text files as real-world writers produce them (BOM, CR, CR LF) or binary garbage named
//! .obj. Each case asserts the exit status, the message (file and problem), that no output
//! file is left behind and that inputs are unmodified.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn surfkit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_surfkit"))
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).to_string()
}

/// `n` separate triangles: every one its own component, so `eat --json` prints far more
/// than a pipe holds.
fn soup(dir: &Path, n: usize) -> PathBuf {
    let mut text = String::new();
    for k in 0..n {
        let x = k as f64;
        text.push_str(&format!("v {x} 0 0\nv {x} 1 0\nv {} 0 0\n", x + 0.5));
    }
    for k in 0..n {
        text.push_str(&format!("f {} {} {}\n", 3 * k + 1, 3 * k + 2, 3 * k + 3));
    }
    let path = dir.join("soup.obj");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_closed_pipe_ends_the_command_quietly() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = soup(dir.path(), 20_000);
    let mut child = surfkit()
        .arg("eat")
        .arg(&mesh)
        .arg("--json")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // the reader goes away at once, as `| head -c 10` does
    let out = child.wait_with_output().unwrap();
    let code = out.status.code();
    assert!(
        code == Some(141) || code == Some(0),
        "status {:?}",
        out.status
    );
    assert_eq!(stderr(&out), "", "a closed pipe is not an error to report");
}

#[test]
fn a_full_disk_on_standard_output_is_a_one_line_error() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = soup(dir.path(), 10);
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let out = surfkit()
        .arg("eat")
        .arg(&mesh)
        .stdout(Stdio::from(full))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let text = stderr(&out);
    assert_eq!(text.lines().count(), 1, "{text}");
    assert!(
        text.contains("cannot write to standard output") && text.contains("No space left"),
        "{text}"
    );
}

/// Runs `args` (with `{in}`, `{csv}`, `{dir}` and `{base}` replaced by a real mesh, a real
/// CSV, a fresh folder holding them and that folder's name) and asserts that it fails with `message` before writing
/// anything, and leaves the inputs as they were.
fn refused(args: &[&str], message: &str) {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("in.obj");
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/meshes/catmark_torus.obj"),
        &mesh,
    )
    .unwrap();
    let csv = dir.path().join("in.csv");
    let mut data = String::from("u,v,x,y,z\n");
    for j in 0..12 {
        for i in 0..12 {
            let (u, v) = (i as f64 / 11.0, j as f64 / 11.0);
            data.push_str(&format!("{u},{v},{u},{v},{}\n", u * v));
        }
    }
    std::fs::write(&csv, &data).unwrap();
    let before: Vec<(PathBuf, Vec<u8>)> = [&mesh, &csv]
        .iter()
        .map(|p| (p.to_path_buf(), std::fs::read(p).unwrap()))
        .collect();
    let args: Vec<String> = args
        .iter()
        .map(|a| {
            a.replace("{in}", mesh.to_str().unwrap())
                .replace("{csv}", csv.to_str().unwrap())
                .replace("{dir}", dir.path().to_str().unwrap())
                .replace("{base}", dir.path().file_name().unwrap().to_str().unwrap())
        })
        .collect();
    let out = surfkit().args(&args).output().unwrap();
    assert_eq!(out.status.code(), Some(1), "{args:?}: {}", stderr(&out));
    assert!(stderr(&out).contains(message), "{args:?}: {}", stderr(&out));
    for (path, bytes) in before {
        assert_eq!(
            std::fs::read(&path).unwrap(),
            bytes,
            "{args:?} modified {}",
            path.display()
        );
    }
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    names.sort();
    assert_eq!(names, ["in.csv", "in.obj"], "{args:?} left files behind");
}

#[test]
fn no_output_may_name_an_input_another_output_or_a_missing_folder() {
    refused(
        &["limit", "{in}", "-o", "{dir}/o.ply", "--png", "{in}"],
        "refusing to write over the input file",
    );
    refused(
        &["eat", "{in}", "--mark", "{in}"],
        "refusing to write over the input file",
    );
    refused(
        &["repair", "{in}", "{in}"],
        "refusing to write over the input file",
    );
    refused(
        &["repair", "{in}", "{dir}/r.obj", "--mark", "{dir}/r.obj"],
        "name the same file",
    );
    refused(
        &["eat", "{in}", "--reference", "{csv}", "--mark", "{csv}"],
        "refusing to write over the input file",
    );
    refused(
        &["fit", "{csv}", "--coefficients", "{csv}"],
        "refusing to write over the input file",
    );
    refused(
        &["fit", "{csv}", "--output", "{dir}/../{base}/in.csv"],
        "refusing to write over the input file",
    );
    refused(
        &["fair", "{in}", "--fixed", "{csv}", "-o", "{csv}"],
        "refusing to write over the input file",
    );
    refused(
        &["limit", "{in}", "-o", "{dir}/x.ply", "--png", "{dir}/x.ply"],
        "name the same file",
    );
    // limit's picture, when --png is not given, is the output's name with .png.
    for message in [
        "--png (by default the output's name with .png) ",
        "/l4.png and --html ",
        "/l4.png name the same file",
    ] {
        refused(
            &[
                "limit",
                "{in}",
                "-o",
                "{dir}/l4.ply",
                "--html",
                "{dir}/l4.png",
            ],
            message,
        );
    }
    // fair's pictures in an existing --figures folder.
    refused(
        &[
            "fair",
            "{in}",
            "-o",
            "{dir}/o.obj",
            "--figures",
            "{dir}",
            "--html",
            "{dir}/curvature_before.png",
        ],
        "/curvature_before.png and --figures ",
    );
    refused(
        &[
            "fit",
            "{csv}",
            "--output",
            "{dir}/s.ply",
            "--coefficients",
            "{dir}/s.ply",
        ],
        "name the same file",
    );
    refused(
        &["subdivide", "{in}", "-o", "{dir}/nodir/x.obj"],
        "does not exist",
    );
    refused(&["convert", "{in}", "{dir}/nodir/x.ply"], "does not exist");
    refused(
        &[
            "fair",
            "{in}",
            "-o",
            "{dir}/o.obj",
            "--samples",
            "{dir}/nodir/s.ply",
        ],
        "does not exist",
    );
}

#[test]
fn symlinks_to_an_input_are_the_input() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("a.obj");
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/meshes/catmark_torus.obj"),
        &mesh,
    )
    .unwrap();
    let link = dir.path().join("link.obj");
    std::os::unix::fs::symlink(&mesh, &link).unwrap();
    let before = std::fs::read(&mesh).unwrap();
    let out = surfkit()
        .arg("convert")
        .arg(&mesh)
        .arg(&link)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr(&out).contains("refusing to write over the input file"),
        "{}",
        stderr(&out)
    );
    assert_eq!(std::fs::read(&mesh).unwrap(), before);
}

#[test]
fn text_files_as_real_writers_make_them_read_alike() {
    // The same triangle fan written with LF, CR LF, CR alone, and a UTF-8 byte-order mark.
    let lf = "# fan\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n";
    let dir = tempfile::tempdir().unwrap();
    let read = |name: &str, bytes: Vec<u8>| {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        surfkit::mesh::io::read(&path).unwrap()
    };
    let reference = read("lf.obj", lf.as_bytes().to_vec());
    assert_eq!(reference.vertex_count(), 4);
    for (name, bytes) in [
        ("crlf.obj", lf.replace('\n', "\r\n").into_bytes()),
        ("cr.obj", lf.replace('\n', "\r").into_bytes()),
        ("bom.obj", [&b"\xEF\xBB\xBF"[..], lf.as_bytes()].concat()),
        (
            "bom_crlf.obj",
            [&b"\xEF\xBB\xBF"[..], lf.replace('\n', "\r\n").as_bytes()].concat(),
        ),
    ] {
        assert_eq!(read(name, bytes), reference, "{name}");
    }
    // OFF too.
    let off = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
    let off_ref = read("lf.off", off.as_bytes().to_vec());
    assert_eq!(
        read("cr.off", off.replace('\n', "\r").into_bytes()),
        off_ref
    );
    assert_eq!(
        read("bom.off", [&b"\xEF\xBB\xBF"[..], off.as_bytes()].concat()),
        off_ref
    );
}

#[test]
fn binary_garbage_named_obj_is_refused_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let garbage = dir.path().join("garbage.obj");
    // Deterministic bytes that are no OBJ: a linear congruential sequence.
    let mut x: u32 = 12345;
    let bytes: Vec<u8> = (0..4096)
        .map(|_| {
            x = x.wrapping_mul(1_103_515_245).wrapping_add(12_345);
            (x >> 16) as u8
        })
        .collect();
    std::fs::write(&garbage, bytes).unwrap();
    let out_path = dir.path().join("out.ply");
    let out = surfkit()
        .arg("convert")
        .arg(&garbage)
        .arg(&out_path)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let text = stderr(&out);
    assert!(
        text.contains("garbage.obj") && text.contains("not an OBJ file"),
        "{text}"
    );
    assert!(!out_path.exists());
    // Garbage in which a record happens to be recognised (an empty group name, found by the
    // Python corpus scan) is refused as well, at its first binary line.
    let lucky = dir.path().join("lucky.obj");
    std::fs::write(&lucky, b"g\n\xd0\xc0!v-\xf9\t\xda/\x12\x1a\n").unwrap();
    let Err(e) = surfkit::mesh::io::read(&lucky) else {
        panic!("binary data read as a mesh");
    };
    let text = e.to_string();
    assert!(
        text.contains("lucky.obj") && text.contains("line 2") && text.contains("byte 0x12"),
        "{text}"
    );
    // A file of comments only is an empty mesh, not garbage.
    let comments = dir.path().join("comments.obj");
    std::fs::write(&comments, "# nothing here yet\n\n# still nothing\n").unwrap();
    assert_eq!(
        surfkit::mesh::io::read(&comments).unwrap().vertex_count(),
        0
    );
}

#[test]
fn outputs_follow_the_umask_keep_a_files_mode_and_write_through_symlinks() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/meshes/catmark_torus.obj");
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    // What the umask gives a new file, measured the way a shell's `>` creates one.
    let reference = dir.path().join("reference");
    std::fs::File::create(&reference).unwrap();
    let out = dir.path().join("out.ply");
    let convert = |to: &Path| {
        let o = surfkit()
            .arg("convert")
            .arg(&input)
            .arg(to)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
    };
    convert(&out);
    assert_eq!(mode(&out), mode(&reference));
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o640)).unwrap();
    convert(&out);
    assert_eq!(mode(&out), 0o640, "a replaced file keeps its mode");
    let link = dir.path().join("link.ply");
    std::os::unix::fs::symlink(&out, &link).unwrap();
    std::fs::write(&out, b"old").unwrap();
    convert(&link);
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(
        std::fs::read(&out).unwrap().starts_with(b"ply"),
        "the link's target was replaced"
    );
}

#[test]
fn absurd_sizes_are_refused_before_any_work_with_the_option_named() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("in.csv");
    std::fs::write(&csv, "0,0,0,0,0\n1,0,1,0,0\n0,1,0,1,0\n1,1,1,1,1\n").unwrap();
    let out = dir.path().join("out.obj");
    let out_arg = out.to_str().unwrap();
    let csv_arg = csv.to_str().unwrap();
    for (args, status, message) in [
        (
            vec!["gen", "tubes", "--size", "100000", "-o", out_arg],
            1,
            "(--size)",
        ),
        (
            vec!["gen", "tubes", "--rings", "4294967295", "-o", out_arg],
            1,
            "(--rings)",
        ),
        (
            vec!["gen", "tubes", "--size", "1000", "-o", out_arg],
            1,
            "at most 4000000",
        ),
        (
            // All the levels are sized before the first (refined one at a time, the 20 were
            // refused after 20 s, at the level that passed the budget, as "1 levels").
            vec!["gen", "tubes", "--refine", "20", "-o", out_arg],
            1,
            "20 levels of refinement",
        ),
        (
            vec!["fit", csv_arg, "--cells", "1000000,1000000"],
            1,
            "cells are supported",
        ),
        (
            vec![
                "fit",
                csv_arg,
                "--resolution",
                "100000",
                "--output",
                out_arg,
            ],
            2,
            "--resolution",
        ),
        (
            vec!["fair", csv_arg, "-o", out_arg, "--sample-density", "0"],
            2,
            "--sample-density",
        ),
    ] {
        let o = surfkit().args(&args).output().unwrap();
        assert_eq!(o.status.code(), Some(status), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(message), "{args:?}: {}", stderr(&o));
        assert!(!out.exists(), "{args:?} wrote its output");
    }
}

/// A cone of `n` triangles around one apex (valence n), written to `dir`.
fn fan(dir: &Path, n: usize) -> PathBuf {
    let mut text = String::from("v 0 0 1\n");
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        text.push_str(&format!("v {} {} 0\n", a.cos(), a.sin()));
    }
    for i in 0..n {
        text.push_str(&format!("f 1 {} {}\n", i + 2, (i + 1) % n + 2));
    }
    let path = dir.join("fan.obj");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn small_inputs_that_imply_huge_work_are_done_linearly_or_refused() {
    let dir = tempfile::tempdir().unwrap();
    // One face of 200 000 corners: info and eat see one face, one boundary loop.
    let n = 200_000;
    let mut text = String::new();
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        text.push_str(&format!("v {:.9} {:.9} 0\n", a.cos(), a.sin()));
    }
    text.push('f');
    for i in 1..=n {
        text.push_str(&format!(" {i}"));
    }
    text.push('\n');
    let big = dir.path().join("big_face.obj");
    std::fs::write(&big, text).unwrap();
    let out = surfkit().arg("info").arg(&big).output().unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let json = surfkit()
        .args(["eat", "--json"])
        .arg(&big)
        .output()
        .unwrap();
    let report: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    let counts = &report["report"]["counts"];
    assert_eq!(counts["vertices_referenced"], n, "{counts}");
    assert_eq!(counts["facets"], 1, "{counts}");
    assert_eq!(counts["edges"], n, "{counts}");
    assert_eq!(counts["boundary_loops"], 1, "{counts}");

    // A fan of valence 1000: the limit surface is built at the full isolation level...
    let mesh = fan(dir.path(), 1000);
    let limit = dir.path().join("limit.ply");
    let out = surfkit()
        .arg("limit")
        .arg(&mesh)
        .arg("-o")
        .arg(&limit)
        .args(["--samples", "1", "--json"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["isolation"], 4, "{report}");
    // ...and fairing, whose work grows as the cube of the valence, refuses it up front.
    let faired = dir.path().join("faired.obj");
    let out = surfkit()
        .arg("fair")
        .arg(&mesh)
        .arg("-o")
        .arg(&faired)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr(&out)
            .contains("vertex 0 lies in 1000 faces; fairing supports vertices of at most 64"),
        "{}",
        stderr(&out)
    );
    assert!(!faired.exists());
    // A memory limit too small for the limit surface is an error naming the limit.
    let out = surfkit()
        .args(["--max-memory", "1M", "limit"])
        .arg(&mesh)
        .arg("-o")
        .arg(dir.path().join("small.ply"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr(&out).contains("needs more than the memory limit of 1.0 MiB"),
        "{}",
        stderr(&out)
    );
    assert!(!dir.path().join("small.ply").exists());
    for bad in ["12Q", "0", "-1G"] {
        let out = surfkit()
            .args(["info", &format!("--max-memory={bad}")])
            .arg(&mesh)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "--max-memory {bad}");
        assert!(stderr(&out).contains("--max-memory"), "{}", stderr(&out));
    }
}

#[test]
fn messages_name_the_file_the_option_and_the_real_problem() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("in.csv");
    let mut data = String::from("u,v,x,y,z\n");
    for j in 0..12 {
        for i in 0..12 {
            let (u, v) = (i as f64 / 11.0, j as f64 / 11.0);
            data.push_str(&format!("{u},{v},{u},{v},{}\n", u * v));
        }
    }
    std::fs::write(&csv, &data).unwrap();
    // The same data scaled to 1e300: the sums of squares would overflow.
    let huge = dir.path().join("huge.csv");
    let mut scaled = String::from("u,v,x,y,z\n");
    for line in data.lines().skip(1) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        scaled.push_str(&format!(
            "{},{},{:e},{:e},{:e}\n",
            v[0],
            v[1],
            v[2] * 1e300,
            v[3] * 1e300,
            v[4] * 1e300
        ));
    }
    std::fs::write(&huge, scaled).unwrap();
    let a_file = dir.path().join("a_file");
    std::fs::write(&a_file, "not a folder").unwrap();
    let mesh = fan(dir.path(), 6);
    let out = dir.path().join("out.ply");
    let p = |p: &Path| p.to_str().unwrap().to_string();
    for (args, status, message) in [
        (
            vec!["fill".into(), p(&csv), "--hole".into(), "circle:0.5,0.5,1".into()],
            1,
            "in.csv: invalid input: --hole \"circle:0.5,0.5,1\": unknown shape \"circle\"".to_string(),
        ),
        (
            vec!["fill".into(), p(&csv), "--hole".into(), "ellipse:0.5,0.5,1".into()],
            1,
            "an ellipse takes 5 numbers (cx,cy,a,b,level), got 3".into(),
        ),
        (
            vec!["fit".into(), p(&huge), "--output".into(), p(&out)],
            1,
            "huge.csv: invalid input: data point 1 (data line 2) has a coordinate of magnitude above 1e150".into(),
        ),
        (
            vec!["fair".into(), p(&mesh), "-o".into(), p(&out), "--tolerance".into(), "NaN".into()],
            2,
            "NaN must lie strictly between 0 and 1".into(),
        ),
        (
            vec!["fair".into(), p(&mesh), "-o".into(), p(&out), "--c-special=-1".into()],
            2,
            "-1 must be positive and finite".into(),
        ),
        (
            vec!["limit".into(), p(&mesh), "-o".into(), p(&out), "--png".into(), p(&dir.path().join("x.jpg"))],
            1,
            "x.jpg: the picture is written as PNG; give a name ending in .png".into(),
        ),
        (
            // A mistyped folder has no extension: what is wrong is that it is not there.
            vec!["eat".into(), p(&dir.path().join("no_such_folder"))],
            1,
            "no_such_folder: No such file or directory".into(),
        ),
        (
            vec!["eat".into(), p(&mesh), "--every".into(), "0".into()],
            2,
            "'0' for '--every <EVERY>'".into(),
        ),
        (
            vec!["fair".into(), p(&mesh), "-o".into(), p(&out), "--figures".into(), p(&a_file)],
            1,
            "--figures ".to_string() + &p(&a_file) + ": is a file; give a folder",
        ),
        (
            vec!["demo".into(), "--out".into(), p(&a_file)],
            1,
            "--out ".to_string() + &p(&a_file) + ": is a file; give a folder",
        ),
        (
            vec!["demo".into(), "--out".into(), p(&a_file.join("sub"))],
            1,
            "--out ".to_string() + &p(&a_file.join("sub")) + ": cannot create this folder",
        ),
        (
            vec!["paper".into(), "kp2004-example2".into(), "--figures".into(), p(&a_file)],
            1,
            "--figures ".to_string() + &p(&a_file) + ": is a file; give a folder",
        ),
        (
            vec!["paper".into(), "kp2022-table1".into(), "--figures".into(), "/proc/nonexistent".into()],
            1,
            "--figures /proc/nonexistent: cannot create this folder: No such file".into(),
        ),
    ] {
        let run = surfkit().args(&args).output().unwrap();
        assert_eq!(run.status.code(), Some(status), "{args:?}: {}", stderr(&run));
        assert!(stderr(&run).contains(&message), "{args:?}: {}", stderr(&run));
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
    }
    assert_eq!(std::fs::read_to_string(&a_file).unwrap(), "not a folder");
    // A missing folder is tried up front and removed again: a command that fails later
    // leaves no empty folders behind.
    let figures = dir.path().join("a/b/c");
    let run = surfkit()
        .args(["paper", "kp2022-table1", "--seeds", "0", "--figures"])
        .arg(&figures)
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(1), "{}", stderr(&run));
    assert!(
        stderr(&run).contains("needs at least one seed"),
        "{}",
        stderr(&run)
    );
    assert!(!dir.path().join("a").exists(), "the probe left a/ behind");
}

/// Makes a node at `path` with `mknod` (`c 1 7`: /dev/full's numbers); false, with a note on
/// stderr, where that is not allowed (not root): the callers then skip, saying so.
fn mknod_full(path: &Path) -> bool {
    let made = Command::new("mknod")
        .arg(path)
        .args(["c", "1", "7"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !made {
        eprintln!(
            "SKIPPED: mknod {} c 1 7 failed (not root?): the device case is not tested",
            path.display()
        );
    }
    made
}

#[test]
fn an_output_that_is_a_fifo_is_written_into_and_stays_a_fifo() {
    use std::io::Read;
    use std::os::unix::fs::{FileTypeExt, OpenOptionsExt};
    let dir = tempfile::tempdir().unwrap();
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/meshes/catmark_torus.obj");
    let fifo = dir.path().join("fifo_out.ply");
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success(), "mkfifo {}", fifo.display());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            std::fs::File::open(&fifo)
                .unwrap()
                .read_to_end(&mut bytes)
                .unwrap();
            bytes
        })
    };
    let out = surfkit()
        .arg("convert")
        .arg(&input)
        .arg(&fifo)
        .arg("--ascii")
        .output()
        .unwrap();
    // Should the command not have opened the FIFO, a writer that comes and goes at once
    // ends the reader's wait (no reader left: the open fails, harmlessly).
    let _ = std::fs::OpenOptions::new()
        .write(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(&fifo);
    let bytes = reader.join().unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        bytes.starts_with(b"ply\nformat ascii 1.0\n"),
        "{:?}",
        String::from_utf8_lossy(&bytes[..bytes.len().min(80)])
    );
    let mesh = surfkit::mesh::io::read(&input).unwrap();
    let text = String::from_utf8(bytes).unwrap();
    assert!(text.contains(&format!("element vertex {}\n", mesh.vertex_count())));
    let kind = std::fs::symlink_metadata(&fifo).unwrap().file_type();
    assert!(kind.is_fifo(), "the FIFO was replaced: {kind:?}");
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(names.len(), 1, "a temporary file was left behind");
}

#[test]
fn an_output_linked_to_a_full_device_fails_and_the_device_stays() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().unwrap();
    // Named .ply so that it can be an output itself as well as a link's target.
    let device = dir.path().join("fulldev.ply");
    if !mknod_full(&device) {
        return;
    }
    let link = dir.path().join("fl.ply");
    std::os::unix::fs::symlink(&device, &link).unwrap();
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/meshes/catmark_torus.obj");
    for target in [&link, &device] {
        let out = surfkit()
            .arg("convert")
            .arg(&input)
            .arg(target)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
        let text = stderr(&out);
        assert!(
            text.contains(target.to_str().unwrap()) && text.contains("No space left on device"),
            "{text}"
        );
        assert!(
            std::fs::symlink_metadata(&device)
                .unwrap()
                .file_type()
                .is_char_device(),
            "the device was replaced"
        );
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
    }
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(names.len(), 2, "a temporary file was left behind");
}

#[test]
fn an_output_linked_to_standard_output_writes_there() {
    let dir = tempfile::tempdir().unwrap();
    let link = dir.path().join("stdout.ply");
    std::os::unix::fs::symlink("/dev/stdout", &link).unwrap();
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/meshes/catmark_torus.obj");
    // Standard output is a pipe here: /dev/stdout resolves to it only through /proc.
    let out = surfkit()
        .arg("convert")
        .arg(&input)
        .arg(&link)
        .arg("--ascii")
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(out.stdout.starts_with(b"ply\nformat ascii 1.0\n"));
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

#[test]
fn an_output_linked_to_a_regular_file_in_another_folder_replaces_that_file() {
    let dir = tempfile::tempdir().unwrap();
    let (links, files) = (dir.path().join("links"), dir.path().join("files"));
    std::fs::create_dir(&links).unwrap();
    std::fs::create_dir(&files).unwrap();
    let target = files.join("out.ply");
    std::fs::write(&target, b"old").unwrap();
    let link = links.join("out.ply");
    std::os::unix::fs::symlink("../files/out.ply", &link).unwrap();
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/meshes/catmark_torus.obj");
    let out = surfkit()
        .arg("convert")
        .arg(&input)
        .arg(&link)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let kind = std::fs::symlink_metadata(&link).unwrap().file_type();
    assert!(kind.is_symlink(), "the link became {kind:?}");
    assert_eq!(
        std::fs::read_link(&link).unwrap(),
        Path::new("../files/out.ply")
    );
    assert!(std::fs::read(&target).unwrap().starts_with(b"ply"));
    assert!(std::fs::symlink_metadata(&target).unwrap().is_file());
    assert_eq!(std::fs::read_dir(&links).unwrap().count(), 1);
    assert_eq!(std::fs::read_dir(&files).unwrap().count(), 1);
}

/// Huge but finite coordinates: the flaw's position is finite, and the measures that are
/// beyond f64 (a perimeter near 2.4e308, an area near 1e616) are `Infinity` in text and
/// JSON alike — never `null`, which reads as "not measured".
#[test]
fn huge_coordinates_give_a_finite_position_and_explicitly_infinite_measures() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("huge.obj");
    std::fs::write(
        &mesh,
        "v 1e308 1e308 1e308\nv -1e308 0 0\nv 0 1e308 0\nf 1 2 3\n",
    )
    .unwrap();
    let out = surfkit()
        .args(["eat", "--json"])
        .arg(&mesh)
        .output()
        .unwrap();
    let json = String::from_utf8_lossy(&out.stdout);
    let report: serde_json::Value = serde_json::from_str(&json).unwrap();
    let flaw = &report["report"]["flaws"][0];
    // An isolated facet: its border is a hole, with the facet in `faces`.
    assert_eq!(flaw["kind"], "hole", "{json}");
    let position: Vec<f64> = flaw["position"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    let expected = [0.0, 1e308 / 3.0 * 2.0, 1e308 / 3.0];
    for (p, e) in position.iter().zip(expected) {
        assert!((p - e).abs() <= 1e-15 * e.abs(), "{position:?}");
    }
    assert_eq!(flaw["shape"]["perimeter"], "Infinity", "{json}");
    assert_eq!(flaw["shape"]["area"], "Infinity", "{json}");
    let text = surfkit().arg("eat").arg(&mesh).output().unwrap();
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(
        text.contains("hole at (0.000000, 6.666667e307, 3.333333e307)")
            && text.contains("perimeter Infinity"),
        "{text}"
    );
}

/// Numeric options outside their range are refused while parsing the arguments (status 2,
/// the option named), before any file is read.
#[test]
fn weld_tolerance_and_newton_after_decrease_must_be_in_range() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("t.obj");
    std::fs::write(&mesh, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let out_path = dir.path().join("out.obj");
    for bad in ["inf", "-inf", "nan", "-1", "1e999"] {
        for command in ["eat", "repair"] {
            let mut run = surfkit();
            run.arg(command)
                .arg(&mesh)
                .arg(format!("--weld-tolerance={bad}"));
            if command == "repair" {
                run.arg(&out_path);
            }
            let out = run.output().unwrap();
            assert_eq!(
                out.status.code(),
                Some(2),
                "{command} --weld-tolerance {bad}"
            );
            assert!(
                stderr(&out).contains("--weld-tolerance")
                    && stderr(&out).contains("must be a finite number ≥ 0"),
                "{}",
                stderr(&out)
            );
            assert!(!out_path.exists());
        }
    }
    for bad in ["nan", "inf", "-0.1", "1.5"] {
        let out = surfkit()
            .arg("fair")
            .arg(&mesh)
            .arg("--output")
            .arg(&out_path)
            .arg(format!("--newton-after-decrease={bad}"))
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "--newton-after-decrease {bad}");
        assert!(
            stderr(&out).contains("--newton-after-decrease")
                && stderr(&out).contains("must lie between 0 and 1"),
            "{}",
            stderr(&out)
        );
        assert!(!out_path.exists());
    }
}
