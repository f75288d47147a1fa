//! `surfkit fit`: fits a smoothing spline (2022 (8)) to scattered (u, v, x, y, z) data
//! from a CSV or a mesh, without filling holes; writes a sampled mesh (fit error as
//! per-vertex quality), the coefficients (JSON) and a report. `surfkit fill` adds holes.

use std::path::PathBuf;

use crate::fit::fill::FillVariant;
use crate::fit::pipeline::{FitSetup, HoleSource, SpaceKind};
use crate::{Error, Result};

/// The spline space.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum FitSpaceArg {
    /// Biquadratic C¹ B-splines (2022).
    Biquadratic,
    /// Bicubic C² B-splines.
    Bicubic,
    /// Bogner–Fox–Schmit C¹ (2024).
    BfsC1,
}

/// Arguments of `surfkit fit`.
#[derive(clap::Args, Debug, Clone)]
pub struct FitArgs {
    /// CSV with lines u,v,x,y,z, or a mesh (.ply/.obj/.off; UVs as (u, v), else a height field).
    pub input: PathBuf,
    /// The spline space.
    #[arg(long, value_enum, default_value = "biquadratic")]
    pub space: FitSpaceArg,
    /// Cells along u and v, as NU,NV.
    #[arg(long, default_value = "8,8")]
    pub cells: String,
    /// The smoothing parameter ε > 0.
    #[arg(long, default_value_t = 1e-9)]
    pub epsilon: f64,
    /// Fit the generalized offset f + d₁e₁ + d₂e₂ + d₃n instead: `d1;d2;d3` in u and v.
    #[arg(long)]
    pub offset: Option<String>,
    /// Sampled mesh to write (.ply, .obj or .off).
    #[arg(long)]
    pub output: Option<PathBuf>,
    /// Coefficients to write (.json).
    #[arg(long)]
    pub coefficients: Option<PathBuf>,
    /// Samples per side of the mesh.
    #[arg(long, default_value_t = 64)]
    pub resolution: usize,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Runs the fit and writes the outputs.
///
/// Errors: unreadable or malformed input (named by file and line), bad arguments,
/// ill-posed problems (too few or collinear points, ε ≤ 0), write failures.
pub fn run(args: &FitArgs) -> Result<()> {
    let cells: Vec<usize> = args
        .cells
        .split(',')
        .map(|t| t.trim().parse::<usize>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| Error::InvalidInput(format!("--cells {:?}: expected NU,NV", args.cells)))?;
    if cells.len() != 2 {
        return Err(Error::InvalidInput(format!(
            "--cells {:?}: expected NU,NV",
            args.cells
        )));
    }
    let setup = FitSetup {
        space: match args.space {
            FitSpaceArg::Biquadratic => SpaceKind::Biquadratic,
            FitSpaceArg::Bicubic => SpaceKind::Bicubic,
            FitSpaceArg::BfsC1 => SpaceKind::BfsC1,
        },
        cells: [cells[0], cells[1]],
        epsilon: args.epsilon,
        hole: HoleSource::None,
        variant: FillVariant::Paper,
    };
    let out = super::fill::load_and_solve(
        &args.input,
        args.offset.as_deref(),
        &setup,
        args.output.as_deref(),
        args.coefficients.as_deref(),
        args.resolution,
    )?;
    let s = &out.summary;
    if args.json {
        let text =
            serde_json::to_string(s).map_err(|e| Error::InvalidInput(format!("JSON: {e}")))?;
        println!("{text}");
        return Ok(());
    }
    println!(
        "{}: {} points, {:?} on {}×{} cells, ε = {:e}; misfit rms {:.3e}, max {:.3e}",
        args.input.display(),
        s.points,
        s.space,
        s.cells[0],
        s.cells[1],
        s.epsilon,
        s.rms_misfit,
        s.max_misfit
    );
    for p in args.output.iter().chain(&args.coefficients) {
        println!("  wrote {}", p.display());
    }
    Ok(())
}
