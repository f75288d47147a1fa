//! The Euler Accompanying Test on a `Mesh`, returning the report as the JSON that `surfkit
//! eat --json` prints under "report" (the Python side turns it into its dict).

use pyo3::prelude::*;
use surfkit::topology::{scan, stage_ends, test_points, EatOptions, LocatorOptions, StageSource};

use crate::errors::{to_py, InvalidInput};
use crate::mesh::Mesh;

/// Scans `mesh` (GIL released): test points after `test_point_facets[i]` facets expecting
/// χ = `expected_chi[i]` (one expected value and no facet counts: the whole mesh), then
/// every flaw located, and each suggested fix checked when `check_fixes`.
#[pyfunction]
#[pyo3(signature = (mesh, *, weld_tolerance, crack_tolerance, halfedge, check_fixes, test_point_facets, expected_chi))]
// Each argument is a keyword argument of the Python function.
#[allow(clippy::too_many_arguments)]
pub fn eat_json(
    py: Python<'_>,
    mesh: &Mesh,
    weld_tolerance: f64,
    crack_tolerance: f64,
    halfedge: bool,
    check_fixes: bool,
    test_point_facets: Vec<usize>,
    expected_chi: Vec<i64>,
) -> PyResult<String> {
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
            test_points: test_points(&ends, &expected_chi)?,
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
