//! `EatRegistry`: the accompanying test for a modelling script (Liu et al. 2020 §3.4) —
//! facets registered one by one as the script makes them, test points that compare χ so
//! far with what the model should have, and the suspects of a failed test point.

use std::sync::{Mutex, MutexGuard};

use pyo3::prelude::*;
use pyo3::types::PyDict;
use surfkit::topology::ModelCompanion;

use crate::errors::{integer, natural, natural_u32, signed, to_py, InvalidInput, SurfkitError};

/// Vertex ids a registry takes when the caller names no count: the registry keeps one item
/// per id up to the largest seen, so an id is a size claim (16.7 M ids, about 0.4 GB).
const DEFAULT_VERTEX_LIMIT: u64 = 1 << 24;

/// The accompanying test of a model built facet by facet. Its state sits behind a lock so
/// that a script may use and drop it on any thread (a thread pool's worker, say).
#[pyclass(module = "surfkit._surfkit", frozen)]
pub struct EatRegistry {
    state: Mutex<State>,
}

struct State {
    companion: ModelCompanion,
    vertex_limit: u64,
}

impl EatRegistry {
    /// The state, locked for one call (no Python code runs while it is held).
    fn state(&self) -> PyResult<MutexGuard<'_, State>> {
        self.state.lock().map_err(|_| {
            SurfkitError::new_err("the registry is unusable: a call on it failed half-way")
        })
    }
}

#[pymethods]
impl EatRegistry {
    /// A registry for vertex ids below `vertex_count` (default 2²⁴; raise it with
    /// `vertex_count = n` as the model grows).
    #[new]
    #[pyo3(signature = (vertex_count=None))]
    fn new(vertex_count: Option<Bound<'_, PyAny>>) -> PyResult<Self> {
        let count = match vertex_count {
            Some(count) => vertex_limit(&count)?,
            None => DEFAULT_VERTEX_LIMIT,
        };
        Ok(EatRegistry {
            state: Mutex::new(State {
                companion: ModelCompanion::new(),
                vertex_limit: count,
            }),
        })
    }

    /// The bound on vertex ids.
    #[getter]
    fn vertex_count(&self) -> PyResult<u64> {
        Ok(self.state()?.vertex_limit)
    }

    #[setter]
    fn set_vertex_count(&self, count: &Bound<'_, PyAny>) -> PyResult<()> {
        let count = vertex_limit(count)?;
        self.state()?.vertex_limit = count;
        Ok(())
    }

    /// Registers one facet (EAT-TA): `corners` its vertex ids, `input_id` how reports name it
    /// (default: its position). Returns the paper's per-facet output: `facet` (fID), `fc`,
    /// `vertex_slots` (vIDs) and `edge_slots` (eIDs).
    #[pyo3(signature = (corners, input_id=None))]
    fn add_facet<'py>(
        &self,
        py: Python<'py>,
        corners: Vec<Bound<'py, PyAny>>,
        input_id: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let input_id = input_id
            .map(|id| natural_u32(&id, "input_id"))
            .transpose()?;
        let r = {
            let mut state = self.state()?;
            let position = state.companion.registry().facet_count();
            let input_id = input_id.unwrap_or(position as u32);
            if corners.is_empty() {
                return Err(InvalidInput::new_err(format!(
                    "facet {input_id} has no corners"
                )));
            }
            let mut ids = Vec::with_capacity(corners.len());
            for v in &corners {
                // An id past the bound (-1 and 2**70 too) names the facet and the bound.
                let id = integer(v, "vertex id", 0, i128::from(state.vertex_limit) - 1).map_err(
                    |e| {
                        if e.is_instance_of::<InvalidInput>(py) {
                            InvalidInput::new_err(format!(
                                "facet {input_id} refers to vertex {v}, but the registry is for \
                                 vertex ids 0..{} (set vertex_count to raise it)",
                                state.vertex_limit
                            ))
                        } else {
                            e
                        }
                    },
                )?;
                ids.push(id as u32);
            }
            state
                .companion
                .register_facet(&ids, input_id)
                .map_err(to_py)?
        };
        let out = PyDict::new(py);
        out.set_item("facet", r.facet)?;
        out.set_item("fc", r.fc)?;
        out.set_item("vertex_slots", r.vertex_slots)?;
        out.set_item("edge_slots", r.edge_slots)?;
        Ok(out)
    }

    /// V, E, F and χ so far (EAT-SA), as JSON.
    fn statistics_json(&self) -> PyResult<String> {
        json(&self.state()?.companion.statistics())
    }

    /// A test point: χ so far against `expected_chi`, as JSON; on a mismatch the facets
    /// since the last verified point with their counters.
    fn checkpoint_json(&self, expected_chi: &Bound<'_, PyAny>) -> PyResult<String> {
        let expected_chi = signed(expected_chi, "expected_chi")?;
        json(&self.state()?.companion.checkpoint(expected_chi))
    }
}

/// `vertex_count` as given: 0 ..= 2³² − 1 (ids are 32-bit), else `InvalidInput` naming it.
fn vertex_limit(count: &Bound<'_, PyAny>) -> PyResult<u64> {
    natural(count, "vertex_count", u64::from(u32::MAX)).map_err(|e| {
        if e.is_instance_of::<InvalidInput>(count.py()) {
            InvalidInput::new_err(format!(
                "vertex_count {count} is out of range: vertex ids are 32-bit, give 0 to {}",
                u32::MAX
            ))
        } else {
            e
        }
    })
}

fn json<T: serde::Serialize>(value: &T) -> PyResult<String> {
    serde_json::to_string(value).map_err(|e| InvalidInput::new_err(format!("as JSON: {e}")))
}
