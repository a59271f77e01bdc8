//! Output files: whole or not at all where that is possible, written through where a
//! replacement would destroy something (a device, a FIFO, a link of the kernel's).

use std::fs;
use std::io::{self, IsTerminal as _, Write as _};
use std::path::{Path, PathBuf};

use super::Content;
use super::stream::{WriteError, reason, refusal};

/// Most symbolic links followed from one output path (Linux's own limit).
const MAX_LINKS: usize = 40;

/// Writes `bytes` to the file at `path`, by what `path` is:
/// - a regular file, or nothing yet: whole or not at all (a temporary file in the same
///   directory, renamed over the target; an existing file keeps its permissions);
/// - a symbolic link: followed, and what it points to is written by these rules (the
///   link stays); a link under `/dev` or `/proc` (`/dev/stdout`, `/proc/self/fd/1`) is
///   opened and written through;
/// - a device (`/dev/null`, `/dev/full`), a FIFO or a socket: opened and written
///   through, with its errors reported;
/// - a directory: an error.
///
/// # Errors
/// One line naming `path` and the reason: a missing directory, a path under a regular
/// file, no permission, a full disk, binary content for a terminal.
pub fn write_file(path: &Path, bytes: &[u8], content: Content) -> Result<(), WriteError> {
    let name = path.display().to_string();
    if path.as_os_str().is_empty() {
        return Err(WriteError::new("''", "an empty path", io::ErrorKind::InvalidInput));
    }
    if is_stdout(path) {
        // `--out /dev/stdout`, or the very file stdout is redirected to: one stream, so
        // that what else goes to stdout comes after, not over, what is written here.
        return super::stream::check_binary(content).and_then(|()| super::stdout(bytes));
    }
    let mut current = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        let label = if current == path { name.clone() } else { format!("{name} (a link to {})", current.display()) };
        let meta = match fs::symlink_metadata(&current) {
            Ok(meta) => meta,
            Err(e) if e.kind() == io::ErrorKind::NotFound => return whole(&current, &label, bytes, None),
            Err(e) => return Err(explain(&current, &label, &e)),
        };
        let kind = meta.file_type();
        if kind.is_symlink() {
            if is_kernel_path(&current) {
                return direct(&current, &label, bytes, content);
            }
            let to = fs::read_link(&current).map_err(|e| WriteError::io(label.as_str(), &e))?;
            current = if to.is_absolute() { to } else { parent(&current).join(to) };
        } else if kind.is_file() {
            return whole(&current, &label, bytes, Some(meta.permissions()));
        } else if kind.is_dir() {
            return Err(WriteError::new(label, "it is a directory", io::ErrorKind::IsADirectory));
        } else {
            return direct(&current, &label, bytes, content);
        }
    }
    Err(WriteError::new(name, "too many levels of symbolic links", io::ErrorKind::InvalidInput))
}

/// Whether `path` is the file stdout is (the same device and inode).
fn is_stdout(path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::fd::AsFd as _;
        use std::os::unix::fs::MetadataExt as _;
        let Ok(target) = fs::metadata(path) else { return false };
        let Ok(fd) = io::stdout().as_fd().try_clone_to_owned() else { return false };
        let Ok(out) = fs::File::from(fd).metadata() else { return false };
        out.dev() == target.dev() && out.ino() == target.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = path;
        false
    }
}

/// The directory a path's file is in (`.` for a bare file name).
fn parent(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// Paths where links are the kernel's aliases of open files (`/dev/stdout`,
/// `/dev/fd/N`, `/proc/self/fd/N`): written through, never resolved and replaced.
fn is_kernel_path(path: &Path) -> bool {
    let abs = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    abs.starts_with("/dev") || abs.starts_with("/proc")
}

/// Writes a new or regular file whole: a temporary file beside it, then a rename.
fn whole(path: &Path, label: &str, bytes: &[u8], keep: Option<fs::Permissions>) -> Result<(), WriteError> {
    let dir = parent(path);
    let Some(file_name) = path.file_name() else {
        return Err(WriteError::new(label, "not a file name", io::ErrorKind::InvalidInput));
    };
    let mut builder = tempfile::Builder::new();
    let prefix = format!(".{}.", file_name.to_string_lossy());
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        // A new file gets what any new file gets: 0666 less the umask.
        builder.permissions(keep.clone().unwrap_or_else(|| fs::Permissions::from_mode(0o666)));
    }
    let mut tmp = builder.tempfile_in(dir).map_err(|e| match e.kind() {
        io::ErrorKind::NotFound | io::ErrorKind::NotADirectory => explain(path, label, &e),
        _ => WriteError::new(
            label,
            format!(
                "cannot create a file in {} (the output is written whole, then renamed): {}",
                dir.display(),
                reason(&e)
            ),
            e.kind(),
        ),
    })?;
    if let Some(p) = keep {
        // Exactly the old mode, whatever the umask.
        tmp.as_file().set_permissions(p).map_err(|e| WriteError::io(label, &e))?;
    }
    // Written through the `File`, not the `NamedTempFile`, so that errors carry the OS's
    // code and no temporary path.
    let file = tmp.as_file_mut();
    file.write_all(bytes).and_then(|()| file.sync_all()).map_err(|e| WriteError::io(label, &e))?;
    tmp.persist(path).map_err(|e| WriteError::io(label, &e.error))?;
    Ok(())
}

/// Opens an existing device, FIFO or kernel link and writes through it.
fn direct(path: &Path, label: &str, bytes: &[u8], content: Content) -> Result<(), WriteError> {
    let mut file =
        fs::OpenOptions::new().write(true).truncate(true).open(path).map_err(|e| WriteError::io(label, &e))?;
    if let Content::Binary(what) = content
        && file.is_terminal()
    {
        return Err(refusal(label, what));
    }
    file.write_all(bytes).and_then(|()| file.flush()).map_err(|e| WriteError::io(label, &e))
}

/// Says why `path` cannot be reached: the nearest ancestor that is a file, or the
/// topmost directory that does not exist.
fn explain(path: &Path, label: &str, e: &io::Error) -> WriteError {
    let mut missing: Option<PathBuf> = None;
    for a in path.ancestors().skip(1) {
        let a = if a.as_os_str().is_empty() { Path::new(".") } else { a };
        match fs::metadata(a) {
            Ok(m) if m.is_dir() => break,
            Ok(_) => {
                return WriteError::new(
                    label,
                    format!("{} is a file, not a directory", a.display()),
                    io::ErrorKind::NotADirectory,
                );
            }
            Err(err) if err.kind() == io::ErrorKind::NotFound => missing = Some(a.to_path_buf()),
            // A file further up: the loop gets to it.
            Err(err) if err.kind() == io::ErrorKind::NotADirectory => {}
            Err(_) => break,
        }
    }
    match missing {
        Some(dir) => {
            WriteError::new(label, format!("directory {} does not exist", dir.display()), io::ErrorKind::NotFound)
        }
        None => WriteError::io(label, e),
    }
}
