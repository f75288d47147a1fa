//! The process's memory limit seen from C: what the CLI's `--max-memory` is to a command.

use std::os::raw::c_int;

use surfkit::limits::{set_process_budget, MemoryBudget};

use crate::status::{guard, Failure, SURFKIT_INVALID_INPUT};

/// Sets the memory every later surfkit call of this process may plan to use, in bytes (at
/// least 1 MiB); 0 goes back to the default, half of the machine's memory. Work that would
/// need more is refused with `SURFKIT_RESOURCE_LIMIT` (or done at a coarser isolation level
/// where the function says so). Thread-safe; calls already running keep their limit.
#[no_mangle]
pub extern "C" fn surfkit_set_max_memory(bytes: u64) -> c_int {
    guard(|| {
        let budget = (bytes != 0)
            .then(|| MemoryBudget::checked(bytes))
            .transpose()
            .map_err(|message| Failure {
                code: SURFKIT_INVALID_INPUT,
                message: format!("{message} (or 0 for the default)"),
            })?;
        set_process_budget(budget);
        Ok(())
    })
}

/// The memory limit in force, in bytes (what [`surfkit_set_max_memory`] set, or half of the
/// machine's memory).
#[no_mangle]
pub extern "C" fn surfkit_max_memory() -> u64 {
    MemoryBudget::default().get()
}
