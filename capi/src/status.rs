//! Status codes, the thread-local error message and the guard every exported function runs
//! its body in: errors become a status + message, panics are caught at the boundary.

use std::cell::RefCell;
use std::ffi::{c_char, c_int, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// The version of the C ABI: bumped whenever a declaration of `surfkit.h` changes
/// incompatibly (2: `SurfkitEatOptions.check_fixes` and `SurfkitFlaw.fix_verified`; 3:
/// `SurfkitFairOptions.method` and `SurfkitFairSummary.method`; 4:
/// `SurfkitFairOptions.coarse_start`, `SurfkitFairSummary.coarse_stage` and
/// `coarse_start_used`; 5: `surfkit_mesh_new` takes `index_count`,
/// `SurfkitEatCounts.boundary_loops_walk` and `non_orientable_genus`). Compare with
/// [`surfkit_abi_version`] at run time.
pub const SURFKIT_ABI_VERSION: c_int = 5;

/// Success.
pub const SURFKIT_OK: c_int = 0;
/// A precondition failed: a null pointer, an id out of range, a NaN, an option out of range.
pub const SURFKIT_INVALID_INPUT: c_int = 1;
/// A file could not be read or written.
pub const SURFKIT_IO: c_int = 2;
/// A file's content is malformed (the message names the file and the line or element).
pub const SURFKIT_PARSE: c_int = 3;
/// The mesh's topology does not allow the operation (non-manifold, not quads, …).
pub const SURFKIT_TOPOLOGY: c_int = 4;
/// A numerical solver failed (not converged, not positive definite, infeasible).
pub const SURFKIT_SOLVER: c_int = 5;
/// OpenMesh or OpenSubdiv refused the input.
pub const SURFKIT_FFI: c_int = 6;
/// An internal error (a caught panic): please report it with the message.
pub const SURFKIT_INTERNAL: c_int = 7;
/// The operation would need more memory than its limit (half of the machine's memory, or
/// what surfkit_set_max_memory set), or more work than one of its bounds: the message names
/// what, the limit and how to raise it.
pub const SURFKIT_RESOURCE_LIMIT: c_int = 8;

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

/// A failed call: its status and message.
pub(crate) struct Failure {
    pub code: c_int,
    pub message: String,
}

impl Failure {
    /// The failure with "point `i`: " before its message.
    pub fn at_point(self, i: usize) -> Self {
        Failure {
            message: format!("point {i}: {}", self.message),
            ..self
        }
    }

    pub fn invalid(message: impl Into<String>) -> Self {
        Failure {
            code: SURFKIT_INVALID_INPUT,
            message: message.into(),
        }
    }
}

impl From<surfkit::Error> for Failure {
    fn from(e: surfkit::Error) -> Self {
        use surfkit::Error as E;
        let code = match &e {
            E::Io { .. } => SURFKIT_IO,
            E::Parse { .. } | E::UnknownFormat { .. } => SURFKIT_PARSE,
            E::InvalidInput(_) => SURFKIT_INVALID_INPUT,
            E::Topology(_) => SURFKIT_TOPOLOGY,
            E::Solver { .. } => SURFKIT_SOLVER,
            E::Ffi { .. } => SURFKIT_FFI,
            E::ResourceLimit { .. } | E::WorkLimit { .. } => SURFKIT_RESOURCE_LIMIT,
        };
        Failure {
            code,
            message: e.to_string(),
        }
    }
}

pub(crate) type Outcome = Result<(), Failure>;

fn set_last_error(message: &str) {
    let text = CString::new(message.replace('\0', " ")).unwrap_or_default();
    LAST_ERROR.with(|m| *m.borrow_mut() = text);
}

/// Runs `body`, turning its error into a status + message and a panic into
/// [`SURFKIT_INTERNAL`]; on success the last error message is cleared.
pub(crate) fn guard(body: impl FnOnce() -> Outcome) -> c_int {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => {
            set_last_error("");
            SURFKIT_OK
        }
        Ok(Err(failure)) => {
            set_last_error(&failure.message);
            failure.code
        }
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            set_last_error(&format!("surfkit internal error: {what}"));
            SURFKIT_INTERNAL
        }
    }
}

/// The message of the last failed call on this thread ("" after a successful call). The
/// pointer stays valid until the next surfkit call on the same thread.
#[no_mangle]
pub extern "C" fn surfkit_last_error() -> *const c_char {
    LAST_ERROR.with(|m| m.borrow().as_ptr())
}

/// surfkit's version, e.g. "0.1.0" (a static string).
#[no_mangle]
pub extern "C" fn surfkit_version() -> *const c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr().cast()
}

/// The ABI version the library was built with ([`SURFKIT_ABI_VERSION`] of its header).
#[no_mangle]
pub extern "C" fn surfkit_abi_version() -> c_int {
    SURFKIT_ABI_VERSION
}
