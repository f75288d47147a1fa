//! `SurfkitMesh`: a polygon soup (positions f64, faces as offsets + indices u32) made from
//! the caller's flat arrays or read from OBJ/PLY/OFF, and its read-only views.

use std::ffi::{c_char, c_int};
use std::path::Path;
use std::ptr::{null, null_mut};

use surfkit::limits::{human_bytes, MemoryBudget};
use surfkit::mesh::io::{read_with, write, ReadOptions, WriteOptions};
use surfkit::mesh::PolygonMesh;

use crate::pointers::{clear, give, output, reference, slice, take, text};
use crate::status::{guard, Failure, SURFKIT_RESOURCE_LIMIT};

/// An opaque polygon mesh owned by the caller (free it with [`surfkit_mesh_free`]).
pub struct SurfkitMesh {
    pub(crate) mesh: PolygonMesh,
}

impl SurfkitMesh {
    /// A mesh from flat arrays, checked: offsets start at 0, never decrease and end at the
    /// index count; every index names a vertex; every coordinate is finite.
    pub(crate) fn from_arrays(
        positions: &[f64],
        offsets: &[u32],
        indices: &[u32],
    ) -> Result<PolygonMesh, Failure> {
        let mesh = PolygonMesh {
            positions: positions
                .chunks_exact(3)
                .map(|p| [p[0], p[1], p[2]])
                .collect(),
            face_offsets: offsets.to_vec(),
            face_indices: indices.to_vec(),
            ..Default::default()
        };
        mesh.validate()?;
        Ok(mesh)
    }
}

/// The bytes surfkit's copy of a mesh of these counts takes (positions, offsets, indices),
/// refused with `SURFKIT_RESOURCE_LIMIT` past the memory limit before anything is read or
/// allocated: a count the caller got wrong must not become a gigantic copy.
fn check_copy_size(
    vertex_count: usize,
    face_count: usize,
    index_count: usize,
) -> Result<(), Failure> {
    let bytes =
        (vertex_count as u128) * 24 + (face_count as u128 + 1) * 4 + (index_count as u128) * 4;
    let limit = MemoryBudget::default();
    if bytes > u128::from(limit.get()) {
        return Err(Failure {
            code: SURFKIT_RESOURCE_LIMIT,
            message: format!(
                "a mesh of {vertex_count} vertices, {face_count} faces and {index_count} face \
                 indices needs {} for surfkit's copy, more than the memory limit of {limit} \
                 (surfkit_set_max_memory raises it)",
                human_bytes(u64::try_from(bytes).unwrap_or(u64::MAX))
            ),
        });
    }
    Ok(())
}

/// The offsets' promises, checked before any index is read: they start at 0, never
/// decrease, and the last one is `index_count` (the length of the caller's index array).
fn check_offsets(offsets: &[u32], index_count: usize) -> Result<(), Failure> {
    if let Some(&first) = offsets.first().filter(|&&o| o != 0) {
        return Err(Failure::invalid(format!(
            "face_offsets[0] is {first}: face 0 must start at index 0"
        )));
    }
    if let Some(f) = offsets.windows(2).position(|w| w[1] < w[0]) {
        return Err(Failure::invalid(format!(
            "face_offsets decrease at face {f}: it starts at {} and ends at {} (offsets never \
             decrease)",
            offsets[f],
            offsets[f + 1]
        )));
    }
    let faces = offsets.len() - 1;
    let last = offsets[faces];
    if last as usize != index_count {
        return Err(Failure::invalid(if faces == 0 {
            format!("face_offsets[0] is {last} but index_count is {index_count}")
        } else {
            format!(
                "face {} ends at face_offsets[{faces}] = {last} but index_count is {index_count} \
                 (the last offset is the number of face indices)",
                faces - 1
            )
        }));
    }
    Ok(())
}

/// Makes a mesh from `vertex_count` positions (x, y, z each), `face_count + 1` face offsets
/// (face f is `face_indices[face_offsets[f] .. face_offsets[f + 1]]`) and `index_count`
/// vertex indices. Polygons of any arity, also fewer than 3 corners (degenerate facets,
/// which the EAT counts); nothing is re-indexed.
///
/// Checked before anything is copied: the copy's size against the memory limit
/// (`SURFKIT_RESOURCE_LIMIT`); `face_offsets[0] = 0`, offsets that never decrease and
/// `face_offsets[face_count] = index_count` (before an index is read); then every index
/// < `vertex_count` and every coordinate finite. Errors name the face or vertex at fault.
///
/// # Safety
/// `positions` must hold `3 · vertex_count` doubles, `face_offsets` `face_count + 1` and
/// `face_indices` `index_count` integers (null only for 0); `out` must be writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_mesh_new(
    positions: *const f64,
    vertex_count: usize,
    face_offsets: *const u32,
    face_count: usize,
    face_indices: *const u32,
    index_count: usize,
    out: *mut *mut SurfkitMesh,
) -> c_int {
    guard(|| {
        clear(out, null_mut());
        let out = output(out, "out")?;
        check_copy_size(vertex_count, face_count, index_count)?;
        let coordinates = vertex_count
            .checked_mul(3)
            .ok_or_else(|| Failure::invalid("vertex_count overflows"))?;
        let positions = slice(positions, coordinates, "positions")?;
        let offsets_len = face_count
            .checked_add(1)
            .ok_or_else(|| Failure::invalid("face_count overflows"))?;
        let offsets = slice(face_offsets, offsets_len, "face_offsets")?;
        check_offsets(offsets, index_count)?;
        let indices = slice(face_indices, index_count, "face_indices")?;
        give(
            out,
            SurfkitMesh {
                mesh: SurfkitMesh::from_arrays(positions, offsets, indices)?,
            },
        );
        Ok(())
    })
}

/// Reads an OBJ, PLY (ASCII or binary), OFF or STL (corners welded by coordinates) file,
/// polygons kept (degenerate facets too: the EAT counts them).
///
/// # Safety
/// `path` must be a NUL-terminated UTF-8 string; `out` writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_mesh_read(
    path: *const c_char,
    out: *mut *mut SurfkitMesh,
) -> c_int {
    guard(|| {
        clear(out, null_mut());
        let out = output(out, "out")?;
        let path = text(path, "path")?;
        let mesh = read_with(
            Path::new(path),
            &ReadOptions {
                keep_degenerate: true,
            },
        )?;
        give(out, SurfkitMesh { mesh });
        Ok(())
    })
}

/// Writes the mesh as OBJ, PLY (binary little endian), OFF or binary STL, by the path's extension,
/// atomically (a temporary file renamed over the target).
///
/// # Safety
/// `mesh` must be a live handle; `path` a NUL-terminated UTF-8 string.
#[no_mangle]
pub unsafe extern "C" fn surfkit_mesh_write(
    mesh: *const SurfkitMesh,
    path: *const c_char,
) -> c_int {
    guard(|| {
        let mesh = reference(mesh, "mesh")?;
        let path = text(path, "path")?;
        write(Path::new(path), &mesh.mesh, &WriteOptions::default())?;
        Ok(())
    })
}

/// The numbers of vertices, faces and face indices (any output may be null).
///
/// # Safety
/// `mesh` must be a live handle; non-null outputs writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_mesh_counts(
    mesh: *const SurfkitMesh,
    vertex_count: *mut usize,
    face_count: *mut usize,
    index_count: *mut usize,
) -> c_int {
    guard(|| {
        for slot in [vertex_count, face_count, index_count] {
            clear(slot, 0);
        }
        let m = &reference(mesh, "mesh")?.mesh;
        for (slot, value) in [
            (vertex_count, m.vertex_count()),
            (face_count, m.face_count()),
            (index_count, m.face_indices.len()),
        ] {
            if let Some(slot) = slot.as_mut() {
                *slot = value;
            }
        }
        Ok(())
    })
}

/// Borrowed views of the mesh's arrays: `3 · vertex_count` positions, `face_count + 1`
/// offsets and `index_count` indices (any output may be null). They stay valid until the
/// mesh is freed.
///
/// # Safety
/// `mesh` must be a live handle; non-null outputs writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_mesh_arrays(
    mesh: *const SurfkitMesh,
    positions: *mut *const f64,
    face_offsets: *mut *const u32,
    face_indices: *mut *const u32,
) -> c_int {
    guard(|| {
        clear(positions, null());
        clear(face_offsets, null());
        clear(face_indices, null());
        let m = &reference(mesh, "mesh")?.mesh;
        if let Some(slot) = positions.as_mut() {
            *slot = m.positions_flat().as_ptr();
        }
        if let Some(slot) = face_offsets.as_mut() {
            *slot = m.face_offsets.as_ptr();
        }
        if let Some(slot) = face_indices.as_mut() {
            *slot = m.face_indices.as_ptr();
        }
        Ok(())
    })
}

/// Frees a mesh (null is ignored).
///
/// # Safety
/// `mesh` must be null or a handle not freed before.
#[no_mangle]
pub unsafe extern "C" fn surfkit_mesh_free(mesh: *mut SurfkitMesh) {
    let _ = guard(|| {
        take(mesh);
        Ok(())
    });
}
