//! `surfkit convert <in> <out>`: OBJ ↔ PLY ↔ OFF ↔ STL, atomically, never over the input.

use std::path::PathBuf;
use std::process::ExitCode;

use crate::mesh::io::{read_with, write, Format, PlyEncoding, ReadOptions, WriteOptions};

#[derive(clap::Args, Debug)]
pub struct ConvertArgs {
    /// The mesh to read (.obj, .ply, .off, .stl).
    pub input: PathBuf,
    /// The file to write; its extension chooses the format.
    pub output: PathBuf,
    /// Write ASCII PLY or STL instead of binary (little endian).
    #[arg(long)]
    pub ascii: bool,
    /// Keep faces with fewer than 3 corners or a repeated vertex instead of refusing the file.
    #[arg(long)]
    pub keep_degenerate: bool,
    /// Print a JSON report.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &ConvertArgs) -> crate::Result<ExitCode> {
    super::check_paths(&[Some(&args.input)], &[("OUTPUT", Some(&args.output))])?;
    let mesh = read_with(
        &args.input,
        &ReadOptions {
            keep_degenerate: args.keep_degenerate,
        },
    )?;
    let options = WriteOptions {
        ply_encoding: if args.ascii {
            PlyEncoding::Ascii
        } else {
            PlyEncoding::BinaryLittleEndian
        },
    };
    write(&args.output, &mesh, &options)?;
    // STL holds triangles: polygons were written as fans.
    let triangles = (Format::from_path(&args.output)? == Format::Stl).then(|| {
        mesh.faces()
            .map(|f| f.len().saturating_sub(2))
            .sum::<usize>()
    });
    if args.json {
        super::print_json(&serde_json::json!({
            "input": args.input, "output": args.output,
            "vertices": mesh.vertex_count(), "faces": mesh.face_count(),
            "triangles_written": triangles,
        }))?;
    } else {
        let written = match triangles {
            Some(t) if t != mesh.face_count() => format!(" (written as {t} triangles)"),
            _ => String::new(),
        };
        println!(
            "{} → {}: {} vertices, {} faces{written}",
            args.input.display(),
            args.output.display(),
            mesh.vertex_count(),
            mesh.face_count()
        );
    }
    Ok(ExitCode::SUCCESS)
}
