//! `surfkit fair <in> -o <out>`: Kiciak's shape optimization of the Catmull–Clark surface of
//! a quad mesh (the work is `fair::optimize`), and `surfkit gen tubes` (`fair::tubes`), the
//! paper's junctions of tubes. Argument parsing and printing only.

use std::path::PathBuf;

use crate::error::Error;
use crate::fair::{optimize, refine_surface, tubes, EndCaps, FairOptions, RepresentationOptions};
use crate::mesh::io::{read, write, WriteOptions};

#[derive(clap::Args, Debug)]
pub struct FairArgs {
    /// The control mesh (.obj, .ply, .off), quads with a boundary (or fixed vertices).
    pub input: PathBuf,
    /// The optimized control mesh; same faces and vertex order as the (prepared) input.
    #[arg(short, long)]
    pub output: PathBuf,
    /// A text file of vertex ids (0-based, whitespace separated) to hold fixed.
    #[arg(long)]
    pub fixed: Option<PathBuf>,
    /// Most uniform refinements to meet the paper's conditions (0: input must meet them).
    #[arg(long, default_value_t = 2)]
    pub max_refinements: u32,
    /// OpenSubdiv's adaptive isolation level around extraordinary vertices.
    #[arg(long, default_value_t = 4)]
    pub isolation: u32,
    /// Gauss–Legendre nodes per direction per patch.
    #[arg(long, default_value_t = 4)]
    pub nodes: usize,
    /// Cᵢ of elements at special vertices (ordinary elements: 1).
    #[arg(long, default_value_t = 1.0)]
    pub c_special: f64,
    /// Integrate S over the end caps at extraordinary vertices too.
    #[arg(long)]
    pub end_caps_in_s: bool,
    /// Stop when the gradient norm falls below this fraction of its initial value.
    #[arg(long, default_value_t = 1e-8)]
    pub tolerance: f64,
    /// Print a JSON report with the per-iteration log (F, S, Q, gradient norm, step kind).
    #[arg(long)]
    pub json: bool,
}

fn read_ids(path: &PathBuf) -> crate::Result<Vec<u32>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    text.split_whitespace()
        .enumerate()
        .map(|(i, w)| {
            w.parse::<u32>().map_err(|_| {
                Error::InvalidInput(format!(
                    "{}: entry {} ({w:?}) is not a vertex id",
                    path.display(),
                    i + 1
                ))
            })
        })
        .collect()
}

pub fn run(args: &FairArgs) -> crate::Result<()> {
    if args
        .input
        .canonicalize()
        .ok()
        .is_some_and(|a| args.output.canonicalize().ok() == Some(a))
    {
        return Err(Error::InvalidInput(format!(
            "{}: refusing to write over the input file",
            args.output.display()
        )));
    }
    let mesh = read(&args.input)?;
    let mut options = FairOptions {
        representation: RepresentationOptions {
            nodes: args.nodes,
            isolation: args.isolation,
            c_special: args.c_special,
            end_caps: if args.end_caps_in_s {
                EndCaps::Include
            } else {
                EndCaps::ExcludeFromS
            },
            ..RepresentationOptions::default()
        },
        max_refinements: args.max_refinements,
        ..FairOptions::default()
    };
    options.newton.relative_gradient = args.tolerance;
    if let Some(path) = &args.fixed {
        options.fixed = read_ids(path)?;
    }
    let start = std::time::Instant::now();
    let (out, report) = optimize(&mesh, &options)?;
    let seconds = start.elapsed().as_secs_f64();
    write(&args.output, &out, &WriteOptions::default())?;
    if args.json {
        let json = serde_json::json!({
            "input": args.input, "output": args.output, "seconds": seconds,
            "report": report,
        });
        let text = serde_json::to_string_pretty(&json)
            .map_err(|e| Error::InvalidInput(format!("report cannot be written as JSON: {e}")))?;
        println!("{text}");
    } else {
        let n = &report.newton;
        println!(
            "{} → {}: {} vertices ({} free, {} refinements), S {:.6e} → {:.6e}, F {:.6e} → \
             {:.6e}, |g| {:.3e} → {:.3e}, {} iterations, {} Hessians, {seconds:.1} s{}",
            args.input.display(),
            args.output.display(),
            report.vertices,
            report.free_vertices,
            report.refinements,
            n.initial.s,
            report.final_terms.s,
            n.initial.f,
            report.final_terms.f,
            n.initial_gradient_norm,
            report.final_gradient_norm,
            n.iterations.len(),
            n.hessian_evaluations,
            if n.converged { "" } else { " (not converged)" }
        );
    }
    Ok(())
}

#[derive(clap::Args, Debug)]
pub struct TubesArgs {
    /// Number of tubes (3 to 64); the two saddle vertices have valence 2n.
    #[arg(long, default_value_t = 3)]
    pub n: u32,
    /// Quads along each side of a disc sector; tube ends have 4 m boundary vertices
    /// (4: the author's 359-vertex mesh; 8 with 2 rings: 1007 vertices, with --n 5: 1677).
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
