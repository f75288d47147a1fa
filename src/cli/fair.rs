//! `surfkit fair <in> -o <out>`: Kiciak's shape optimization of the Catmull–Clark surface of
//! a quad mesh (the work is `fair::optimize`), and `surfkit gen tubes` (`fair::tubes`), the
//! paper's junctions of tubes. Argument parsing and printing only.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use indicatif::{ProgressBar, ProgressStyle};

use std::process::ExitCode;

use crate::error::Error;

use super::html_pages::{fair_log_plot, fair_summary};
use crate::fair::{
    optimize_levels_observed, read_fixed, refine_surface, shape_change, surface_samples, tubes,
    write_bezier_patches, BlockOptions, CoarseCorrection, CoarseStart, CoarseStartReport, EndCaps,
    FairMethod, FairOptions, FairReport, G2Surface, Iteration, LevelReport, LmMatrix, LmSearch,
    MeshTopology, NewtonOptions, QDomain, RepresentationOptions, ShapeChange, StepKind,
    SurfaceKind, DEFAULT_C_SPECIAL, DEFAULT_C_SPECIAL_G2, DEFAULT_FAR_HESSIAN_NODES,
    DEFAULT_HESSIAN_NODES, DEFAULT_REGULARIZATION, NEWTON_AFTER_DECREASE, SLOW_NEAR_RATE,
    SLOW_NEAR_STEPS,
};
use crate::limits::MemoryBudget;
use crate::mesh::io::{read, write, WriteOptions};
use crate::mesh::PolygonMesh;
use crate::report::html::{surface_page, write_html};
use crate::report::{paired_color_range, render_png, RenderOptions};

/// `--surface`.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum SurfaceArg {
    G2,
    CatmullClark,
}

impl SurfaceArg {
    pub fn kind(self) -> SurfaceKind {
        match self {
            SurfaceArg::G2 => SurfaceKind::G2,
            SurfaceArg::CatmullClark => SurfaceKind::CatmullClark,
        }
    }
}

/// `--method`.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum MethodArg {
    /// Multilevel from 3000 free vertices when the mesh is a refinement, else plain.
    Auto,
    /// A sparse Cholesky factor of every Hessian (paper §5).
    Plain,
    /// Inexact Newton, CG with a multigrid V-cycle over the coarser control meshes.
    Multilevel,
}

/// `--coarse-correction`.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum CoarseCorrectionArg {
    /// From 70 000 free vertices (multilevel method, Catmull–Clark surface).
    Auto,
    /// After every damped step (multilevel method).
    Always,
    Never,
}

#[derive(clap::Args, Debug)]
pub struct FairArgs {
    /// The control mesh (.obj, .ply, .off, .stl), quads with a boundary (or fixed vertices).
    pub input: PathBuf,
    /// The optimized control mesh; same faces and vertex order as the (prepared) input.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Vertices to hold fixed: a text file of 0-based ids, or a PLY of the mesh with a
    /// selection (vertex property `flags` with MeshLab's selected bit 0x20, or `selected`
    /// nonzero, or `quality` > 0).
    #[arg(long)]
    pub fixed: Option<PathBuf>,
    /// Most uniform refinements to meet the paper's conditions (0: input must meet them).
    #[arg(long, default_value_t = 2)]
    pub max_refinements: u32,
    /// The surface to optimize: Kiciak's curvature-continuous one (the paper's: bicubic
    /// patches, and degree-(9, 9) patches at special vertices) or the Catmull–Clark limit.
    #[arg(long, value_enum, default_value_t = SurfaceArg::G2)]
    pub surface: SurfaceArg,
    /// OpenSubdiv's adaptive isolation level around extraordinary vertices (Catmull–Clark
    /// surface).
    #[arg(long, default_value_t = 4)]
    pub isolation: u32,
    /// Gauss–Legendre nodes per direction per patch.
    #[arg(long, default_value_t = 4)]
    pub nodes: usize,
    /// Gauss–Legendre nodes per direction for the Newton Hessians, at most --nodes: F, its
    /// gradient and the minimum keep --nodes (the author's program: Hessians at 6, F at 8);
    /// fewer make each Hessian cheaper and the steps slightly inexact.
    #[arg(long, default_value_t = DEFAULT_HESSIAN_NODES)]
    pub hessian_nodes: usize,
    /// Nodes per direction for the Hessians far from the minimum (from the start and after
    /// Levenberg–Marquardt steps that lowered F by at least 10⁻³ of it, whose damped steps
    /// gain nothing from a finer model), at most --hessian-nodes.
    #[arg(long, default_value_t = DEFAULT_FAR_HESSIAN_NODES)]
    pub far_hessian_nodes: usize,
    /// Cᵢ of elements at special vertices (ordinary elements: 1). Default: 1 on the G²
    /// surface (the paper's Cᵢ = C, as the author's program); 0.01 on the Catmull–Clark
    /// surface, where at 1 the regularization pulls the mesh toward the special vertices.
    #[arg(long, value_parser = super::positive_finite)]
    pub c_special: Option<f64>,
    /// C in F = S + C·c·Q (c = |E|²/D⁴, paper §4): 1 is the paper's text; the default is
    /// the author's test program's (at 1, Q outweighs S on his finer meshes: S rises).
    #[arg(long, default_value_t = DEFAULT_REGULARIZATION, value_parser = super::positive_finite)]
    pub regularization: f64,
    /// Integrate S over the end caps at extraordinary vertices too.
    #[arg(long)]
    pub end_caps_in_s: bool,
    /// Integrate Q of the sub-patches around extraordinary vertices in their face's
    /// parameters instead of their own (Q then grows with --isolation).
    #[arg(long)]
    pub q_in_face_parameters: bool,
    /// Stop when the gradient norm falls below this fraction of its initial value (0 < t < 1).
    #[arg(long, default_value_t = 1e-8, value_parser = super::open_unit_interval)]
    pub tolerance: f64,
    /// Most Newton / Levenberg–Marquardt iterations (per level); a run stopped by it
    /// exits with status 3.
    #[arg(long, default_value_t = NewtonOptions::default().max_iterations)]
    pub max_iterations: usize,
    /// Limit samples of the optimized surface (.ply: mean curvature as vertex quality).
    #[arg(long)]
    pub samples: Option<PathBuf>,
    /// Grid cells along each side of a face for --samples and --figures (1 to 256: checked
    /// before any work).
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=i64::from(crate::subdiv::MAX_SAMPLES)))]
    pub sample_density: u32,
    /// Folder for before/after curvature-map pictures (PNG, one colour scale for both).
    #[arg(long)]
    pub figures: Option<PathBuf>,
    /// Write a self-contained HTML report here: the surface before and after side by side,
    /// mean curvature under one colour scale with its bar, isophotes and reflection lines,
    /// and the optimization log as a plot.
    #[arg(long)]
    pub html: Option<PathBuf>,
    /// Write the optimized G² surface here as Bézier patches (JSON, format
    /// `surfkit-bezier-patches`: one patch of degree 3 or 9 per internal face; README).
    #[arg(long)]
    pub bezier: Option<PathBuf>,
    /// How Newton's steps are solved: `plain` (a sparse Cholesky factor of every Hessian),
    /// `multilevel` (conjugate gradients with a multigrid V-cycle over the coarser control
    /// meshes the input was refined from), `auto` (multilevel for large refined meshes).
    #[arg(long, value_enum, default_value_t = MethodArg::Auto)]
    pub method: MethodArg,
    /// Start the multilevel method from the refined optimum of the mesh the input
    /// un-subdivides to (nested iteration) instead of from the input: faster on the
    /// junctions measured, but it may end in another local minimum (README).
    #[arg(long)]
    pub coarse_start: bool,
    /// Use the block method of the paper's §5 with this many blocks (for large meshes:
    /// block Newton iterations, then global Newton steps by Schwarz-preconditioned CG).
    #[arg(long)]
    pub blocks: Option<usize>,
    /// Rings of edges by which each block overlaps its neighbours (with --blocks).
    #[arg(long, default_value_t = 2)]
    pub overlap: u32,
    /// Most sweeps over the blocks before each try of the global phase (with --blocks; the
    /// paper sweeps until every block's Newton step is effective).
    #[arg(long, default_value_t = 30)]
    pub max_sweeps: usize,
    /// With --blocks: search the Levenberg–Marquardt trajectory with PCG when a global
    /// Newton system fails, before going back to block iterations (beyond the paper).
    #[arg(long)]
    pub global_lm: bool,
    /// Search the Levenberg–Marquardt trajectory (H + νI) δ = −g with the exact Hessian H,
    /// as the paper's eq. 8–9, instead of its Gauss–Newton part (the default, beyond the
    /// paper: fewer iterations to the same minimum).
    #[arg(long)]
    pub lm_exact_hessian: bool,
    /// When a Newton step does not decrease F, try up to this many halvings of it before
    /// the Levenberg–Marquardt search (0: straight to the search, as the paper).
    #[arg(long, default_value_t = 4)]
    pub newton_halvings: usize,
    /// After a Levenberg–Marquardt step that lowered F by more than this fraction of it,
    /// search the trajectory again from the Hessian's Gauss–Newton part alone, without the
    /// exact Hessian and its Newton trial (1 with --no-newton-backoff: always try Newton, as
    /// the paper). In [0, 1].
    #[arg(long, default_value_t = NEWTON_AFTER_DECREASE,
          value_parser = super::closed_unit_interval)]
    pub newton_after_decrease: f64,
    /// Try Newton after every Levenberg–Marquardt step that lowered F by little, even right
    /// after Newton trials that failed (default: after a failed trial skip 1, then 2, 4, …
    /// such passes).
    #[arg(long)]
    pub no_newton_backoff: bool,
    /// Stop following each Levenberg–Marquardt trajectory at the first trial that gains
    /// less than 1 % of the decrease found, and raise ν by 16 after a failed trial
    /// (default: follow it while F decreases at all, raise ν by 4).
    #[arg(long)]
    pub frugal_lm_search: bool,
    /// Bend each Levenberg–Marquardt step along the residuals' curvature (geodesic
    /// acceleration, Transtrum and Sethna 2012): one more solve per trial; faster at no
    /// size measured since the damped phase's 2 × 2 Hessians (docs/fairing-at-scale-log.md).
    /// Default: off.
    #[arg(long, conflicts_with = "no_geodesic_acceleration")]
    pub geodesic_acceleration: bool,
    /// Do not bend the Levenberg–Marquardt steps: the default (see
    /// --geodesic-acceleration).
    #[arg(long)]
    pub no_geodesic_acceleration: bool,
    /// Follow each Levenberg–Marquardt step of the multilevel method by the same matrix's
    /// step in the first coarse level's subspace, where it lowers F: faster at 72 190, 90 237
    /// and 218 879 free vertices, slower at 13 247 and 54 143 (docs/fairing-at-scale-log.md).
    #[arg(long, value_enum, default_value_t = CoarseCorrectionArg::Auto)]
    pub coarse_correction: CoarseCorrectionArg,
    /// Coarse-to-fine (paper §6): optimize the input, then this many times refine its
    /// surface (Catmull–Clark dropping the boundary ring, as `gen tubes --refine`) and
    /// optimize again from the refined optimum; writes the finest level. The finest problem
    /// is the raw refined mesh's (its fixed vertices bit-identical), reached in a few Newton
    /// steps instead of a long Levenberg–Marquardt phase.
    #[arg(long, default_value_t = 0)]
    pub levels: u32,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Print a JSON report with the per-iteration log (F, S, Q, gradient norm, step kind).
    #[arg(long)]
    pub json: bool,
}

/// An HTML report [`write_results`] is asked for: where, and what the page says besides
/// the two surfaces.
pub(super) struct HtmlRequest<'a> {
    pub path: &'a Path,
    pub title: String,
    pub summary: Vec<(String, String)>,
    pub plot: Option<crate::report::html::Plot>,
}

/// The files [`write_results`] wrote, for the summary.
pub(super) struct Written {
    pub samples: Option<PathBuf>,
    pub figures: Vec<PathBuf>,
    pub html: Option<PathBuf>,
    /// Colour range of the figures (mean curvature).
    pub range: Option<(f64, f64)>,
}

/// Limit samples of the optimized surface, before/after curvature maps with one colour
/// scale, and the HTML report, as asked.
pub(super) fn write_results(
    before: &PolygonMesh,
    after: &PolygonMesh,
    samples: Option<&Path>,
    figures: Option<&Path>,
    html: Option<HtmlRequest>,
    density: u32,
    surface: &RepresentationOptions,
) -> crate::Result<Written> {
    let mut written = Written {
        samples: None,
        figures: Vec::new(),
        html: None,
        range: None,
    };
    if samples.is_none() && figures.is_none() && html.is_none() {
        return Ok(written);
    }
    let after_samples = surface_samples(after, density, surface)?.mesh;
    if let Some(path) = samples {
        write(path, &after_samples, &WriteOptions::default())?;
        written.samples = Some(path.to_path_buf());
    }
    let before_samples = if figures.is_some() || html.is_some() {
        surface_samples(before, density, surface)?.mesh
    } else {
        PolygonMesh::default()
    };
    let range = paired_color_range(
        before_samples.quality.as_deref().unwrap_or(&[]),
        after_samples.quality.as_deref().unwrap_or(&[]),
    );
    if let Some(request) = html {
        let mut page = surface_page(
            &request.title,
            request.summary,
            &[("before", &before_samples), ("after", &after_samples)],
            "mean curvature H",
            Some(range),
        );
        page.plot = request.plot;
        write_html(request.path, &page)?;
        written.html = Some(request.path.to_path_buf());
    }
    if let Some(dir) = figures {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        for ((name, title), mesh) in FIGURES.into_iter().zip([&before_samples, &after_samples]) {
            let path = dir.join(name);
            let options = RenderOptions {
                range: Some(range),
                title: Some(title.to_string()),
                quantity: Some("mean curvature H".to_string()),
                ..RenderOptions::default()
            };
            render_png(mesh, &path, &options)?;
            written.figures.push(path);
        }
        written.range = Some(range);
    }
    Ok(written)
}

/// The pictures `--figures` writes in its folder (before, after) and their titles.
const FIGURES: [(&str, &str); 2] = [
    ("curvature_before.png", "before fairing"),
    ("curvature_after.png", "after fairing (same colour scale)"),
];

/// A progress bar on standard error towards the gradient tolerance: its position is
/// log(|g|/|g0|) / log(tolerance); hidden unless `show` and stderr is a terminal.
pub(super) struct Progress {
    bar: ProgressBar,
    tolerance: f64,
    iterations: usize,
}

impl Progress {
    const STEPS: u64 = 1000;

    pub fn new(show: bool, tolerance: f64) -> Self {
        let bar = if show && std::io::stderr().is_terminal() {
            let bar = ProgressBar::new(Self::STEPS);
            // The position is the share of log(|g|/|g0|) done towards the tolerance, so
            // indicatif's estimate of the time left follows the gradient's decay.
            if let Ok(style) =
                ProgressStyle::with_template("{elapsed_precise} [{bar:30}] ETA {eta} {msg}")
            {
                bar.set_style(style.progress_chars("=> "));
            }
            // A Hessian of a large mesh takes tens of seconds: keep the clock moving.
            bar.enable_steady_tick(std::time::Duration::from_millis(500));
            bar.set_message(format!("optimizing (|g|/|g0| → {tolerance:.0e})"));
            bar
        } else {
            ProgressBar::hidden()
        };
        Progress {
            bar,
            tolerance,
            iterations: 0,
        }
    }

    /// For `optimize_levels_observed`: one Newton iteration of `level` done.
    pub fn observe(&mut self, level: u32, it: &Iteration, g0: f64) {
        self.iterations += 1;
        let ratio = if g0 > 0.0 { it.gradient_norm / g0 } else { 0.0 };
        let done = if ratio > 0.0 && self.tolerance < 1.0 {
            (ratio.ln() / self.tolerance.ln()).clamp(0.0, 1.0)
        } else {
            1.0
        };
        self.bar.set_position((done * Self::STEPS as f64) as u64);
        let step = match it.step {
            StepKind::Newton => "Newton step",
            StepKind::ReusedNewton => "Newton step (kept matrix)",
            StepKind::DampedNewton => "damped Newton step",
            StepKind::LevenbergMarquardt => "Levenberg–Marquardt step",
            StepKind::SteepestDescent => "descent step",
            StepKind::LatticeRounding => "Newton step, rounding chosen",
        };
        self.bar.set_message(format!(
            "level {level}, iteration {} ({step}): F {:.6e}, |g|/|g0| {ratio:.2e} → {:.0e}",
            self.iterations, it.terms.f, self.tolerance
        ));
    }

    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// The options of `surfkit fair` (and the demo, which uses the defaults).
fn options(args: &FairArgs, memory: MemoryBudget) -> FairOptions {
    let mut options = FairOptions {
        representation: RepresentationOptions {
            surface: args.surface.kind(),
            nodes: args.nodes,
            isolation: args.isolation,
            c_special: args.c_special.unwrap_or(match args.surface {
                SurfaceArg::G2 => DEFAULT_C_SPECIAL_G2,
                SurfaceArg::CatmullClark => DEFAULT_C_SPECIAL,
            }),
            end_caps: if args.end_caps_in_s {
                EndCaps::Include
            } else {
                EndCaps::ExcludeFromS
            },
            q_domain: if args.q_in_face_parameters {
                QDomain::Face
            } else {
                QDomain::Patch
            },
            memory,
            ..RepresentationOptions::default()
        },
        max_refinements: args.max_refinements,
        regularization: args.regularization,
        hessian_nodes: Some(args.hessian_nodes),
        far_hessian_nodes: Some(args.far_hessian_nodes),
        method: match args.method {
            MethodArg::Auto => FairMethod::Automatic,
            MethodArg::Plain => FairMethod::Plain,
            MethodArg::Multilevel => FairMethod::Multilevel,
        },
        coarse_start: if args.coarse_start {
            CoarseStart::Multilevel
        } else {
            CoarseStart::Never
        },
        ..FairOptions::default()
    };
    options.newton.relative_gradient = args.tolerance;
    options.newton.max_iterations = args.max_iterations;
    if args.lm_exact_hessian {
        options.newton.lm_matrix = LmMatrix::Exact;
    }
    options.newton.newton_halvings = args.newton_halvings;
    options.newton.newton_after_decrease = args.newton_after_decrease;
    options.newton.newton_backoff = !args.no_newton_backoff;
    // `--no-geodesic-acceleration` is the default, kept so that scripts that pass it run.
    options.newton.geodesic_acceleration = args.geodesic_acceleration;
    options.newton.coarse_correction = match args.coarse_correction {
        CoarseCorrectionArg::Auto => CoarseCorrection::Auto,
        CoarseCorrectionArg::Always => CoarseCorrection::Always,
        CoarseCorrectionArg::Never => CoarseCorrection::Never,
    };
    if args.frugal_lm_search {
        options.newton.lm_search = LmSearch::Frugal;
    }
    options.blocks = args.blocks.map(|count| BlockOptions {
        count,
        overlap: args.overlap,
        max_sweeps: args.max_sweeps,
        global_lm: args.global_lm,
        ..BlockOptions::default()
    });
    options
}

/// What [`optimize_with_progress`] returns.
pub(super) struct Optimized {
    /// The raw mesh of the finest level (the input, prepared and refined `levels` times).
    pub before: PolygonMesh,
    pub after: PolygonMesh,
    /// One report per level; the last is the finest.
    pub levels: Vec<LevelReport>,
    pub change: ShapeChange,
    pub seconds: f64,
}

impl Optimized {
    pub fn report(&self) -> &FairReport {
        &self.levels.last().expect("level 0 is always there").report
    }
}

/// Optimizes (coarse-to-fine over `levels` surface refinements) with a progress bar and
/// measures the change of S and H: the shared core of `surfkit fair` and `surfkit demo`.
pub(super) fn optimize_with_progress(
    mesh: &PolygonMesh,
    levels: u32,
    options: &FairOptions,
    show_progress: bool,
) -> crate::Result<Optimized> {
    let mut progress = Progress::new(show_progress, options.newton.relative_gradient);
    let start = std::time::Instant::now();
    let result = optimize_levels_observed(mesh, levels, options, &mut |level, it, g0| {
        progress.observe(level, it, g0);
        std::ops::ControlFlow::Continue(())
    });
    let seconds = start.elapsed().as_secs_f64();
    progress.finish();
    let run = result?;
    let last = &run.levels.last().expect("level 0 is always there").report;
    // One level: the optimizer started from the raw mesh and measured the change itself.
    let change = if levels == 0 {
        last.change
    } else {
        shape_change(
            &run.raw,
            &run.optimized,
            options,
            last.regularization * last.c,
        )?
    };
    Ok(Optimized {
        before: run.raw,
        after: run.optimized,
        levels: run.levels,
        change,
        seconds,
    })
}

/// The coarse stage of the multilevel method, in one line (its own coarse stages nested).
fn coarse_start_line(stage: &CoarseStartReport) -> String {
    let r = &stage.report;
    let mut line = format!(
        "coarse start: {} vertices ({} free, {} method), F {:.6e} → {:.6e}, {} Hessians, \
         {:.1} s{}; refined: F {:.6e}, |g| {:.3e}{}",
        r.vertices,
        r.free_vertices,
        if r.method == FairMethod::Multilevel {
            "multilevel"
        } else {
            "plain"
        },
        r.initial_terms.f,
        r.final_terms.f,
        r.newton.hessian_evaluations,
        stage.seconds,
        r.newton.status_note(),
        stage.start_f,
        stage.start_gradient_norm,
        if stage.used {
            ""
        } else {
            " (not below the input's F: not used)"
        }
    );
    if let Some(inner) = &r.coarse_start {
        line.push_str(&format!("\n    {}", coarse_start_line(inner)));
    }
    line
}

/// Exit status 3 (as `eat`'s failed test) when the run stopped short: not converged and
/// not at the gradient's round-off floor (which is as far as any method gets).
pub fn run(args: &FairArgs, memory: MemoryBudget) -> crate::Result<ExitCode> {
    super::check_folder("--figures", args.figures.as_deref())?;
    // The pictures in --figures' folder are outputs too (a missing folder is created
    // empty: nothing else can be in it).
    let pictures: Vec<PathBuf> = match &args.figures {
        Some(dir) if dir.is_dir() => FIGURES.iter().map(|(name, _)| dir.join(name)).collect(),
        _ => Vec::new(),
    };
    let mut outputs = vec![
        ("--output", Some(args.output.as_path())),
        ("--samples", args.samples.as_deref()),
        ("--html", args.html.as_deref()),
        ("--bezier", args.bezier.as_deref()),
    ];
    outputs.extend(pictures.iter().map(|p| ("--figures", Some(p.as_path()))));
    super::check_paths(&[Some(&args.input), args.fixed.as_deref()], &outputs)?;
    if args.bezier.is_some() && args.surface != SurfaceArg::G2 {
        return Err(Error::InvalidInput(
            "--bezier writes the G² surface's patches; it needs --surface g2".into(),
        ));
    }
    let mesh = read(&args.input)?;
    if mesh.sharp_features.is_some() {
        eprintln!(
            "surfkit: note: {}'s crease/corner tags are ignored: Kiciak's surface has no sharp \
             features",
            args.input.display()
        );
    }
    let mut options = options(args, memory);
    if let Some(path) = &args.fixed {
        options.fixed = read_fixed(path, mesh.vertex_count())?;
    }
    let run = optimize_with_progress(&mesh, args.levels, &options, !args.quiet && !args.json)?;
    let (out, report, change, seconds) = (&run.after, run.report(), &run.change, run.seconds);
    write(&args.output, out, &WriteOptions::default())?;
    let input_name = args.input.display().to_string();
    let html = args.html.as_deref().map(|path| HtmlRequest {
        path,
        title: format!("fairing of {input_name} (Kiciak)"),
        summary: fair_summary(&input_name, report, change, seconds),
        plot: Some(fair_log_plot(report)),
    });
    let written = write_results(
        &run.before,
        out,
        args.samples.as_deref(),
        args.figures.as_deref(),
        html,
        args.sample_density,
        &options.representation,
    )?;
    if let Some(path) = &args.bezier {
        let topo = MeshTopology::new(out)?;
        let surface = G2Surface::new(out, &topo.boundary, &topo.special_flags(), memory)?;
        write_bezier_patches(path, &surface, &out.positions)?;
    }
    if args.json {
        let json = serde_json::json!({
            "bezier": args.bezier,
            "input": args.input, "output": args.output, "seconds": seconds,
            "fixed_given": options.fixed.len(),
            "shape": change,
            "samples": written.samples, "figures": written.figures, "html": written.html,
            "figure_range": written.range,
            "report": report,
            "levels": run.levels,
        });
        super::print_json(&json)?;
    } else {
        for level in run.levels.iter().filter(|_| args.levels > 0) {
            let r = &level.report;
            println!(
                "  level {}: {} vertices ({} free), F {:.6e} → {:.6e}, {} Hessians, {:.1} s{}",
                level.level,
                r.vertices,
                r.free_vertices,
                r.initial_terms.f,
                r.final_terms.f,
                r.newton.hessian_evaluations,
                level.seconds,
                r.newton.status_note()
            );
        }
        let n = &report.newton;
        println!(
            "{} → {}: {} vertices ({} free, {} refinements), S {:.6e} → {:.6e} (before/after \
             {:.2}), std H {:.4e} → {:.4e}, F {:.6e} → {:.6e}, |g| {:.3e} → {:.3e}, {} \
             iterations, {} Hessians{}, {seconds:.1} s{}",
            args.input.display(),
            args.output.display(),
            report.vertices,
            report.free_vertices,
            run.levels[0].report.refinements + args.levels,
            change.s_before,
            change.s_after,
            change.s_before / change.s_after,
            change.std_h_before,
            change.std_h_after,
            report.initial_terms.f,
            report.final_terms.f,
            report.initial_gradient_norm,
            report.final_gradient_norm,
            n.iterations.len(),
            n.hessian_evaluations,
            match n.gauss_newton_only_evaluations {
                0 => String::new(),
                k => format!(" (+ {k} Gauss–Newton parts alone)"),
            },
            n.status_note()
        );
        if report.method == FairMethod::Multilevel {
            println!(
                "  multilevel method: levels of {:?} unknown vertices, {} CG iterations \
                 ({:.1} s), {} V-cycle set-ups ({:.1} s), {} fine Cholesky factors ({:.1} s), \
                 Hessians {:.1} s",
                report.multilevel_sizes,
                n.cg_iterations,
                n.cg_seconds,
                n.factorizations,
                n.factorization_seconds,
                n.fine_factorizations,
                n.fine_factorization_seconds,
                n.hessian_seconds
            );
        }
        if n.near_hessians_raised {
            println!(
                "  near Hessians raised from {} to F's {} nodes per direction: {SLOW_NEAR_STEPS} \
                 Newton steps in a row left |g| above {SLOW_NEAR_RATE} of its value",
                options.hessian_node_counts().0,
                options.representation.nodes
            );
        }
        if n.coarse_correction {
            println!(
                "  coarse correction: {} of {} Levenberg–Marquardt steps moved further in the \
                 first coarse level's subspace ({:.1} s)",
                n.coarse_corrections,
                n.iterations
                    .iter()
                    .filter(|it| it.step == StepKind::LevenbergMarquardt)
                    .count(),
                n.coarse_correction_seconds
            );
        }
        if n.geodesic_acceleration {
            println!(
                "  geodesic acceleration: {} Levenberg–Marquardt trials bent ({:.1} s, {} of the \
                 CG iterations)",
                n.accelerated_trials, n.acceleration_seconds, n.acceleration_cg_iterations
            );
        }
        let lattice = n
            .iterations
            .iter()
            .filter(|it| it.step == StepKind::LatticeRounding)
            .count();
        if let (true, Some(floor)) = (lattice > 0, n.coordinate_floor) {
            println!(
                "  rounding chosen at the floor of f64 coordinates: {lattice} step(s), {} sweep(s), \
                 {:.1} s, to |g|/|g0| {:.2e} (rounding to nearest: {:.2e})",
                n.lattice_sweeps,
                n.lattice_seconds,
                report.final_gradient_norm / report.initial_gradient_norm,
                floor / report.initial_gradient_norm
            );
        }
        if let Some(stage) = &report.coarse_start {
            println!("  {}", coarse_start_line(stage));
        }
        if let Some(b) = &report.blocks {
            println!(
                "  block method: {} blocks of {}–{} vertices (coverage {:.2}), {} sweeps, {} \
                 block Hessians (≈ {:.1} whole-surface), {} global Hessians, {} CG iterations",
                b.blocks,
                b.smallest_block,
                b.largest_block,
                b.coverage,
                b.sweeps,
                b.block_hessian_evaluations,
                b.block_hessians_equivalent,
                b.global_hessian_evaluations,
                b.cg_iterations
            );
        }
        if let Some(path) = &written.samples {
            println!(
                "  {}  (limit samples, mean curvature as quality)",
                path.display()
            );
        }
        for path in &written.figures {
            println!("  {}  (curvature map)", path.display());
        }
        if let Some(path) = &written.html {
            println!("  {}  (HTML report: open it in a browser)", path.display());
        }
        if let Some(path) = &args.bezier {
            println!(
                "  {}  (Bézier patches of the G² surface, JSON)",
                path.display()
            );
        }
    }
    let n = &report.newton;
    if n.converged {
        return Ok(ExitCode::SUCCESS);
    }
    if let (true, Some(floor)) = (n.stalled, n.coordinate_floor) {
        // As close as f64 coordinates come: the goal is met as far as the output can hold it.
        eprintln!(
            "surfkit fair: stopped at |g|/|g0| = {:.3e}, the floor of f64 coordinates \
             (rounding them to nearest moves |g| by {:.3e} of |g0|, and no rounding chosen \
             went further); --tolerance {:.1e} is below it",
            report.final_gradient_norm / report.initial_gradient_norm,
            floor / report.initial_gradient_norm,
            args.tolerance,
        );
        return Ok(ExitCode::SUCCESS);
    }
    eprintln!(
        "surfkit fair: not converged{}: |g|/|g0| = {:.3e} after {} iterations, above \
         --tolerance {:.1e}; {} holds the positions reached",
        n.status_note(),
        report.final_gradient_norm / report.initial_gradient_norm,
        n.iterations.len(),
        args.tolerance,
        args.output.display()
    );
    Ok(ExitCode::from(super::eat::TEST_FAILED))
}

#[derive(clap::Args, Debug)]
pub struct TubesArgs {
    /// Number of tubes (3 to 64); the two saddle vertices have valence 2n.
    #[arg(long, default_value_t = 3)]
    pub n: u32,
    /// Quads along each side of a disc sector; tube ends have 4 m boundary vertices
    /// (4: the topology of the author's 359-vertex mesh, not its coordinates; 8 with 2
    /// rings: 1007 vertices, with --n 5: 1677).
    #[arg(long, default_value_t = 4)]
    pub size: u32,
    /// Rings of quads per tube.
    #[arg(long, default_value_t = 3)]
    pub rings: u32,
    /// Refine the surface this many times as the author does (Catmull–Clark, then the
    /// boundary ring dropped): 359 → 1295 → 4895 vertices, 1007 → 3743 → 14399.
    #[arg(long, default_value_t = 0)]
    pub refine: u32,
    /// The mesh to write.
    #[arg(short, long)]
    pub output: PathBuf,
}

/// `surfkit gen tubes`.
pub fn run_tubes(args: &TubesArgs) -> crate::Result<()> {
    let mesh = refine_surface(&tubes(args.n, args.size, args.rings)?, args.refine)?;
    write(&args.output, &mesh, &WriteOptions::default())?;
    println!(
        "{}: junction of {} tubes, {} refinements, {} vertices, {} quads",
        args.output.display(),
        args.n,
        args.refine,
        mesh.vertex_count(),
        mesh.face_count()
    );
    Ok(())
}
