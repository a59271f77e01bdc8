//! A `core::fmt` renderer: the indented view people know from py_trees, with behavior
//! names and, optionally, each node's last status. Works on host and target alike.
//!
//! ```text
//! [o] Fallback [*]
//!     --> cube on goal? [✕]
//!     {-} Sequence [*]
//!         --> MoveTo(cube) [*]
//! ```
//!
//! Glyphs: `{-}` sequence, `[o]` fallback, `{*}`/`[*]` their with-memory forms, `/_/`
//! parallel, `<?>` if-then-else, `-^-` decorator, `-->` leaf. Marks: `[✓]` success, `[✕]` failure, `[*]`
//! running; Idle nodes have none.

use core::fmt;

use crate::catalog::Catalog;
use crate::exec::NodeState;
use crate::node::{Leaf, NodeKind};
use crate::status::NodeStatus;
use crate::tree::Tree;

/// Displays a tree; made by [`Tree::display`].
#[derive(Debug)]
pub struct Render<'t, 'c, 's, const DEPTH: usize, C: ?Sized> {
    tree: Tree<'t, DEPTH>,
    catalog: &'c C,
    states: Option<&'s [NodeState]>,
}

impl<'t, const DEPTH: usize> Tree<'t, DEPTH> {
    /// A [`Display`](fmt::Display) of this tree with names from `catalog`.
    #[must_use]
    pub fn display<'c, C: Catalog + ?Sized>(&self, catalog: &'c C) -> Render<'t, 'c, 'static, DEPTH, C> {
        Render { tree: *self, catalog, states: None }
    }
}

impl<'t, 'c, const DEPTH: usize, C: Catalog + ?Sized> Render<'t, 'c, '_, DEPTH, C> {
    /// Also shows each node's status from `states` (e.g. [`Executor::states`](crate::Executor::states)).
    #[must_use]
    pub fn with_states<'s>(self, states: &'s [NodeState]) -> Render<'t, 'c, 's, DEPTH, C> {
        Render { tree: self.tree, catalog: self.catalog, states: Some(states) }
    }
}

impl<const DEPTH: usize, C: Catalog + ?Sized> fmt::Display for Render<'_, '_, '_, DEPTH, C> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut ends: heapless::Vec<usize, DEPTH> = heapless::Vec::new();
        for (i, node) in self.tree.nodes().iter().enumerate() {
            while ends.last().is_some_and(|&e| e <= i) {
                ends.pop();
            }
            for _ in 0..ends.len() {
                f.write_str("    ")?;
            }
            write_label(f, self.catalog, node.kind(), self.tree.values())?;
            let status = self.states.and_then(|s| s.get(i)).map_or(NodeStatus::Idle, NodeState::status);
            f.write_str(match status {
                NodeStatus::Idle => "",
                NodeStatus::Success => " [✓]",
                NodeStatus::Failure => " [✕]",
                NodeStatus::Running => " [*]",
            })?;
            f.write_str("\n")?;
            if node.kind().arity() != crate::node::Arity::Leaf {
                // Validated depth <= DEPTH, so this cannot overflow; if it did, the
                // indentation would merely flatten.
                let _ = ends.push(i + usize::from(node.size()));
            }
        }
        Ok(())
    }
}

/// Writes one node's label (glyph, name, parameters or arguments) without a newline;
/// extended leaves take their values from `values`, the tree's value table.
///
/// # Errors
/// Whatever the formatter returns.
pub fn write_label<C: Catalog + ?Sized>(
    f: &mut fmt::Formatter<'_>,
    catalog: &C,
    kind: &NodeKind,
    values: &[u16],
) -> fmt::Result {
    match *kind {
        NodeKind::Condition(ref leaf) | NodeKind::Action(ref leaf) => {
            f.write_str("--> ")?;
            return write_leaf(f, catalog, leaf, values);
        }
        NodeKind::Gate(ref leaf) => {
            f.write_str("-^- Gate ")?;
            return write_leaf(f, catalog, leaf, values);
        }
        _ => {}
    }
    write!(f, "{} {}", glyph(kind), kind.name())?;
    write_params(f, kind, values)
}

/// The glyph in front of a kind's name: by family for control nodes, else by arity.
fn glyph(kind: &NodeKind) -> &'static str {
    match kind {
        NodeKind::Sequence | NodeKind::PipelineSequence => "{-}",
        NodeKind::Fallback | NodeKind::Recovery { .. } | NodeKind::RoundRobin => "[o]",
        NodeKind::SequenceWithMemory | NodeKind::SequenceStar => "{*}",
        NodeKind::FallbackWithMemory => "[*]",
        NodeKind::Parallel { .. } | NodeKind::ParallelAll { .. } => "/_/",
        NodeKind::IfThenElse | NodeKind::WhileDoElse => "<?>",
        NodeKind::ManualSelector { .. } => "[?]",
        _ => match kind.arity() {
            crate::node::Arity::Leaf => "-->",
            _ => "-^-",
        },
    }
}

/// A kind's parameters after its name, if it has any.
fn write_params(f: &mut fmt::Formatter<'_>, kind: &NodeKind, values: &[u16]) -> fmt::Result {
    match *kind {
        NodeKind::Parallel { success_threshold, failure_threshold, count_skipped } => {
            let skipped = if count_skipped { ", skipped count" } else { "" };
            write!(f, "(success {success_threshold}, failure {failure_threshold}{skipped})")
        }
        NodeKind::Repeat(n) | NodeKind::Retry(n) => write!(f, "({n})"),
        NodeKind::Timeout(n) => write!(f, "({})", crate::error::Count(usize::from(n), "tick", "ticks")),
        NodeKind::ParallelAll { max_failures } => write!(f, "(max failures {max_failures})"),
        NodeKind::Recovery { retries } => write!(f, "({retries} retries)"),
        NodeKind::RepeatCycles(n) | NodeKind::RetryUntilSuccessful(n) => {
            if n == NodeKind::FOREVER {
                f.write_str("(forever)")
            } else {
                write!(f, "({n})")
            }
        }
        NodeKind::RunOnce { then_skip: true } => f.write_str("(then skip)"),
        NodeKind::TimeLimit(d) | NodeKind::Delay(d) | NodeKind::RateController(d) | NodeKind::Sleep(d) => {
            write!(f, "({})", d.get())
        }
        NodeKind::Script(c) | NodeKind::ScriptCondition(c) | NodeKind::Guard(c) => write!(f, " ({} words)", c.len),
        NodeKind::Precondition { code, otherwise } => write!(f, " ({} words, else {otherwise:?})", code.len),
        NodeKind::Loop { table, if_empty } => match crate::script::queue(table.words(values)) {
            Some(crate::script::Queue::Literal(l)) => {
                write!(f, "({} elements, if empty {if_empty:?})", l.first().copied().unwrap_or(0))
            }
            Some(crate::script::Queue::Key { queue, .. }) => {
                write!(f, "(queue in slot {queue}, if empty {if_empty:?})")
            }
            None => write!(f, "(if empty {if_empty:?})"),
        },
        NodeKind::ManualSelector { repeat_last: true } => f.write_str("(repeat last)"),
        _ => Ok(()),
    }
}

/// Writes a leaf as the catalog names it (by default `name` or `name(arg, ...)`);
/// an extended leaf takes its values from `values`, the tree's value table.
///
/// # Errors
/// Whatever the formatter returns.
pub fn write_leaf<C: Catalog + ?Sized>(
    f: &mut fmt::Formatter<'_>,
    catalog: &C,
    leaf: &Leaf,
    values: &[u16],
) -> fmt::Result {
    catalog.write_leaf(f, leaf, leaf.args_in(values))
}

/// A [`Display`](fmt::Display) of one leaf as the catalog names it; made by
/// [`display_leaf`].
#[derive(Debug)]
pub struct DisplayLeaf<'a, C: ?Sized> {
    catalog: &'a C,
    leaf: &'a Leaf,
    values: &'a [u16],
}

/// Displays `leaf` as `catalog` names it, e.g. `holding(cube)`; an extended leaf takes
/// its values from `values`, the tree's value table.
#[must_use]
pub fn display_leaf<'a, C: Catalog + ?Sized>(catalog: &'a C, leaf: &'a Leaf, values: &'a [u16]) -> DisplayLeaf<'a, C> {
    DisplayLeaf { catalog, leaf, values }
}

impl<C: Catalog + ?Sized> fmt::Display for DisplayLeaf<'_, C> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write_leaf(f, self.catalog, self.leaf, self.values)
    }
}
