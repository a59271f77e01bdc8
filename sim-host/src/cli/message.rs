//! Error messages as one clean line: line breaks, control and invisible characters
//! escaped, and a line too long to read cut in the middle.

use std::fmt::Write as _;

/// Most characters of an error line. A longer one keeps its first [`HEAD`] and last
/// [`TAIL`] characters (where the file, line and column and the reason are) and says
/// how much was cut.
pub const MAX_LINE: usize = 1000;
/// Characters kept from the start of a line that is cut.
const HEAD: usize = 700;
/// Characters kept from the end of a line that is cut.
const TAIL: usize = 250;

/// Whether `c` must be escaped to be seen: control characters (NUL, line breaks, ESC,
/// DEL, C1), and invisible or reordering ones (zero-width, bidi controls, line and
/// paragraph separators, the byte-order mark).
fn hidden(c: char) -> bool {
    c.is_control()
        || matches!(c, '\u{200b}'..='\u{200f}' | '\u{2028}'..='\u{202e}' | '\u{2060}'..='\u{206f}' | '\u{feff}')
}

/// `s` as one line that shows what it holds: `\n`, `\t`, `\0`, `\u{1b}`, `\u{feff}`
/// for what would break or hide in a terminal, and the middle of an over-long line
/// replaced by `[... N characters cut ...]`.
#[must_use]
pub fn one_line(s: &str) -> String {
    let mut escaped = String::with_capacity(s.len().min(4 * MAX_LINE));
    let mut count = 0usize;
    let total = s.chars().count();
    let cut = total > MAX_LINE;
    for (i, c) in s.chars().enumerate() {
        if cut && i == HEAD {
            let _ = write!(escaped, " [... {} cut ...] ", sim_host::text::count(total - HEAD - TAIL, "character"));
        }
        if cut && i >= HEAD && i < total - TAIL {
            continue;
        }
        count += 1;
        match c {
            '\n' => escaped.push_str("\\n"),
            '\r' => escaped.push_str("\\r"),
            '\t' => escaped.push_str("\\t"),
            '\0' => escaped.push_str("\\0"),
            c if hidden(c) => {
                let _ = write!(escaped, "\\u{{{:x}}}", u32::from(c));
            }
            c => escaped.push(c),
        }
    }
    debug_assert!(count <= MAX_LINE);
    escaped
}

/// An error and its causes in one line, `what: why: deeper why`, each cause said once:
/// a cause whose text its parent's message already ends with (`#[error("...: {0}")]`
/// on a `#[from]` field) is not repeated.
#[must_use]
pub fn chain(e: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if line.is_empty() {
            line = text;
        } else if !line.ends_with(&text) {
            line.push_str(": ");
            line.push_str(&text);
        }
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, thiserror::Error)]
    #[error("tick failed: {0}")]
    struct Wraps(#[from] std::io::Error);

    #[test]
    fn each_cause_is_said_once() {
        let io = std::io::Error::other("the wire broke");
        let e = anyhow::Error::new(Wraps(io)).context("reading x.bt");
        assert_eq!(format!("{e:#}"), "reading x.bt: tick failed: the wire broke: the wire broke");
        assert_eq!(chain(&e), "reading x.bt: tick failed: the wire broke");
    }

    #[test]
    fn escapes_what_would_break_or_hide() {
        assert_eq!(one_line("a\nb\tc\0d\u{1b}[31m\u{feff}e\r"), "a\\nb\\tc\\0d\\u{1b}[31m\\u{feff}e\\r");
        assert_eq!(one_line("brique `ü` ok"), "brique `ü` ok");
    }

    #[test]
    fn cuts_the_middle_of_a_long_line() {
        let long = format!("f.pddl:3:7: unknown predicate `{}` (declared: p)", "x".repeat(50_000_000 / 1000));
        let line = one_line(&long);
        assert!(line.len() < MAX_LINE + 60, "{}", line.len());
        assert!(line.starts_with("f.pddl:3:7: unknown predicate `xxx"));
        assert!(line.ends_with("xxx` (declared: p)"));
        assert!(line.contains("characters cut"));
        let short = "x".repeat(MAX_LINE);
        assert_eq!(one_line(&short), short);
    }
}
