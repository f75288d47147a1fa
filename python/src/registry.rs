//! `EatRegistry`: the accompanying test for a modelling script (Liu et al. 2020 §3.4) —
//! facets registered one by one as the script makes them, test points that compare χ so
//! far with what the model should have, and the suspects of a failed test point.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use surfkit::topology::ModelCompanion;

use crate::errors::{to_py, InvalidInput};

/// Vertex ids a registry takes when the caller names no count: the registry keeps one item
/// per id up to the largest seen, so an id is a size claim (16.7 M ids, about 0.4 GB).
const DEFAULT_VERTEX_LIMIT: u64 = 1 << 24;

/// The accompanying test of a model built facet by facet.
#[pyclass(module = "surfkit._surfkit", unsendable)]
pub struct EatRegistry {
    companion: ModelCompanion,
    vertex_limit: u64,
}

#[pymethods]
impl EatRegistry {
    /// A registry for vertex ids below `vertex_count` (default 2²⁴; raise it with
    /// `vertex_count = n` as the model grows).
    #[new]
    #[pyo3(signature = (vertex_count=None))]
    fn new(vertex_count: Option<u64>) -> PyResult<Self> {
        Ok(EatRegistry {
            companion: ModelCompanion::new(),
            vertex_limit: checked_limit(vertex_count.unwrap_or(DEFAULT_VERTEX_LIMIT))?,
        })
    }

    /// The bound on vertex ids.
    #[getter]
    fn vertex_count(&self) -> u64 {
        self.vertex_limit
    }

    #[setter]
    fn set_vertex_count(&mut self, count: u64) -> PyResult<()> {
        self.vertex_limit = checked_limit(count)?;
        Ok(())
    }

    /// Registers one facet (EAT-TA): `corners` its vertex ids, `input_id` how reports name it
    /// (default: its position). Returns the paper's per-facet output: `facet` (fID), `fc`,
    /// `vertex_slots` (vIDs) and `edge_slots` (eIDs).
    #[pyo3(signature = (corners, input_id=None))]
    fn add_facet<'py>(
        &mut self,
        py: Python<'py>,
        corners: Vec<i64>,
        input_id: Option<u32>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let position = self.companion.registry().facet_count();
        let input_id = input_id.unwrap_or(position as u32);
        if corners.is_empty() {
            return Err(InvalidInput::new_err(format!(
                "facet {input_id} has no corners"
            )));
        }
        let mut ids = Vec::with_capacity(corners.len());
        for v in corners {
            if v < 0 || v as u64 >= self.vertex_limit {
                return Err(InvalidInput::new_err(format!(
                    "facet {input_id} refers to vertex {v}, but the registry is for vertex ids \
                     0..{} (set vertex_count to raise it)",
                    self.vertex_limit
                )));
            }
            ids.push(v as u32);
        }
        let r = self
            .companion
            .register_facet(&ids, input_id)
            .map_err(to_py)?;
        let out = PyDict::new(py);
        out.set_item("facet", r.facet)?;
        out.set_item("fc", r.fc)?;
        out.set_item("vertex_slots", r.vertex_slots)?;
        out.set_item("edge_slots", r.edge_slots)?;
        Ok(out)
    }

    /// V, E, F and χ so far (EAT-SA), as JSON.
    fn statistics_json(&self) -> PyResult<String> {
        json(&self.companion.statistics())
    }

    /// A test point: χ so far against `expected_chi`, as JSON; on a mismatch the facets
    /// since the last verified point with their counters.
    fn checkpoint_json(&mut self, expected_chi: i64) -> PyResult<String> {
        json(&self.companion.checkpoint(expected_chi))
    }
}

fn checked_limit(count: u64) -> PyResult<u64> {
    if count > u64::from(u32::MAX) {
        return Err(InvalidInput::new_err(format!(
            "vertex_count {count} is beyond 32-bit vertex ids"
        )));
    }
    Ok(count)
}

fn json<T: serde::Serialize>(value: &T) -> PyResult<String> {
    serde_json::to_string(value).map_err(|e| InvalidInput::new_err(format!("as JSON: {e}")))
}
