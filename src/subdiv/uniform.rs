//! Uniform Catmull–Clark refinement: every face split `levels` times, quads out.

use crate::error::{Error, Result};
use crate::ffi::opensubdiv as ffi;
use crate::limits::MemoryBudget;
use crate::mesh::{CornerUvs, PolygonMesh};
use crate::subdiv::topology::ControlMesh;
use crate::subdiv::SubdivOptions;

/// The most levels accepted: OpenSubdiv's own cap.
pub const MAX_LEVELS: u32 = 10;

/// Peak bytes per face of the last level of a uniform refinement: OpenSubdiv's refiner
/// (every level), the refined mesh and its file (measured: 2 097 152 quads in 642 MB).
pub const BYTES_PER_REFINED_FACE: u64 = 320;

/// The quads of `levels` uniform Catmull–Clark levels of `mesh`: an n-gon makes n quads,
/// each of which makes 4 per further level (saturating at `u64::MAX`).
pub fn refined_face_count(mesh: &PolygonMesh, levels: u32) -> u64 {
    if levels == 0 {
        return mesh.face_count() as u64;
    }
    let first: u64 = mesh.faces().map(|f| f.len() as u64).sum();
    let growth = 1u64.checked_shl(2 * (levels - 1)).unwrap_or(u64::MAX);
    first.saturating_mul(growth)
}

/// Refuses `levels` of `mesh` where the last level's quads would pass `memory` at
/// [`BYTES_PER_REFINED_FACE`] each, naming the most levels that fit.
pub(crate) fn check_memory(mesh: &PolygonMesh, levels: u32, memory: MemoryBudget) -> Result<()> {
    let fits =
        |l: u32| refined_face_count(mesh, l).saturating_mul(BYTES_PER_REFINED_FACE) <= memory.get();
    if fits(levels) {
        return Ok(());
    }
    Err(Error::ResourceLimit {
        what: format!(
            "{levels} levels of refinement ({} quads)",
            refined_face_count(mesh, levels)
        ),
        limit: memory.get(),
        advice: match (0..levels).rev().find(|&l| fits(l)) {
            Some(l) if l > 0 => format!("{l} levels fit"),
            _ => "not even one level fits".into(),
        },
    })
}

/// Refines `mesh` uniformly `levels` times with Catmull–Clark's rules (OpenSubdiv's
/// `Far::TopologyRefiner::RefineUniform` + `PrimvarRefiner`, in doubles) and returns the last
/// level: a mesh of quads, with refined UVs when `mesh` has UVs (interpolated by
/// `options.face_varying`). `levels == 0` returns a copy of the positions, faces and UVs.
///
/// The refined mesh approximates the limit surface; it is not the limit surface (its faces
/// are bilinear). Use [`crate::subdiv::PatchSurface`] for limit positions and derivatives.
///
/// # Errors
/// [`Error::ResourceLimit`] where the refined mesh would pass the process's memory budget
/// ([`MemoryBudget::default`]); [`Error::InvalidInput`] for `levels > 10`, for a refined
/// mesh above `u32` or `i32` indices, and for the conditions of the control mesh (see `SubdivOptions`: creases must
/// be edges, sharpness finite and ≥ 0, faces of ≥ 3 corners); [`Error::Ffi`] when
/// OpenSubdiv refuses the topology.
pub fn refine_uniform(
    mesh: &PolygonMesh,
    levels: u32,
    options: &SubdivOptions,
) -> Result<PolygonMesh> {
    if levels > MAX_LEVELS {
        return Err(Error::InvalidInput(format!(
            "{levels} levels of refinement requested; at most {MAX_LEVELS} are supported"
        )));
    }
    check_memory(mesh, levels, MemoryBudget::default())?;
    let control = ControlMesh::new(mesh, options, true)?;
    if levels == 0 {
        return Ok(PolygonMesh {
            positions: mesh.positions.clone(),
            face_offsets: mesh.face_offsets.clone(),
            face_indices: mesh.face_indices.clone(),
            uvs: mesh.uvs.clone(),
            ..Default::default()
        });
    }
    // Each level turns every corner into a quad: the last level has corners · 4^(levels−1)
    // faces and 4 times as many corners. Refuse what overflows 32-bit indices up front.
    let corners = mesh.face_indices.len() as u128;
    if corners * 4u128.pow(levels) > i32::MAX as u128 {
        return Err(Error::InvalidInput(format!(
            "{levels} levels would give {} face corners, beyond OpenSubdiv's 32-bit indices",
            corners * 4u128.pow(levels)
        )));
    }
    // The mesh's coordinates, then the stand-ins of faces without (see `ControlMesh`).
    let uv_coords: Vec<[f64; 2]> = match &mesh.uvs {
        Some(uv) if control.num_uvs > 0 => {
            let stand_ins = control.num_uvs - uv.coords.len();
            let stand_in = std::iter::repeat_n(CornerUvs::UNTEXTURED_VALUE, stand_ins);
            uv.coords.iter().copied().chain(stand_in).collect()
        }
        _ => Vec::new(),
    };
    let level = ffi::refine_uniform(
        &control.topology(),
        levels as i32,
        &mesh.positions,
        &uv_coords,
    )?;
    let nf = level.face_vertices.len() / 4;
    let uvs = (control.num_uvs > 0).then_some(CornerUvs {
        coords: level.fvar_values,
        corner_indices: level.fvar_indices,
        untextured: None,
    });
    let uvs = match (uvs, &mesh.uvs) {
        (Some(refined), Some(control_uvs)) if control_uvs.untextured.is_some() => {
            Some(untextured_children(control_uvs, levels, refined))
        }
        (uvs, _) => uvs,
    };
    Ok(PolygonMesh {
        positions: level.positions,
        face_offsets: (0..=nf as u32).map(|f| 4 * f).collect(),
        face_indices: level.face_vertices,
        uvs,
        ..Default::default()
    })
}

/// The refined UVs with the children of each control face that had no texture coordinates
/// pointing to one stand-in again (the last coordinate), and the values OpenSubdiv refined
/// from the stand-ins dropped, the others kept in order.
///
/// OpenSubdiv numbers child faces consecutively per parent face, one per parent corner, so
/// refined face `f` descends from control corner `f / 4^(levels − 1)` (`levels ≥ 1`).
fn untextured_children(control: &CornerUvs, levels: u32, refined: CornerUvs) -> CornerUvs {
    let shift = 2 * (levels - 1);
    let textured = |corner: usize| control.is_textured((corner / 4) >> shift);
    let mut used = vec![false; refined.coords.len()];
    for (k, &t) in refined.corner_indices.iter().enumerate() {
        used[t as usize] |= textured(k);
    }
    let mut coords = Vec::with_capacity(refined.coords.len());
    let new_index: Vec<u32> = (used.iter().zip(&refined.coords))
        .map(|(&used, &uv)| {
            if used {
                coords.push(uv);
            }
            coords.len() as u32 - u32::from(used)
        })
        .collect();
    let stand_in = coords.len() as u32;
    coords.push(CornerUvs::UNTEXTURED_VALUE);
    let corner_indices = refined
        .corner_indices
        .iter()
        .enumerate()
        .map(|(k, &t)| {
            if textured(k) {
                new_index[t as usize]
            } else {
                stand_in
            }
        })
        .collect();
    CornerUvs {
        coords,
        corner_indices,
        untextured: Some(stand_in),
    }
}
