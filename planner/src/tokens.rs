//! The token notation of seed 003: a tree as one line of pre-order tokens.
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
//! use planner::duplo::Task;
//! use planner::tokens;
//!
//! let spec = Task::Tower.spec();
//! let nodes = tokens::parse("s( f( picked 0? pick 0! ) apply force 0! )", &spec)?;
//! assert_eq!(nodes.len(), 5);
//! assert_eq!(tokens::to_string(&nodes, &spec)?, "s( f( picked 0? pick 0! ) apply force 0! )");
//! # Ok::<(), tokens::TokenError>(())
//! ```

use std::fmt::Write as _;

use bt_core::{Catalog, Leaf, LeafKind, Node, NodeKind};

/// Why a tree could not be written as, or read from, tokens.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TokenError {
    /// A node kind the notation has no token for.
    #[error("node {node} is a {kind}; the token notation has only s( f( ) and leaves")]
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
    #[error("column {column}: unknown behavior `{name}`")]
    UnknownLeaf {
        /// 1-based character column where the name starts.
        column: usize,
        /// The name as written.
        name: String,
    },
    /// A leaf name that does not end in `?` or `!`.
    #[error("column {column}: `{text}` is not a token (leaves end in `?` or `!`, controls are `s(`, `f(`, `)`)")]
    BadToken {
        /// 1-based character column.
        column: usize,
        /// The text found.
        text: String,
    },
    /// A `)` with nothing open.
    #[error("column {column}: `)` closes nothing")]
    UnbalancedClose {
        /// 1-based character column.
        column: usize,
    },
    /// The text ended with control nodes still open.
    #[error("{open} control node(s) not closed at the end of the text")]
    Unclosed {
        /// How many are open.
        open: usize,
    },
    /// A control node closed without children.
    #[error("column {column}: `)` closes a control node with no children")]
    EmptyControl {
        /// 1-based character column of the `)`.
        column: usize,
    },
    /// Nothing, or more than one tree.
    #[error("{0}")]
    NotOneTree(&'static str),
    /// More nodes than a tree can hold.
    #[error("more than {} nodes", u16::MAX)]
    TooLong,
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
/// A [`TokenError`] naming the column of the first fault.
pub fn parse<C: Catalog + ?Sized>(text: &str, catalog: &C) -> Result<Vec<Node>, TokenError> {
    let mut names: Vec<(String, LeafKind, u16)> = Vec::with_capacity(catalog.len());
    for id in 0..catalog.len() {
        let Ok(id) = u16::try_from(id) else { break };
        if let Some(info) = catalog.info(id)
            && info.arity == 0
        {
            let mut name = info.name.to_string();
            let mark = if info.kind == LeafKind::Condition { '?' } else { '!' };
            if !name.ends_with(mark) {
                name.push(mark);
            }
            names.push((name, info.kind, id));
        }
    }
    parse_with(text, |token| {
        names.iter().find(|(n, ..)| n == token).map(|&(_, kind, id)| match kind {
            LeafKind::Condition => NodeKind::Condition(Leaf::new(id)),
            LeafKind::Action => NodeKind::Action(Leaf::new(id)),
        })
    })
}

/// Reads tokens, resolving each leaf token (the name with its `?` or `!`) with
/// `resolve`, which returns the leaf node kind or `None` for an unknown name.
///
/// # Errors
/// A [`TokenError`] naming the column of the first fault.
pub fn parse_with(text: &str, mut resolve: impl FnMut(&str) -> Option<NodeKind>) -> Result<Vec<Node>, TokenError> {
    let mut nodes: Vec<Node> = Vec::new();
    let mut open: Vec<usize> = Vec::new();
    let mut rest = text;
    let column = |rest: &str| text[..text.len() - rest.len()].chars().count() + 1;
    loop {
        rest = rest.trim_start();
        if rest.is_empty() {
            break;
        }
        let col = column(rest);
        if nodes.len() >= usize::from(u16::MAX) {
            return Err(TokenError::TooLong);
        }
        if !nodes.is_empty() && open.is_empty() {
            return Err(TokenError::NotOneTree("more than one tree: text continues after the root closed"));
        }
        let control = ["s(", "f("]
            .into_iter()
            .find(|c| rest.starts_with(c) && rest[c.len()..].chars().next().is_none_or(char::is_whitespace));
        if let Some(c) = control {
            open.push(nodes.len());
            let kind = if c == "s(" { NodeKind::Sequence } else { NodeKind::Fallback };
            nodes.push(Node::new(kind, 1));
            rest = &rest[2..];
            continue;
        }
        if let Some(after) = rest.strip_prefix(')') {
            let Some(start) = open.pop() else {
                return Err(TokenError::UnbalancedClose { column: col });
            };
            let size = nodes.len() - start;
            if size < 2 {
                return Err(TokenError::EmptyControl { column: col });
            }
            // size <= nodes.len() < u16::MAX, checked above.
            let kind = *nodes[start].kind();
            nodes[start] = Node::new(kind, size as u16);
            rest = after;
            continue;
        }
        let Some(end) = rest.find(['?', '!']) else {
            let text = rest.split_whitespace().next().unwrap_or(rest).to_string();
            return Err(TokenError::BadToken { column: col, text });
        };
        let name = &rest[..=end];
        let Some(kind) = resolve(name) else {
            return Err(TokenError::UnknownLeaf { column: col, name: name.to_string() });
        };
        nodes.push(Node::new(kind, 1));
        rest = &rest[end + 1..];
    }
    if !open.is_empty() {
        return Err(TokenError::Unclosed { open: open.len() });
    }
    if nodes.is_empty() {
        return Err(TokenError::NotOneTree("no tokens"));
    }
    Ok(nodes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::duplo::Task;

    #[test]
    fn round_trips_every_brick_behavior() {
        for task in Task::ALL {
            let spec = task.spec();
            let leaves: Vec<&str> = spec.names.iter().map(String::as_str).collect();
            let text = format!("f( s( {} ) )", leaves.join(" "));
            let nodes = parse(&text, &spec).unwrap();
            assert_eq!(nodes.len(), leaves.len() + 2);
            assert_eq!(to_string(&nodes, &spec).unwrap(), text);
        }
    }

    #[test]
    fn nested_controls_and_sizes() {
        let spec = Task::Tower.spec();
        let nodes = parse("s( f( 0 on 1? s( pick 0! place on 1! ) ) apply force 0! )", &spec).unwrap();
        let sizes: Vec<u16> = nodes.iter().map(Node::size).collect();
        assert_eq!(sizes, [7, 5, 1, 3, 1, 1, 1]);
        assert_eq!(nodes[2].kind(), &NodeKind::Condition(Leaf::new(spec.id_by_name("0 on 1?").unwrap())));
    }

    #[test]
    fn errors_name_the_column() {
        let spec = Task::Tower.spec();
        assert_eq!(parse("s( pick 9! )", &spec), Err(TokenError::UnknownLeaf { column: 4, name: "pick 9!".into() }));
        assert_eq!(
            parse("s( pick 0! ) )", &spec),
            Err(TokenError::NotOneTree("more than one tree: text continues after the root closed"))
        );
        assert_eq!(
            parse("pick 0! )", &spec),
            Err(TokenError::NotOneTree("more than one tree: text continues after the root closed"))
        );
        assert_eq!(parse(")", &spec), Err(TokenError::UnbalancedClose { column: 1 }));
        assert_eq!(parse("s( f( )", &spec), Err(TokenError::EmptyControl { column: 7 }));
        assert_eq!(parse("s( pick 0!", &spec), Err(TokenError::Unclosed { open: 1 }));
        assert_eq!(parse("s( hello )", &spec), Err(TokenError::BadToken { column: 4, text: "hello".into() }));
        assert_eq!(parse("   ", &spec), Err(TokenError::NotOneTree("no tokens")));
        // A condition name written as an action is unknown.
        assert!(matches!(parse("picked 0!", &spec), Err(TokenError::UnknownLeaf { column: 1, .. })));
    }

    #[test]
    fn other_kinds_are_refused() {
        let spec = Task::Tower.spec();
        let nodes = [Node::new(NodeKind::Inverter, 2), Node::new(NodeKind::Condition(Leaf::new(0)), 1)];
        assert_eq!(to_string(&nodes, &spec), Err(TokenError::NotExpressible { node: 0, kind: "Inverter" }));
        let bad = [Node::new(NodeKind::Sequence, 3), Node::new(NodeKind::Condition(Leaf::new(0)), 1)];
        assert_eq!(to_string(&bad, &spec), Err(TokenError::Malformed { node: 0, size: 3 }));
    }
}
