//! The `surfkit` command line: one file per subcommand; argument parsing and printing only.

mod convert;
mod demo;
mod eat;
mod fair;
mod fill;
mod fit;
mod info;
mod limit;
mod paper;
mod subdivide;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// surfkit — the quality of surface models: topology checks, spline hole filling,
/// subdivision and fairing, cross-checked with OpenMesh, OpenSubdiv, MeshLab and CGAL.
#[derive(Parser, Debug)]
#[command(name = "surfkit", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Counts, face arities, bounding box, and what OpenMesh's half-edge structure refused.
    Info(info::InfoArgs),
    /// Converts between OBJ, PLY (binary by default) and OFF.
    Convert(convert::ConvertArgs),
    /// The Euler Accompanying Test: V, E, F, χ at test points, and every topological flaw.
    Eat(eat::EatArgs),
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

/// Runs the command line; errors are printed as one line naming the file and the problem.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Info(a) => info::run(a),
        Command::Convert(a) => convert::run(a),
        Command::Demo(a) => demo::run(a),
        Command::Eat(a) => eat::run(a),
        Command::Subdivide(a) => subdivide::run(a).map(|()| ExitCode::SUCCESS),
        Command::Limit(a) => limit::run(a).map(|()| ExitCode::SUCCESS),
        Command::Fill(a) => fill::run(a).map(|()| ExitCode::SUCCESS),
        Command::Fit(a) => fit::run(a).map(|()| ExitCode::SUCCESS),
        Command::Paper(a) => paper::run(a).map(|()| ExitCode::SUCCESS),
        Command::Fair(a) => fair::run(a).map(|()| ExitCode::SUCCESS),
        Command::Gen(Generate::Tubes(a)) => fair::run_tubes(a).map(|()| ExitCode::SUCCESS),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("surfkit: error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// An error when `output` names the same file as `input`: surfkit never writes over its input.
fn refuse_overwrite(input: &std::path::Path, output: &std::path::Path) -> crate::Result<()> {
    match (input.canonicalize(), output.canonicalize()) {
        (Ok(a), Ok(b)) if a == b => Err(crate::Error::InvalidInput(format!(
            "{}: refusing to write over the input file",
            output.display()
        ))),
        _ => Ok(()),
    }
}

/// Prints a report as pretty JSON on standard output.
fn print_json<T: serde::Serialize>(report: &T) -> crate::Result<()> {
    let text = serde_json::to_string_pretty(report).map_err(|e| {
        crate::Error::InvalidInput(format!("report cannot be written as JSON: {e}"))
    })?;
    println!("{text}");
    Ok(())
}
