//! `surfkit limit <in> -o out.ply --samples K`: samples the Catmull–Clark limit surface
//! (OpenSubdiv's adaptive patches) on a K × K grid per face, with mean curvature as
//! per-vertex `quality`, so MeshLab shows a curvature map. Argument parsing and printing
//! only; the work is `subdiv::limit_surface` and `subdiv::sample_limit`.

use std::path::PathBuf;

use crate::limits::MemoryBudget;
use crate::mesh::io::{read, write, WriteOptions};
use crate::subdiv::{
    limit_surface, sample_limit, PatchOptions, SampleOptions, SubdivOptions,
    DEFAULT_MAX_STENCIL_WEIGHTS,
};

use super::subdivide::BoundaryArg;

#[derive(clap::Args, Debug)]
pub struct LimitArgs {
    /// The control mesh (.obj, .ply, .off, .stl).
    pub input: PathBuf,
    /// The sampled surface to write (.ply keeps the curvature as `quality`).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Grid cells along each side of every (ptex) face [default: 4, fewer where the samples
    /// would pass 2 million]
    #[arg(long)]
    pub samples: Option<u32>,
    /// Feature-adaptive isolation levels around extraordinary vertices (1–10).
    #[arg(long, default_value_t = 4)]
    pub max_isolation: u32,
    /// Stencil weights the patch table may hold, the work of building it (about 0.7 s per
    /// 10 million): the isolation is lowered to stay under it, and a mesh that passes it
    /// even at level 1 is refused
    #[arg(long, default_value_t = DEFAULT_MAX_STENCIL_WEIGHTS)]
    pub max_stencils: usize,
    /// Boundary rule.
    #[arg(long, value_enum, default_value_t = BoundaryArg::EdgesAndCorners)]
    pub boundary: BoundaryArg,
    #[command(flatten)]
    pub sharp: super::sharp_args::SharpArgs,
    /// Where to write the PNG picture of the curvature map (default: the output's name
    /// with `.png`).
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Write a self-contained HTML report here: the limit surface coloured by mean
    /// curvature with its colour bar, isophotes and reflection lines.
    #[arg(long)]
    pub html: Option<PathBuf>,
    /// Print a JSON report.
    #[arg(long)]
    pub json: bool,
}

/// Sample cells per face side when `--samples` is not given.
const DEFAULT_SAMPLES: u32 = 4;

/// Samples the default may produce (about 2.5 s of evaluation and 170 MB of PLY): a
/// curvature map of a big mesh at 4 cells per side would be tens of millions of samples.
const MAX_AUTO_SAMPLES: usize = 2_000_000;

/// The most cells per side, up to [`DEFAULT_SAMPLES`] and at least 1, whose (k + 1)² samples
/// per ptex face keep `ptex_faces` faces under [`MAX_AUTO_SAMPLES`].
fn auto_samples(ptex_faces: usize) -> u32 {
    (1..=DEFAULT_SAMPLES)
        .rev()
        .find(|&k| ptex_faces.saturating_mul(((k + 1) * (k + 1)) as usize) <= MAX_AUTO_SAMPLES)
        .unwrap_or(1)
}

pub fn run(args: &LimitArgs, memory: MemoryBudget) -> crate::Result<()> {
    // The picture is always written: to --png, or next to the output.
    let png = args
        .png
        .clone()
        .unwrap_or_else(|| args.output.with_extension("png"));
    let png_option = if args.png.is_some() {
        "--png"
    } else {
        "--png (by default the output's name with .png)"
    };
    super::check_paths(
        &[Some(&args.input)],
        &[
            ("--output", Some(&args.output)),
            (png_option, Some(&png)),
            ("--html", args.html.as_deref()),
        ],
    )?;
    // The picture is PNG bytes: a name that says otherwise would mislead the next program.
    if let Some(ext) = args.png.as_deref().and_then(|p| p.extension()) {
        if !ext.eq_ignore_ascii_case("png") {
            return Err(crate::Error::InvalidInput(format!(
                "--png {}: the picture is written as PNG; give a name ending in .png",
                png.display()
            )));
        }
    }
    let mesh = read(&args.input)?;
    let (creases, corners, creasing) = super::sharp_args::sharp_features(&mesh, &args.sharp)?;
    let options = SubdivOptions {
        boundary: args.boundary.into(),
        creases,
        corners,
        creasing,
        ..Default::default()
    };
    let surface = limit_surface(
        &mesh,
        &options,
        &PatchOptions {
            max_isolation: args.max_isolation,
            memory,
            max_stencil_weights: args.max_stencils,
        },
    )?;
    if surface.isolation() < args.max_isolation {
        eprintln!(
            "surfkit: note: isolation lowered from {} to {} to stay under the memory limit of \
             {memory} (--max-memory) and {} stencil weights (--max-stencils): near \
             extraordinary vertices the surface is the level-{} approximation",
            args.max_isolation,
            surface.isolation(),
            args.max_stencils,
            surface.isolation()
        );
    }
    let samples_per_side = match args.samples {
        Some(k) => k,
        None => {
            let k = auto_samples(surface.ptex_face_count());
            if k < DEFAULT_SAMPLES {
                eprintln!(
                    "surfkit: note: {k} sample cells per face side instead of \
                     {DEFAULT_SAMPLES}, to keep {} faces under {MAX_AUTO_SAMPLES} samples \
                     (--samples sets it)",
                    surface.ptex_face_count()
                );
            }
            k
        }
    };
    let sampled = sample_limit(
        &surface,
        &SampleOptions {
            samples: samples_per_side,
        },
    )?;
    let samples = &sampled.mesh;
    write(&args.output, samples, &WriteOptions::default())?;
    let options = crate::report::RenderOptions {
        title: Some(format!("limit surface of {}", args.input.display())),
        quantity: Some("mean curvature H".to_string()),
        ..crate::report::RenderOptions::default()
    };
    crate::report::render_png(samples, &png, &options)?;
    let regular = surface.patches().iter().filter(|p| p.regular).count();
    if let Some(path) = &args.html {
        let summary = vec![
            ("control mesh".into(), args.input.display().to_string()),
            (
                "patches".into(),
                format!(
                    "{} ({regular} regular, {} B-spline end caps)",
                    surface.patches().len(),
                    surface.patches().len() - regular
                ),
            ),
            ("isolation level".into(), surface.isolation().to_string()),
            (
                "samples".into(),
                format!(
                    "{} ({samples_per_side} cells per face side)",
                    samples.vertex_count()
                ),
            ),
        ];
        let page = crate::report::html::surface_page(
            &format!("limit surface of {}", args.input.display()),
            summary,
            &[("limit surface", samples)],
            "mean curvature H",
            None,
        );
        crate::report::html::write_html(path, &page)?;
    }
    let (lo, hi) = crate::report::finite_extent(samples.quality.as_deref().unwrap_or(&[]))
        .unwrap_or((f64::INFINITY, f64::NEG_INFINITY));
    if args.json {
        let report = serde_json::json!({
            "input": args.input, "output": args.output, "picture": png, "html": args.html,
            "patches": surface.patches().len(), "regular_patches": regular,
            "isolation": surface.isolation(),
            "ptex_faces": surface.ptex_face_count(),
            "samples_per_side": samples_per_side,
            "samples": samples.vertex_count(),
            "degenerate_samples": sampled.degenerate.len(),
            "mean_curvature": { "min": lo, "max": hi },
        });
        super::print_json(&report)?;
    } else {
        println!(
            "{} → {}: limit surface of {} patches ({} regular, {} B-spline end caps), {} samples \
             ({} at degenerate points), mean curvature in [{lo:.4e}, {hi:.4e}] as quality; picture {}",
            args.input.display(),
            args.output.display(),
            surface.patches().len(),
            regular,
            surface.patches().len() - regular,
            samples.vertex_count(),
            sampled.degenerate.len(),
            png.display()
        );
        if let Some(path) = &args.html {
            println!("  {}  (HTML report: open it in a browser)", path.display());
        }
    }
    Ok(())
}
