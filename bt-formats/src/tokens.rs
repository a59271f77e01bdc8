//! The token notation of Styrud et al.: a tree as one line of pre-order tokens.
//!
//! `s(` opens a reactive Sequence, `f(` a reactive Fallback, `)` closes the innermost
//! open one, and a leaf is written by its name, which ends in `?` for a condition and
//! `!` for an action:
//!
//! ```text
//! s( f( 0 on 1? put 0 on 1! ) apply force 0! )
//! ```
//!
//! Tokens are separated by whitespace. A leaf name may itself contain spaces,
//! parentheses and commas (`0 at pos (0.0, 0.05, 0.0)?`): it runs up to and including
//! the first `?` or `!`. Only reactive Sequence, Fallback and leaves can be written;
//! other node kinds are refused with [`TokenError::NotExpressible`].
//!
//! ```
//! use bt_core::BehaviorInfo;
//! use bt_formats::tokens;
//!
//! const SET: [BehaviorInfo<'static>; 3] = [
//!     BehaviorInfo::condition("picked 0?", 0),
//!     BehaviorInfo::action("pick 0!", 0),
//!     BehaviorInfo::action("apply force 0!", 0),
//! ];
//! let nodes = tokens::parse("s( f( picked 0? pick 0! ) apply force 0! )", &SET[..])?;
//! assert_eq!(nodes.len(), 5);
//! assert_eq!(tokens::to_string(&nodes, &SET[..])?, "s( f( picked 0? pick 0! ) apply force 0! )");
//! # Ok::<(), tokens::TokenError>(())
//! ```

use std::collections::HashMap;
use std::fmt::Write as _;

use bt_core::{Catalog, Leaf, LeafKind, Node, NodeKind};

/// Where in a token text: 1-based line and column (in characters).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Location {
    /// 1-based line.
    pub line: usize,
    /// 1-based column, in characters.
    pub column: usize,
}

impl std::fmt::Display for Location {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}", self.line, self.column)
    }
}

/// Most characters of a token an error message quotes.
const QUOTED: usize = 60;

/// `text` cut to [`QUOTED`] characters for a message (`...` and the length after it).
fn quoted(text: &str) -> String {
    match text.char_indices().nth(QUOTED) {
        None => text.to_string(),
        Some((at, _)) => format!("{}... ({} characters)", &text[..at], text.chars().count()),
    }
}

/// `n` and the noun, singular for 1: `1 control node`, `3 control nodes`.
fn count(n: usize, noun: &str) -> String {
    if n == 1 { format!("1 {noun}") } else { format!("{n} {noun}s") }
}

/// `a` or `an` and the word, by its first letter's sound: `an Inverter`, `a Sequence`.
fn article(word: &str) -> String {
    let vowel = word.chars().next().is_some_and(|c| "aeiouAEIOU".contains(c));
    format!("{} {word}", if vowel { "an" } else { "a" })
}

/// Why a tree could not be written as, or read from, tokens. Reading errors start with
/// the `line:column` of the fault.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TokenError {
    /// A node kind the notation has no token for.
    #[error(
        "the token notation cannot express this tree: node {node} is {}; it has only s( f( ) and leaves",
        article(kind)
    )]
    NotExpressible {
        /// Index of the node.
        node: usize,
        /// Its kind's name.
        kind: &'static str,
    },
    /// The node array is not a well-formed pre-order tree.
    #[error("node {node}: subtree size {size} does not fit inside its parent")]
    Malformed {
        /// Index of the node.
        node: usize,
        /// Its stored size.
        size: u16,
    },
    /// A leaf name that the behavior set does not have.
    #[error("{at}: unknown behavior `{name}`")]
    UnknownLeaf {
        /// Where the name starts.
        at: Location,
        /// The name as written (cut to 60 characters).
        name: String,
    },
    /// A leaf name that does not end in `?` or `!` on its line.
    #[error("{at}: `{text}` is not a token (leaves end in `?` or `!` on the same line, controls are `s(`, `f(`, `)`)")]
    BadToken {
        /// Where it starts.
        at: Location,
        /// The text found (cut to 60 characters).
        text: String,
    },
    /// A `)` with nothing open.
    #[error("{at}: `)` closes nothing")]
    UnbalancedClose {
        /// Where the `)` is.
        at: Location,
    },
    /// The text ended with control nodes still open.
    #[error("{at}: the text ends with {} not closed", count(*open, "control node"))]
    Unclosed {
        /// The end of the text.
        at: Location,
        /// How many are open.
        open: usize,
    },
    /// A control node closed without children.
    #[error("{at}: `)` closes a control node with no children")]
    EmptyControl {
        /// Where the `)` is.
        at: Location,
    },
    /// Text after the root closed.
    #[error("{at}: more than one tree: text continues after the root closed")]
    SecondTree {
        /// Where the second tree starts.
        at: Location,
    },
    /// No tokens at all.
    #[error("no tokens: the text is empty or only whitespace")]
    Empty,
    /// More nodes than a tree can hold.
    #[error("{at}: more than {} nodes, the most a tree holds", u16::MAX)]
    TooLong {
        /// Where the node beyond the limit starts.
        at: Location,
    },
}

impl TokenError {
    /// Where in the text the fault is, for errors of reading.
    #[must_use]
    pub fn at(&self) -> Option<Location> {
        match self {
            Self::UnknownLeaf { at, .. }
            | Self::BadToken { at, .. }
            | Self::UnbalancedClose { at }
            | Self::Unclosed { at, .. }
            | Self::EmptyControl { at }
            | Self::SecondTree { at }
            | Self::TooLong { at } => Some(*at),
            Self::NotExpressible { .. } | Self::Malformed { .. } | Self::Empty => None,
        }
    }
}

/// Writes `nodes` (a pre-order array) as tokens, naming leaves by `catalog`.
///
/// A leaf is written as the catalog renders it; `?` or `!` is appended when the
/// rendering does not already end in the one its kind takes.
///
/// # Errors
/// [`TokenError::NotExpressible`] for node kinds other than reactive Sequence, Fallback
/// and leaves; [`TokenError::Malformed`] when subtree sizes do not nest.
pub fn to_string<C: Catalog + ?Sized>(nodes: &[Node], catalog: &C) -> Result<String, TokenError> {
    let mut out = String::new();
    let mut ends: Vec<usize> = Vec::new();
    for (i, node) in nodes.iter().enumerate() {
        while ends.last().is_some_and(|&e| e <= i) {
            ends.pop();
            out.push_str(") ");
        }
        let end = i + usize::from(node.size());
        if node.size() == 0 || ends.last().is_some_and(|&e| end > e) || end > nodes.len() {
            return Err(TokenError::Malformed { node: i, size: node.size() });
        }
        match node.kind() {
            NodeKind::Sequence => {
                out.push_str("s( ");
                ends.push(end);
            }
            NodeKind::Fallback => {
                out.push_str("f( ");
                ends.push(end);
            }
            NodeKind::Condition(leaf) => push_leaf(&mut out, catalog, leaf, '?'),
            NodeKind::Action(leaf) => push_leaf(&mut out, catalog, leaf, '!'),
            other => return Err(TokenError::NotExpressible { node: i, kind: other.name() }),
        }
    }
    for _ in ends {
        out.push_str(") ");
    }
    out.truncate(out.trim_end().len());
    Ok(out)
}

fn push_leaf<C: Catalog + ?Sized>(out: &mut String, catalog: &C, leaf: &Leaf, mark: char) {
    let start = out.len();
    let _ = write!(out, "{}", bt_core::render::display_leaf(catalog, leaf, &[]));
    if !out[start..].ends_with(mark) {
        out.push(mark);
    }
    out.push(' ');
}

/// Reads tokens into a pre-order node array, resolving each leaf name with `catalog`:
/// a name matches a behavior without arguments whose name (with `?`/`!` appended when
/// missing) is exactly the token.
///
/// # Errors
/// A [`TokenError`] naming the line and column of the first fault.
pub fn parse<C: Catalog + ?Sized>(text: &str, catalog: &C) -> Result<Vec<Node>, TokenError> {
    let mut names: HashMap<String, NodeKind> = HashMap::with_capacity(catalog.len());
    for id in 0..catalog.len() {
        let Ok(id) = u16::try_from(id) else { break };
        if let Some(info) = catalog.info(id)
            && info.arity == 0
        {
            let mut name = info.name.to_string();
            let (mark, kind) = match info.kind {
                LeafKind::Condition => ('?', NodeKind::Condition(Leaf::new(id))),
                LeafKind::Action => ('!', NodeKind::Action(Leaf::new(id))),
            };
            if !name.ends_with(mark) {
                name.push(mark);
            }
            // The first behavior of a name wins, as a linear search would find it.
            names.entry(name).or_insert(kind);
        }
    }
    parse_with(text, |token| names.get(token).copied())
}

/// The reader's place in the text: the rest, and the line and column where it starts.
/// Every character is counted once, so reading is linear in the text's length.
struct Cursor<'t> {
    rest: &'t str,
    at: Location,
}

impl<'t> Cursor<'t> {
    /// Moves past the first `bytes` bytes of the rest (a char boundary).
    fn advance(&mut self, bytes: usize) {
        let (done, rest) = self.rest.split_at(bytes);
        for c in done.chars() {
            if c == '\n' {
                self.at.line += 1;
                self.at.column = 1;
            } else {
                self.at.column += 1;
            }
        }
        self.rest = rest;
    }

    fn skip_whitespace(&mut self) {
        let n = self.rest.len() - self.rest.trim_start().len();
        self.advance(n);
    }
}

/// Reads tokens, resolving each leaf token (the name with its `?` or `!`) with
/// `resolve`, which returns the leaf node kind or `None` for an unknown name. Time and
/// memory are linear in the text's length.
///
/// # Errors
/// A [`TokenError`] naming the line and column of the first fault.
pub fn parse_with(text: &str, mut resolve: impl FnMut(&str) -> Option<NodeKind>) -> Result<Vec<Node>, TokenError> {
    let mut nodes: Vec<Node> = Vec::new();
    let mut open: Vec<usize> = Vec::new();
    let mut cur = Cursor { rest: text, at: Location { line: 1, column: 1 } };
    loop {
        cur.skip_whitespace();
        if cur.rest.is_empty() {
            break;
        }
        let at = cur.at;
        if !nodes.is_empty() && open.is_empty() {
            return Err(TokenError::SecondTree { at });
        }
        if cur.rest.starts_with(')') {
            let Some(start) = open.pop() else {
                return Err(TokenError::UnbalancedClose { at });
            };
            let size = nodes.len() - start;
            if size < 2 {
                return Err(TokenError::EmptyControl { at });
            }
            // size <= nodes.len() <= u16::MAX, checked at every push.
            if let Some(node) = nodes.get_mut(start) {
                *node = Node::new(*node.kind(), size as u16);
            }
            cur.advance(1);
            continue;
        }
        // Every other token is a node.
        if nodes.len() >= usize::from(u16::MAX) {
            return Err(TokenError::TooLong { at });
        }
        let control = ["s(", "f("]
            .into_iter()
            .find(|c| cur.rest.starts_with(c) && cur.rest[c.len()..].chars().next().is_none_or(char::is_whitespace));
        if let Some(c) = control {
            open.push(nodes.len());
            let kind = if c == "s(" { NodeKind::Sequence } else { NodeKind::Fallback };
            nodes.push(Node::new(kind, 1));
            cur.advance(2);
            continue;
        }
        let end = cur.rest.find(['?', '!', '\n']).filter(|&e| cur.rest.as_bytes().get(e) != Some(&b'\n'));
        let Some(end) = end else {
            let word = cur.rest.split_whitespace().next().unwrap_or(cur.rest);
            return Err(TokenError::BadToken { at, text: quoted(word) });
        };
        let name = &cur.rest[..=end];
        let Some(kind) = resolve(name) else {
            return Err(TokenError::UnknownLeaf { at, name: quoted(name) });
        };
        nodes.push(Node::new(kind, 1));
        cur.advance(end + 1);
    }
    if !open.is_empty() {
        return Err(TokenError::Unclosed { at: cur.at, open: open.len() });
    }
    if nodes.is_empty() {
        return Err(TokenError::Empty);
    }
    Ok(nodes)
}

#[cfg(test)]
mod tests {
    use bt_core::BehaviorInfo;

    use super::*;

    const SET: [BehaviorInfo<'static>; 3] = [
        BehaviorInfo::condition("0 at pos (0.0, 0.05, 0.0)?", 0),
        BehaviorInfo::action("pick 0!", 0),
        BehaviorInfo::action("MoveTo", 0),
    ];

    #[test]
    fn names_with_spaces_and_without_marks_read_back() {
        let text = "f( 0 at pos (0.0, 0.05, 0.0)? s( pick 0! MoveTo! ) )";
        let nodes = parse(text, &SET[..]).unwrap();
        assert_eq!(nodes.iter().map(Node::size).collect::<Vec<_>>(), [5, 1, 3, 1, 1]);
        assert_eq!(to_string(&nodes, &SET[..]).unwrap(), text);
        assert_eq!(
            parse("s(\n  MoveTo", &SET[..]).map_err(|e| e.to_string()),
            Err("2:3: `MoveTo` is not a token (leaves end in `?` or `!` on the same line, controls are `s(`, `f(`, `)`)"
                .into())
        );
    }
}
