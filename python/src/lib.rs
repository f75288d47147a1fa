//! The native half of the `surfkit` Python package (`surfkit._surfkit`): the Rust library's
//! mesh, Euler Accompanying Test, subdivision, fairing and spline fitting behind PyO3, numpy
//! arrays in and out. The Pythonic API
//! (dicts with pymeshlab's keys, faces as lists or arrays) is `surfkit/__init__.py`; this
//! module only converts, releases the GIL around the work and maps errors to exceptions.

mod eat;
mod errors;
mod fair;
mod fit;
mod limits;
mod mesh;
mod registry;
mod subdiv;

use pyo3::prelude::*;

#[pymodule]
fn _surfkit(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<mesh::Mesh>()?;
    m.add_function(wrap_pyfunction!(mesh::read_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(eat::eat_json, m)?)?;
    m.add_class::<registry::EatRegistry>()?;
    m.add_function(wrap_pyfunction!(subdiv::subdivide, m)?)?;
    m.add_class::<subdiv::LimitSurface>()?;
    m.add_function(wrap_pyfunction!(fair::fair_json, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fit_spline, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fit_parallel, m)?)?;
    m.add_class::<fit::Spline>()?;
    m.add_function(wrap_pyfunction!(limits::set_max_memory, m)?)?;
    m.add_function(wrap_pyfunction!(limits::max_memory, m)?)?;
    errors::register(m)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // The names flaws carry in "kind", in the CLI's order.
    let kinds: Vec<&str> = surfkit::topology::FlawKind::ALL
        .iter()
        .map(|k| k.name())
        .collect();
    m.add("FLAW_KINDS", kinds)?;
    Ok(())
}
