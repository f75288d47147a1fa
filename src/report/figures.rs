//! Named figures written as a pair of files: the mesh (PLY, quality kept for MeshLab) and
//! its picture (PNG).

use std::path::{Path, PathBuf};

use super::render::{render_png, RenderOptions};
use crate::error::{Error, Result};
use crate::mesh::io::{write, WriteOptions};
use crate::mesh::PolygonMesh;

/// Writes `<dir>/<name>.ply` and `<dir>/<name>.png` for each figure; returns the paths.
///
/// # Errors
/// [`Error::Io`] when the folder or a file cannot be written.
pub fn write_figures(dir: &Path, figures: &[(String, PolygonMesh)]) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let mut written = Vec::new();
    for (name, mesh) in figures {
        let (ply, png) = (
            dir.join(format!("{name}.ply")),
            dir.join(format!("{name}.png")),
        );
        write(&ply, mesh, &WriteOptions::default())?;
        let options = RenderOptions {
            title: Some(name.clone()),
            ..RenderOptions::default()
        };
        render_png(mesh, &png, &options)?;
        written.push(ply);
        written.push(png);
    }
    Ok(written)
}
