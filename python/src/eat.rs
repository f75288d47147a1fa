//! The Euler Accompanying Test on a `Mesh`, returning the report as the JSON that `surfkit
//! eat --json` prints under "report" (the Python side turns it into its dict).

use pyo3::prelude::*;
use surfkit::topology::{
    paired_test_points, scan, stage_ends, EatOptions, LocatorOptions, StageSource,
};

use crate::errors::{natural_usize, signed, to_py, InvalidInput};
use crate::mesh::Mesh;

/// Scans `mesh` (GIL released): test points `(facets, expected χ)` (or `target`, the whole
/// mesh's expected χ), then every flaw located, and each suggested fix checked when
/// `check_fixes`. Out-of-range ints raise `InvalidInput` naming the test point or `target`.
#[pyfunction]
#[pyo3(signature = (mesh, *, weld_tolerance, crack_tolerance, halfedge, check_fixes, test_points, target))]
// Each argument is a keyword argument of the Python function.
#[allow(clippy::too_many_arguments)]
pub fn eat_json(
    py: Python<'_>,
    mesh: &Mesh,
    weld_tolerance: f64,
    crack_tolerance: f64,
    halfedge: bool,
    check_fixes: bool,
    test_points: Vec<(Bound<'_, PyAny>, Bound<'_, PyAny>)>,
    target: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    if target.is_some() && !test_points.is_empty() {
        return Err(InvalidInput::new_err(
            "give test_points or target, not both",
        ));
    }
    let mut test_point_facets = Vec::with_capacity(test_points.len());
    let mut expected_chi = Vec::with_capacity(test_points.len() + 1);
    for (i, (facets, chi)) in test_points.iter().enumerate() {
        test_point_facets.push(natural_usize(
            facets,
            &format!("test_points[{i}] facet count"),
        )?);
        expected_chi.push(signed(chi, &format!("test_points[{i}] expected χ"))?);
    }
    if let Some(chi) = &target {
        expected_chi.push(signed(chi, "target")?);
    }
    for (name, value) in [
        ("weld_tolerance", weld_tolerance),
        ("crack_tolerance", crack_tolerance),
    ] {
        if !(value.is_finite() && value >= 0.0) {
            return Err(InvalidInput::new_err(format!(
                "{name} {value} must be a finite number ≥ 0"
            )));
        }
    }
    let mesh = &mesh.mesh;
    let text = py.detach(|| -> surfkit::Result<String> {
        let source = if test_point_facets.is_empty() {
            StageSource::Whole
        } else {
            StageSource::FacetCounts(test_point_facets)
        };
        let ends = stage_ends(mesh, &source)?;
        let locator = LocatorOptions {
            weld_tolerance,
            crack_tolerance,
        };
        let options = EatOptions {
            test_points: paired_test_points(&ends, &expected_chi)?,
            locator,
            halfedge,
        };
        let mut report = scan(mesh, &options)?;
        if check_fixes {
            surfkit::repair::check_fixes(mesh, &mut report.flaws, locator)?;
        }
        serde_json::to_string(&report)
            .map_err(|e| surfkit::Error::InvalidInput(format!("the report as JSON: {e}")))
    });
    text.map_err(to_py)
}
