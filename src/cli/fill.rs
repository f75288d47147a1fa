//! `surfkit fill`: fits a smoothing spline to scattered (u, v, x, y, z) data from a CSV or a
//! mesh and
//! fills its holes (2022 §4); writes a sampled mesh (PLY/OBJ/OFF, fit error as per-vertex
//! quality), the coefficients (JSON) and a report. Without a hole it is `surfkit fit`.

use std::path::PathBuf;

use crate::fit::data::{from_mesh, read_csv, read_uv_points};
use crate::fit::expr::Expr;
use crate::fit::fill::FillVariant;
use crate::fit::hole::{Hole, HoleShape};
use crate::fit::pipeline::{fit_and_fill, offset_data, FitSetup, HoleSource, SpaceKind};
use crate::fit::shape::{ShapeConstraints, Tau};
use crate::report::html::{surface_page, write_html, HtmlPage, LegendEntry, Lines, Points};
use crate::{Error, Result};

/// The spline space.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpaceArg {
    /// Biquadratic C¹ B-splines (2022).
    Biquadratic,
    /// Bicubic C² B-splines.
    Bicubic,
    /// Bogner–Fox–Schmit C¹ (2024).
    BfsC1,
}

/// The arguments `fit` and `fill` share.
#[derive(clap::Args, Debug, Clone)]
pub struct SplineArgs {
    /// CSV with lines u,v,x,y,z (a header line is allowed), or a mesh (.ply/.obj/.off):
    /// with UVs, (u, v) are its texture coordinates; without, it is a height field (u, v) = (x, y).
    pub input: PathBuf,
    /// The spline space.
    #[arg(long, value_enum, default_value = "biquadratic")]
    pub space: SpaceArg,
    /// Cells along u and v, as NU,NV.
    #[arg(long, default_value = "8,8")]
    pub cells: String,
    /// The smoothing parameter ε > 0.
    #[arg(long, default_value_t = 1e-9)]
    pub epsilon: f64,
    /// Fit the generalized offset f + d₁e₁ + d₂e₂ + d₃n of the data's surface instead of the
    /// surface: `d1;d2;d3` as expressions in u and v (evalexpr syntax, e.g.
    /// `0.2*math::sin(u-v);0;-0.1`). The frame comes from a first fit of the data.
    #[arg(long)]
    pub offset: Option<String>,
    /// Sampled mesh to write (.ply, .obj or .off).
    #[arg(long)]
    pub output: Option<PathBuf>,
    /// Coefficients to write (.json).
    #[arg(long)]
    pub coefficients: Option<PathBuf>,
    /// Write a self-contained HTML report here: the spline surface coloured by the fit
    /// error (RMS misfit of each cell's data), the data points, and the hole's border.
    #[arg(long)]
    pub html: Option<PathBuf>,
    /// Samples per side of the mesh (1 to 4096: checked before any work).
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub resolution: u32,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `surfkit fill`.
#[derive(clap::Args, Debug, Clone)]
pub struct FillArgs {
    #[command(flatten)]
    pub spline: SplineArgs,
    /// A hole component: `ellipse:cx,cy,a,b,level` for a(u−cx)² + b(v−cy)² ≤ level, or
    /// `polygon:u1,v1,u2,v2,…`. Repeatable.
    #[arg(long)]
    pub hole: Vec<String>,
    /// Take the cells without data as the hole.
    #[arg(long)]
    pub hole_from_data: bool,
    /// Keep σ in the spline space exactly (C¹ across the hole's border) instead of the
    /// paper's boundary constraints.
    #[arg(long)]
    pub exact_c1: bool,
    /// Fill the hole preserving shape (2024 §4, needs `--space bfs-c1`): the condition
    /// τL(σ) ≥ 0 with L = σ, ∂σ/∂u or ∂σ/∂v and τ = +1 (positive, increasing) or −1
    /// (negative, decreasing), imposed on one component at the free nodes of the hole, a
    /// lattice in each hole cell and `--shape-points`. Repeatable, e.g. `--shape positive
    /// --shape increasing-u`.
    #[arg(long, value_enum)]
    pub shape: Vec<ShapeArg>,
    /// The component the shape conditions apply to [default: z].
    #[arg(long, value_enum)]
    pub shape_component: Option<ComponentArg>,
    /// Constraint points per side of the n × n lattice inside each hole cell [default: 3].
    #[arg(long)]
    pub shape_lattice: Option<usize>,
    /// A CSV of extra constraint points `u,v` (each inside the hole).
    #[arg(long)]
    pub shape_points: Option<PathBuf>,
}

/// A shape condition τL(σ) ≥ 0 of the 2024 paper's (10).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeArg {
    /// σ ≥ 0 (L = identity, τ = +1).
    Positive,
    /// σ ≤ 0 (τ = −1).
    Negative,
    /// ∂σ/∂u ≥ 0.
    IncreasingU,
    /// ∂σ/∂u ≤ 0.
    DecreasingU,
    /// ∂σ/∂v ≥ 0.
    IncreasingV,
    /// ∂σ/∂v ≤ 0.
    DecreasingV,
}

/// A component of σ = (x, y, z).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ComponentArg {
    X,
    Y,
    Z,
}

/// The shape conditions of the arguments, or `None` without `--shape`.
///
/// Errors: `InvalidInput` for contradicting conditions (positive and negative, increasing
/// and decreasing in the same variable), shape options without `--shape`, `--shape` with
/// `--offset` (the 2024 method constrains the base surface before the offset terms are
/// added, which `fill` does not do), and as [`read_uv_points`] for the points file.
fn shape_constraints(args: &FillArgs) -> Result<Option<ShapeConstraints>> {
    if args.shape.is_empty() {
        let stray = [
            (args.shape_component.is_some(), "--shape-component"),
            (args.shape_lattice.is_some(), "--shape-lattice"),
            (args.shape_points.is_some(), "--shape-points"),
        ];
        if let Some((_, name)) = stray.iter().find(|(given, _)| *given) {
            return Err(Error::InvalidInput(format!(
                "{name} needs at least one --shape condition (positive, increasing-u, …)"
            )));
        }
        return Ok(None);
    }
    if args.spline.offset.is_some() {
        return Err(Error::InvalidInput(
            "--shape with --offset is not supported: the 2024 method constrains the base \
             surface σ̄ = σ − offset terms, which `fill` does not separate yet"
                .into(),
        ));
    }
    let pick = |plus: ShapeArg, minus: ShapeArg, what: &str| -> Result<Option<Tau>> {
        match (args.shape.contains(&plus), args.shape.contains(&minus)) {
            (true, true) => {
                let name = |a: ShapeArg| {
                    clap::ValueEnum::to_possible_value(&a)
                        .map_or_else(|| format!("{a:?}"), |v| v.get_name().to_string())
                };
                Err(Error::InvalidInput(format!(
                    "--shape {} and {} contradict each other ({what})",
                    name(plus),
                    name(minus)
                )))
            }
            (true, false) => Ok(Some(Tau::Plus)),
            (false, true) => Ok(Some(Tau::Minus)),
            (false, false) => Ok(None),
        }
    };
    Ok(Some(ShapeConstraints {
        component: match args.shape_component.unwrap_or(ComponentArg::Z) {
            ComponentArg::X => 0,
            ComponentArg::Y => 1,
            ComponentArg::Z => 2,
        },
        value: pick(ShapeArg::Positive, ShapeArg::Negative, "the sign of σ")?,
        slope_x: pick(
            ShapeArg::IncreasingU,
            ShapeArg::DecreasingU,
            "monotonicity in u",
        )?,
        slope_y: pick(
            ShapeArg::IncreasingV,
            ShapeArg::DecreasingV,
            "monotonicity in v",
        )?,
        extra_per_side: args.shape_lattice.unwrap_or(3),
        extra_points: match &args.shape_points {
            Some(p) => read_uv_points(p)?,
            None => vec![],
        },
    }))
}

fn numbers(s: &str, what: &str) -> Result<Vec<f64>> {
    s.split(',')
        .map(|t| {
            t.trim()
                .parse::<f64>()
                .map_err(|_| Error::InvalidInput(format!("{what}: {t:?} is not a number")))
        })
        .collect()
}

fn hole_shape(spec: &str) -> Result<HoleShape> {
    const SHAPES: &str = "ellipse:cx,cy,a,b,level or polygon:u1,v1,u2,v2,u3,v3,…";
    let (kind, rest) = spec
        .split_once(':')
        .ok_or_else(|| Error::InvalidInput(format!("--hole {spec:?}: expected {SHAPES}")))?;
    if kind != "ellipse" && kind != "polygon" {
        return Err(Error::InvalidInput(format!(
            "--hole {spec:?}: unknown shape {kind:?}; expected {SHAPES}"
        )));
    }
    let v = numbers(rest, &format!("--hole {spec:?}"))?;
    match kind {
        "ellipse" if v.len() == 5 => Ok(HoleShape::Ellipse {
            center: [v[0], v[1]],
            coeffs: [v[2], v[3]],
            level: v[4],
        }),
        "ellipse" => Err(Error::InvalidInput(format!(
            "--hole {spec:?}: an ellipse takes 5 numbers (cx,cy,a,b,level), got {}",
            v.len()
        ))),
        _ if v.len() >= 6 && v.len() % 2 == 0 => Ok(HoleShape::Polygon(
            v.chunks(2).map(|c| [c[0], c[1]]).collect(),
        )),
        _ => Err(Error::InvalidInput(format!(
            "--hole {spec:?}: a polygon takes u,v pairs of at least 3 corners (an even count \
             ≥ 6 of numbers), got {}",
            v.len()
        ))),
    }
}

/// Runs the fit and fill and writes the outputs.
///
/// Errors: unreadable or malformed input (named by file and line), bad arguments,
/// ill-posed problems (too few points, a hole covering everything, ε ≤ 0), write failures.
pub fn run(args: &FillArgs) -> Result<()> {
    let a = &args.spline;
    super::check_paths(
        &[Some(&a.input), args.shape_points.as_deref()],
        &[
            ("--output", a.output.as_deref()),
            ("--coefficients", a.coefficients.as_deref()),
            ("--html", a.html.as_deref()),
        ],
    )?;
    let hole = if args.hole_from_data {
        HoleSource::CellsWithoutData
    } else if args.hole.is_empty() {
        HoleSource::None
    } else {
        HoleSource::Shapes(Hole {
            shapes: args
                .hole
                .iter()
                .map(|s| hole_shape(s))
                .collect::<Result<_>>()?,
        })
    };
    let variant = if args.exact_c1 {
        FillVariant::ExactC1
    } else {
        FillVariant::Paper
    };
    let mut setup = setup(&args.spline, hole, variant)?;
    setup.shape = shape_constraints(args)?;
    let out = load_and_solve(&args.spline, &setup)?;
    let s = &out.summary;
    if args.spline.json {
        println!(
            "{}",
            serde_json::to_string(s).map_err(|e| Error::InvalidInput(format!("JSON: {e}")))?
        );
        return Ok(());
    }
    println!(
        "{}: {} points, {:?} on {}×{} cells of [{:.4}, {:.4}]×[{:.4}, {:.4}], ε = {:e}",
        args.spline.input.display(),
        s.points,
        s.space,
        s.cells[0],
        s.cells[1],
        s.u_range[0],
        s.u_range[1],
        s.v_range[0],
        s.v_range[1],
        s.epsilon
    );
    println!(
        "  misfit at the data: rms {:.3e}, max {:.3e}; {} cells without data",
        s.rms_misfit, s.max_misfit, s.empty_cells
    );
    match (&s.fill, &s.shape) {
        (Some(f), Some(sh)) => {
            println!(
                "  hole: {} cells filled preserving shape (2024 (11)), {} free coefficients, jumps across its border C⁰ {:.2e}, C¹ {:.2e}",
                s.hole_cells, sh.unknowns, f.c0_jump, f.c1_jump
            );
            println!(
                "  shape conditions: {} inequalities ({}), {} violated, worst violation {:.2e} (tolerance {:.2e})",
                sh.inequalities, sh.status, sh.violated, sh.max_violation, sh.tolerance
            );
        }
        (Some(f), None) => println!(
            "  hole: {} cells, {} constraints (rank {}), jumps across its border C⁰ {:.2e}, C¹ {:.2e}",
            s.hole_cells, f.constraints, f.constraint_rank, f.c0_jump, f.c1_jump
        ),
        (None, _) => println!("  no hole filled"),
    }
    if let Some(p) = &args.spline.output {
        println!("  wrote {}", p.display());
    }
    if let Some(p) = &args.spline.coefficients {
        println!("  wrote {}", p.display());
    }
    if let Some(p) = &args.spline.html {
        println!(
            "  wrote {} (HTML report: open it in a browser)",
            p.display()
        );
    }
    Ok(())
}

/// The HTML report of a fit: the sampled spline coloured by the fit error, the data points
/// and the hole's border on the surface.
fn fit_page(
    args: &SplineArgs,
    out: &crate::fit::pipeline::FitOutcome,
    data: &crate::fit::data::ScatteredData,
    mesh: &crate::mesh::PolygonMesh,
) -> Result<HtmlPage> {
    let s = &out.summary;
    let mut summary = vec![
        ("data".to_string(), args.input.display().to_string()),
        ("points".to_string(), s.points.to_string()),
        (
            "space".to_string(),
            format!("{:?}, {} × {} cells", s.space, s.cells[0], s.cells[1]),
        ),
        ("ε".to_string(), format!("{:e}", s.epsilon)),
        (
            "misfit at the data".to_string(),
            format!("rms {:.3e}, max {:.3e}", s.rms_misfit, s.max_misfit),
        ),
        ("hole cells".to_string(), s.hole_cells.to_string()),
    ];
    if let Some(f) = &s.fill {
        summary.push((
            "jumps across the hole's border".to_string(),
            format!("C⁰ {:.2e}, C¹ {:.2e}", f.c0_jump, f.c1_jump),
        ));
    }
    let name = args.input.display().to_string();
    let title = if s.fill.is_some() {
        format!("hole filling of {name}")
    } else {
        format!("spline fit of {name}")
    };
    let mut page = surface_page(
        &title,
        summary,
        &[("spline surface", mesh)],
        "fit error (RMS misfit per cell)",
        None,
    );
    let view = &mut page.views[0];
    let points = view.local_positions(data.points.iter());
    view.points.push(Points {
        name: "data points".into(),
        colour: [255, 216, 74],
        positions: points,
        size: 3.0,
    });
    page.legend.push(LegendEntry {
        name: "data points".into(),
        colour: [255, 216, 74],
        count: data.points.len(),
    });
    let border = out.hole_border(8)?;
    if !border.is_empty() {
        let segments = view.local_positions(border.iter());
        view.lines.push(Lines {
            name: "hole border".into(),
            colour: [0, 230, 160],
            segments,
        });
        page.legend.push(LegendEntry {
            name: "hole border".into(),
            colour: [0, 230, 160],
            count: border.len() / 2,
        });
    }
    Ok(page)
}

/// The spline setup of `fit` and `fill`: space and cells from the arguments.
///
/// Errors: `InvalidInput` for cells that are not two whole numbers ≥ 1.
pub(super) fn setup(args: &SplineArgs, hole: HoleSource, variant: FillVariant) -> Result<FitSetup> {
    let cells = numbers(&args.cells, "--cells")?;
    if cells.len() != 2 || cells.iter().any(|&c| !(c >= 1.0 && c.fract() == 0.0)) {
        return Err(Error::InvalidInput(format!(
            "--cells {:?}: expected NU,NV ≥ 1",
            args.cells
        )));
    }
    Ok(FitSetup {
        space: match args.space {
            SpaceArg::Biquadratic => SpaceKind::Biquadratic,
            SpaceArg::Bicubic => SpaceKind::Bicubic,
            SpaceArg::BfsC1 => SpaceKind::BfsC1,
        },
        cells: [cells[0] as usize, cells[1] as usize],
        epsilon: args.epsilon,
        hole,
        variant,
        shape: None,
    })
}

/// Bytes a sample of the written mesh takes at its peak: its position, quality, a quad's
/// corners and the writer's buffer, rounded up from the peak RSS of `fit --cells 4,4
/// --resolution 4096 --output o.ply` (1.13 GB: 67 bytes a sample; 2026-12-01).
const SAMPLE_BYTES: u64 = 72;

/// Refuses a `--resolution` whose sampled mesh exceeds the memory budget, before the solve.
fn check_sampled_mesh_fits(resolution: usize) -> Result<()> {
    let samples = (resolution as u64).saturating_mul(resolution as u64);
    let needed = samples.saturating_mul(SAMPLE_BYTES);
    let budget = crate::limits::MemoryBudget::default();
    if needed > budget.get() {
        return Err(Error::ResourceLimit {
            what: format!(
                "the sampled mesh of --resolution {resolution} ({samples} samples, {})",
                crate::limits::human_bytes(needed)
            ),
            limit: budget.get(),
            advice: "lower --resolution".into(),
        });
    }
    Ok(())
}

/// What `fit` and `fill` share: reads the data (CSV or mesh), applies the offset, solves,
/// and writes the sampled mesh and the coefficients when asked.
pub(super) fn load_and_solve(
    args: &SplineArgs,
    setup: &FitSetup,
) -> Result<crate::fit::pipeline::FitOutcome> {
    let (input, offset, output, coefficients, resolution) = (
        args.input.as_path(),
        args.offset.as_deref(),
        args.output.as_deref(),
        args.coefficients.as_deref(),
        args.resolution as usize,
    );
    let is_csv = input
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    let data = if is_csv {
        read_csv(input)?
    } else {
        from_mesh(&crate::mesh::io::read(input)?)?
    };
    let data = match offset {
        Some(spec) => {
            let parts: Vec<&str> = spec.split(';').collect();
            if parts.len() != 3 {
                return Err(Error::InvalidInput(format!(
                    "--offset {spec:?}: expected three expressions d1;d2;d3"
                )));
            }
            let d: Vec<Expr> = parts
                .iter()
                .map(|p| Expr::parse(p))
                .collect::<Result<_>>()?;
            offset_data(&data, setup, &|u, v| {
                Ok([d[0].eval(u, v)?, d[1].eval(u, v)?, d[2].eval(u, v)?])
            })?
        }
        None => data,
    };
    if output.is_some() || args.html.is_some() {
        check_sampled_mesh_fits(resolution)?;
    }
    let out = fit_and_fill(&data, setup)?;
    if output.is_some() || args.html.is_some() {
        let mesh = out.mesh(&data, resolution)?;
        if let Some(path) = output {
            crate::mesh::io::write(path, &mesh, &crate::mesh::io::WriteOptions::default())?;
        }
        if let Some(path) = &args.html {
            write_html(path, &fit_page(args, &out, &data, &mesh)?)?;
        }
    }
    if let Some(path) = coefficients {
        let text = serde_json::to_string(&out.coefficients())
            .map_err(|e| Error::InvalidInput(format!("JSON: {e}")))?;
        crate::mesh::io::write_atomically(path, |w| w.write_all(text.as_bytes()))?;
    }
    Ok(out)
}
