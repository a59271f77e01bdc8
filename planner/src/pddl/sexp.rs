//! PDDL's surface syntax: symbols and parenthesised lists, with `;` comments. Read
//! without recursion; nesting is bounded so that hostile input cannot exhaust the
//! stack of the recursive interpretation that follows.
//!
//! Line ends may be `\n`, `\r\n` or a lone `\r`; a UTF-8 byte-order mark at the start
//! is skipped. A `?` inside a symbol starts a new one, as other PDDL readers take it:
//! `(aircraft?a)` is `(aircraft ?a)`.
//!
//! The sections that declare names are counted while they are read, so a file that
//! declares more predicates, actions or objects than ids exist for is refused at the
//! first one too many, before the rest of it takes time and memory.

use super::{ErrorKind, Pos};

/// Deepest nesting accepted. Real domains stay under 10.
pub const MAX_DEPTH: usize = 64;

/// Most predicates and actions together (behavior ids are `u16`).
pub const MAX_BEHAVIORS: usize = u16::MAX as usize;
/// Most objects and constants (object ids are `u16`; two values are reserved).
pub const MAX_OBJECTS: usize = crate::model::builder::MAX_OBJECTS as usize;

/// A symbol or a list, with where it starts.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Sexp {
    /// A symbol (name, variable, keyword, ...).
    Symbol(String, Pos),
    /// A parenthesised list.
    List(Vec<Sexp>, Pos),
}

impl Sexp {
    /// Where it starts.
    pub fn pos(&self) -> Pos {
        match self {
            Self::Symbol(_, p) | Self::List(_, p) => *p,
        }
    }

    /// The symbol's text, lower-cased by the reader.
    pub fn symbol(&self) -> Option<&str> {
        match self {
            Self::Symbol(s, _) => Some(s),
            Self::List(..) => None,
        }
    }

    /// The list's items.
    pub fn list(&self) -> Option<&[Sexp]> {
        match self {
            Self::List(items, _) => Some(items),
            Self::Symbol(..) => None,
        }
    }

    /// The head symbol of a list, if it has one.
    pub fn head(&self) -> Option<&str> {
        self.list().and_then(|l| l.first()).and_then(Sexp::symbol)
    }

    /// How a message names it: the symbol in backquotes, or "a list".
    pub fn describe(&self) -> String {
        match self {
            Self::Symbol(s, _) => format!("`{}`", clip(s)),
            Self::List(items, _) => match items.first().and_then(Sexp::symbol) {
                Some(head) => format!("a list `({} ...)`", clip(head)),
                None => "a list".into(),
            },
        }
    }
}

/// At most 40 characters of a symbol for a message, with `...` when cut.
pub fn clip(s: &str) -> String {
    let mut out: String = s.chars().take(40).collect();
    if s.chars().nth(40).is_some() {
        out.push_str("...");
    }
    out
}

/// Counts the names a declaring section holds while it is read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Count {
    /// Not a counted section.
    None,
    /// `(:predicates (p ...) ...)`: one per list.
    Lists { what: &'static str, limit: usize },
    /// `(:objects a b - t ...)`: one per symbol that is not `-` or a type after it.
    Names { what: &'static str, limit: usize },
}

struct Open {
    items: Vec<Sexp>,
    at: Pos,
    count: Count,
    counted: usize,
    /// The last item was `-`: the next one is a type, not a name.
    after_dash: bool,
}

/// Reads exactly one top-level list from `text`.
pub fn read(text: &str) -> Result<Sexp, (Pos, ErrorKind)> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut stack: Vec<Open> = Vec::new();
    let mut done: Option<Sexp> = None;
    let mut behaviors = 0usize;
    let mut line = 1usize;
    let mut column = 1usize;
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        let here = Pos { line, column };
        // A line ends at `\n`, at `\r\n` (one end), or at a lone `\r`.
        let newline = c == '\n' || (c == '\r' && chars.peek() != Some(&'\n'));
        if newline {
            line += 1;
            column = 1;
        } else if c != '\r' {
            column += 1;
        }
        match c {
            ';' => {
                while let Some(&n) = chars.peek() {
                    if n == '\n' || n == '\r' {
                        break;
                    }
                    column += 1;
                    chars.next();
                }
            }
            c if c.is_whitespace() => {}
            '(' => {
                if done.is_some() {
                    return Err((here, ErrorKind::Trailing));
                }
                if stack.len() >= MAX_DEPTH {
                    return Err((here, ErrorKind::TooDeep { limit: MAX_DEPTH }));
                }
                if let Some(parent) = stack.last_mut() {
                    counted(parent, None, here)?;
                }
                stack.push(Open { items: Vec::new(), at: here, count: Count::None, counted: 0, after_dash: false });
            }
            ')' => {
                let Some(open) = stack.pop() else {
                    return Err((here, ErrorKind::UnexpectedClose));
                };
                let list = Sexp::List(open.items, open.at);
                // Actions count against the behavior ids with the predicates.
                if stack.len() == 1 && list.head() == Some(":action") {
                    behaviors += 1;
                    if behaviors > MAX_BEHAVIORS {
                        return Err((
                            open.at,
                            ErrorKind::TooMany { what: "predicates and actions", limit: MAX_BEHAVIORS },
                        ));
                    }
                }
                if stack.len() == 1 && list.head() == Some(":predicates") {
                    behaviors += list.list().map_or(0, |l| l.len().saturating_sub(1));
                    if behaviors > MAX_BEHAVIORS {
                        return Err((
                            open.at,
                            ErrorKind::TooMany { what: "predicates and actions", limit: MAX_BEHAVIORS },
                        ));
                    }
                }
                match stack.last_mut() {
                    Some(parent) => parent.items.push(list),
                    None => done = Some(list),
                }
            }
            c => {
                let mut s = String::new();
                s.push(c.to_ascii_lowercase());
                while let Some(&n) = chars.peek() {
                    if n.is_whitespace() || n == '(' || n == ')' || n == ';' || n == '?' {
                        break;
                    }
                    column += 1;
                    s.push(n.to_ascii_lowercase());
                    chars.next();
                }
                if let Some(bad) = s.chars().find(|ch| ch.is_control()) {
                    return Err((here, ErrorKind::BadCharacter(bad)));
                }
                let Some(parent) = stack.last_mut() else {
                    return Err((
                        here,
                        ErrorKind::Expected { expected: "`(define ...)`".into(), found: format!("`{}`", clip(&s)) },
                    ));
                };
                // The head of a section inside `define` decides what it counts.
                if parent.items.is_empty() && stack.len() == 2 {
                    let section = Count::for_head(&s);
                    if let Some(p) = stack.last_mut() {
                        p.count = section;
                    }
                }
                let Some(parent) = stack.last_mut() else { continue };
                if !parent.items.is_empty() {
                    counted(parent, Some(&s), here)?;
                }
                parent.items.push(Sexp::Symbol(s, here));
            }
        }
    }
    if let Some(first) = stack.first() {
        // Report the innermost unclosed list: that is where the parenthesis is missing.
        let at = stack.last().map_or(first.at, |l| l.at);
        return Err((at, ErrorKind::Unclosed));
    }
    done.ok_or((
        Pos { line, column },
        ErrorKind::Expected { expected: "`(define ...)`".into(), found: "end of file".into() },
    ))
}

impl Count {
    fn for_head(head: &str) -> Self {
        match head {
            ":predicates" => Self::Lists { what: "predicates and actions", limit: MAX_BEHAVIORS },
            ":functions" => Self::Lists { what: "functions", limit: usize::from(u16::MAX) },
            ":objects" | ":constants" => Self::Names { what: "objects", limit: MAX_OBJECTS },
            ":types" => Self::Names { what: "types", limit: usize::from(u16::MAX) - 1 },
            _ => Self::None,
        }
    }
}

/// Counts one more item of a counting section (a list, or the symbol given), refusing
/// the first one past the limit.
fn counted(open: &mut Open, symbol: Option<&str>, at: Pos) -> Result<(), (Pos, ErrorKind)> {
    let one = match (open.count, symbol) {
        (Count::None, _) => false,
        (Count::Lists { .. }, s) => s.is_none(),
        (Count::Names { .. }, Some(s)) => s != "-" && !open.after_dash,
        (Count::Names { .. }, None) => false,
    };
    open.after_dash = symbol == Some("-");
    if one {
        open.counted += 1;
        let (Count::Lists { what, limit } | Count::Names { what, limit }) = open.count else { return Ok(()) };
        if open.counted > limit {
            return Err((at, ErrorKind::TooMany { what, limit }));
        }
    }
    Ok(())
}
