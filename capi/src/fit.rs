//! Smoothing splines of scattered (u, v) → (x, y, z) data and the filling of their holes
//! (Kouibia & Pasadas 2022; BFS C¹ of 2024), from point arrays, as an evaluator handle.

use std::ffi::{c_char, c_int, CString};

use surfkit::fit::fill::FillVariant;
use surfkit::fit::pipeline::{fit_and_fill, FitOutcome, FitSetup, HoleSource, SpaceKind};
use surfkit::fit::shape::{ShapeConstraints, ShapePoint, Tau};
use surfkit::fit::{data::ScatteredData, Hole, HoleShape};

use crate::pointers::{clear, give, output, reference, slice, slice_mut, take};
use crate::status::{guard, Failure};

/// Biquadratic C¹ B-splines (2022).
pub const SURFKIT_SPACE_BIQUADRATIC: c_int = 0;
/// Bicubic C² B-splines.
pub const SURFKIT_SPACE_BICUBIC: c_int = 1;
/// Bogner–Fox–Schmit C¹ (2024).
pub const SURFKIT_SPACE_BFS_C1: c_int = 2;
/// No hole: the smoothing spline only.
pub const SURFKIT_HOLE_NONE: c_int = 0;
/// The cells that hold no data point form the hole.
pub const SURFKIT_HOLE_CELLS_WITHOUT_DATA: c_int = 1;
/// A closed simple polygon in (u, v) (`hole_polygon`, `hole_polygon_count` corners).
pub const SURFKIT_HOLE_POLYGON: c_int = 2;
/// The ellipse a(u − cu)² + b(v − cv)² ≤ level (`hole_ellipse` = cu, cv, a, b, level).
pub const SURFKIT_HOLE_ELLIPSE: c_int = 3;

/// Options of [`surfkit_fit`].
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct SurfkitFitOptions {
    /// `SURFKIT_SPACE_*`.
    pub space: c_int,
    pub cells_u: u32,
    pub cells_v: u32,
    /// ε > 0 of the smoothing term.
    pub epsilon: f64,
    /// `SURFKIT_HOLE_*`.
    pub hole: c_int,
    pub hole_polygon: *const f64,
    pub hole_polygon_count: usize,
    pub hole_ellipse: [f64; 5],
    /// Non-zero: the filled spline is C¹ across the hole's border (σ ∈ V_h); zero: the
    /// paper's σ₂ with the constraints of (14).
    pub exact_c1: c_int,
    /// Shape-preserving filling (2024 §4, needs `SURFKIT_SPACE_BFS_C1`): the component
    /// (0 x, 1 y, 2 z) the conditions τ L(σ) ≥ 0 of (10) apply to, or −1 for none; each
    /// condition +1 (value ≥ 0 / increasing), −1 (≤ 0 / decreasing) or 0 (not imposed).
    pub shape_component: c_int,
    pub shape_value: c_int,
    pub shape_slope_u: c_int,
    pub shape_slope_v: c_int,
    /// Extra constraint points: a k × k lattice in each hole cell, and
    /// `shape_point_count` points (u, v) given one by one.
    pub shape_lattice: u32,
    pub shape_points: *const f64,
    pub shape_point_count: usize,
}

/// An opaque solved spline (free with [`surfkit_spline_free`]).
pub struct SurfkitSpline {
    outcome: FitOutcome,
    json: Option<CString>,
}

/// Biquadratic, 8 × 8 cells, ε = 1e-9, no hole, the paper's fill (as `surfkit fit`).
///
/// # Safety
/// `options` must be writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_fit_options_default(options: *mut SurfkitFitOptions) -> c_int {
    guard(|| {
        *output(options, "options")? = SurfkitFitOptions {
            space: SURFKIT_SPACE_BIQUADRATIC,
            cells_u: 8,
            cells_v: 8,
            epsilon: 1e-9,
            hole: SURFKIT_HOLE_NONE,
            hole_polygon: std::ptr::null(),
            hole_polygon_count: 0,
            hole_ellipse: [0.0; 5],
            exact_c1: 0,
            shape_component: -1,
            shape_value: 0,
            shape_slope_u: 0,
            shape_slope_v: 0,
            shape_lattice: 0,
            shape_points: std::ptr::null(),
            shape_point_count: 0,
        };
        Ok(())
    })
}

unsafe fn setup(o: &SurfkitFitOptions) -> Result<FitSetup, Failure> {
    let space = match o.space {
        SURFKIT_SPACE_BIQUADRATIC => SpaceKind::Biquadratic,
        SURFKIT_SPACE_BICUBIC => SpaceKind::Bicubic,
        SURFKIT_SPACE_BFS_C1 => SpaceKind::BfsC1,
        s => {
            return Err(Failure::invalid(format!(
                "space {s} is not one of SURFKIT_SPACE_*"
            )))
        }
    };
    let hole = match o.hole {
        SURFKIT_HOLE_NONE => HoleSource::None,
        SURFKIT_HOLE_CELLS_WITHOUT_DATA => HoleSource::CellsWithoutData,
        SURFKIT_HOLE_POLYGON => {
            let corners = slice(
                o.hole_polygon,
                o.hole_polygon_count
                    .checked_mul(2)
                    .ok_or_else(|| Failure::invalid("hole_polygon_count overflows"))?,
                "hole_polygon",
            )?;
            if o.hole_polygon_count < 3 {
                return Err(Failure::invalid(format!(
                    "a hole polygon needs at least 3 corners, not {}",
                    o.hole_polygon_count
                )));
            }
            HoleSource::Shapes(Hole {
                shapes: vec![HoleShape::Polygon(
                    corners.chunks_exact(2).map(|c| [c[0], c[1]]).collect(),
                )],
            })
        }
        SURFKIT_HOLE_ELLIPSE => {
            let [cu, cv, a, b, level] = o.hole_ellipse;
            HoleSource::Shapes(Hole {
                shapes: vec![HoleShape::Ellipse {
                    center: [cu, cv],
                    coeffs: [a, b],
                    level,
                }],
            })
        }
        h => {
            return Err(Failure::invalid(format!(
                "hole {h} is not one of SURFKIT_HOLE_*"
            )))
        }
    };
    Ok(FitSetup {
        space,
        cells: [o.cells_u as usize, o.cells_v as usize],
        epsilon: o.epsilon,
        hole,
        variant: if o.exact_c1 != 0 {
            FillVariant::ExactC1
        } else {
            FillVariant::Paper
        },
        shape: shape(o)?,
    })
}

fn tau(value: c_int, what: &str) -> Result<Option<Tau>, Failure> {
    match value {
        0 => Ok(None),
        1 => Ok(Some(Tau::Plus)),
        -1 => Ok(Some(Tau::Minus)),
        v => Err(Failure::invalid(format!("{what} {v} must be −1, 0 or +1"))),
    }
}

unsafe fn shape(o: &SurfkitFitOptions) -> Result<Option<ShapeConstraints>, Failure> {
    if o.shape_component == -1 {
        return Ok(None);
    }
    if !(0..=2).contains(&o.shape_component) {
        return Err(Failure::invalid(format!(
            "shape_component {} must be 0, 1, 2 or −1 (none)",
            o.shape_component
        )));
    }
    let points = slice(
        o.shape_points,
        o.shape_point_count
            .checked_mul(2)
            .ok_or_else(|| Failure::invalid("shape_point_count overflows"))?,
        "shape_points",
    )?;
    Ok(Some(ShapeConstraints {
        component: o.shape_component as usize,
        value: tau(o.shape_value, "shape_value")?,
        slope_x: tau(o.shape_slope_u, "shape_slope_u")?,
        slope_y: tau(o.shape_slope_v, "shape_slope_v")?,
        extra_per_side: o.shape_lattice as usize,
        extra_points: points
            .chunks_exact(2)
            .enumerate()
            .map(|(i, p)| ShapePoint {
                uv: [p[0], p[1]],
                label: format!("shape point {i}"),
            })
            .collect(),
    }))
}

/// Fits the smoothing spline to `count` data points — parameters `uv` (2 per point) and
/// values `xyz` (3 per point) — on the data's parameter rectangle, and fills the hole the
/// options name (`options` may be null: the defaults).
///
/// Errors: too few points to determine the spline, a cell outside the hole without data,
/// ε ≤ 0, a hole that covers every cell, NaN data (naming the point).
///
/// # Safety
/// `uv` of `2 · count` and `xyz` of `3 · count` doubles; `options` null or valid; `out`
/// writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_fit(
    uv: *const f64,
    xyz: *const f64,
    count: usize,
    options: *const SurfkitFitOptions,
    out: *mut *mut SurfkitSpline,
) -> c_int {
    guard(|| {
        clear(out, std::ptr::null_mut());
        let out = output(out, "out")?;
        let uv = slice(
            uv,
            count
                .checked_mul(2)
                .ok_or_else(|| Failure::invalid("count overflows"))?,
            "uv",
        )?;
        let xyz = slice(
            xyz,
            count
                .checked_mul(3)
                .ok_or_else(|| Failure::invalid("count overflows"))?,
            "xyz",
        )?;
        if let Some(i) = (0..count).find(|&i| {
            !(uv[2 * i..2 * i + 2]
                .iter()
                .chain(&xyz[3 * i..3 * i + 3])
                .all(|x| x.is_finite()))
        }) {
            return Err(Failure::invalid(format!(
                "data point {i} has a non-finite coordinate"
            )));
        }
        let data = ScatteredData {
            params: uv.chunks_exact(2).map(|p| [p[0], p[1]]).collect(),
            points: xyz.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect(),
        };
        let defaults = {
            let mut d = std::mem::MaybeUninit::<SurfkitFitOptions>::uninit();
            surfkit_fit_options_default(d.as_mut_ptr());
            d.assume_init()
        };
        let setup = setup(options.as_ref().unwrap_or(&defaults))?;
        give(
            out,
            SurfkitSpline {
                outcome: fit_and_fill(&data, &setup)?,
                json: None,
            },
        );
        Ok(())
    })
}

/// Evaluates σ (the filled surface where there is a hole, else the smoothing spline) at
/// `count` parameter points `uv` into `xyz` (3 per point). Points outside the data's
/// parameter rectangle are an error naming the point; on any failure `xyz` is all NaN.
///
/// # Safety
/// `spline` a live handle; `uv` of `2 · count`, `xyz` of `3 · count` doubles.
#[no_mangle]
pub unsafe extern "C" fn surfkit_spline_evaluate(
    spline: *const SurfkitSpline,
    count: usize,
    uv: *const f64,
    xyz: *mut f64,
) -> c_int {
    guard(|| {
        let xyz = slice_mut(
            xyz,
            count
                .checked_mul(3)
                .ok_or_else(|| Failure::invalid("count overflows"))?,
            "xyz",
        )?;
        // NaN until every point is evaluated: a failed call leaves no stale numbers.
        xyz.fill(f64::NAN);
        let s = reference(spline, "spline")?;
        let uv = slice(uv, count * 2, "uv")?;
        let values = uv
            .chunks_exact(2)
            .enumerate()
            .map(|(i, p)| {
                s.outcome
                    .eval(p[0], p[1])
                    .map_err(|e| Failure::from(e).at_point(i))
            })
            .collect::<Result<Vec<[f64; 3]>, Failure>>()?;
        xyz.copy_from_slice(values.as_flattened());
        Ok(())
    })
}

/// The fit's report (misfit, cells, the fill's constraints and jumps) as JSON, borrowed
/// from the spline.
///
/// # Safety
/// `spline` a live handle; `out` writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_spline_report_json(
    spline: *mut SurfkitSpline,
    out: *mut *const c_char,
) -> c_int {
    guard(|| {
        clear(out, std::ptr::null());
        let out = output(out, "out")?;
        let s = spline
            .as_mut()
            .ok_or_else(|| Failure::invalid("spline is a null pointer"))?;
        if s.json.is_none() {
            let text = serde_json::to_string(&s.outcome.summary).map_err(|e| {
                Failure::invalid(format!("the report cannot be written as JSON: {e}"))
            })?;
            s.json = Some(CString::new(text).unwrap_or_default());
        }
        *out = s.json.as_ref().expect("just set").as_ptr();
        Ok(())
    })
}

/// Frees a spline (null is ignored).
///
/// # Safety
/// `spline` must be null or a handle not freed before.
#[no_mangle]
pub unsafe extern "C" fn surfkit_spline_free(spline: *mut SurfkitSpline) {
    let _ = guard(|| {
        take(spline);
        Ok(())
    });
}
