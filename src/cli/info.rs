//! `surfkit info <mesh>`: what the file holds and what OpenMesh made of it.

use std::path::PathBuf;
use std::process::ExitCode;

use crate::halfedge::{openmesh_version, MeshSummary};
use crate::mesh::io::{read_with, Format, ReadOptions};

#[derive(clap::Args, Debug)]
pub struct InfoArgs {
    /// The mesh (.obj, .ply, .off or .stl).
    pub mesh: PathBuf,
    /// Print a JSON report instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Reads leniently (degenerate faces are reported as refused, not an error).
pub fn run(args: &InfoArgs) -> crate::Result<ExitCode> {
    let format = Format::from_path(&args.mesh)?;
    let mesh = read_with(
        &args.mesh,
        &ReadOptions {
            keep_degenerate: true,
        },
    )?;
    let summary = MeshSummary::of(&mesh)?;
    if args.json {
        #[derive(serde::Serialize)]
        struct Report<'a> {
            file: &'a std::path::Path,
            format: Format,
            #[serde(flatten)]
            summary: &'a MeshSummary,
        }
        super::print_json(&Report {
            file: &args.mesh,
            format,
            summary: &summary,
        })?;
    } else {
        print!("{}", render(&args.mesh, format, &summary));
    }
    Ok(ExitCode::SUCCESS)
}

/// The human summary.
pub fn render(path: &std::path::Path, format: Format, s: &MeshSummary) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let arities: Vec<String> = s
        .arity_histogram
        .iter()
        .map(|(n, c)| format!("{c} with {n} corner{}", if *n == 1 { "" } else { "s" }))
        .collect();
    let _ = writeln!(out, "{} ({format})", path.display());
    let _ = writeln!(
        out,
        "  vertices {}  faces {} ({})",
        s.vertices,
        s.faces,
        arities.join(", ")
    );
    if let Some([lo, hi]) = s.bounding_box {
        let _ = writeln!(
            out,
            "  bounding box [{:.6}, {:.6}, {:.6}] – [{:.6}, {:.6}, {:.6}]",
            lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]
        );
    }
    let yes = |b: bool| if b { "yes" } else { "no" };
    let uvs = if s.has_uvs && s.textured_faces < s.faces {
        format!("on {} of {} faces", s.textured_faces, s.faces)
    } else {
        yes(s.has_uvs).to_string()
    };
    let _ = writeln!(
        out,
        "  objects {}  groups {}  uvs {}  quality {}  colours {}",
        s.objects,
        s.groups,
        uvs,
        yes(s.has_quality),
        yes(s.has_colors)
    );
    let h = &s.halfedge;
    let _ = writeln!(out, "OpenMesh {} half-edge structure:", openmesh_version());
    let _ = writeln!(
        out,
        "  V {}  E {}  F {}  χ {}  boundary loops {}  components {}",
        h.vertices, h.edges, h.faces, h.euler_characteristic, h.boundary_loops, h.components
    );
    if s.refused.is_empty() {
        let _ = writeln!(out, "  every face accepted");
    } else {
        let _ = writeln!(out, "  {} faces refused:", s.refused.len());
        for r in s.refused.iter().take(20) {
            let _ = writeln!(
                out,
                "    face {} {}: {}",
                r.face,
                crate::topology::show_ids(&r.vertices),
                r.reason.describe()
            );
        }
        if s.refused.len() > 20 {
            let _ = writeln!(
                out,
                "    … and {} more (--json lists all)",
                s.refused.len() - 20
            );
        }
    }
    out
}
