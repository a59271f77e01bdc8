//! stdout and stderr, written with errors returned instead of `print!`'s panics.

use std::io::{self, IsTerminal as _, Write as _};

use super::Content;

/// A write that failed: what was written to, and why, in one line without temporary
/// paths.
#[derive(Debug, thiserror::Error)]
#[error("cannot write {target}: {reason}")]
pub struct WriteError {
    target: String,
    reason: String,
    kind: io::ErrorKind,
}

impl WriteError {
    /// An error writing `target` (`stdout`, a path, ...) because of `reason`.
    pub(crate) fn new(target: impl Into<String>, reason: impl Into<String>, kind: io::ErrorKind) -> Self {
        Self { target: target.into(), reason: reason.into(), kind }
    }

    /// An error from the OS.
    pub(crate) fn io(target: impl Into<String>, e: &io::Error) -> Self {
        Self::new(target, reason(e), e.kind())
    }

    /// Whether the reader of a pipe went away: the program ends quietly, as `cat` does.
    #[must_use]
    pub fn is_broken_pipe(&self) -> bool {
        self.kind == io::ErrorKind::BrokenPipe
    }
}

/// Why an I/O operation failed, without any path (the `tempfile` crate puts the
/// temporary file's path into its errors' messages; a user never needs to see it).
pub(crate) fn reason(e: &io::Error) -> String {
    if let Some(code) = e.raw_os_error() {
        return io::Error::from_raw_os_error(code).to_string();
    }
    match e.kind() {
        io::ErrorKind::PermissionDenied => "permission denied".to_string(),
        io::ErrorKind::ReadOnlyFilesystem => "read-only file system".to_string(),
        io::ErrorKind::StorageFull => "no space left on device".to_string(),
        io::ErrorKind::QuotaExceeded => "disk quota exceeded".to_string(),
        io::ErrorKind::NotADirectory => "not a directory".to_string(),
        io::ErrorKind::NotFound => "no such file or directory".to_string(),
        io::ErrorKind::BrokenPipe => "broken pipe".to_string(),
        kind => kind.to_string(),
    }
}

/// Writes `bytes` to stdout and flushes.
///
/// # Errors
/// The write or the flush failed (a closed pipe, a full disk behind `>`).
pub fn stdout(bytes: &[u8]) -> Result<(), WriteError> {
    let mut out = io::stdout().lock();
    out.write_all(bytes).and_then(|()| out.flush()).map_err(|e| WriteError::io("stdout", &e))
}

/// Writes `bytes` to stderr.
///
/// # Errors
/// The write failed.
pub fn stderr(bytes: &[u8]) -> Result<(), WriteError> {
    let mut err = io::stderr().lock();
    err.write_all(bytes).and_then(|()| err.flush()).map_err(|e| WriteError::io("stderr", &e))
}

/// Refuses binary content when stdout is a terminal.
pub(super) fn check_binary(content: Content) -> Result<(), WriteError> {
    match content {
        Content::Binary(what) if io::stdout().is_terminal() => Err(refusal("stdout", what)),
        _ => Ok(()),
    }
}

/// The error for binary content bound for a terminal.
pub(super) fn refusal(target: &str, what: &str) -> WriteError {
    WriteError::new(
        target,
        format!("it is a terminal and {what} is binary; give --out FILE or redirect the output"),
        io::ErrorKind::InvalidInput,
    )
}
