//! What the text summaries say about unusual but legal inputs: a facet of thousands of
//! corners stays one short line (JSON keeps every id), zero levels of subdivision leave
//! triangles triangles, and an OBJ whose faces are only partly textured keeps the UVs it has.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn surfkit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_surfkit"))
}

fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Runs surfkit with `args` (paths as `&OsStr`s), asserts it succeeded, returns its stdout.
fn succeeds(args: &[&std::ffi::OsStr]) -> String {
    let out = surfkit().args(args).output().unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    stdout(&out)
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("surfkit-text-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A fan of `n` triangles round vertex 1 and one facet through all rim vertices, the
/// other way round, that comes back to its second corner (a vertex repeated apart:
/// degenerate).
fn long_degenerate_facet(dir: &Path, n: usize) -> PathBuf {
    let mut text = String::from("v 0 0 0\n");
    for k in 0..n {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        text += &format!("v {} {} 0\n", a.cos(), a.sin());
    }
    for k in 0..n {
        text += &format!("f 1 {} {}\n", 2 + k, 2 + (k + 1) % n);
    }
    text += "f";
    for k in (0..n).rev() {
        text += &format!(" {}", 2 + k);
    }
    text += &format!(" {}\n", n);
    let path = dir.join("long.obj");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_facet_of_thousands_of_corners_is_one_short_line_and_whole_in_json() {
    let dir = scratch("long");
    let n = 5000;
    let mesh = long_degenerate_facet(&dir, n);
    let out = surfkit().arg("eat").arg(&mesh).output().unwrap();
    let text = stdout(&out);
    let line = text
        .lines()
        .find(|l| l.contains("fewer than 3 or a repeated vertex"))
        .unwrap_or_else(|| panic!("no degenerate facet in:\n{text}"));
    assert!(
        line.contains(&format!(
            "corners [5000, 4999, 4998, 4997, 4996, 4995, 4994, 4993, … ({} in all)]",
            n + 1
        )),
        "{line}"
    );
    assert!(line.len() < 200, "{} characters: {line}", line.len());
    let out = surfkit()
        .args(["eat", "--json"])
        .arg(&mesh)
        .output()
        .unwrap();
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let degenerate = json["report"]["flaws"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["kind"] == "degenerate_facet")
        .expect("the degenerate facet in JSON");
    assert_eq!(degenerate["vertices"].as_array().unwrap().len(), n + 1);

    let repaired = dir.join("repaired.obj");
    let out = surfkit()
        .arg("repair")
        .arg(&mesh)
        .arg(&repaired)
        .output()
        .unwrap();
    let text = stdout(&out);
    let line = text
        .lines()
        .find(|l| l.contains("has no area left"))
        .unwrap_or_else(|| panic!("no deleted facet in:\n{text}"));
    assert!(line.contains(&format!("… ({} in all)]", n + 1)), "{line}");
    assert!(line.len() < 200, "{} characters: {line}", line.len());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn zero_levels_of_subdivision_keep_triangles_and_say_faces() {
    let dir = scratch("zero");
    let tri = dir.join("tri.obj");
    std::fs::write(&tri, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let out = dir.join("out.obj");
    for (levels, said) in [("0", "1 faces → 1 faces"), ("1", "1 faces → 3 quads")] {
        let text = succeeds(&[
            "subdivide".as_ref(),
            "-l".as_ref(),
            levels.as_ref(),
            tri.as_ref(),
            "-o".as_ref(),
            out.as_ref(),
        ]);
        assert!(text.contains(said), "{levels}: {text}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn faces_without_texture_coordinates_leave_the_others_theirs() {
    let dir = scratch("uv");
    // A textured quad (o label) and an untextured triangle joined to it, as when a textured
    // and an untextured part are exported to one OBJ.
    let mesh = dir.join("joined.obj");
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0.5 0\n\
                vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
                o body\nf 1/1 2/2 3/3 4/4\no bolt\nf 2 5 3\n";
    std::fs::write(&mesh, text).unwrap();
    let text = succeeds(&["info".as_ref(), mesh.as_ref()]);
    assert!(text.contains("uvs on 1 of 2 faces"), "{text}");

    // Converted: the same text back (the untextured face without `/vt`).
    let copy = dir.join("copy.obj");
    succeeds(&["convert".as_ref(), mesh.as_ref(), copy.as_ref()]);
    let written = std::fs::read_to_string(&copy).unwrap();
    assert!(written.contains("f 1/1 2/2 3/3 4/4\n"), "{written}");
    assert!(written.contains("f 2 5 3\n"), "{written}");
    assert_eq!(written.matches("\nvt ").count(), 4, "{written}");

    // Subdivided: the quad's 4 children textured, the triangle's 3 not.
    let refined = dir.join("refined.obj");
    let subdivide = |extra: &str| {
        let mut args = vec!["subdivide".as_ref(), "-l".as_ref(), "1".as_ref()];
        args.extend((!extra.is_empty()).then_some(std::ffi::OsStr::new(extra)));
        args.extend([mesh.as_os_str(), "-o".as_ref(), refined.as_os_str()]);
        succeeds(&args)
    };
    let json: serde_json::Value = serde_json::from_str(&subdivide("--json")).unwrap();
    assert_eq!(
        (json["faces"].as_u64(), json["textured_faces"].as_u64()),
        (Some(7), Some(4))
    );
    let text = subdivide("");
    assert!(
        text.contains("UVs refined on 4 faces (from the 1 of 2 control faces that have them)"),
        "{text}"
    );
    let written = std::fs::read_to_string(&refined).unwrap();
    let faces: Vec<&str> = written.lines().filter(|l| l.starts_with("f ")).collect();
    assert_eq!(
        faces.iter().filter(|f| f.contains('/')).count(),
        4,
        "{written}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
