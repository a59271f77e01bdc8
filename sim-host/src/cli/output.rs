//! Everything the CLI writes goes through here: stdout, stderr and output files. Every
//! write returns its error; nothing panics on a closed or full stream.
//!
//! - **Streams** ([`stdout`], [`stderr`]): a write that fails is a [`WriteError`]. When
//!   the reader of a pipe has gone away ([`WriteError::is_broken_pipe`]), `main` ends
//!   the program quietly with exit code 0, as `head`'s writers expect; any other failure
//!   (a full disk behind a redirection, say) is the usual one-line error and exit 2.
//! - **Output targets** (`--out`, `--svg`, [`Target`]): `-` is stdout. A regular file or
//!   a new path is written whole or not at all: into a temporary file in the same
//!   directory, then renamed over the target (an existing file keeps its permissions).
//!   A symbolic link is followed: the file it points to is replaced the same way and the
//!   link stays. Anything else (a device such as `/dev/null` or `/dev/full`, a FIFO) and
//!   every path under `/dev` or `/proc` (such as `/dev/stdout`) is opened and written
//!   through, never replaced, and its errors (`ENOSPC`, ...) are reported.
//! - **Binary output** ([`Content::Binary`]: images, PNG) is refused when it would go to
//!   a terminal.

mod file;
mod stream;

use std::path::{Path, PathBuf};

pub use file::write_file;
pub use stream::{WriteError, stderr, stdout};

/// Where an output goes: a file, or stdout (`-`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Target {
    /// Standard output.
    Stdout,
    /// A file, device or FIFO.
    File(PathBuf),
}

impl Target {
    /// The clap value parser of an output option: `-` is stdout, anything else a path.
    ///
    /// # Errors
    /// An empty value.
    pub fn parse(s: &str) -> Result<Self, String> {
        match s {
            "" => Err("an empty path; give a file name, or `-` for stdout".to_string()),
            "-" => Ok(Self::Stdout),
            _ => Ok(Self::File(PathBuf::from(s))),
        }
    }
}

/// What is being written: text may go to a terminal, binary may not.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Content {
    /// Text (ASCII trees, DOT, XML, SVG, ...).
    Text,
    /// Bytes meant for a program (tree images, PNG), with the name used in messages.
    Binary(&'static str),
}

/// Refuses binary content bound for a terminal, before any work is done.
///
/// # Errors
/// `content` is binary and `target` is stdout, and stdout is a terminal.
pub fn check(target: &Target, content: Content) -> Result<(), WriteError> {
    match target {
        Target::Stdout => stream::check_binary(content),
        Target::File(_) => Ok(()),
    }
}

/// Writes `bytes` to `target`: stdout, or a file as [`write_file`] does.
///
/// # Errors
/// As [`stdout`] and [`write_file`].
pub fn write(target: &Target, bytes: &[u8], content: Content) -> Result<(), WriteError> {
    match target {
        Target::Stdout => {
            stream::check_binary(content)?;
            stdout(bytes)
        }
        Target::File(path) => write_file(path, bytes, content),
    }
}

/// Writes a text file the CLI makes (see [`write_file`]); kept for callers that write
/// files with no `--out` of their own, such as the files of a run folder.
///
/// # Errors
/// As [`write_file`].
pub fn write_whole(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    write_file(path, bytes, Content::Text)
}

/// Writes formatted text to stdout: `out!("{x} nodes")`. Returns the write's result.
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::cli::output::stdout(format!($($arg)*).as_bytes())
    };
}
pub(crate) use out;
