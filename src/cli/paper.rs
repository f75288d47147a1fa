//! `surfkit paper <name>`: reruns a table or example of the Kouibia–Pasadas papers and
//! prints ours next to the paper's (human table, or `--json`).

use crate::fit::fill::FillVariant;
use crate::fit::papers::{kp2004, kp2022, kpo2024};
use crate::report::write_figures;

/// Which reproduction to run.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum PaperName {
    /// 2022, Table 1: biquadratic offset approximation and hole filling.
    #[value(name = "kp2022-table1")]
    Kp2022Table1,
    /// 2024, Table 1 (first block): BFS C¹ offset approximation.
    #[value(name = "kpo2024-table1")]
    Kpo2024Table1,
    /// 2004, example 1: parallelism conditions, τ sweep.
    #[value(name = "kp2004-example1")]
    Kp2004Example1,
    /// 2004, example 2.
    #[value(name = "kp2004-example2")]
    Kp2004Example2,
}

/// The hole-filling variant of the 2022 table.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum VariantArg {
    /// The paper's σ₂ with the constraints of (14).
    Paper,
    /// σ kept in V_h exactly (C¹ across ∂H_h).
    ExactC1,
}

/// Arguments of `surfkit paper`.
#[derive(clap::Args, Debug, Clone)]
pub struct PaperArgs {
    /// The table or example to reproduce.
    #[arg(value_enum)]
    pub name: PaperName,
    /// Random point sets per row (the papers' points are unknown).
    #[arg(long, default_value_t = 10)]
    pub seeds: usize,
    /// Hole-filling variant (kp2022-table1).
    #[arg(long, value_enum, default_value = "paper")]
    pub variant: VariantArg,
    /// Folder for the figures (PLY with the error as quality, and PNG pictures).
    #[arg(long, default_value = "surfkit-figures")]
    pub figures: std::path::PathBuf,
    /// Print one JSON object per row instead of a table.
    #[arg(long)]
    pub json: bool,
}

fn json<T: serde::Serialize>(rows: &[T]) -> crate::Result<()> {
    for r in rows {
        let s = serde_json::to_string(r)
            .map_err(|e| crate::Error::InvalidInput(format!("JSON: {e}")))?;
        println!("{s}");
    }
    Ok(())
}

/// Runs the reproduction and prints it.
///
/// Errors: a `--figures` that is a file or cannot be created (before any work), those of
/// the reproduction functions (invalid seeds, solver failures).
pub fn run(args: &PaperArgs) -> crate::Result<()> {
    super::check_folder("--figures", Some(&args.figures))?;
    match args.name {
        PaperName::Kp2022Table1 => {
            let variant = match args.variant {
                VariantArg::Paper => FillVariant::Paper,
                VariantArg::ExactC1 => FillVariant::ExactC1,
            };
            let rows = kp2022::table1(args.seeds, variant)?;
            let written = write_figures(&args.figures, &kp2022::figure_meshes(0)?)?;
            if args.json {
                return json(&rows);
            }
            println!(
                "Kouibia & Pasadas 2022, Table 1 — {} seeds, variant {:?}",
                args.seeds, args.variant
            );
            println!("n=m     k       ε |   Error₁ median [min, max]        paper |    Error median [min, max]         paper | C⁰ jump  C¹ jump");
            for r in &rows {
                println!(
                    "{:>3} {:>5} {:>7.0e} | {:.3e} [{:.3e}, {:.3e}] {:.4e} | {:.3e} [{:.3e}, {:.3e}] {:.4e} | {:.1e}  {:.1e}",
                    r.knots_per_side, r.points, r.epsilon, r.error1.median, r.error1.min, r.error1.max, r.paper_error1,
                    r.error.median, r.error.min, r.error.max, r.paper_error, r.max_c0_jump, r.max_c1_jump
                );
            }
            println!("figures (the text example: 9 knots, 500 points, ε = 1e-9, seed 0):");
            for path in written {
                println!("  {}", path.display());
            }
        }
        PaperName::Kpo2024Table1 => {
            let rows = kpo2024::table1(args.seeds)?;
            if args.json {
                return json(&rows);
            }
            println!(
                "Kouibia, Pasadas & Omri 2024, Table 1 (first block) — {} seeds",
                args.seeds
            );
            println!("    M       ε |    E_r median [min, max]         paper");
            for r in &rows {
                println!(
                    "{:>5} {:>7.0e} | {:.3e} [{:.3e}, {:.3e}] {:.4e}",
                    r.points, r.epsilon, r.error.median, r.error.min, r.error.max, r.paper_error
                );
            }
            let fill = kpo2024::fill_run(1500, 1e-9, 0, 3, true)?;
            println!(
                "shape-preserving filling (§4–5), M = 1500, ε = 1e-9, seed 0: {} inequalities (positive, increasing in u and v), \
                 worst violation {:.1e}, {} of {} check points in H violating, σ₁ E_r {:.3e}, filled surface E_r {:.3e}",
                fill.inequalities, fill.max_violation, fill.lattice_violations, fill.lattice_points, fill.error1, fill.error
            );
            println!("figures:");
            for path in write_figures(&args.figures, &fill.figures)? {
                println!("  {}", path.display());
            }
        }
        PaperName::Kp2004Example1 | PaperName::Kp2004Example2 => {
            let which = if args.name == PaperName::Kp2004Example1 {
                1
            } else {
                2
            };
            let rows = kp2004::sweep(which, &[0.0, 0.1, 1.0, kp2004::TAU, 100.0])?;
            let figures = kp2004::Kp2004Problem::new(which)?
                .figures(kp2004::TAU, kp2004::FIGURE_RESOLUTION)?;
            let written = write_figures(&args.figures, &figures)?;
            if args.json {
                return json(&rows);
            }
            println!(
                "Kouibia & Pasadas 2004, example {which} — m = 3, ε = 1e-7, BFS C² on 6 × 6 cells"
            );
            println!("      τ   dim V_h     Π(s,s)/|B|   Σ‖s(a) − p_a‖²");
            for r in &rows {
                println!(
                    "{:>7} {:>9} {:>14.4e} {:>16.4e}",
                    r.tau, r.system_dimension, r.pi_per_point, r.data_misfit
                );
            }
            println!(
                "figures (x₀, the fit at τ = 0 and at τ = {}; quality: the local parallelism defect):",
                kp2004::TAU
            );
            for path in written {
                println!("  {}", path.display());
            }
        }
    }
    Ok(())
}
