//! `surfkit eat DIR --jsonl`: a whole folder scanned in parallel gives, file by file, what
//! `surfkit eat FILE --json` gives; a file that cannot be read is a line with its error
//! and the others are kept; the exit status says whether every file passed.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

fn surfkit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_surfkit"))
}

/// The fixture meshes, a copy in a sub-folder with an upper-case extension, and a file of
/// garbage named .obj.
fn corpus(dir: &Path) -> usize {
    let sub = dir.join("sub");
    std::fs::create_dir(&sub).unwrap();
    let mut count = 0;
    for (path, _) in crate::common::reference_meshes() {
        std::fs::copy(&path, dir.join(path.file_name().unwrap())).unwrap();
        count += 1;
    }
    std::fs::copy(
        crate::common::meshes_dir().join("spot.obj"),
        sub.join("SPOT.OBJ"),
    )
    .unwrap();
    std::fs::write(sub.join("bad.obj"), "garbage\n").unwrap();
    std::fs::write(sub.join("notes.txt"), "not a mesh\n").unwrap();
    count + 2
}

fn lines(stdout: &[u8]) -> Vec<serde_json::Value> {
    String::from_utf8_lossy(stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

#[test]
fn a_folder_gives_per_file_what_single_scans_give() {
    let dir = tempfile::tempdir().unwrap();
    let files = corpus(dir.path());
    let mut by_jobs = Vec::new();
    for jobs in ["1", "2"] {
        let out = surfkit()
            .args(["eat", "--jsonl", "--jobs", jobs])
            .arg(dir.path())
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1), "one file could not be read");
        let all = lines(&out.stdout);
        assert_eq!(
            all.len(),
            files + 1,
            "one line per mesh file, then the summary"
        );
        let summary = &all.last().unwrap()["summary"];
        assert_eq!(summary["files"], files as u64);
        assert_eq!(summary["errors"], 1);
        let mut results = BTreeMap::new();
        for line in &all[..files] {
            let file = line["file"].as_str().unwrap().to_string();
            if file.ends_with("bad.obj") {
                let e = line["error"].as_str().unwrap();
                assert!(e.contains("bad.obj") && e.contains("line 1"), "{e}");
                continue;
            }
            let single = surfkit().args(["eat", "--json", &file]).output().unwrap();
            let single: serde_json::Value = serde_json::from_slice(&single.stdout).unwrap();
            assert_eq!(line["counts"], single["report"]["counts"], "{file}");
            assert_eq!(line["statistics"], single["report"]["statistics"], "{file}");
            let kinds: usize = line["flaw_counts"]
                .as_object()
                .unwrap()
                .values()
                .map(|n| n.as_u64().unwrap() as usize)
                .sum();
            assert_eq!(kinds, single["report"]["flaws"].as_array().unwrap().len());
            results.insert(file, line["counts"].clone());
        }
        by_jobs.push(results);
    }
    assert_eq!(
        by_jobs[0], by_jobs[1],
        "the same results with 1 and 2 workers"
    );
}

#[test]
fn exit_status_says_whether_every_file_passed() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a.obj"), dir.path().join("b.obj"));
    std::fs::copy(crate::common::meshes_dir().join("spot.obj"), &a).unwrap();
    std::fs::copy(crate::common::meshes_dir().join("target.obj"), &b).unwrap();
    let status = |extra: &[&str]| {
        surfkit()
            .arg("eat")
            .args([&a, &b])
            .args(extra)
            .output()
            .unwrap()
            .status
            .code()
    };
    assert_eq!(status(&[]), Some(0));
    assert_eq!(
        status(&["--fail-on", "hole"]),
        Some(3),
        "target.obj has holes"
    );
    assert_eq!(
        status(&["--target", "genus=0"]),
        Some(3),
        "χ of target.obj is -4"
    );
    let out = surfkit()
        .arg("eat")
        .args([&a, &b])
        .args(["--mark", "m.ply"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--mark"));
}

#[test]
fn a_folder_without_mesh_files_is_an_error_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let empty = dir.path().join("empty");
    let only_notes = dir.path().join("notes");
    std::fs::create_dir(&empty).unwrap();
    std::fs::create_dir_all(only_notes.join("sub")).unwrap();
    std::fs::write(only_notes.join("readme.txt"), "not a mesh\n").unwrap();
    std::fs::write(only_notes.join("sub").join("mesh.obj.bak"), "v 0 0 0\n").unwrap();
    let spot = dir.path().join("spot.obj");
    std::fs::copy(crate::common::meshes_dir().join("spot.obj"), &spot).unwrap();
    for (args, folder) in [
        (vec![empty.as_path()], &empty),
        (vec![only_notes.as_path()], &only_notes),
        // With a good file beside it: the empty folder is still an error, and nothing is
        // scanned (no line for spot.obj).
        (vec![spot.as_path(), empty.as_path()], &empty),
    ] {
        for jsonl in [false, true] {
            let out = surfkit()
                .arg("eat")
                .args(&args)
                .args(if jsonl { &["--jsonl"][..] } else { &[][..] })
                .output()
                .unwrap();
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(1), "{args:?} jsonl {jsonl}: {err}");
            assert!(
                err.contains(&folder.display().to_string())
                    && err.contains("no mesh file")
                    && err.contains(".obj, .ply, .off or .stl"),
                "{err}"
            );
            assert!(out.stdout.is_empty(), "nothing scanned");
        }
    }
}
