//! `surfkit subdivide <in> -l N -o <out>`: uniform Catmull–Clark refinement (OpenSubdiv),
//! quads and refined UVs out. Argument parsing and printing only; the work is
//! `subdiv::refine_uniform`.

use std::path::PathBuf;

use crate::mesh::io::{read, write, WriteOptions};
use crate::subdiv::{
    refine_uniform, BoundaryInterpolation, FaceVaryingInterpolation, SubdivOptions,
};

/// The boundary rule on the command line (see `subdiv::BoundaryInterpolation`).
#[derive(clap::ValueEnum, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BoundaryArg {
    /// Boundary edges and corners sharp: the surface interpolates corners (default).
    #[default]
    EdgesAndCorners,
    /// Boundary edges sharp, corners smoothed (as CGAL's Catmull–Clark).
    EdgesOnly,
    /// OpenSubdiv's default: boundary faces get no limit surface.
    None,
}

impl From<BoundaryArg> for BoundaryInterpolation {
    fn from(b: BoundaryArg) -> Self {
        match b {
            BoundaryArg::EdgesAndCorners => BoundaryInterpolation::EdgesAndCorners,
            BoundaryArg::EdgesOnly => BoundaryInterpolation::EdgesOnly,
            BoundaryArg::None => BoundaryInterpolation::None,
        }
    }
}

/// The UV rule on the command line (see `subdiv::FaceVaryingInterpolation`).
#[derive(clap::ValueEnum, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum UvArg {
    /// Bilinear UVs (OpenSubdiv's default).
    #[default]
    Linear,
    /// Smooth everywhere.
    Smooth,
    /// Smooth, UV corners kept.
    CornersOnly,
    /// Smooth, UV corners and junctions kept.
    CornersPlus1,
    /// Smooth, UV corners, junctions, darts and concave corners kept.
    CornersPlus2,
    /// Linear along UV boundaries, smooth inside.
    Boundaries,
}

impl From<UvArg> for FaceVaryingInterpolation {
    fn from(u: UvArg) -> Self {
        match u {
            UvArg::Linear => FaceVaryingInterpolation::All,
            UvArg::Smooth => FaceVaryingInterpolation::None,
            UvArg::CornersOnly => FaceVaryingInterpolation::CornersOnly,
            UvArg::CornersPlus1 => FaceVaryingInterpolation::CornersPlus1,
            UvArg::CornersPlus2 => FaceVaryingInterpolation::CornersPlus2,
            UvArg::Boundaries => FaceVaryingInterpolation::Boundaries,
        }
    }
}

#[derive(clap::Args, Debug)]
pub struct SubdivideArgs {
    /// The control mesh (.obj, .ply, .off, .stl).
    pub input: PathBuf,
    /// Levels of refinement (each splits every face into quads, ×4 faces per level).
    #[arg(short, long, default_value_t = 2)]
    pub levels: u32,
    /// The refined mesh to write; its extension chooses the format.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Boundary rule.
    #[arg(long, value_enum, default_value_t = BoundaryArg::EdgesAndCorners)]
    pub boundary: BoundaryArg,
    /// How UVs are refined.
    #[arg(long, value_enum, default_value_t = UvArg::Linear)]
    pub uv: UvArg,
    #[command(flatten)]
    pub sharp: super::sharp_args::SharpArgs,
    /// Print a JSON report.
    #[arg(long)]
    pub json: bool,
}

/// The memory budget is the process's (`--max-memory`), checked by `refine_uniform`.
pub fn run(args: &SubdivideArgs) -> crate::Result<()> {
    super::check_paths(&[Some(&args.input)], &[("--output", Some(&args.output))])?;
    let mesh = read(&args.input)?;
    let (creases, corners, creasing) = super::sharp_args::sharp_features(&mesh, &args.sharp)?;
    let options = SubdivOptions {
        boundary: args.boundary.into(),
        face_varying: args.uv.into(),
        creases,
        corners,
        creasing,
        ..Default::default()
    };
    let refined = refine_uniform(&mesh, args.levels, &options)?;
    write(&args.output, &refined, &WriteOptions::default())?;
    if args.json {
        let report = serde_json::json!({
            "input": args.input, "output": args.output, "levels": args.levels,
            "input_vertices": mesh.vertex_count(), "input_faces": mesh.face_count(),
            "vertices": refined.vertex_count(), "faces": refined.face_count(),
            "uvs": refined.uvs.is_some(),
            "textured_faces": refined.uvs.as_ref().map_or(0, |uv| uv.textured_faces(&refined.face_offsets)),
        });
        super::print_json(&report)?;
    } else {
        println!(
            "{} → {}: Catmull–Clark ×{} (OpenSubdiv), {} faces → {} {}, {} vertices{}",
            args.input.display(),
            args.output.display(),
            args.levels,
            mesh.face_count(),
            refined.face_count(),
            // Zero levels leave the control faces as they are (triangles stay triangles).
            if args.levels == 0 { "faces" } else { "quads" },
            refined.vertex_count(),
            match &refined.uvs {
                Some(uv) if uv.untextured.is_some() => format!(
                    ", UVs refined on {} faces (from the {} of {} control faces that have them)",
                    uv.textured_faces(&refined.face_offsets),
                    mesh.uvs
                        .as_ref()
                        .map_or(0, |c| c.textured_faces(&mesh.face_offsets)),
                    mesh.face_count()
                ),
                Some(_) => ", UVs refined".into(),
                None => String::new(),
            }
        );
    }
    Ok(())
}
