//! Graphviz DOT, drawn as in the papers: `→` boxes for Sequences, `?` boxes for
//! Fallbacks, ellipses for conditions, rectangles for actions.

use std::fmt::Write as _;

use bt_core::{Catalog, Node, NodeKind};

use crate::ascii::leaf_text;

fn escape(s: &str) -> String {
    s.replace('\\', "\\\\").replace('"', "\\\"")
}

/// The tree as a DOT digraph; node `n{i}` is bt-core node `i`. Malformed subtree
/// sizes end the drawing early instead of panicking.
#[must_use]
pub fn to_dot<C: Catalog + ?Sized>(nodes: &[Node], catalog: &C) -> String {
    to_dot_with(nodes, &[], catalog)
}

/// [`to_dot`] for a tree with a value table (leaves with more than
/// [`bt_core::MAX_ARGS`] arguments).
#[must_use]
pub fn to_dot_with<C: Catalog + ?Sized>(nodes: &[Node], values: &[u16], catalog: &C) -> String {
    let mut out = String::from("digraph bt {\n  ordering=out;\n  node [fontname=\"Helvetica\"];\n");
    let mut open: Vec<(usize, usize)> = Vec::new();
    for (i, n) in nodes.iter().enumerate() {
        while open.last().is_some_and(|&(_, end)| end <= i) {
            open.pop();
        }
        let (label, shape) = match n.kind() {
            NodeKind::Sequence => ("→".to_string(), "box"),
            NodeKind::Fallback => ("?".to_string(), "box"),
            NodeKind::SequenceWithMemory => ("→*".to_string(), "box"),
            NodeKind::FallbackWithMemory => ("?*".to_string(), "box"),
            NodeKind::Parallel { success_threshold, failure_threshold, .. } => {
                (format!("⇉ {success_threshold}/{failure_threshold}"), "box")
            }
            NodeKind::Inverter => ("¬".to_string(), "diamond"),
            NodeKind::Condition(leaf) => (leaf_text(catalog, leaf, values), "ellipse"),
            NodeKind::Action(leaf) => (leaf_text(catalog, leaf, values), "box"),
            other => (other.name().to_string(), "diamond"),
        };
        let style = match n.kind() {
            NodeKind::Action(_) => ", style=filled, fillcolor=\"#dde8f7\"",
            NodeKind::Condition(_) => ", style=filled, fillcolor=\"#e6f4e0\"",
            _ => "",
        };
        let _ = writeln!(out, "  n{i} [label=\"{}\", shape={shape}{style}];", escape(&label));
        if let Some(&(p, _)) = open.last() {
            let _ = writeln!(out, "  n{p} -> n{i};");
        }
        let end = i + usize::from(n.size());
        if end > nodes.len() || n.size() == 0 {
            break;
        }
        if n.size() > 1 {
            open.push((i, end));
        }
    }
    out.push_str("}\n");
    out
}
