//! Kiciak's shape optimization of a control mesh (his G² surface or the Catmull–Clark
//! limit), with a Python callback
//! after every iteration that can stop the run (the GIL is held only while it runs).

use std::ops::ControlFlow;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use surfkit::fair::{
    optimize_observed, CoarseStart, FairMethod, FairOptions, Iteration, RepresentationOptions,
};

use crate::errors::{natural_u32, natural_usize, to_py, InvalidInput};
use crate::mesh::Mesh;

/// Optimizes `mesh` (GIL released between callbacks) and returns the optimized mesh and the
/// report as JSON. `callback(info: dict) -> bool | None` runs after every iteration; a true
/// return stops the run (the positions reached are returned, the report says `cancelled`),
/// an exception stops it and is raised once the run has ended.
#[pyfunction]
#[pyo3(signature = (mesh, *, fixed, boundary_rings, max_refinements, relative_gradient, max_iterations, surface, isolation, nodes, c_special, regularization, method, coarse_start, callback))]
#[allow(clippy::too_many_arguments)]
// Each argument is a keyword argument of the Python function.
pub fn fair_json(
    py: Python<'_>,
    mesh: &Mesh,
    fixed: Vec<u32>,
    boundary_rings: Option<Bound<'_, PyAny>>,
    max_refinements: Option<Bound<'_, PyAny>>,
    relative_gradient: Option<f64>,
    max_iterations: Option<Bound<'_, PyAny>>,
    surface: Option<String>,
    isolation: Option<Bound<'_, PyAny>>,
    nodes: Option<Bound<'_, PyAny>>,
    c_special: Option<f64>,
    regularization: Option<f64>,
    method: Option<String>,
    coarse_start: Option<bool>,
    callback: Option<Py<PyAny>>,
) -> PyResult<(Mesh, String)> {
    let input = &mesh.mesh;
    if let Some(&v) = fixed.iter().find(|&&v| v as usize >= input.vertex_count()) {
        return Err(InvalidInput::new_err(format!(
            "fixed vertex {v} out of range: the mesh has {} vertices",
            input.vertex_count()
        )));
    }
    // Unset options keep the defaults of `surfkit fair`.
    let mut options = FairOptions {
        fixed,
        ..FairOptions::default()
    };
    if let Some(rings) = boundary_rings {
        options.boundary_rings = natural_u32(&rings, "boundary_rings")?;
    }
    if let Some(levels) = max_refinements {
        options.max_refinements = natural_u32(&levels, "max_refinements")?;
    }
    match surface.as_deref() {
        None | Some("g2") => {}
        Some("catmull-clark") => {
            options.representation = RepresentationOptions {
                memory: options.representation.memory,
                ..RepresentationOptions::catmull_clark()
            }
        }
        Some(other) => {
            return Err(InvalidInput::new_err(format!(
                "surface {other:?}: use \"g2\" (Kiciak's curvature-continuous surface) or \
                 \"catmull-clark\""
            )))
        }
    }
    if let Some(level) = isolation {
        options.representation.isolation = natural_u32(&level, "isolation")?;
    }
    if let Some(n) = nodes {
        options.representation.nodes = natural_usize(&n, "nodes")?;
    }
    if let Some(c) = c_special {
        if !(c > 0.0 && c.is_finite()) {
            return Err(InvalidInput::new_err(format!(
                "c_special {c} must be a finite number > 0"
            )));
        }
        options.representation.c_special = c;
    }
    if let Some(c) = regularization {
        if !(c > 0.0 && c.is_finite()) {
            return Err(InvalidInput::new_err(format!(
                "regularization {c} must be a finite number > 0"
            )));
        }
        options.regularization = c;
    }
    options.method = match method.as_deref() {
        None | Some("auto") => FairMethod::Automatic,
        Some("plain") => FairMethod::Plain,
        Some("multilevel") => FairMethod::Multilevel,
        Some(other) => {
            return Err(InvalidInput::new_err(format!(
                "method {other:?}: use \"auto\", \"plain\" (a Cholesky factor per step) or \
                 \"multilevel\" (CG with a multigrid V-cycle, for refined meshes)"
            )))
        }
    };
    if coarse_start == Some(true) {
        options.coarse_start = CoarseStart::Multilevel;
    }
    if let Some(r) = relative_gradient {
        if !(r > 0.0 && r < 1.0) {
            return Err(InvalidInput::new_err(format!(
                "relative_gradient {r} must lie in (0, 1)"
            )));
        }
        options.newton.relative_gradient = r;
    }
    if let Some(n) = max_iterations {
        options.newton.max_iterations = natural_usize(&n, "max_iterations")?;
    }

    let mut raised: Option<PyErr> = None;
    let mut count = 0usize;
    let outcome = py.detach(|| {
        let mut observe = |it: &Iteration, g0: f64| {
            count += 1;
            let Some(callback) = callback.as_ref() else {
                return ControlFlow::Continue(());
            };
            Python::attach(|py| match call(py, callback, count, it, g0) {
                Ok(false) => ControlFlow::Continue(()),
                Ok(true) => ControlFlow::Break(()),
                Err(e) => {
                    raised = Some(e);
                    ControlFlow::Break(())
                }
            })
        };
        optimize_observed(input, &options, &mut observe)
    });
    if let Some(e) = raised {
        return Err(e);
    }
    let (optimized, report) = outcome.map_err(to_py)?;
    let json = serde_json::to_string(&report)
        .map_err(|e| InvalidInput::new_err(format!("the report as JSON: {e}")))?;
    Ok((Mesh { mesh: optimized }, json))
}

/// Calls `callback` with one iteration as a dict; true when it asks to stop.
fn call(
    py: Python<'_>,
    callback: &Py<PyAny>,
    count: usize,
    it: &Iteration,
    g0: f64,
) -> PyResult<bool> {
    let info = PyDict::new(py);
    info.set_item("iteration", count)?;
    info.set_item("f", it.terms.f)?;
    info.set_item("s", it.terms.s)?;
    info.set_item("q", it.terms.q)?;
    info.set_item("gradient_norm", it.gradient_norm)?;
    info.set_item("initial_gradient_norm", g0)?;
    // The step's name as the JSON report spells it.
    let step = serde_json::to_value(it.step)
        .ok()
        .and_then(|v| v.as_str().map(str::to_owned));
    info.set_item("step", step)?;
    callback.bind(py).call1((info,))?.is_truthy()
}
