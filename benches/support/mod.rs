//! What the benches share: timing by median of repeats, the generated-data folder, and the
//! Python peers (trimesh, pymeshlab) run in the same run from the .venv `scripts/setup.sh` makes.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

/// The repository's root (the benches of workspace members include this module too).
pub fn repo_root() -> PathBuf {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    if manifest.join("benches/peers").exists() {
        manifest.to_path_buf()
    } else {
        manifest.parent().unwrap().to_path_buf()
    }
}

/// Folder for generated inputs (kept between runs).
pub fn data_dir() -> PathBuf {
    let dir = repo_root().join("target/bench-data");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Median wall time of `repeats` runs of `f`, after one warm-up run.
pub fn median_seconds(repeats: usize, mut f: impl FnMut()) -> f64 {
    f();
    let mut t: Vec<Duration> = (0..repeats.max(1))
        .map(|_| {
            let t0 = Instant::now();
            f();
            t0.elapsed()
        })
        .collect();
    t.sort();
    t[t.len() / 2].as_secs_f64()
}

/// Runs `benches/peers/<script>` with the venv's Python and parses its one JSON line.
pub fn python_peer(script: &str, args: &[String]) -> Result<serde_json::Value, String> {
    let root = repo_root();
    let python = std::env::var("SURFKIT_PYTHON")
        .unwrap_or_else(|_| root.join(".venv/bin/python").display().to_string());
    let out = Command::new(&python)
        .arg(root.join("benches/peers").join(script))
        .args(args)
        .output()
        .map_err(|e| format!("{python}: {e} (run scripts/setup.sh)"))?;
    if !out.status.success() {
        return Err(String::from_utf8_lossy(&out.stderr)
            .lines()
            .last()
            .unwrap_or("")
            .to_string());
    }
    serde_json::from_slice(&out.stdout).map_err(|e| e.to_string())
}
