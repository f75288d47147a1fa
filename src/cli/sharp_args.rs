//! The sharp-feature options of `subdivide` and `limit`: creases and corners from the
//! input's OBJ tags (`t crease`, `t corner`, `t creasemethod`) and from the command line,
//! which adds to them and overrides the same edge or vertex.

use crate::error::{Error, Result};
use crate::mesh::PolygonMesh;
use crate::subdiv::{Corner, Crease, CreasingMethod};

/// How sharpness falls from one level to the next on the command line.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum CreaseMethodArg {
    /// Sharpness drops by 1 per level (OpenSubdiv's default).
    Uniform,
    /// Chaikin's rule: sharpness averaged along a crease.
    Chaikin,
}

#[derive(clap::Args, Debug, Default)]
pub struct SharpArgs {
    /// A crease: an edge's two vertices (0-based, as OBJ tags count them) and its sharpness
    /// (0 smooth, k sharp for k levels, ≥ 10 infinitely sharp); repeatable.
    #[arg(long, value_name = "V0,V1,S", value_parser = parse_crease)]
    pub crease: Vec<(u32, u32, f32)>,
    /// A sharp corner: a vertex (0-based) and its sharpness; repeatable.
    #[arg(long, value_name = "V,S", value_parser = parse_corner)]
    pub corner: Vec<(u32, f32)>,
    /// The crease rule [default: the input's `t creasemethod` tag, else uniform].
    #[arg(long, value_enum)]
    pub crease_method: Option<CreaseMethodArg>,
}

fn sharpness(text: &str) -> std::result::Result<f32, String> {
    match text.trim().parse::<f32>() {
        Ok(s) if s.is_finite() && s >= 0.0 => Ok(s),
        _ => Err(format!("sharpness {text:?} is not a finite number ≥ 0")),
    }
}

fn vertex(text: &str) -> std::result::Result<u32, String> {
    text.trim()
        .parse::<u32>()
        .map_err(|_| format!("{text:?} is not a vertex id (0-based)"))
}

fn parse_crease(text: &str) -> std::result::Result<(u32, u32, f32), String> {
    match text.split(',').collect::<Vec<_>>()[..] {
        [a, b, s] => Ok((vertex(a)?, vertex(b)?, sharpness(s)?)),
        _ => Err(format!("{text:?}: a crease is V0,V1,SHARPNESS")),
    }
}

fn parse_corner(text: &str) -> std::result::Result<(u32, f32), String> {
    match text.split(',').collect::<Vec<_>>()[..] {
        [v, s] => Ok((vertex(v)?, sharpness(s)?)),
        _ => Err(format!("{text:?}: a corner is V,SHARPNESS")),
    }
}

/// The creases, corners and rule for `mesh`: its tags, then the command line's (an edge or
/// vertex given on both takes the command line's sharpness).
///
/// # Errors
/// A command-line vertex that is not a vertex of the mesh (an edge that is not one is
/// refused by the subdivision layer, naming it).
pub fn sharp_features(
    mesh: &PolygonMesh,
    args: &SharpArgs,
) -> Result<(Vec<Crease>, Vec<Corner>, CreasingMethod)> {
    let n = mesh.vertex_count();
    let check = |v: u32| {
        if (v as usize) < n {
            Ok(v)
        } else {
            Err(Error::InvalidInput(format!(
                "--crease/--corner: vertex {v} is not a vertex of the mesh (0 to {})",
                n.saturating_sub(1)
            )))
        }
    };
    let tags = mesh.sharp_features.clone().unwrap_or_default();
    let mut creases: Vec<Crease> = tags
        .creases
        .iter()
        .map(|&(vertices, sharpness)| Crease {
            vertices,
            sharpness,
        })
        .collect();
    for &(a, b, sharpness) in &args.crease {
        let vertices = [check(a)?, check(b)?];
        let same = |c: &Crease| c.vertices == vertices || c.vertices == [vertices[1], vertices[0]];
        creases.retain(|c| !same(c));
        creases.push(Crease {
            vertices,
            sharpness,
        });
    }
    let mut corners: Vec<Corner> = tags
        .corners
        .iter()
        .map(|&(vertex, sharpness)| Corner { vertex, sharpness })
        .collect();
    for &(v, sharpness) in &args.corner {
        let vertex = check(v)?;
        corners.retain(|c| c.vertex != vertex);
        corners.push(Corner { vertex, sharpness });
    }
    let creasing = match args.crease_method {
        Some(CreaseMethodArg::Chaikin) => CreasingMethod::Chaikin,
        Some(CreaseMethodArg::Uniform) => CreasingMethod::Uniform,
        None if tags.chaikin => CreasingMethod::Chaikin,
        None => CreasingMethod::Uniform,
    };
    Ok((creases, corners, creasing))
}
