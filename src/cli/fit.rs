//! `surfkit fit`: fits a smoothing spline (2022 (8)) to scattered (u, v, x, y, z) data
//! from a CSV or a mesh, without filling holes; writes a sampled mesh (fit error as
//! per-vertex quality), the coefficients (JSON) and a report. `surfkit fill` adds holes.

use crate::fit::fill::FillVariant;
use crate::fit::pipeline::HoleSource;
use crate::{Error, Result};

/// Arguments of `surfkit fit` (those of `fill` without a hole).
#[derive(clap::Args, Debug, Clone)]
pub struct FitArgs {
    #[command(flatten)]
    pub spline: super::fill::SplineArgs,
}

/// Runs the fit and writes the outputs.
///
/// Errors: unreadable or malformed input (named by file and line), bad arguments,
/// ill-posed problems (too few or collinear points, ε ≤ 0), write failures.
pub fn run(args: &FitArgs) -> Result<()> {
    let a = &args.spline;
    super::check_paths(
        &[Some(&a.input)],
        &[
            ("--output", a.output.as_deref()),
            ("--coefficients", a.coefficients.as_deref()),
            ("--html", a.html.as_deref()),
        ],
    )?;
    let setup = super::fill::setup(&args.spline, HoleSource::None, FillVariant::Paper)?;
    let out = super::fill::load_and_solve(&args.spline, &setup)?;
    let s = &out.summary;
    if args.spline.json {
        let text =
            serde_json::to_string(s).map_err(|e| Error::InvalidInput(format!("JSON: {e}")))?;
        println!("{text}");
        return Ok(());
    }
    println!(
        "{}: {} points, {:?} on {}×{} cells, ε = {:e}; misfit rms {:.3e}, max {:.3e}",
        args.spline.input.display(),
        s.points,
        s.space,
        s.cells[0],
        s.cells[1],
        s.epsilon,
        s.rms_misfit,
        s.max_misfit
    );
    for p in args
        .spline
        .output
        .iter()
        .chain(&args.spline.coefficients)
        .chain(&args.spline.html)
    {
        println!("  wrote {}", p.display());
    }
    Ok(())
}
