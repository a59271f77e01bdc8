//! Reading what users hand over, within limits: every input file is read through a
//! bounded reader, so that `/dev/zero` or a runaway file is refused after at most the
//! limit's bytes, with a message naming the file and the limit; text must be UTF-8, and
//! where it is not, the message gives the line, column and byte offset.
//!
//! | input | limit |
//! |---|---|
//! | tree image | [`Limit::IMAGE`]: the largest tree (65,535 nodes) with the largest value table (65,535 values), plus 16 MiB for the names and ports sections, whose size the format leaves open |
//! | PDDL domain or problem | [`Limit::PDDL`]: 64 MiB |
//! | tree in the token notation | [`Limit::TOKENS`]: 64 MiB |
//! | a run folder's `run.txt`, `curve.csv` | [`Limit::RUN_FILE`]: 64 MiB |
//! | a controller's trace (`btlog --from-trace`) | [`Limit::TRACE`]: 64 MiB |

use std::fs::File;
use std::io::Read as _;
use std::path::Path;

/// The limit on text inputs (PDDL, token text, run records): 64 MiB, far beyond any
/// real file and small enough to refuse a runaway one at once.
pub const TEXT_LIMIT: u64 = 64 << 20;

/// Room in an image for its names and ports sections together: 16 MiB, hundreds of
/// times what a tree of 65,535 nodes with long names needs.
pub const SECTIONS_LIMIT: u64 = 16 << 20;

/// How much of what an input may be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limit {
    /// Most bytes.
    pub bytes: u64,
    /// What the input is, for messages: `a PDDL file`.
    pub what: &'static str,
}

impl Limit {
    /// A tree image: as long as the format allows for the most nodes and values a tree
    /// has, plus [`SECTIONS_LIMIT`] for the names and ports sections (the format does not
    /// bound them).
    pub const IMAGE: Self = Self {
        bytes: (bt_core::image::max_image_len_with(u16::MAX as usize, u16::MAX as usize, 0)
            + 2 * bt_core::image::MAX_SECTION_HEAD_LEN) as u64
            + SECTIONS_LIMIT,
        what: "a tree image",
    };
    /// A PDDL domain or problem.
    pub const PDDL: Self = Self { bytes: TEXT_LIMIT, what: "a PDDL file" };
    /// A tree in the token notation (or a file that may be an image or tokens).
    pub const TOKENS: Self = Self { bytes: TEXT_LIMIT, what: "a tree file" };
    /// A controller's trace (`sim-host btlog --from-trace`).
    pub const TRACE: Self = Self { bytes: TEXT_LIMIT, what: "a controller trace" };
    /// A file of a `learn` run folder.
    pub const RUN_FILE: Self = Self { bytes: TEXT_LIMIT, what: "a run folder's file" };
}

/// Why an input could not be read.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    /// The file cannot be opened or read.
    #[error("cannot read {path}: {error}")]
    Io {
        /// The file.
        path: String,
        /// Why (in the message; not a separate cause, so it is said once).
        error: std::io::Error,
    },
    /// The file goes on past its limit.
    #[error("{path}: larger than {}, the most {} may be (read no further)", bytes(.limit.bytes), .limit.what)]
    TooLarge {
        /// The file.
        path: String,
        /// The limit it hit.
        limit: Limit,
    },
    /// Text that is not UTF-8.
    #[error("{path}:{line}:{column}: not UTF-8 (byte offset {offset}: {byte:#04x})")]
    NotUtf8 {
        /// The file.
        path: String,
        /// 1-based line of the first bad byte.
        line: usize,
        /// 1-based column, in characters.
        column: usize,
        /// 0-based byte offset in the file.
        offset: usize,
        /// The bad byte.
        byte: u8,
    },
}

/// `n` bytes for people: `64 MiB` when exact, else `1,114,115 bytes`.
fn bytes(n: u64) -> String {
    if n >= 1 << 20 && n.is_multiple_of(1 << 20) {
        return format!("{} MiB", n >> 20);
    }
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    format!("{out} bytes")
}

/// Reads at most `limit` bytes of `path`.
///
/// # Errors
/// [`InputError::Io`] when it cannot be read, [`InputError::TooLarge`] when it holds
/// more than the limit (a regular file is refused by its size, without reading it).
pub fn read(path: &Path, limit: Limit) -> Result<Vec<u8>, InputError> {
    let name = || path.display().to_string();
    let io = |error| InputError::Io { path: name(), error };
    let file = File::open(path).map_err(io)?;
    let known = file.metadata().ok().filter(std::fs::Metadata::is_file).map(|m| m.len());
    if known.is_some_and(|len| len > limit.bytes) {
        return Err(InputError::TooLarge { path: name(), limit });
    }
    let mut buf = Vec::with_capacity(known.map_or(8 << 10, |len| usize::try_from(len).unwrap_or(0)));
    file.take(limit.bytes.saturating_add(1)).read_to_end(&mut buf).map_err(io)?;
    if buf.len() as u64 > limit.bytes {
        return Err(InputError::TooLarge { path: name(), limit });
    }
    Ok(buf)
}

/// Reads `path` as UTF-8 text of at most `limit` bytes.
///
/// # Errors
/// As [`read`], and [`InputError::NotUtf8`] with the place of the first bad byte.
pub fn read_text(path: &Path, limit: Limit) -> Result<String, InputError> {
    text(path, read(path, limit)?)
}

/// `bytes` of the file `path` as UTF-8 text.
///
/// # Errors
/// [`InputError::NotUtf8`] with the line, column and byte offset of the first bad byte.
pub fn text(path: &Path, bytes: Vec<u8>) -> Result<String, InputError> {
    String::from_utf8(bytes).map_err(|e| {
        let bytes = e.as_bytes();
        let offset = e.utf8_error().valid_up_to();
        let good = bytes.get(..offset).unwrap_or_default();
        let line_start = good.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
        let line = 1 + good.iter().filter(|&&b| b == b'\n').count();
        let column =
            1 + std::str::from_utf8(good.get(line_start..).unwrap_or_default()).map_or(0, |s| s.chars().count());
        InputError::NotUtf8 {
            path: path.display().to_string(),
            line,
            column,
            offset,
            byte: bytes.get(offset).copied().unwrap_or(0),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_read_as_people_write_them() {
        assert_eq!(bytes(64 << 20), "64 MiB");
        assert_eq!(bytes(1_114_115), "1,114,115 bytes");
        assert_eq!(bytes(Limit::IMAGE.bytes), "18,087,957 bytes");
        assert_eq!(bytes(999), "999 bytes");
        assert_eq!(Limit::IMAGE.bytes, 1_114_115 + 6 + 3 + 3 * 65_535 + 2 * 6 + (16 << 20));
    }

    #[test]
    fn not_utf8_names_line_column_and_offset() {
        let e = text(Path::new("d.pddl"), b"(define\n  (domain \xc3\xa9x\xff)".to_vec()).unwrap_err();
        assert_eq!(e.to_string(), "d.pddl:2:13: not UTF-8 (byte offset 21: 0xff)");
    }

    #[test]
    fn an_endless_input_stops_at_the_limit() {
        let small = Limit { bytes: 1000, what: "a test file" };
        let e = read(Path::new("/dev/zero"), small).unwrap_err();
        assert_eq!(e.to_string(), "/dev/zero: larger than 1,000 bytes, the most a test file may be (read no further)");
    }
}
