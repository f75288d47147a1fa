//! Kiciak's shape optimization of a Catmull–Clark control mesh: `surfkit_fair` with the
//! options of `surfkit fair`, a per-iteration callback that can cancel, the optimized mesh
//! as a new handle (same topology and vertex order when no refinement was needed) and a
//! report.

use std::ffi::{c_char, c_int, c_void, CString};
use std::ops::ControlFlow;

use surfkit::fair::{
    optimize_observed, CoarseStart, FairMethod, FairOptions, FairReport, Iteration, StepKind,
    SurfaceKind,
};

use crate::mesh::SurfkitMesh;
use crate::pointers::{clear, give, output, reference, slice, take};
use crate::status::{guard, Failure};

/// One Newton / Levenberg–Marquardt iteration, for progress display.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct SurfkitFairIteration {
    /// 1-based iteration number of the run (warm-start stage included).
    pub iteration: usize,
    /// F = S + c·Q, S and Q after the step.
    pub f: f64,
    pub s: f64,
    pub q: f64,
    /// ‖∇F‖ after the step, and at the start of the stage.
    pub gradient_norm: f64,
    pub initial_gradient_norm: f64,
    /// Non-zero for a Levenberg–Marquardt step.
    pub levenberg_marquardt: c_int,
}

/// Called after every iteration with the caller's `user_data`; a non-zero return cancels
/// the run (the positions reached are returned, `cancelled` set in the summary).
pub type SurfkitFairCallback = Option<
    unsafe extern "C" fn(iteration: *const SurfkitFairIteration, user_data: *mut c_void) -> c_int,
>;

/// `SurfkitFairOptions::surface`: Kiciak's curvature-continuous surface (the default).
pub const SURFKIT_SURFACE_G2: c_int = 0;
/// `SurfkitFairOptions::surface`: the Catmull–Clark limit surface.
pub const SURFKIT_SURFACE_CATMULL_CLARK: c_int = 1;

/// `SurfkitFairOptions::method`: by size, as `surfkit fair --method auto` (the default).
pub const SURFKIT_METHOD_AUTO: c_int = 0;
/// `SurfkitFairOptions::method`: a sparse Cholesky factor of every Newton matrix.
pub const SURFKIT_METHOD_PLAIN: c_int = 1;
/// `SurfkitFairOptions::method`: conjugate gradients with a multigrid V-cycle over the
/// coarser control meshes (a Catmull–Clark refinement of more than 2000 free vertices).
pub const SURFKIT_METHOD_MULTILEVEL: c_int = 2;

/// Options of [`surfkit_fair`]; start from [`surfkit_fair_options_default`] (the defaults
/// of `surfkit fair`).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct SurfkitFairOptions {
    /// Vertices closer than this many edges to the boundary are fixed (the paper: 3).
    pub boundary_rings: u32,
    /// Most uniform refinements applied to meet the method's conditions; 0 keeps the
    /// input's topology (then the output has its vertex order, for writing back).
    pub max_refinements: u32,
    /// Stopping rule: ‖∇F‖ ≤ relative_gradient · ‖∇F₀‖, at most max_iterations steps.
    pub relative_gradient: f64,
    pub max_iterations: u32,
    /// The surface: [`SURFKIT_SURFACE_G2`] or [`SURFKIT_SURFACE_CATMULL_CLARK`].
    pub surface: c_int,
    /// OpenSubdiv's isolation level (Catmull–Clark surface) and Gauss–Legendre nodes per
    /// direction per patch.
    pub isolation: u32,
    pub nodes: u32,
    /// Cᵢ of the faces at special vertices (eq. 5); the default suits the G² surface (1);
    /// `surfkit fair --surface catmull-clark` uses 0.01.
    pub c_special: f64,
    /// C in F = S + C·c·Q (1: the paper's text; the author's program: 0.01).
    pub regularization: f64,
    /// How Newton's steps are solved: [`SURFKIT_METHOD_AUTO`], [`SURFKIT_METHOD_PLAIN`] or
    /// [`SURFKIT_METHOD_MULTILEVEL`].
    pub method: c_int,
    /// Non-zero: the multilevel method starts from the optimum of the mesh the input
    /// un-subdivides to, refined (nested iteration, `surfkit fair --coarse-start`): faster on
    /// the junctions measured, but it may end in another local minimum. Not used with fixed
    /// vertices given (their ids name fine vertices) nor by the plain method. 0 (the
    /// default): from the input.
    pub coarse_start: c_int,
    /// `fixed_count` more fixed vertices (ids of the input mesh).
    pub fixed: *const u32,
    pub fixed_count: usize,
    pub callback: SurfkitFairCallback,
    pub user_data: *mut c_void,
}

/// The defaults of `surfkit fair`.
///
/// # Safety
/// `options` must be writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_fair_options_default(options: *mut SurfkitFairOptions) -> c_int {
    guard(|| {
        let d = FairOptions::default();
        *output(options, "options")? = SurfkitFairOptions {
            boundary_rings: d.boundary_rings,
            max_refinements: d.max_refinements,
            relative_gradient: d.newton.relative_gradient,
            max_iterations: d.newton.max_iterations.min(u32::MAX as usize) as u32,
            surface: SURFKIT_SURFACE_G2,
            isolation: d.representation.isolation,
            nodes: d.representation.nodes as u32,
            c_special: d.representation.c_special,
            regularization: d.regularization,
            method: SURFKIT_METHOD_AUTO,
            coarse_start: 0,
            fixed: std::ptr::null(),
            fixed_count: 0,
            callback: None,
            user_data: std::ptr::null_mut(),
        };
        Ok(())
    })
}

/// What a run did.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct SurfkitFairSummary {
    /// The surface optimized ([`SURFKIT_SURFACE_G2`] or [`SURFKIT_SURFACE_CATMULL_CLARK`]).
    pub surface: c_int,
    /// The method that ran ([`SURFKIT_METHOD_PLAIN`] or [`SURFKIT_METHOD_MULTILEVEL`]).
    pub method: c_int,
    /// Non-zero when the coarse stage ran (`SurfkitFairOptions::coarse_start`).
    pub coarse_stage: c_int,
    /// Non-zero when the fine iteration started from the coarse optimum (0 when F there was
    /// not below the input's, and it started from the input).
    pub coarse_start_used: c_int,
    pub converged: c_int,
    pub cancelled: c_int,
    /// Stopped without converging where steps no longer decrease F or the gradient.
    pub stuck: c_int,
    /// Stopped above the tolerance within twice `coordinate_floor`, after choosing the
    /// coordinates' rounding: as close to the minimum as the run could bring
    /// double-precision coordinates (it did what it could; not `converged`).
    pub stalled: c_int,
    pub iterations: usize,
    pub hessian_evaluations: usize,
    pub refinements: u32,
    pub vertices: usize,
    pub free_vertices: usize,
    /// c of eq. 4 (|E|²/D⁴); Q's weight in F is regularization · c.
    pub c: f64,
    pub regularization: f64,
    pub f_before: f64,
    pub s_before: f64,
    pub q_before: f64,
    pub f_after: f64,
    pub s_after: f64,
    pub q_after: f64,
    pub gradient_norm_before: f64,
    pub gradient_norm_after: f64,
    /// The gradient norm that rounding the free coordinates to doubles gives (about the
    /// smallest stored positions can have); 0 when the run computed no Hessian.
    pub coordinate_floor: f64,
}

/// An opaque fairing report (free with [`surfkit_fair_report_free`]).
pub struct SurfkitFairReport {
    report: FairReport,
    json: Option<CString>,
}

unsafe fn fair_options(o: &SurfkitFairOptions) -> Result<FairOptions, Failure> {
    if !(o.relative_gradient > 0.0 && o.relative_gradient < 1.0) {
        return Err(Failure::invalid(format!(
            "relative_gradient {} must lie in (0, 1)",
            o.relative_gradient
        )));
    }
    if !(o.c_special > 0.0 && o.c_special.is_finite()) {
        return Err(Failure::invalid(format!(
            "c_special {} must be a finite number > 0",
            o.c_special
        )));
    }
    if !(o.regularization > 0.0 && o.regularization.is_finite()) {
        return Err(Failure::invalid(format!(
            "regularization {} must be a finite number > 0",
            o.regularization
        )));
    }
    let mut options = FairOptions {
        boundary_rings: o.boundary_rings,
        regularization: o.regularization,
        max_refinements: o.max_refinements,
        fixed: slice(o.fixed, o.fixed_count, "fixed")?.to_vec(),
        ..FairOptions::default()
    };
    options.representation.surface = match o.surface {
        SURFKIT_SURFACE_G2 => SurfaceKind::G2,
        SURFKIT_SURFACE_CATMULL_CLARK => SurfaceKind::CatmullClark,
        other => {
            return Err(Failure::invalid(format!(
                "surface {other}: use SURFKIT_SURFACE_G2 (0) or SURFKIT_SURFACE_CATMULL_CLARK (1)"
            )))
        }
    };
    options.method = match o.method {
        SURFKIT_METHOD_AUTO => FairMethod::Automatic,
        SURFKIT_METHOD_PLAIN => FairMethod::Plain,
        SURFKIT_METHOD_MULTILEVEL => FairMethod::Multilevel,
        other => {
            return Err(Failure::invalid(format!(
                "method {other}: use SURFKIT_METHOD_AUTO (0), SURFKIT_METHOD_PLAIN (1) or \
                 SURFKIT_METHOD_MULTILEVEL (2)"
            )))
        }
    };
    options.coarse_start = if o.coarse_start != 0 {
        CoarseStart::Multilevel
    } else {
        CoarseStart::Never
    };
    options.representation.isolation = o.isolation;
    options.representation.nodes = o.nodes as usize;
    options.representation.c_special = o.c_special;
    options.newton.relative_gradient = o.relative_gradient;
    options.newton.max_iterations = o.max_iterations as usize;
    Ok(options)
}

/// Optimizes `mesh` (`options` may be null: the defaults). The optimized mesh goes to
/// `out_mesh`, the report to `out_report` (may be null). A run that stops without
/// converging still succeeds: read `converged` in the summary.
///
/// Errors: a closed mesh with nothing fixed, fixed ids out of range, a mesh the method
/// cannot prepare (non-manifold, …), options out of range.
///
/// # Safety
/// `mesh` a live handle, `options` null or valid (its callback, if any, callable with its
/// user_data), `out_mesh` writable, `out_report` null or writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_fair(
    mesh: *const SurfkitMesh,
    options: *const SurfkitFairOptions,
    out_mesh: *mut *mut SurfkitMesh,
    out_report: *mut *mut SurfkitFairReport,
) -> c_int {
    guard(|| {
        clear(out_mesh, std::ptr::null_mut());
        clear(out_report, std::ptr::null_mut());
        let out_mesh = output(out_mesh, "out_mesh")?;
        let input = &reference(mesh, "mesh")?.mesh;
        let c_options = match options.as_ref() {
            Some(o) => *o,
            None => {
                let mut d = std::mem::MaybeUninit::<SurfkitFairOptions>::uninit();
                surfkit_fair_options_default(d.as_mut_ptr());
                d.assume_init()
            }
        };
        let options = fair_options(&c_options)?;
        if let Some(&v) = options
            .fixed
            .iter()
            .find(|&&v| v as usize >= input.vertex_count())
        {
            return Err(Failure::invalid(format!(
                "fixed vertex {v} out of range: the mesh has {} vertices",
                input.vertex_count()
            )));
        }
        let mut count = 0;
        let mut observe = |it: &Iteration, g0: f64| {
            count += 1;
            let Some(callback) = c_options.callback else {
                return ControlFlow::Continue(());
            };
            let info = SurfkitFairIteration {
                iteration: count,
                f: it.terms.f,
                s: it.terms.s,
                q: it.terms.q,
                gradient_norm: it.gradient_norm,
                initial_gradient_norm: g0,
                levenberg_marquardt: (it.step == StepKind::LevenbergMarquardt) as c_int,
            };
            if callback(&info, c_options.user_data) != 0 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        };
        let (optimized, report) = optimize_observed(input, &options, &mut observe)?;
        give(out_mesh, SurfkitMesh { mesh: optimized });
        if let Some(slot) = out_report.as_mut() {
            give(slot, SurfkitFairReport { report, json: None });
        }
        Ok(())
    })
}

/// The report's figures.
///
/// # Safety
/// `report` must be a live handle; `out` writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_fair_report_summary(
    report: *const SurfkitFairReport,
    out: *mut SurfkitFairSummary,
) -> c_int {
    guard(|| {
        clear(out, SurfkitFairSummary::default());
        let r = &reference(report, "report")?.report;
        let n = &r.newton;
        let before = r.initial_terms;
        *output(out, "out")? = SurfkitFairSummary {
            surface: match r.surface {
                SurfaceKind::G2 => SURFKIT_SURFACE_G2,
                SurfaceKind::CatmullClark => SURFKIT_SURFACE_CATMULL_CLARK,
            },
            method: match r.method {
                FairMethod::Multilevel => SURFKIT_METHOD_MULTILEVEL,
                FairMethod::Plain | FairMethod::Automatic => SURFKIT_METHOD_PLAIN,
            },
            coarse_stage: r.coarse_start.is_some() as c_int,
            coarse_start_used: r.coarse_start.as_ref().is_some_and(|s| s.used) as c_int,
            converged: n.converged as c_int,
            cancelled: (n.cancelled || r.warm_start.as_ref().is_some_and(|w| w.cancelled)) as c_int,
            stuck: n.stuck as c_int,
            stalled: n.stalled as c_int,
            iterations: n.iterations.len(),
            hessian_evaluations: n.hessian_evaluations,
            refinements: r.refinements,
            vertices: r.vertices,
            free_vertices: r.free_vertices,
            c: r.c,
            regularization: r.regularization,
            f_before: before.f,
            s_before: before.s,
            q_before: before.q,
            f_after: r.final_terms.f,
            s_after: r.final_terms.s,
            q_after: r.final_terms.q,
            gradient_norm_before: r.initial_gradient_norm,
            gradient_norm_after: r.final_gradient_norm,
            coordinate_floor: n.coordinate_floor.unwrap_or(0.0),
        };
        Ok(())
    })
}

/// The whole report as JSON (iterations included), borrowed from the report.
///
/// # Safety
/// `report` must be a live handle; `out` writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_fair_report_json(
    report: *mut SurfkitFairReport,
    out: *mut *const c_char,
) -> c_int {
    guard(|| {
        clear(out, std::ptr::null());
        let out = output(out, "out")?;
        let r = report
            .as_mut()
            .ok_or_else(|| Failure::invalid("report is a null pointer"))?;
        if r.json.is_none() {
            let text = serde_json::to_string(&r.report).map_err(|e| {
                Failure::invalid(format!("the report cannot be written as JSON: {e}"))
            })?;
            r.json = Some(CString::new(text).unwrap_or_default());
        }
        *out = r.json.as_ref().expect("just set").as_ptr();
        Ok(())
    })
}

/// Frees a report (null is ignored).
///
/// # Safety
/// `report` must be null or a handle not freed before.
#[no_mangle]
pub unsafe extern "C" fn surfkit_fair_report_free(report: *mut SurfkitFairReport) {
    let _ = guard(|| {
        take(report);
        Ok(())
    });
}
