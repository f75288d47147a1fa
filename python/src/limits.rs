//! The process's memory limit, as the C door's `surfkit_set_max_memory` and the CLI's
//! `--max-memory`: work whose planned size passes it (a fairing problem's solver, a
//! subdivision's levels) raises `ResourceLimit` before it allocates.

use pyo3::prelude::*;
use surfkit::limits::{set_process_budget, MemoryBudget};

use crate::errors::{integer, InvalidInput};

/// Sets the limit: bytes (at least 1 MiB), a size such as "512M" or "12G", or None for
/// the default, half of the machine's memory.
#[pyfunction]
#[pyo3(signature = (size))]
pub fn set_max_memory(size: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
    let budget = match size {
        None => None,
        Some(value) => Some(if let Ok(text) = value.extract::<String>() {
            MemoryBudget::parse(&text).map_err(InvalidInput::new_err)?
        } else {
            let smallest = i128::from(MemoryBudget::SMALLEST);
            match integer(value, "size", smallest, u64::MAX.into()) {
                Ok(bytes) => MemoryBudget::checked(bytes as u64).map_err(InvalidInput::new_err)?,
                Err(e) if e.is_instance_of::<InvalidInput>(value.py()) => return Err(e),
                Err(_) => {
                    return Err(InvalidInput::new_err(format!(
                        "a memory limit of {value}: give bytes (an int), a size such as \
                         \"12G\", or None"
                    )))
                }
            }
        }),
    };
    set_process_budget(budget);
    Ok(())
}

/// The limit in force, in bytes.
#[pyfunction]
pub fn max_memory() -> u64 {
    MemoryBudget::default().get()
}
