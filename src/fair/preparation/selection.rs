//! User-given fixed vertices (paper §4: soft constraints) from a file: a list of vertex ids,
//! or a PLY whose vertices carry a selection, as MeshLab saves one.
//!
//! A PLY selection is read from the first of these vertex properties the header declares:
//! - `flags`: VCG's per-vertex bit flags, as MeshLab writes them when "Flags" is ticked on
//!   export; a vertex is fixed when its selected bit is set. The bit is `SELECTED = 0x0020`
//!   of the vertex flag enum in vcglib (`vcg/simplex/vertex/base.h`, `VertexArityMax`:
//!   DELETED 0x0001, NOTREAD 0x0002, NOTWRITE 0x0004, MODIFIED 0x0008, VISITED 0x0010,
//!   SELECTED 0x0020, BORDER 0x0100, USER0 0x0200).
//! - `selected`: fixed when nonzero (a plain 0/1 mask from a script).
//! - `quality`: fixed when > 0 (MeshLab can paint quality, or compute it by a filter).
//!
//! The PLY must have the mesh's vertices in the mesh's order (it is the mesh saved with the
//! selection): its vertex count must equal the mesh's.

use std::path::Path;

use crate::error::{Error, Result};
use crate::mesh::io::read_vertex_property;

/// VCG's "selected" vertex flag (vcglib `vcg/simplex/vertex/base.h`).
pub const VCG_SELECTED: i64 = 0x0020;

/// The vertex ids `path` fixes, for a mesh of `vertex_count` vertices: a PLY selection (by
/// extension `.ply`, see the module doc) or a text file of 0-based ids separated by
/// whitespace or commas (`#` starts a comment to the end of the line).
///
/// # Errors
/// [`Error::Io`] when the file cannot be read; [`Error::InvalidInput`] naming the file and
/// the entry for an entry that is not a non-negative integer or not a vertex of the mesh,
/// a PLY with another vertex count or without a selection property, or a `flags` value
/// that is not an integer; [`Error::Parse`] for a malformed PLY.
pub fn read_fixed(path: &Path, vertex_count: usize) -> Result<Vec<u32>> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let is_ply = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("ply"));
    if is_ply {
        ply_selection(path, &bytes, vertex_count)
    } else {
        id_list(path, &bytes, vertex_count)
    }
}

fn id_list(path: &Path, bytes: &[u8], vertex_count: usize) -> Result<Vec<u32>> {
    let text = std::str::from_utf8(bytes).map_err(|_| {
        Error::InvalidInput(format!(
            "{}: not a text file of vertex ids (nor a .ply selection)",
            path.display()
        ))
    })?;
    let mut ids = Vec::new();
    for (line_number, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("");
        for word in line
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|w| !w.is_empty())
        {
            let entry = ids.len() + 1;
            let id: u64 = word.parse().map_err(|_| {
                Error::InvalidInput(format!(
                    "{}: line {}, entry {entry} ({word:?}) is not a vertex id (a non-negative \
                     integer)",
                    path.display(),
                    line_number + 1
                ))
            })?;
            if id >= vertex_count as u64 {
                return Err(Error::InvalidInput(format!(
                    "{}: line {}, entry {entry}: vertex {id} does not exist (the mesh has \
                     {vertex_count} vertices, ids 0 to {})",
                    path.display(),
                    line_number + 1,
                    vertex_count.saturating_sub(1)
                )));
            }
            ids.push(id as u32);
        }
    }
    Ok(ids)
}

fn ply_selection(path: &Path, bytes: &[u8], vertex_count: usize) -> Result<Vec<u32>> {
    let Some((name, values)) =
        read_vertex_property(path, bytes, &["flags", "selected", "quality"])?
    else {
        return Err(Error::InvalidInput(format!(
            "{}: the PLY's vertices have no selection: expected a vertex property \"flags\" \
             (MeshLab's, selected bit 0x20), \"selected\" (nonzero) or \"quality\" (> 0)",
            path.display()
        )));
    };
    if values.len() != vertex_count {
        return Err(Error::InvalidInput(format!(
            "{}: the selection has {} vertices but the mesh has {vertex_count}: save the \
             selection from the same mesh",
            path.display(),
            values.len()
        )));
    }
    let mut ids = Vec::new();
    for (v, &x) in values.iter().enumerate() {
        if !x.is_finite() {
            return Err(Error::InvalidInput(format!(
                "{}: vertex {v}: {name} {x} is not a finite number",
                path.display()
            )));
        }
        let chosen = match name.as_str() {
            "flags" => {
                if x.fract() != 0.0 {
                    return Err(Error::InvalidInput(format!(
                        "{}: vertex {v}: flags {x} is not an integer",
                        path.display()
                    )));
                }
                (x as i64) & VCG_SELECTED != 0
            }
            "selected" => x != 0.0,
            _ => x > 0.0,
        };
        if chosen {
            ids.push(v as u32);
        }
    }
    Ok(ids)
}
