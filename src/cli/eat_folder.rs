//! `surfkit eat FILE... | DIR [--jsonl] [--jobs N]`: the EAT over a whole data set. Files are
//! scanned in parallel (rayon, one file per worker) and reported as each finishes — a JSON
//! object per line with `--jsonl`, a one-line summary otherwise — then a summary of all.
//! A file that cannot be read (or that would crash a reader) is a line with its error;
//! the others are kept.
//!
//! Exit status: 0 when every file was scanned and verified, 3 when some file failed its
//! test points or has a `--fail-on` flaw, 1 when some file could not be scanned or a folder
//! holds no mesh file (then nothing is scanned).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use rayon::prelude::*;

use super::eat::{expected_chis, fail_kinds, scan_file, EatArgs, TEST_FAILED};
use crate::error::{Error, Result};
use crate::topology::{EatReport, FlawKind};

/// The mesh files named on the command line: files as given, folders searched
/// recursively for .obj, .ply, .off and .stl (in path order). A folder that holds none is an
/// error: there is nothing in it to check, and a pipeline must not read that as a pass.
fn mesh_files(inputs: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for input in inputs {
        if !input.is_dir() {
            files.push(input.clone());
            continue;
        }
        let mut found = Vec::new();
        for entry in walkdir::WalkDir::new(input).follow_links(true) {
            let entry = entry.map_err(|e| Error::Io {
                path: e.path().unwrap_or(input).to_path_buf(),
                source: e
                    .into_io_error()
                    .unwrap_or_else(|| std::io::Error::other("a folder loop")),
            })?;
            let is_mesh = entry.path().extension().is_some_and(|x| {
                let x = x.to_string_lossy().to_ascii_lowercase();
                x == "obj" || x == "ply" || x == "off" || x == "stl"
            });
            if entry.file_type().is_file() && is_mesh {
                found.push(entry.into_path());
            }
        }
        if found.is_empty() {
            return Err(Error::InvalidInput(format!(
                "{}: no mesh file to check: the folder and its subfolders hold no .obj, .ply, \
                 .off or .stl file (extensions in any case)",
                input.display()
            )));
        }
        found.sort();
        files.extend(found);
    }
    Ok(files)
}

/// What became of one file.
struct Outcome {
    path: PathBuf,
    seconds: f64,
    result: std::result::Result<(EatReport, Vec<FlawKind>), String>,
}

/// Scans one file; any error (or a panic, which would be a bug) becomes its message.
fn scan_one(path: &Path, args: &EatArgs, expected: &[i64], fail_on: &[FlawKind]) -> Outcome {
    let start = Instant::now();
    let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        scan_file(path, args, expected, fail_on)
    }));
    let result = match run {
        Ok(Ok((_, report, failing))) => Ok((report, failing)),
        Ok(Err(e)) if super::names_a_file(&e) => Err(e.to_string()),
        Ok(Err(e)) => Err(format!("{}: {e}", path.display())),
        Err(_) => Err(format!(
            "{}: internal error while scanning (please report it with this file)",
            path.display()
        )),
    };
    Outcome {
        path: path.to_path_buf(),
        seconds: start.elapsed().as_secs_f64(),
        result,
    }
}

fn flaw_counts(report: &EatReport) -> BTreeMap<&'static str, usize> {
    report
        .flaw_counts()
        .into_iter()
        .map(|(k, n)| (k.name(), n))
        .collect()
}

/// The JSON line of one file: counts, flaw counts and the first `show` flaws (or the error).
#[derive(serde::Serialize)]
struct FileLine<'a> {
    file: &'a Path,
    #[serde(skip_serializing_if = "Option::is_none")]
    error: Option<&'a str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    verified: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    failing_flaw_kinds: Option<&'a [FlawKind]>,
    seconds: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    statistics: Option<&'a crate::topology::EatStatistics>,
    #[serde(skip_serializing_if = "Option::is_none")]
    counts: Option<&'a crate::topology::TopologyCounts>,
    #[serde(skip_serializing_if = "Option::is_none")]
    flaw_counts: Option<BTreeMap<&'static str, usize>>,
    /// The first `--show` flaws (all are counted in `flaw_counts`).
    #[serde(skip_serializing_if = "Option::is_none")]
    flaws: Option<&'a [crate::topology::Flaw]>,
}

fn json_line(o: &Outcome, show: usize) -> String {
    let line = match &o.result {
        Ok((report, failing)) => FileLine {
            file: &o.path,
            error: None,
            verified: Some(report.verified() && failing.is_empty()),
            failing_flaw_kinds: Some(failing),
            seconds: o.seconds,
            statistics: Some(&report.statistics),
            counts: Some(&report.counts),
            flaw_counts: Some(flaw_counts(report)),
            flaws: Some(&report.flaws[..report.flaws.len().min(show)]),
        },
        Err(message) => FileLine {
            file: &o.path,
            error: Some(message),
            verified: None,
            failing_flaw_kinds: None,
            seconds: o.seconds,
            statistics: None,
            counts: None,
            flaw_counts: None,
            flaws: None,
        },
    };
    // Every field is plain data: serialization cannot fail.
    serde_json::to_string(&line).unwrap_or_default()
}

/// The human line of one file.
fn text_line(o: &Outcome) -> String {
    match &o.result {
        Ok((report, failing)) => {
            let s = &report.statistics;
            let flaws: Vec<String> = flaw_counts(report)
                .iter()
                .map(|(k, n)| format!("{n} {k}"))
                .collect();
            let status = if !report.verified() || !failing.is_empty() {
                "FAILED"
            } else if report.flaws.is_empty() {
                "ok"
            } else {
                "flaws"
            };
            format!(
                "{status:6} {}: V {} E {} F {} χ {}; {}",
                o.path.display(),
                s.vertices,
                s.edges,
                s.facets,
                s.euler_characteristic,
                if flaws.is_empty() {
                    "no flaws".to_string()
                } else {
                    flaws.join(", ")
                }
            )
        }
        Err(message) => format!("error  {message}"),
    }
}

/// Running totals for the summary line.
#[derive(Default)]
struct Totals {
    files: usize,
    verified: usize,
    failed: usize,
    errors: usize,
    flaw_counts: BTreeMap<&'static str, usize>,
}

impl Totals {
    fn add(&mut self, o: &Outcome) {
        self.files += 1;
        match &o.result {
            Ok((report, failing)) => {
                if report.verified() && failing.is_empty() {
                    self.verified += 1;
                } else {
                    self.failed += 1;
                }
                for (k, n) in flaw_counts(report) {
                    *self.flaw_counts.entry(k).or_insert(0) += n;
                }
            }
            Err(_) => self.errors += 1,
        }
    }
}

pub fn run(args: &EatArgs) -> Result<ExitCode> {
    if args.mark.is_some() {
        return Err(Error::InvalidInput(
            "--mark writes one marked mesh: give a single mesh file (not several, a folder or --jsonl)".into(),
        ));
    }
    if args.json {
        return Err(Error::InvalidInput(
            "--json prints one report: for several files or a folder use --jsonl".into(),
        ));
    }
    let fail_on = fail_kinds(&args.fail_on)?;
    let expected = expected_chis(args)?;
    let files = mesh_files(&args.meshes)?;
    let jobs = args.jobs.unwrap_or_else(rayon::current_num_threads);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .map_err(|e| Error::InvalidInput(format!("--jobs {jobs}: no thread pool: {e}")))?;
    let start = Instant::now();
    let mut totals = Totals::default();
    let (sender, receiver) = std::sync::mpsc::channel::<Outcome>();
    std::thread::scope(|scope| {
        let (files, args, expected, fail_on) = (&files, args, &expected, &fail_on);
        scope.spawn(move || {
            pool.install(|| {
                files.par_iter().for_each_with(sender, |sender, path| {
                    // The receiver only goes away when printing failed and the process ends.
                    let _ = sender.send(scan_one(path, args, expected, fail_on));
                });
            });
        });
        for outcome in receiver {
            totals.add(&outcome);
            if args.jsonl {
                println!("{}", json_line(&outcome, args.show));
            } else {
                println!("{}", text_line(&outcome));
            }
        }
    });
    let seconds = start.elapsed().as_secs_f64();
    if args.jsonl {
        println!(
            "{}",
            serde_json::json!({ "summary": {
                "files": totals.files,
                "passed": totals.verified,
                "failed": totals.failed,
                "errors": totals.errors,
                "flaw_counts": totals.flaw_counts,
                "seconds": seconds,
                "jobs": jobs,
            }})
        );
    } else {
        println!(
            "{} files in {seconds:.2} s ({jobs} at once): {} passed, {} failed, {} could not be scanned",
            totals.files, totals.verified, totals.failed, totals.errors
        );
    }
    Ok(if totals.errors > 0 {
        ExitCode::FAILURE
    } else if totals.failed > 0 {
        ExitCode::from(TEST_FAILED)
    } else {
        ExitCode::SUCCESS
    })
}
