//! The one error type of surfkit.
//!
//! Every public fallible function returns `Result<_, surfkit::Error>`. Messages name the
//! file, the line or element and what was wrong, so that a user can fix the input without
//! reading our code.

use std::fmt;
use std::path::{Path, PathBuf};

/// Where in an input a problem was found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Location {
    /// A 1-based line of a text file.
    Line(usize),
    /// An element of a binary file: its kind (`vertex`, `face`, …), 0-based index, and byte offset.
    Element {
        kind: String,
        index: usize,
        byte_offset: usize,
    },
    /// The header of a file.
    Header,
    /// The whole file (empty, unknown format).
    File,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Line(n) => write!(f, "line {n}"),
            Location::Element {
                kind,
                index,
                byte_offset,
            } => write!(f, "{kind} {index} (byte {byte_offset})"),
            Location::Header => write!(f, "header"),
            Location::File => write!(f, "file"),
        }
    }
}

/// What went wrong in solving a numerical problem.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SolverFailure {
    NotConverged,
    NotPositiveDefinite,
    Infeasible,
    Singular,
}

impl fmt::Display for SolverFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            SolverFailure::NotConverged => "not converged",
            SolverFailure::NotPositiveDefinite => "matrix not positive definite",
            SolverFailure::Infeasible => "problem infeasible",
            SolverFailure::Singular => "matrix singular",
        })
    }
}

/// The surfkit error.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The operating system refused a read or write.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A file's content is malformed.
    #[error("{}: {location}: {message}", path.display())]
    Parse {
        path: PathBuf,
        location: Location,
        message: String,
    },
    /// A file's extension names no format we read or write.
    #[error("{}: unknown mesh format (extension {extension:?}); surfkit reads and writes .obj, .ply, .off and .stl", path.display())]
    UnknownFormat { path: PathBuf, extension: String },
    /// A precondition of a function was not met by its arguments.
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// An operation would need more memory than its budget allows
    /// ([`crate::limits::MemoryBudget`]).
    #[error("{what} needs more than the memory limit of {} ({advice}; raise the limit with --max-memory)", crate::limits::human_bytes(*limit))]
    ResourceLimit {
        what: String,
        limit: u64,
        advice: String,
    },
    /// An operation would pass a bound on its work that is not memory (stencil weights of a
    /// limit surface, …): `limit` names the bound and how to raise it.
    #[error("{what} needs more than {limit} ({advice})")]
    WorkLimit {
        what: String,
        limit: String,
        advice: String,
    },
    /// The mesh's topology does not allow the operation.
    #[error("topology: {0}")]
    Topology(String),
    /// A numerical solve failed.
    #[error("solver: {failure}: {detail}")]
    Solver {
        failure: SolverFailure,
        detail: String,
    },
    /// A C++ library reported a failure.
    #[error("{library}: {message}")]
    Ffi {
        library: &'static str,
        message: String,
    },
}

/// The surfkit result.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// A parse error at `location` of `path`.
    pub fn parse(path: &Path, location: Location, message: impl Into<String>) -> Self {
        Error::Parse {
            path: path.to_path_buf(),
            location,
            message: message.into(),
        }
    }

    /// An I/O error on `path`.
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        Error::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}
