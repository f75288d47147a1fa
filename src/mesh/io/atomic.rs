//! Atomic file output: temporary file in the same folder, renamed over the target when complete.

use std::io::{BufWriter, Write};
use std::path::Path;

use crate::error::{Error, Result};

/// Writes a file through `fill`, atomically: readers of `path` see the old file or the
/// complete new one, never a partial one; on any error the temporary file is removed.
///
/// # Errors
/// [`Error::Io`] naming `path` when the folder is not writable or a write fails.
pub fn write_atomically(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let io = |e| Error::io(path, e);
    let tmp = tempfile::Builder::new()
        .prefix(".surfkit-")
        .tempfile_in(dir)
        .map_err(io)?;
    {
        let mut out = BufWriter::with_capacity(1 << 20, tmp.as_file());
        fill(&mut out).map_err(io)?;
        out.flush().map_err(io)?;
    }
    tmp.as_file().sync_all().map_err(io)?;
    tmp.persist(path).map_err(|e| io(e.error))?;
    Ok(())
}
