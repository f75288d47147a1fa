//! Atomic file output: temporary file in the same folder, renamed over the target when complete.
//! A target that is not a regular file (a FIFO, `/dev/stdout`, a device) is written in place.

use std::io::{BufWriter, Write};
use std::path::Path;

use crate::error::{Error, Result};

/// Writes a file through `fill`, atomically: readers of `path` see the old file or the
/// complete new one, never a partial one; on any error the temporary file is removed.
/// A new file gets mode 0666 less the umask (as `>` in a shell gives it); a file replaced
/// keeps its mode; a symlink keeps pointing where it did, and its target is replaced.
/// An existing target that is neither a regular file nor a folder, itself or through
/// symlinks (a FIFO, `/dev/stdout`, `/dev/null`), is opened and written as a shell's `>`
/// does ([`write_in_place`]): renaming over it would replace the pipe or device.
///
/// # Errors
/// [`Error::Io`] naming `path` when the folder is not writable or a write fails (also a
/// device's: `/dev/full` is "No space left on device").
pub fn write_atomically(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    use std::os::unix::fs::PermissionsExt;
    // `metadata` follows symlinks in the kernel, so /proc's links (/dev/stdout → a pipe)
    // are seen for what they are; `canonicalize` cannot resolve those.
    if std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir()) {
        return write_in_place(path, fill);
    }
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

/// Writes `fill`'s bytes to an existing pipe or device opened for writing: no temporary, no
/// rename, not atomic (a pipe's reader sees the bytes as they come). Opening a FIFO waits
/// for its reader, as `>` does.
fn write_in_place(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let io = |e| Error::io(path, e);
    let file = std::fs::OpenOptions::new()
        .write(true)
        .open(path)
        .map_err(io)?;
    let mut out = BufWriter::with_capacity(1 << 20, &file);
    fill(&mut out).map_err(io)?;
    out.flush().map_err(io)?;
    Ok(())
}
