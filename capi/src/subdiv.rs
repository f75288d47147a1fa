//! Catmull–Clark with OpenSubdiv: uniform refinement to a new mesh, and the limit surface
//! as an evaluator handle (positions, derivatives to 3rd order, normals and curvature at
//! (ptex face, u, v)).

use std::ffi::c_int;

use surfkit::subdiv::{
    curvature, limit_surface, refine_uniform, BoundaryInterpolation, Corner, Crease,
    CreasingMethod, Derivatives, PatchOptions, PatchSurface, SubdivOptions,
};

use crate::mesh::SurfkitMesh;
use crate::pointers::{clear, give, output, reference, slice, slice_mut, take};
use crate::status::{guard, Failure};

/// Boundary rule: no limit surface on boundary faces.
pub const SURFKIT_BOUNDARY_NONE: c_int = 0;
/// Boundary edges infinitely sharp.
pub const SURFKIT_BOUNDARY_EDGES: c_int = 1;
/// Boundary edges and corners infinitely sharp (the default).
pub const SURFKIT_BOUNDARY_EDGES_AND_CORNERS: c_int = 2;
/// Crease sharpness drops by 1 per level.
pub const SURFKIT_CREASING_UNIFORM: c_int = 0;
/// Chaikin's rule: sharpness averaged along a crease.
pub const SURFKIT_CREASING_CHAIKIN: c_int = 1;

/// Sharp features and rules; start from [`surfkit_subdiv_options_default`].
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct SurfkitSubdivOptions {
    /// `SURFKIT_BOUNDARY_*`.
    pub boundary: c_int,
    /// `SURFKIT_CREASING_*`.
    pub creasing: c_int,
    /// `crease_count` edges as vertex pairs (2 ids each) with their sharpness (0 smooth,
    /// k sharp for k levels, ≥ 10 infinitely sharp).
    pub crease_vertices: *const u32,
    pub crease_sharpness: *const f32,
    pub crease_count: usize,
    /// `corner_count` sharp vertices with their sharpness.
    pub corner_vertices: *const u32,
    pub corner_sharpness: *const f32,
    pub corner_count: usize,
}

/// Smooth surface, boundary edges and corners sharp, uniform creasing, no crease.
///
/// # Safety
/// `options` must be writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_subdiv_options_default(
    options: *mut SurfkitSubdivOptions,
) -> c_int {
    guard(|| {
        *output(options, "options")? = SurfkitSubdivOptions {
            boundary: SURFKIT_BOUNDARY_EDGES_AND_CORNERS,
            creasing: SURFKIT_CREASING_UNIFORM,
            crease_vertices: std::ptr::null(),
            crease_sharpness: std::ptr::null(),
            crease_count: 0,
            corner_vertices: std::ptr::null(),
            corner_sharpness: std::ptr::null(),
            corner_count: 0,
        };
        Ok(())
    })
}

pub(crate) unsafe fn subdiv_options(
    options: *const SurfkitSubdivOptions,
) -> Result<SubdivOptions, Failure> {
    let Some(o) = options.as_ref() else {
        return Ok(SubdivOptions::default());
    };
    let boundary = match o.boundary {
        SURFKIT_BOUNDARY_NONE => BoundaryInterpolation::None,
        SURFKIT_BOUNDARY_EDGES => BoundaryInterpolation::EdgesOnly,
        SURFKIT_BOUNDARY_EDGES_AND_CORNERS => BoundaryInterpolation::EdgesAndCorners,
        b => {
            return Err(Failure::invalid(format!(
                "boundary rule {b} is not one of SURFKIT_BOUNDARY_*"
            )))
        }
    };
    let creasing = match o.creasing {
        SURFKIT_CREASING_UNIFORM => CreasingMethod::Uniform,
        SURFKIT_CREASING_CHAIKIN => CreasingMethod::Chaikin,
        c => {
            return Err(Failure::invalid(format!(
                "creasing method {c} is not one of SURFKIT_CREASING_*"
            )))
        }
    };
    let pairs = slice(
        o.crease_vertices,
        o.crease_count
            .checked_mul(2)
            .ok_or_else(|| Failure::invalid("crease_count overflows"))?,
        "crease_vertices",
    )?;
    let sharpness = slice(o.crease_sharpness, o.crease_count, "crease_sharpness")?;
    let corners = slice(o.corner_vertices, o.corner_count, "corner_vertices")?;
    let corner_sharpness = slice(o.corner_sharpness, o.corner_count, "corner_sharpness")?;
    Ok(SubdivOptions {
        creases: pairs
            .chunks_exact(2)
            .zip(sharpness)
            .map(|(p, &s)| Crease {
                vertices: [p[0], p[1]],
                sharpness: s,
            })
            .collect(),
        corners: corners
            .iter()
            .zip(corner_sharpness)
            .map(|(&vertex, &sharpness)| Corner { vertex, sharpness })
            .collect(),
        boundary,
        creasing,
        ..Default::default()
    })
}

/// `levels` uniform Catmull–Clark refinements (0–10) of `mesh` into a new mesh (quads;
/// the control vertices keep their ids, new vertices follow).
///
/// # Safety
/// `mesh` must be a live handle, `options` null or valid, `out` writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_subdivide(
    mesh: *const SurfkitMesh,
    levels: u32,
    options: *const SurfkitSubdivOptions,
    out: *mut *mut SurfkitMesh,
) -> c_int {
    guard(|| {
        clear(out, std::ptr::null_mut());
        let out = output(out, "out")?;
        let mesh = &reference(mesh, "mesh")?.mesh;
        let options = subdiv_options(options)?;
        give(
            out,
            SurfkitMesh {
                mesh: refine_uniform(mesh, levels, &options)?,
            },
        );
        Ok(())
    })
}

/// An opaque limit surface (free with [`surfkit_limit_free`]).
pub struct SurfkitLimit {
    surface: PatchSurface,
}

/// The limit surface of `mesh` as bicubic patches, end caps after `max_isolation` (1–10;
/// 4 is OpenSubdiv's usual) levels of feature-adaptive refinement.
///
/// # Safety
/// `mesh` must be a live handle, `options` null or valid, `out` writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_limit_new(
    mesh: *const SurfkitMesh,
    options: *const SurfkitSubdivOptions,
    max_isolation: u32,
    out: *mut *mut SurfkitLimit,
) -> c_int {
    guard(|| {
        clear(out, std::ptr::null_mut());
        let out = output(out, "out")?;
        let mesh = &reference(mesh, "mesh")?.mesh;
        let options = subdiv_options(options)?;
        let surface = limit_surface(
            mesh,
            &options,
            &PatchOptions {
                max_isolation,
                ..PatchOptions::default()
            },
        )?;
        give(out, SurfkitLimit { surface });
        Ok(())
    })
}

/// The ptex faces of control face `face`: `first .. first + count` (one for a quad, n for
/// an n-gon, whose ptex face i starts at its corner i).
///
/// # Safety
/// `limit` must be a live handle; outputs writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_limit_ptex_faces(
    limit: *const SurfkitLimit,
    face: u32,
    first: *mut u32,
    count: *mut u32,
) -> c_int {
    guard(|| {
        clear(first, 0);
        clear(count, 0);
        let range = reference(limit, "limit")?
            .surface
            .ptex_faces(face as usize)?;
        let (first, count) = (output(first, "first")?, output(count, "count")?);
        *first = range.start;
        *count = range.end - range.start;
        Ok(())
    })
}

unsafe fn points(
    surface: &PatchSurface,
    count: usize,
    ptex: *const u32,
    u: *const f64,
    v: *const f64,
) -> Result<Vec<Derivatives>, Failure> {
    let ptex = slice(ptex, count, "ptex_faces")?;
    let u = slice(u, count, "u")?;
    let v = slice(v, count, "v")?;
    let points = surface.surface_points(ptex, u, v)?;
    Ok(surface.evaluate(&points)?)
}

/// Evaluates `count` points (ptex face, u, v): `derivatives` receives 30 doubles per
/// point — position, S_u, S_v, S_uu, S_uv, S_vv, S_uuu, S_uuv, S_uvv, S_vvv (x, y, z each),
/// with respect to the ptex face's (u, v). On any failure `derivatives` is all NaN.
///
/// # Safety
/// `limit` must be a live handle; input arrays of `count` elements; `derivatives` of
/// `30 · count`.
#[no_mangle]
pub unsafe extern "C" fn surfkit_limit_evaluate(
    limit: *const SurfkitLimit,
    count: usize,
    ptex_faces: *const u32,
    u: *const f64,
    v: *const f64,
    derivatives: *mut f64,
) -> c_int {
    guard(|| {
        let out = slice_mut(
            derivatives,
            count
                .checked_mul(30)
                .ok_or_else(|| Failure::invalid("count overflows"))?,
            "derivatives",
        )?;
        // NaN until every point is evaluated: a failed call leaves no stale numbers.
        out.fill(f64::NAN);
        let surface = &reference(limit, "limit")?.surface;
        for (d, chunk) in points(surface, count, ptex_faces, u, v)?
            .iter()
            .zip(out.chunks_exact_mut(30))
        {
            let all = [
                d.position, d.du, d.dv, d.duu, d.duv, d.dvv, d.duuu, d.duuv, d.duvv, d.dvvv,
            ];
            chunk.copy_from_slice(all.as_flattened());
        }
        Ok(())
    })
}

/// Unit normals (3 per point) and mean, Gaussian and principal curvatures (k1 ≥ k2) at
/// `count` points; any output may be null. Signs: the normal is S_u × S_v normalized, and
/// curvature is positive where the surface bends towards it. A point without a normal
/// (vanishing tangents) is an error naming the point. On any failure the non-null outputs
/// are all NaN.
///
/// # Safety
/// `limit` must be a live handle; inputs of `count` elements; non-null outputs of
/// `3 · count` (normals) or `count` elements.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn surfkit_limit_curvature(
    limit: *const SurfkitLimit,
    count: usize,
    ptex_faces: *const u32,
    u: *const f64,
    v: *const f64,
    normals: *mut f64,
    mean: *mut f64,
    gaussian: *mut f64,
    k1: *mut f64,
    k2: *mut f64,
) -> c_int {
    guard(|| {
        let optional = |p: *mut f64, n: usize, what: &str| -> Result<Option<&mut [f64]>, Failure> {
            if p.is_null() {
                Ok(None)
            } else {
                slice_mut(p, n, what).map(Some)
            }
        };
        let triples = count
            .checked_mul(3)
            .ok_or_else(|| Failure::invalid("count overflows"))?;
        let mut normals = optional(normals, triples, "normals")?;
        let mut outputs = [
            optional(mean, count, "mean")?,
            optional(gaussian, count, "gaussian")?,
            optional(k1, count, "k1")?,
            optional(k2, count, "k2")?,
        ];
        // NaN until every point is evaluated: a failed call leaves no stale numbers.
        for slot in outputs.iter_mut().chain([&mut normals]).flatten() {
            slot.fill(f64::NAN);
        }
        let surface = &reference(limit, "limit")?.surface;
        let curvatures = points(surface, count, ptex_faces, u, v)?
            .iter()
            .enumerate()
            .map(|(i, d)| curvature(d).map_err(|e| Failure::from(e).at_point(i)))
            .collect::<Result<Vec<_>, Failure>>()?;
        for (i, c) in curvatures.iter().enumerate() {
            if let Some(n) = normals.as_deref_mut() {
                n[3 * i..3 * i + 3].copy_from_slice(&c.normal);
            }
            for (slot, value) in outputs.iter_mut().zip([c.mean, c.gaussian, c.k1, c.k2]) {
                if let Some(s) = slot.as_deref_mut() {
                    s[i] = value;
                }
            }
        }
        Ok(())
    })
}

/// Frees a limit surface (null is ignored).
///
/// # Safety
/// `limit` must be null or a handle not freed before.
#[no_mangle]
pub unsafe extern "C" fn surfkit_limit_free(limit: *mut SurfkitLimit) {
    let _ = guard(|| {
        take(limit);
        Ok(())
    });
}
