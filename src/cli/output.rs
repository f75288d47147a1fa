//! Standard output for the command line. `print!`/`println!` of the subcommands go through
//! here (the cli module shadows the std macros): a reader that went away (`| head`) ends
//! the command quietly, as `cat` and `grep` do — exit status 141, nothing on stderr — and
//! any other write error (a full disk, `> /dev/full`) is reported on one line with exit
//! status 1, instead of the panic "failed printing to stdout" (exit 101).
//!
//! Output files are written atomically before their summary is printed, so ending here
//! never leaves a half-written file.

use std::io::{ErrorKind, Write};

/// The status of a command whose reader closed the pipe (128 + SIGPIPE, as a shell reports
/// `cat` killed by the signal).
pub const CLOSED_PIPE_STATUS: i32 = 141;

/// Writes `text` to standard output; see the module doc for what a failed write does.
pub fn write_stdout(text: std::fmt::Arguments<'_>) {
    let mut out = std::io::stdout().lock();
    let result = out.write_fmt(text).and_then(|()| out.flush());
    if let Err(e) = result {
        if e.kind() == ErrorKind::BrokenPipe {
            std::process::exit(CLOSED_PIPE_STATUS);
        }
        // Dropping the lock first: the process ends here, stdout is not written again.
        drop(out);
        eprintln!("surfkit: error: cannot write to standard output: {e}");
        std::process::exit(1);
    }
}
