//! `surfkit demo`: surfkit's main job on a built-in example, for a first look.
//!
//! The example is `target.obj` (a quad-dominant open surface with six holes, from the
//! trimesh test models, MIT; see fixtures/README.md), compiled into the binary.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use crate::error::Error;
use crate::halfedge::{build, HalfEdgeTopology, MeshSummary};
use crate::mesh::io::{parse, write, Format, ReadOptions, WriteOptions};

const EXAMPLE_NAME: &str = "target.obj";
const EXAMPLE: &[u8] = include_bytes!("../../fixtures/meshes/target.obj");

#[derive(clap::Args, Debug)]
pub struct DemoArgs {
    /// Folder for the files the demo writes.
    #[arg(long, default_value = "surfkit-demo")]
    pub out: PathBuf,
}

pub fn run(args: &DemoArgs) -> crate::Result<ExitCode> {
    let source = Path::new(EXAMPLE_NAME);
    let mut mesh = parse(source, EXAMPLE, Format::Obj, &ReadOptions::default())?;
    let summary = MeshSummary::of(&mesh)?;
    println!("surfkit demo — built-in example");
    print!("{}", super::info::render(source, Format::Obj, &summary));

    // Vertex valence as PLY quality, so MeshLab colours the mesh by it.
    let valences = build(&mesh)?.mesh.vertex_valences();
    mesh.quality = Some(valences.iter().map(|&v| f64::from(v)).collect());
    std::fs::create_dir_all(&args.out).map_err(|e| Error::io(&args.out, e))?;
    let written = [
        args.out.join("target_valence.ply"),
        args.out.join("target.off"),
    ];
    for path in &written {
        write(path, &mesh, &WriteOptions::default())?;
    }
    println!("wrote:");
    println!(
        "  {}  (binary PLY, vertex valence as quality: open it in MeshLab and colour by quality)",
        written[0].display()
    );
    println!("  {}  (OFF)", written[1].display());
    Ok(ExitCode::SUCCESS)
}
