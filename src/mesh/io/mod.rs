//! Reading and writing polygon meshes: OBJ, PLY (ASCII, binary little and big endian), OFF
//! and STL (binary and ASCII).
//!
//! Readers keep polygons as written (no triangulation, no welding, unreferenced vertices
//! kept), so that counts such as V, E and χ describe the file; STL, which has no vertex
//! indices, is welded by exact coordinates (`stl`). Writers are atomic: the data
//! goes to a temporary file in the target's folder which is renamed over the target only
//! once complete, so a failed write never leaves a half-written file behind. A target
//! that is a pipe or a device (`-o /dev/stdout`, a FIFO) is written in place instead.

mod atomic;
mod face_check;
mod obj;
mod off;
mod ply;
mod ply_fast;
mod stl;
mod text;

use std::path::Path;

use crate::error::{Error, Result};
use crate::mesh::PolygonMesh;

pub use atomic::write_atomically;
pub use face_check::{degeneracy, repeated_vertex};
pub use ply::{read_vertex_property, PlyEncoding};

/// The mesh file formats surfkit reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "UPPERCASE")]
pub enum Format {
    Obj,
    Ply,
    Off,
    Stl,
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Format::Obj => "OBJ",
            Format::Ply => "PLY",
            Format::Off => "OFF",
            Format::Stl => "STL",
        })
    }
}

impl Format {
    /// The format named by `path`'s extension (case-insensitive).
    ///
    /// # Errors
    /// [`Error::UnknownFormat`] for any other extension.
    pub fn from_path(path: &Path) -> Result<Format> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Ok(Format::Obj),
            "ply" => Ok(Format::Ply),
            "off" => Ok(Format::Off),
            "stl" => Ok(Format::Stl),
            _ => Err(Error::UnknownFormat {
                path: path.to_path_buf(),
                extension: ext,
            }),
        }
    }
}

/// How strictly readers treat faces that are well-formed but degenerate.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ReadOptions {
    /// Keep faces with fewer than 3 corners or a repeated vertex instead of refusing the file.
    /// Flaw finders (EAT) set this: degenerate faces are among what they report.
    pub keep_degenerate: bool,
}

/// Options for writing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WriteOptions {
    /// PLY encoding; binary little endian unless asked otherwise. ASCII also asks for ASCII
    /// STL (binary otherwise: STL has one byte order).
    pub ply_encoding: PlyEncoding,
}

impl Default for WriteOptions {
    fn default() -> Self {
        WriteOptions {
            ply_encoding: PlyEncoding::BinaryLittleEndian,
        }
    }
}

/// Reads a mesh, choosing the format from the extension; degenerate faces are an error.
///
/// # Errors
/// [`Error::Io`] when the file cannot be read, [`Error::UnknownFormat`], and
/// [`Error::Parse`] naming the line (text) or element (binary) and the problem: malformed
/// numbers, out-of-range indices, non-finite coordinates, truncated data, header counts
/// that disagree with the data, faces with fewer than 3 corners or a repeated vertex.
pub fn read(path: &Path) -> Result<PolygonMesh> {
    read_with(path, &ReadOptions::default())
}

/// Reads a mesh with explicit options (see [`read`]).
pub fn read_with(path: &Path, options: &ReadOptions) -> Result<PolygonMesh> {
    // A path that is not there is that, whatever its extension (a mistyped folder has none).
    if let Err(e) = std::fs::metadata(path) {
        return Err(Error::io(path, e));
    }
    let format = Format::from_path(path)?;
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    parse(path, &bytes, format, options)
}

/// Parses a mesh held in memory; `path` is used in error messages only.
pub fn parse(
    path: &Path,
    bytes: &[u8],
    format: Format,
    options: &ReadOptions,
) -> Result<PolygonMesh> {
    if bytes.iter().all(u8::is_ascii_whitespace) {
        return Err(Error::parse(
            path,
            crate::error::Location::File,
            if bytes.is_empty() {
                "the file is empty"
            } else {
                "the file is empty (it holds only whitespace)"
            },
        ));
    }
    let mesh = match format {
        Format::Obj => obj::parse(path, bytes, options)?,
        Format::Ply => ply::parse(path, bytes, options)?,
        Format::Off => off::parse(path, bytes, options)?,
        Format::Stl => stl::parse(path, bytes, options)?,
    };
    debug_assert!(mesh.validate().is_ok());
    Ok(mesh)
}

/// Writes `mesh` atomically in the format named by `path`'s extension.
///
/// OBJ keeps positions, faces, objects, groups, UVs and vertex colours (as `v x y z r g b`),
/// not quality; PLY keeps everything (objects and groups as face properties with their
/// names in header comments); OFF keeps positions, faces, vertex colours (COFF) and
/// objects/groups as `# surfkit` comments that surfkit reads back; STL keeps positions
/// (rounded to 32-bit floats in binary STL) and polygons as fans of triangles, and ASCII STL
/// objects as `solid` names.
///
/// # Errors
/// [`Error::InvalidInput`] when the mesh breaks its invariants, [`Error::UnknownFormat`],
/// [`Error::Io`] when the file cannot be written.
pub fn write(path: &Path, mesh: &PolygonMesh, options: &WriteOptions) -> Result<()> {
    let format = Format::from_path(path)?;
    mesh.validate()?;
    if format == Format::Stl {
        stl::check(mesh)?;
    }
    write_atomically(path, |out| match format {
        Format::Obj => obj::write(out, mesh),
        Format::Ply => ply::write(out, mesh, options.ply_encoding),
        Format::Off => off::write(out, mesh),
        Format::Stl if options.ply_encoding == PlyEncoding::Ascii => stl::write_ascii(out, mesh),
        Format::Stl => stl::write_binary(out, mesh),
    })
}
