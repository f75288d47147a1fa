//! bindgen's bindings of `cpp/opensubdiv/shim.h` (allowlist `surfkit_osd_*`), and the thin
//! safe wrappers `subdiv` calls: slices in, owned vectors out, every shim status turned into
//! [`Error::Ffi`] with the shim's message (freed here, exactly once).

use std::ffi::CStr;
use std::os::raw::c_char;
use std::ptr;

use crate::error::{Error, Result};

#[allow(
    non_upper_case_globals,
    non_camel_case_types,
    non_snake_case,
    dead_code
)]
mod raw {
    include!(concat!(env!("OUT_DIR"), "/opensubdiv_shim.rs"));
}

const LIBRARY: &str = "OpenSubdiv";

/// Turns a shim status and message into a `Result`, freeing the message once.
/// Status of `surfkit_osd_patches_create` when the stencils would pass their budget.
const OVER_BUDGET: i32 = 3;

fn check(status: i32, message: *mut c_char) -> Result<()> {
    let text = if message.is_null() {
        None
    } else {
        // SAFETY: the shim returns a NUL-terminated malloc'd string or NULL.
        let s = unsafe { CStr::from_ptr(message) }
            .to_string_lossy()
            .into_owned();
        // SAFETY: freed exactly once, by the shim's own allocator.
        unsafe { raw::surfkit_osd_free_message(message) };
        Some(s)
    };
    if status == 0 {
        return Ok(());
    }
    Err(Error::Ffi {
        library: LIBRARY,
        message: text.unwrap_or_else(|| format!("status {status} without a message")),
    })
}

/// OpenSubdiv's version as major*10000 + minor*100 + patch.
pub fn version() -> i32 {
    // SAFETY: no arguments, no state.
    unsafe { raw::surfkit_osd_version() }
}

/// Refines a cube once and checks the counts (links and runs).
pub fn self_test() -> Result<()> {
    let mut msg = ptr::null_mut();
    // SAFETY: msg is a valid out pointer.
    let status = unsafe { raw::surfkit_osd_self_test(&mut msg) };
    check(status, msg)
}

/// A control mesh as the shim takes it: borrowed flat arrays and Sdc option values.
/// The caller (`subdiv`) has validated indices and lengths.
pub struct Topology<'a> {
    pub num_vertices: i32,
    pub verts_per_face: &'a [i32],
    pub face_vertices: &'a [i32],
    pub crease_vertex_pairs: &'a [i32],
    pub crease_sharpness: &'a [f32],
    pub corner_vertices: &'a [i32],
    pub corner_sharpness: &'a [f32],
    /// Number of face-varying values (0: no channel) and per-corner indices.
    pub num_fvar_values: i32,
    pub fvar_indices: &'a [i32],
    pub vtx_boundary_interpolation: i32,
    pub fvar_linear_interpolation: i32,
    pub creasing_method: i32,
    pub triangle_subdivision: i32,
}

impl Topology<'_> {
    fn raw(&self) -> Result<raw::surfkit_osd_topology> {
        let ok = self.face_vertices.len()
            == self
                .verts_per_face
                .iter()
                .map(|&n| n as usize)
                .sum::<usize>()
            && self.crease_vertex_pairs.len() == 2 * self.crease_sharpness.len()
            && self.corner_vertices.len() == self.corner_sharpness.len()
            && (self.num_fvar_values == 0 || self.fvar_indices.len() == self.face_vertices.len());
        if !ok {
            return Err(Error::InvalidInput(
                "OpenSubdiv topology arrays have inconsistent lengths".into(),
            ));
        }
        Ok(raw::surfkit_osd_topology {
            num_vertices: self.num_vertices,
            num_faces: self.verts_per_face.len() as i32,
            verts_per_face: self.verts_per_face.as_ptr(),
            face_vertices: self.face_vertices.as_ptr(),
            num_creases: self.crease_sharpness.len() as i32,
            crease_vertex_pairs: self.crease_vertex_pairs.as_ptr(),
            crease_sharpness: self.crease_sharpness.as_ptr(),
            num_corners: self.corner_sharpness.len() as i32,
            corner_vertices: self.corner_vertices.as_ptr(),
            corner_sharpness: self.corner_sharpness.as_ptr(),
            num_fvar_values: self.num_fvar_values,
            fvar_indices: self.fvar_indices.as_ptr(),
            vtx_boundary_interpolation: self.vtx_boundary_interpolation,
            fvar_linear_interpolation: self.fvar_linear_interpolation,
            creasing_method: self.creasing_method,
            triangle_subdivision: self.triangle_subdivision,
        })
    }
}

/// The last level of a uniform refinement: quads only, in the layout `PolygonMesh` keeps,
/// so that the shim writes the result in place without further copies.
pub struct UniformLevel {
    pub positions: Vec<[f64; 3]>,
    /// 4 per face.
    pub face_vertices: Vec<u32>,
    /// Empty without a face-varying channel.
    pub fvar_values: Vec<[f64; 2]>,
    /// 4 per face (empty without a channel).
    pub fvar_indices: Vec<u32>,
}

/// Uniform Catmull–Clark refinement by `levels` (1..=10) of `positions` and of
/// `fvar_values` when the topology has a face-varying channel.
pub fn refine_uniform(
    topology: &Topology,
    levels: i32,
    positions: &[[f64; 3]],
    fvar_values: &[[f64; 2]],
) -> Result<UniformLevel> {
    let t = topology.raw()?;
    if positions.len() != topology.num_vertices as usize
        || fvar_values.len() != topology.num_fvar_values as usize
    {
        return Err(Error::InvalidInput(
            "positions or face-varying values do not match the topology".into(),
        ));
    }
    let mut handle = ptr::null_mut();
    let mut counts = raw::surfkit_osd_uniform_counts {
        num_vertices: 0,
        num_faces: 0,
        num_fvar_values: 0,
    };
    let mut msg = ptr::null_mut();
    // SAFETY: every pointer in `t` borrows a live slice of the length the counts say
    // (checked in `raw`); out pointers valid.
    let status =
        unsafe { raw::surfkit_osd_uniform_create(&t, levels, &mut handle, &mut counts, &mut msg) };
    check(status, msg)?;
    let guard = UniformHandle(handle);
    let nv = counts.num_vertices as usize;
    let nf = counts.num_faces as usize;
    let nfv = counts.num_fvar_values as usize;
    let mut out = UniformLevel {
        positions: vec![[0.0; 3]; nv],
        face_vertices: vec![0; 4 * nf],
        fvar_values: vec![[0.0; 2]; nfv],
        fvar_indices: vec![0; if nfv > 0 { 4 * nf } else { 0 }],
    };
    let mut msg = ptr::null_mut();
    // SAFETY: output arrays sized from the counts the shim reported for this handle;
    // [f64; N] arrays are N contiguous doubles; u32 and i32 share size and alignment and
    // OpenSubdiv's indices are non-negative. Inputs checked against the topology above.
    let status = unsafe {
        raw::surfkit_osd_uniform_copy(
            guard.0,
            positions.as_flattened().as_ptr(),
            fvar_values.as_flattened().as_ptr(),
            out.positions.as_flattened_mut().as_mut_ptr(),
            out.face_vertices.as_mut_ptr().cast::<i32>(),
            out.fvar_values.as_flattened_mut().as_mut_ptr(),
            out.fvar_indices.as_mut_ptr().cast::<i32>(),
            &mut msg,
        )
    };
    check(status, msg)?;
    Ok(out)
}

struct UniformHandle(*mut raw::surfkit_osd_uniform);

impl Drop for UniformHandle {
    fn drop(&mut self) {
        // SAFETY: created by surfkit_osd_uniform_create, destroyed once.
        unsafe { raw::surfkit_osd_uniform_destroy(self.0) }
    }
}

/// Everything Rust needs of an adaptive patch table (see `shim.h` for each field).
#[derive(Debug, Clone)]
pub struct PatchData {
    pub num_control_vertices: usize,
    pub num_patch_points: usize,
    pub num_ptex_faces: usize,
    pub patch_points: Vec<i32>,
    pub ptex_face: Vec<i32>,
    pub depth: Vec<i32>,
    pub boundary_mask: Vec<i32>,
    pub is_regular: Vec<i32>,
    pub u0: Vec<f64>,
    pub v0: Vec<f64>,
    pub size: Vec<f64>,
    pub ptex_of_face: Vec<i32>,
}

/// The stencils of the patch points beyond the control vertices, borrowed from the table
/// (see `surfkit_osd_stencils` in `shim.h`): the refined points' then the end caps' local
/// points'. Point `ncv + s` has stencil `s`.
#[derive(Debug, Clone, Copy)]
pub struct Stencils<'a> {
    refined_offsets: &'a [usize],
    refined_indices: &'a [i32],
    refined_weights: &'a [f64],
    local_offsets: &'a [i32],
    local_sizes: &'a [i32],
    local_indices: &'a [i32],
    local_weights: &'a [f64],
}

impl<'a> Stencils<'a> {
    /// Number of stencils.
    pub fn len(&self) -> usize {
        self.refined_offsets.len() - 1 + self.local_offsets.len()
    }

    /// Point indices and weights of stencil `s`; empty for an `s` out of range or a range
    /// the table got wrong ([`Stencils::well_formed`] says whether any is).
    pub fn get(&self, s: usize) -> (&'a [i32], &'a [f64]) {
        let refined = self.refined_offsets.len() - 1;
        let range = if s < refined {
            Some(self.refined_offsets[s]..self.refined_offsets[s + 1])
        } else {
            let k = s - refined;
            match (self.local_offsets.get(k), self.local_sizes.get(k)) {
                (Some(&o), Some(&n)) if o >= 0 && n >= 0 => Some(o as usize..(o + n) as usize),
                _ => None,
            }
        };
        let (indices, weights) = if s < refined {
            (self.refined_indices, self.refined_weights)
        } else {
            (self.local_indices, self.local_weights)
        };
        range
            .and_then(|r| Some((indices.get(r.clone())?, weights.get(r)?)))
            .unwrap_or_default()
    }

    /// Every range inside its arrays, and every stencil of point `ncv + s` on points
    /// before it (`ncv` control vertices).
    pub fn well_formed(&self, ncv: usize) -> bool {
        let refined = self.refined_offsets.len() - 1;
        let ranges_ok = self.refined_offsets.windows(2).all(|w| w[0] <= w[1])
            && self.refined_offsets[refined] == self.refined_indices.len()
            && self
                .local_offsets
                .iter()
                .zip(self.local_sizes)
                .all(|(&o, &n)| {
                    o >= 0 && n >= 0 && (o as usize + n as usize) <= self.local_indices.len()
                });
        ranges_ok
            && (0..self.len()).all(|s| {
                let (indices, weights) = self.get(s);
                indices.len() == weights.len()
                    && indices.iter().all(|&i| i >= 0 && (i as usize) < ncv + s)
            })
    }
}

/// A slice from a pointer the shim may leave null when `len` is 0.
///
/// # Safety
/// A non-null `ptr` must point to `len` initialised values that outlive `'a`.
unsafe fn view<'a, T>(ptr: *const T, len: usize) -> &'a [T] {
    if ptr.is_null() || len == 0 {
        &[]
    } else {
        std::slice::from_raw_parts(ptr, len)
    }
}

/// An OpenSubdiv patch table (feature-adaptive, B-spline end caps, doubles), owned.
pub struct PatchTable {
    handle: *mut raw::surfkit_osd_patches,
    counts: raw::surfkit_osd_patch_counts,
    /// Where the table keeps its stencils, asked once (the pointers live as long as the
    /// handle): [`PatchTable::stencils`] is read per patch on the fairing's hot path.
    stencils: raw::surfkit_osd_stencils,
}

// SAFETY: the table is immutable after creation and the shim's evaluation only reads it.
unsafe impl Send for PatchTable {}
// SAFETY: as above, read-only use.
unsafe impl Sync for PatchTable {}

impl Drop for PatchTable {
    fn drop(&mut self) {
        // SAFETY: created by surfkit_osd_patches_create, destroyed once.
        unsafe { raw::surfkit_osd_patches_destroy(self.handle) }
    }
}

impl PatchTable {
    /// Builds the table by adaptive refinement to `max_isolation` (1..=10), or to the highest
    /// level whose refined vertices stay within `max_refined_points`
    /// ([`PatchTable::isolation`]); `None` when even level 1 passes that or the stencils
    /// would pass `max_stencil_weights` entries (nothing is kept).
    pub fn new(
        topology: &Topology,
        max_isolation: i32,
        max_refined_points: usize,
        max_stencil_weights: usize,
    ) -> Result<Option<PatchTable>> {
        let t = topology.raw()?;
        let mut handle = ptr::null_mut();
        let mut counts = raw::surfkit_osd_patch_counts {
            num_patches: 0,
            num_ptex_faces: 0,
            num_control_vertices: 0,
            num_patch_points: 0,
            num_stencil_weights: 0,
            isolation: 0,
        };
        let limits = raw::surfkit_osd_patch_limits {
            max_refined_points,
            max_stencil_weights,
        };
        let mut msg = ptr::null_mut();
        // SAFETY: `t` borrows live slices of checked lengths; out pointers valid.
        let status = unsafe {
            raw::surfkit_osd_patches_create(
                &t,
                max_isolation,
                &limits,
                &mut handle,
                &mut counts,
                &mut msg,
            )
        };
        if status == OVER_BUDGET {
            check(0, msg)?; // frees the message
            return Ok(None);
        }
        check(status, msg)?;
        let mut table = PatchTable {
            handle,
            counts,
            stencils: raw::surfkit_osd_stencils {
                refined_count: 0,
                refined_offsets: ptr::null(),
                refined_indices: ptr::null(),
                refined_weights: ptr::null(),
                local_count: 0,
                local_offsets: ptr::null(),
                local_sizes: ptr::null(),
                local_entries: 0,
                local_indices: ptr::null(),
                local_weights: ptr::null(),
            },
        };
        let mut msg = ptr::null_mut();
        // SAFETY: live handle, the view struct writable; `table` frees the handle on error.
        let status = unsafe {
            raw::surfkit_osd_patches_stencils(table.handle, &mut table.stencils, &mut msg)
        };
        check(status, msg)?;
        // The composer always holds offset 0: stencils() can index it.
        if table.stencils.refined_offsets.is_null() {
            return Err(Error::Ffi {
                library: "OpenSubdiv",
                message: "the shim reported no stencil offsets".into(),
            });
        }
        Ok(Some(table))
    }

    /// The isolation level the table was built with.
    pub fn isolation(&self) -> u32 {
        self.counts.isolation as u32
    }

    /// Copies the table's per-patch arrays out in one call (the stencils stay in the table:
    /// [`PatchTable::stencils`]).
    pub fn data(&self, num_faces: usize) -> Result<PatchData> {
        let c = &self.counts;
        let np = c.num_patches as usize;
        let mut d = PatchData {
            num_control_vertices: c.num_control_vertices as usize,
            num_patch_points: c.num_patch_points as usize,
            num_ptex_faces: c.num_ptex_faces as usize,
            patch_points: vec![0; 16 * np],
            ptex_face: vec![0; np],
            depth: vec![0; np],
            boundary_mask: vec![0; np],
            is_regular: vec![0; np],
            u0: vec![0.0; np],
            v0: vec![0.0; np],
            size: vec![0.0; np],
            ptex_of_face: vec![0; num_faces + 1],
        };
        let arrays = raw::surfkit_osd_patch_arrays {
            patch_points: d.patch_points.as_mut_ptr(),
            ptex_face: d.ptex_face.as_mut_ptr(),
            depth: d.depth.as_mut_ptr(),
            boundary_mask: d.boundary_mask.as_mut_ptr(),
            is_regular: d.is_regular.as_mut_ptr(),
            u0: d.u0.as_mut_ptr(),
            v0: d.v0.as_mut_ptr(),
            size: d.size.as_mut_ptr(),
            ptex_of_face: d.ptex_of_face.as_mut_ptr(),
        };
        let mut msg = ptr::null_mut();
        // SAFETY: every array sized from the counts of this handle; num_faces is the base
        // face count the topology was created with (caller's invariant).
        let status = unsafe { raw::surfkit_osd_patches_copy(self.handle, &arrays, &mut msg) };
        check(status, msg)?;
        Ok(d)
    }

    /// The stencils of the patch points beyond the control vertices, where the table keeps
    /// them.
    pub fn stencils(&self) -> Stencils<'_> {
        let v = &self.stencils;
        // SAFETY: the shim's vectors live as long as the handle, which `self` borrows, and are
        // never resized after creation; their lengths are the counts it reported
        // (refined_offsets, checked non-null in `new`, has refined_count + 1 entries).
        unsafe {
            let refined_offsets = view(v.refined_offsets, v.refined_count + 1);
            let refined_len = refined_offsets[v.refined_count];
            Stencils {
                refined_offsets,
                refined_indices: view(v.refined_indices, refined_len),
                refined_weights: view(v.refined_weights, refined_len),
                local_offsets: view(v.local_offsets, v.local_count),
                local_sizes: view(v.local_sizes, v.local_count),
                local_indices: view(v.local_indices, v.local_entries),
                local_weights: view(v.local_weights, v.local_entries),
            }
        }
    }

    /// OpenSubdiv's `EvaluateBasis` at `(patch[i], u[i], v[i])`: 96 weights per point
    /// (P, Du, Dv, Duu, Duv, Dvv, 16 each).
    pub fn evaluate_basis(&self, patch: &[i32], u: &[f64], v: &[f64]) -> Result<Vec<f64>> {
        let n = patch.len();
        if u.len() != n || v.len() != n {
            return Err(Error::InvalidInput(
                "evaluate_basis: patch, u and v differ in length".into(),
            ));
        }
        let mut w = vec![0.0; 96 * n];
        let mut msg = ptr::null_mut();
        // SAFETY: all slices have n entries, w has 96 n; the shim checks patch indices.
        let status = unsafe {
            raw::surfkit_osd_patches_evaluate_basis(
                self.handle,
                n as i32,
                patch.as_ptr(),
                u.as_ptr(),
                v.as_ptr(),
                w.as_mut_ptr(),
                &mut msg,
            )
        };
        check(status, msg)?;
        Ok(w)
    }
}
