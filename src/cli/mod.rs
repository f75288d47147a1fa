//! The `surfkit` command line: one file per subcommand; argument parsing and printing only.

/// `print!` for the subcommands: through [`output::write_stdout`] (closed pipes end quietly,
/// other write errors are an error, never a panic).
macro_rules! print {
    ($($arg:tt)*) => { $crate::cli::output::write_stdout(format_args!($($arg)*)) };
}

/// `println!` for the subcommands, as [`print!`].
macro_rules! println {
    () => { $crate::cli::output::write_stdout(format_args!("\n")) };
    ($($arg:tt)*) => {
        $crate::cli::output::write_stdout(format_args!("{}\n", format_args!($($arg)*)))
    };
}

mod output;

mod convert;
mod demo;
mod eat;
mod eat_folder;
mod fair;
mod fill;
mod fit;
mod html_pages;
mod info;
mod limit;
mod paper;
mod repair;
mod sharp_args;
mod subdivide;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use crate::limits::MemoryBudget;

/// surfkit — the quality of surface models: topology checks, spline hole filling,
/// subdivision and fairing, cross-checked with OpenMesh, OpenSubdiv, MeshLab and CGAL.
#[derive(Parser, Debug)]
#[command(name = "surfkit", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Memory one command may plan to use (e.g. 512M, 12G): work that would need more is
    /// refused, or done at a coarser level where the command says so. Default: half of the
    /// machine's memory.
    #[arg(long, global = true, value_name = "SIZE", value_parser = MemoryBudget::parse)]
    max_memory: Option<MemoryBudget>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Counts, face arities, bounding box, and what OpenMesh's half-edge structure refused.
    Info(info::InfoArgs),
    /// Converts between OBJ, PLY (binary by default), OFF and STL (binary by default).
    Convert(convert::ConvertArgs),
    /// The Euler Accompanying Test: V, E, F, χ at test points, and every topological flaw.
    Eat(eat::EatArgs),
    /// Applies the fixes the EAT suggests, checks the result with the EAT again.
    Repair(repair::RepairArgs),
    /// Uniform Catmull–Clark refinement with OpenSubdiv (quads and refined UVs out).
    Subdivide(subdivide::SubdivideArgs),
    /// Limit-surface samples with mean curvature as quality (a curvature map for MeshLab).
    Limit(limit::LimitArgs),
    /// Fits a smoothing spline to scattered (u, v, x, y, z) data and fills its holes.
    Fill(fill::FillArgs),
    /// Fits a smoothing spline to scattered (u, v, x, y, z) data.
    Fit(fit::FitArgs),
    /// Reruns a table or example of the Kouibia–Pasadas papers next to the paper's values.
    Paper(paper::PaperArgs),
    /// Kiciak's shape optimization of a Catmull–Clark control mesh (mean curvature evened out).
    Fair(fair::FairArgs),
    /// Generates example meshes.
    #[command(subcommand)]
    Gen(Generate),
    /// Runs surfkit on its built-in example and writes the results to a folder.
    Demo(demo::DemoArgs),
}

#[derive(Subcommand, Debug)]
enum Generate {
    /// A junction of tubes like Kiciak's figures 9–11 (quads, genus 0, one loop per tube end).
    Tubes(fair::TubesArgs),
}

/// A number parsed from `text` and accepted by `ok`, else `text` and what it `must` be.
fn number_where(text: &str, ok: impl Fn(f64) -> bool, must: &str) -> Result<f64, String> {
    let x: f64 = text
        .parse()
        .map_err(|_| format!("{text:?} is not a number"))?;
    if ok(x) {
        Ok(x)
    } else {
        Err(format!("{text} must {must}"))
    }
}

/// clap parser of a number in (0, 1), e.g. a relative tolerance.
fn open_unit_interval(text: &str) -> Result<f64, String> {
    number_where(text, |x| x > 0.0 && x < 1.0, "lie strictly between 0 and 1")
}

/// clap parser of a number in [0, 1], e.g. a fraction of F.
fn closed_unit_interval(text: &str) -> Result<f64, String> {
    number_where(text, |x| (0.0..=1.0).contains(&x), "lie between 0 and 1")
}

/// clap parser of a finite number ≥ 0, e.g. a distance. An infinite weld tolerance would
/// make every vertex coincident with every other (a repair would weld the mesh away).
fn non_negative_finite(text: &str) -> Result<f64, String> {
    number_where(
        text,
        |x| x >= 0.0 && x.is_finite(),
        "be a finite number ≥ 0",
    )
}

/// clap parser of a positive finite number.
fn positive_finite(text: &str) -> Result<f64, String> {
    number_where(text, |x| x > 0.0 && x.is_finite(), "be positive and finite")
}

/// Runs the command line; errors are printed as one line naming the file and the problem.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    // Library calls without an explicit budget (uniform refinement, …) use it too.
    crate::limits::set_process_budget(cli.max_memory);
    let budget = cli.max_memory.unwrap_or_default();
    let result = match &cli.command {
        Command::Info(a) => info::run(a),
        Command::Convert(a) => convert::run(a),
        Command::Demo(a) => demo::run(a),
        Command::Eat(a) => eat::run(a),
        Command::Repair(a) => repair::run(a),
        Command::Subdivide(a) => subdivide::run(a).map(|()| ExitCode::SUCCESS),
        Command::Limit(a) => limit::run(a, budget).map(|()| ExitCode::SUCCESS),
        Command::Fill(a) => fill::run(a).map(|()| ExitCode::SUCCESS),
        Command::Fit(a) => fit::run(a).map(|()| ExitCode::SUCCESS),
        Command::Paper(a) => paper::run(a).map(|()| ExitCode::SUCCESS),
        Command::Fair(a) => fair::run(a, budget),
        Command::Gen(Generate::Tubes(a)) => fair::run_tubes(a).map(|()| ExitCode::SUCCESS),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            match (names_a_file(&e), cli.command.input()) {
                (false, Some(input)) => eprintln!("surfkit: error: {}: {e}", input.display()),
                _ => eprintln!("surfkit: error: {e}"),
            }
            exit_code(&e)
        }
    }
}

/// 3 when the command ran but its numerical goal cannot be met with these data (a solver
/// that did not converge, conditions that contradict each other or the data, a shape
/// condition violated beyond its tolerance) — as `eat`'s failed test; 1 for every other
/// error (bad input, I/O, an ill-posed system, limits).
fn exit_code(e: &crate::Error) -> ExitCode {
    use crate::error::SolverFailure;
    match e {
        crate::Error::Solver {
            failure: SolverFailure::NotConverged | SolverFailure::Infeasible,
            ..
        } => ExitCode::from(eat::TEST_FAILED),
        _ => ExitCode::FAILURE,
    }
}

/// Whether an error's message starts with the file it is about.
pub(super) fn names_a_file(e: &crate::Error) -> bool {
    use crate::Error as E;
    matches!(e, E::Io { .. } | E::Parse { .. } | E::UnknownFormat { .. })
}

impl Command {
    /// The input file of the command, which its errors are about unless they name another.
    fn input(&self) -> Option<&Path> {
        Some(match self {
            Command::Info(a) => &a.mesh,
            Command::Convert(a) => &a.input,
            Command::Eat(a) if a.many() => return None,
            Command::Eat(a) => &a.meshes[0],
            Command::Repair(a) => &a.input,
            Command::Subdivide(a) => &a.input,
            Command::Limit(a) => &a.input,
            Command::Fill(a) => &a.spline.input,
            Command::Fit(a) => &a.spline.input,
            Command::Fair(a) => &a.input,
            Command::Paper(_) | Command::Gen(_) | Command::Demo(_) => return None,
        })
    }
}

/// Checks, before any work, that a folder option (`--figures`, `demo --out`) names a folder
/// or one that can be created, not a file: a missing folder is created and removed again
/// (with any missing parents), so one the system refuses (`/proc/x`, `a_file/x`) is refused
/// here and a command that fails later leaves nothing behind.
///
/// # Errors
/// [`crate::Error::InvalidInput`] naming the option and the path.
fn check_folder(option: &str, path: Option<&Path>) -> crate::Result<()> {
    let Some(path) = path else {
        return Ok(());
    };
    let refuse = |why: String| {
        Err(crate::Error::InvalidInput(format!(
            "{option} {}: {why}",
            path.display()
        )))
    };
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Ok(()),
        Ok(_) => refuse("is a file; give a folder (it is created if missing)".into()),
        Err(_) => {
            // Deepest first, so that each is empty when it is removed.
            let missing: Vec<&Path> = path
                .ancestors()
                .take_while(|a| !a.as_os_str().is_empty() && a.symlink_metadata().is_err())
                .collect();
            let created = std::fs::create_dir_all(path);
            for folder in &missing {
                let _ = std::fs::remove_dir(folder);
            }
            created.or_else(|e| refuse(format!("cannot create this folder: {e}")))
        }
    }
}

/// An output of a command for [`check_paths`]: the option that names it (or what it is, for
/// a positional argument or an implied path) and the path, when the command writes it.
type Output<'a> = (&'a str, Option<&'a Path>);

/// Checks a command's paths before any work: every output's folder exists, no output names
/// an input (after resolving symlinks and `..`: surfkit never writes over its input), and
/// no two outputs name the same file. `outputs` lists every file the command will write,
/// implied ones too (`limit`'s default picture), each with the option that names it.
///
/// # Errors
/// [`crate::Error::InvalidInput`] naming the option, the path and the problem.
fn check_paths(inputs: &[Option<&Path>], outputs: &[Output<'_>]) -> crate::Result<()> {
    let bad = |m: String| Err(crate::Error::InvalidInput(m));
    let inputs: Vec<(&Path, Option<PathBuf>)> = inputs
        .iter()
        .flatten()
        .map(|p| (*p, p.canonicalize().ok()))
        .collect();
    let mut seen: Vec<(&str, &Path, PathBuf)> = Vec::new();
    for &(option, output) in outputs {
        let Some(output) = output else {
            continue;
        };
        let resolved = match output.canonicalize() {
            Ok(p) => p,
            Err(_) => {
                let folder = match output.parent() {
                    Some(f) if !f.as_os_str().is_empty() => f,
                    _ => Path::new("."),
                };
                let Ok(folder) = folder.canonicalize() else {
                    return bad(format!(
                        "{option} {}: the folder {} does not exist",
                        output.display(),
                        folder.display()
                    ));
                };
                folder.join(output.file_name().unwrap_or_default())
            }
        };
        if let Some((input, _)) = inputs.iter().find(|(_, i)| i.as_ref() == Some(&resolved)) {
            return bad(format!(
                "{option} {}: refusing to write over the input file {}",
                output.display(),
                input.display()
            ));
        }
        if let Some((other_option, other, _)) = seen.iter().find(|(_, _, r)| *r == resolved) {
            return bad(format!(
                "{other_option} {} and {option} {} name the same file: each output needs its \
                 own path",
                other.display(),
                output.display()
            ));
        }
        seen.push((option, output, resolved));
    }
    Ok(())
}

/// Prints a report as pretty JSON on standard output.
fn print_json<T: serde::Serialize>(report: &T) -> crate::Result<()> {
    let text = serde_json::to_string_pretty(report).map_err(|e| {
        crate::Error::InvalidInput(format!("report cannot be written as JSON: {e}"))
    })?;
    println!("{text}");
    Ok(())
}
