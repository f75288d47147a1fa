//! surfkit's errors as Python exceptions: `SurfkitError` and one subclass per kind, carrying
//! the Rust message (which names the file, line or element).

use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyOverflowError};
use pyo3::prelude::*;

create_exception!(_surfkit, SurfkitError, PyException, "Any surfkit failure.");
create_exception!(
    _surfkit,
    InvalidInput,
    SurfkitError,
    "Input surfkit cannot take: a malformed file, arrays of the wrong shape, NaN, ids out of range."
);
create_exception!(
    _surfkit,
    TopologyError,
    SurfkitError,
    "The mesh's topology does not allow the operation."
);
create_exception!(
    _surfkit,
    SolverError,
    SurfkitError,
    "A numerical solve failed."
);
create_exception!(
    _surfkit,
    ResourceLimit,
    SurfkitError,
    "The operation would pass the memory limit or a bound on its work."
);

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("SurfkitError", py.get_type::<SurfkitError>())?;
    m.add("InvalidInput", py.get_type::<InvalidInput>())?;
    m.add("TopologyError", py.get_type::<TopologyError>())?;
    m.add("SolverError", py.get_type::<SolverError>())?;
    m.add("ResourceLimit", py.get_type::<ResourceLimit>())?;
    Ok(())
}

/// The exception of a library error.
pub fn to_py(e: surfkit::Error) -> PyErr {
    use surfkit::Error as E;
    let message = e.to_string();
    match e {
        E::Parse { .. } | E::UnknownFormat { .. } | E::InvalidInput(_) => {
            InvalidInput::new_err(message)
        }
        E::Topology(_) => TopologyError::new_err(message),
        E::Solver { .. } => SolverError::new_err(message),
        E::ResourceLimit { .. } | E::WorkLimit { .. } => ResourceLimit::new_err(message),
        E::Io { .. } | E::Ffi { .. } => SurfkitError::new_err(message),
    }
}

/// An integer argument within `min ..= max` (a count, an id, a number of levels, an expected
/// χ): PyO3's own `OverflowError` for an int outside the Rust type names no argument, this
/// `InvalidInput` names the argument and the range. Other failures (not an int at all) stay
/// PyO3's. Every int parameter of the module goes through here (or [`natural`] and its
/// siblings, which call it).
pub fn integer(value: &Bound<'_, PyAny>, name: &str, min: i128, max: i128) -> PyResult<i128> {
    match value.extract::<i128>() {
        Ok(n) if (min..=max).contains(&n) => Ok(n),
        Err(e) if !e.is_instance_of::<PyOverflowError>(value.py()) => Err(e),
        _ => Err(InvalidInput::new_err(format!(
            "{name} {value} is out of range: it must be an integer from {min} to {max}"
        ))),
    }
}

/// An integer argument from 0 to `max` (see [`integer`]).
pub fn natural(value: &Bound<'_, PyAny>, name: &str, max: u64) -> PyResult<u64> {
    integer(value, name, 0, max.into()).map(|n| n as u64)
}

/// [`natural`] for a `u32` argument (a vertex id, a level).
pub fn natural_u32(value: &Bound<'_, PyAny>, name: &str) -> PyResult<u32> {
    natural(value, name, u64::from(u32::MAX)).map(|n| n as u32)
}

/// [`natural`] for a `usize` argument (a count).
pub fn natural_usize(value: &Bound<'_, PyAny>, name: &str) -> PyResult<usize> {
    natural(value, name, usize::MAX as u64).map(|n| n as usize)
}

/// [`integer`] for an `i64` argument (an expected Euler characteristic).
pub fn signed(value: &Bound<'_, PyAny>, name: &str) -> PyResult<i64> {
    integer(value, name, i64::MIN.into(), i64::MAX.into()).map(|n| n as i64)
}
