//! Atomic file output: temporary file in the same folder, renamed over the target when complete.

use std::io::{BufWriter, Write};
use std::path::Path;

use crate::error::{Error, Result};

/// Writes a file through `fill`, atomically: readers of `path` see the old file or the
/// complete new one, never a partial one; on any error the temporary file is removed.
/// A new file gets mode 0666 less the umask (as `>` in a shell gives it); a file replaced
/// keeps its mode; a symlink keeps pointing where it did, and its target is replaced.
///
/// # Errors
/// [`Error::Io`] naming `path` when the folder is not writable or a write fails.
pub fn write_atomically(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    use std::os::unix::fs::PermissionsExt;
    let named = path;
    let io = |e| Error::io(named, e);
    let resolved;
    let path = if path
        .symlink_metadata()
        .is_ok_and(|m| m.file_type().is_symlink())
    {
        resolved = path.canonicalize().map_err(io)?;
        resolved.as_path()
    } else {
        path
    };
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let existing_mode = std::fs::metadata(path).ok().map(|m| m.permissions().mode());
    let tmp = tempfile::Builder::new()
        .prefix(".surfkit-")
        .permissions(std::fs::Permissions::from_mode(0o666))
        .tempfile_in(dir)
        .map_err(io)?;
    if let Some(mode) = existing_mode {
        tmp.as_file()
            .set_permissions(std::fs::Permissions::from_mode(mode))
            .map_err(io)?;
    }
    {
        let mut out = BufWriter::with_capacity(1 << 20, tmp.as_file());
        fill(&mut out).map_err(io)?;
        out.flush().map_err(io)?;
    }
    tmp.as_file().sync_all().map_err(io)?;
    tmp.persist(path).map_err(|e| io(e.error))?;
    Ok(())
}
