//! The one-shot Euler Accompanying Test: `surfkit_eat_scan` on a mesh, and the report's
//! counts, test points and flaws as flat C views (plus the whole report as the JSON that
//! `surfkit eat --json` prints under "report").

use std::ffi::{c_char, c_int, CString};

use surfkit::topology::{
    paired_test_points, scan, stage_ends, EatOptions, EatReport, LocatorOptions, StageSource,
};

use surfkit::repair::check_fixes;

use crate::mesh::SurfkitMesh;
use crate::pointers::{clear, give, output, reference, slice, take};
use crate::status::{guard, Failure};

/// Options of [`surfkit_eat_scan`]; start from [`surfkit_eat_options_default`].
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct SurfkitEatOptions {
    /// Non-zero: build OpenMesh's half-edge structure too (refused faces, loop walks).
    pub halfedge: c_int,
    /// Distance under which distinct vertices count as coincident (0: same coordinates).
    pub weld_tolerance: f64,
    /// A boundary vertex within this fraction of a boundary edge's length of that edge is
    /// a T-vertex on it (a crack); default 0.01.
    pub crack_tolerance: f64,
    /// Test points: after `test_point_facets[i]` facets, χ must be `test_point_expected[i]`
    /// (`test_point_count` of each, in non-decreasing facet counts; the whole mesh is
    /// checked only as a pair of its own, its face count, or as below). With one expected
    /// value and no facet counts (`test_point_facets` null), the whole mesh is the one test
    /// point.
    pub test_point_facets: *const usize,
    pub test_point_expected: *const i64,
    pub test_point_count: usize,
    /// Non-zero: check every suggested fix by applying it to a copy and scanning that
    /// again (each flaw's `fix_verified`); a mesh without flaws costs nothing more.
    pub check_fixes: c_int,
}

/// The defaults of `surfkit eat`: half-edge structure on, exact coincidence, no test point,
/// every suggested fix checked.
///
/// # Safety
/// `options` must be writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_eat_options_default(options: *mut SurfkitEatOptions) -> c_int {
    guard(|| {
        let defaults = LocatorOptions::default();
        *output(options, "options")? = SurfkitEatOptions {
            halfedge: 1,
            weld_tolerance: defaults.weld_tolerance,
            crack_tolerance: defaults.crack_tolerance,
            test_point_facets: std::ptr::null(),
            test_point_expected: std::ptr::null(),
            test_point_count: 0,
            check_fixes: 1,
        };
        Ok(())
    })
}

/// The counts of a report, as `surfkit eat --json` gives them under `report.counts` (with
/// −1 for its nulls), and the number of faces OpenMesh refused.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct SurfkitEatCounts {
    pub vertices_in_file: usize,
    pub vertices: usize,
    pub edges: usize,
    pub faces: usize,
    pub euler_characteristic: i64,
    pub boundary_edges: usize,
    pub boundary_loops: usize,
    pub non_manifold_edges: usize,
    pub non_manifold_vertices: usize,
    pub components: usize,
    /// Genus of a closed orientable manifold mesh, else −1.
    pub genus: i64,
    pub unreferenced_vertices: usize,
    pub duplicated_facets: usize,
    pub degenerate_facets: usize,
    pub inconsistent_orientation_edges: usize,
    pub coincident_vertices: usize,
    /// Non-zero when every test point was verified.
    pub verified: c_int,
    /// Faces OpenMesh refused (0 without the half-edge structure); the JSON's
    /// `halfedge.refused` lists them.
    pub refused_faces: usize,
    /// Boundary loops as a half-edge walk that continues within each fan counts them
    /// (differs from `boundary_loops` at pinch vertices); −1 where a non-manifold edge or an
    /// inconsistent orientation leaves it undefined.
    pub boundary_loops_walk: i64,
    /// Cross-caps, 2c − b − χ, when every component is a non-orientable manifold (Möbius
    /// strip 1, Klein bottle 2), else −1.
    pub non_orientable_genus: i64,
}

/// A test point's outcome.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct SurfkitTestPoint {
    pub facets: usize,
    pub expected_euler_characteristic: i64,
    pub euler_characteristic: i64,
    pub verified: c_int,
}

/// One flaw, borrowed from its report (valid until the report is freed).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct SurfkitFlaw {
    /// The CLI's kind name: "non_manifold_edge", "hole", "crack", …
    pub kind: *const c_char,
    pub vertices: *const u32,
    pub vertex_count: usize,
    pub faces: *const u32,
    pub face_count: usize,
    pub position: [f64; 3],
    /// Connected component, or −1.
    pub component: i64,
    pub description: *const c_char,
    pub suggested_fix: *const c_char,
    /// 1: applying the suggested fix removed the flaw (checked on a copy); 0: it did not;
    /// −1: not checked (`check_fixes` off).
    pub fix_verified: c_int,
}

impl SurfkitFlaw {
    /// What a failed `surfkit_eat_report_flaw` leaves: null pointers, zero counts.
    const EMPTY: SurfkitFlaw = SurfkitFlaw {
        kind: std::ptr::null(),
        vertices: std::ptr::null(),
        vertex_count: 0,
        faces: std::ptr::null(),
        face_count: 0,
        position: [0.0; 3],
        component: 0,
        description: std::ptr::null(),
        suggested_fix: std::ptr::null(),
        fix_verified: 0,
    };
}

/// Texts of a flaw kept as C strings.
struct FlawTexts {
    kind: CString,
    description: CString,
    suggested_fix: CString,
}

/// An opaque EAT report (free with [`surfkit_eat_report_free`]).
pub struct SurfkitEatReport {
    report: EatReport,
    texts: Vec<FlawTexts>,
    json: Option<CString>,
}

fn c_text(s: &str) -> CString {
    CString::new(s.replace('\0', " ")).unwrap_or_default()
}

impl SurfkitEatReport {
    pub(crate) fn new(report: EatReport) -> Self {
        let texts = report
            .flaws
            .iter()
            .map(|f| FlawTexts {
                kind: c_text(f.kind.name()),
                description: c_text(&f.description),
                suggested_fix: c_text(&f.suggested_fix),
            })
            .collect();
        SurfkitEatReport {
            report,
            texts,
            json: None,
        }
    }
}

unsafe fn options_from(
    mesh: &surfkit::mesh::PolygonMesh,
    options: *const SurfkitEatOptions,
) -> Result<EatOptions, Failure> {
    let Some(o) = options.as_ref() else {
        return Ok(EatOptions {
            halfedge: true,
            ..Default::default()
        });
    };
    for (name, value) in [
        ("weld_tolerance", o.weld_tolerance),
        ("crack_tolerance", o.crack_tolerance),
    ] {
        if !(value >= 0.0 && value.is_finite()) {
            return Err(Failure::invalid(format!(
                "{name} {value} must be a finite number ≥ 0"
            )));
        }
    }
    // One expected value with null facet counts is the documented whole-mesh test point.
    let facets = if o.test_point_facets.is_null() && o.test_point_count == 1 {
        &[]
    } else {
        slice(o.test_point_facets, o.test_point_count, "test_point_facets")?
    };
    let expected = slice(
        o.test_point_expected,
        o.test_point_count,
        "test_point_expected",
    )?;
    let source = if facets.is_empty() {
        StageSource::Whole
    } else {
        StageSource::FacetCounts(facets.to_vec())
    };
    let ends = stage_ends(mesh, &source)?;
    Ok(EatOptions {
        test_points: paired_test_points(&ends, expected)?,
        locator: LocatorOptions {
            weld_tolerance: o.weld_tolerance,
            crack_tolerance: o.crack_tolerance,
        },
        halfedge: o.halfedge != 0,
    })
}

/// Runs the Euler Accompanying Test on `mesh` (`options` may be null: the defaults).
///
/// # Safety
/// `mesh` must be a live handle, `options` null or valid, `out` writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_eat_scan(
    mesh: *const SurfkitMesh,
    options: *const SurfkitEatOptions,
    out: *mut *mut SurfkitEatReport,
) -> c_int {
    guard(|| {
        clear(out, std::ptr::null_mut());
        let out = output(out, "out")?;
        let mesh = &reference(mesh, "mesh")?.mesh;
        let check = options.as_ref().is_none_or(|o| o.check_fixes != 0);
        let options = options_from(mesh, options)?;
        let mut report = scan(mesh, &options)?;
        if check {
            check_fixes(mesh, &mut report.flaws, options.locator)?;
        }
        give(out, SurfkitEatReport::new(report));
        Ok(())
    })
}

/// The report's counts.
///
/// # Safety
/// `report` must be a live handle; `out` writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_eat_report_counts(
    report: *const SurfkitEatReport,
    out: *mut SurfkitEatCounts,
) -> c_int {
    guard(|| {
        clear(out, SurfkitEatCounts::default());
        let r = &reference(report, "report")?.report;
        let c = &r.counts;
        *output(out, "out")? = SurfkitEatCounts {
            vertices_in_file: c.vertices_in_file,
            vertices: c.vertices_referenced,
            edges: c.edges,
            faces: c.facets,
            euler_characteristic: c.euler_characteristic,
            boundary_edges: c.boundary_edges,
            boundary_loops: c.boundary_loops,
            non_manifold_edges: c.non_manifold_edges,
            non_manifold_vertices: c.non_manifold_vertices,
            components: c.components,
            genus: c.genus.unwrap_or(-1),
            unreferenced_vertices: c.unreferenced_vertices,
            duplicated_facets: c.duplicated_facets,
            degenerate_facets: c.degenerate_facets,
            inconsistent_orientation_edges: c.inconsistent_orientation_edges,
            coincident_vertices: c.coincident_vertices,
            verified: r.verified() as c_int,
            refused_faces: r.halfedge.as_ref().map_or(0, |h| h.refused.len()),
            boundary_loops_walk: c
                .boundary_loops_walk
                .map_or(-1, |n| i64::try_from(n).unwrap_or(i64::MAX)),
            non_orientable_genus: c.non_orientable_genus.unwrap_or(-1),
        };
        Ok(())
    })
}

/// The number of test points, and test point `index` (either output may be null).
///
/// # Safety
/// `report` must be a live handle; non-null outputs writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_eat_report_test_point(
    report: *const SurfkitEatReport,
    index: usize,
    count: *mut usize,
    out: *mut SurfkitTestPoint,
) -> c_int {
    guard(|| {
        clear(count, 0);
        clear(out, SurfkitTestPoint::default());
        let r = &reference(report, "report")?.report;
        if let Some(out) = out.as_mut() {
            let (point, checkpoint) = r.checkpoints.get(index).ok_or_else(|| {
                Failure::invalid(format!(
                    "test point {index} out of range: the report has {}",
                    r.checkpoints.len()
                ))
            })?;
            *out = SurfkitTestPoint {
                facets: point.facets,
                expected_euler_characteristic: point.expected,
                euler_characteristic: checkpoint.statistics.euler_characteristic,
                verified: checkpoint.verified as c_int,
            };
        }
        if let Some(count) = count.as_mut() {
            *count = r.checkpoints.len();
        }
        Ok(())
    })
}

/// The number of flaws.
///
/// # Safety
/// `report` must be a live handle; `count` writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_eat_report_flaw_count(
    report: *const SurfkitEatReport,
    count: *mut usize,
) -> c_int {
    guard(|| {
        clear(count, 0);
        *output(count, "count")? = reference(report, "report")?.report.flaws.len();
        Ok(())
    })
}

/// Flaw `index`, borrowed from the report.
///
/// # Safety
/// `report` must be a live handle; `out` writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_eat_report_flaw(
    report: *const SurfkitEatReport,
    index: usize,
    out: *mut SurfkitFlaw,
) -> c_int {
    guard(|| {
        clear(out, SurfkitFlaw::EMPTY);
        let r = reference(report, "report")?;
        let flaw = r.report.flaws.get(index).ok_or_else(|| {
            Failure::invalid(format!(
                "flaw {index} out of range: the report has {}",
                r.report.flaws.len()
            ))
        })?;
        let texts = &r.texts[index];
        *output(out, "out")? = SurfkitFlaw {
            kind: texts.kind.as_ptr(),
            vertices: flaw.vertices.as_ptr(),
            vertex_count: flaw.vertices.len(),
            faces: flaw.faces.as_ptr(),
            face_count: flaw.faces.len(),
            position: flaw.position,
            component: flaw.component.map_or(-1, i64::from),
            description: texts.description.as_ptr(),
            suggested_fix: texts.suggested_fix.as_ptr(),
            fix_verified: flaw.fix_verified.map_or(-1, c_int::from),
        };
        Ok(())
    })
}

/// The whole report as JSON (the object `surfkit eat --json` prints under "report"),
/// borrowed from the report.
///
/// # Safety
/// `report` must be a live handle (not shared with another thread during the call);
/// `out` writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_eat_report_json(
    report: *mut SurfkitEatReport,
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
            r.json = Some(c_text(&text));
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
pub unsafe extern "C" fn surfkit_eat_report_free(report: *mut SurfkitEatReport) {
    let _ = guard(|| {
        take(report);
        Ok(())
    });
}
