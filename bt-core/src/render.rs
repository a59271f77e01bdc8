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
        NodeKind::Sequence => f.write_str("{-} Sequence"),
        NodeKind::Fallback => f.write_str("[o] Fallback"),
        NodeKind::SequenceWithMemory => f.write_str("{*} SequenceWithMemory"),
        NodeKind::FallbackWithMemory => f.write_str("[*] FallbackWithMemory"),
        NodeKind::Parallel { success_threshold, failure_threshold, count_skipped } => {
            let skipped = if count_skipped { ", skipped count" } else { "" };
            write!(f, "/_/ Parallel(success {success_threshold}, failure {failure_threshold}{skipped})")
        }
        NodeKind::Inverter => f.write_str("-^- Inverter"),
        NodeKind::ForceSuccess => f.write_str("-^- ForceSuccess"),
        NodeKind::ForceFailure => f.write_str("-^- ForceFailure"),
        NodeKind::Repeat(n) => write!(f, "-^- Repeat({n})"),
        NodeKind::Retry(n) => write!(f, "-^- Retry({n})"),
        NodeKind::Timeout(n) => write!(f, "-^- Timeout({})", crate::error::Count(usize::from(n), "tick", "ticks")),
        NodeKind::Condition(ref leaf) | NodeKind::Action(ref leaf) => {
            f.write_str("--> ")?;
            write_leaf(f, catalog, leaf, values)
        }
        NodeKind::SequenceStar => f.write_str("{*} SequenceStar"),
        NodeKind::IfThenElse => f.write_str("<?> IfThenElse"),
        NodeKind::WhileDoElse => f.write_str("<?> WhileDoElse"),
        NodeKind::ParallelAll { max_failures } => write!(f, "/_/ ParallelAll(max failures {max_failures})"),
        NodeKind::PipelineSequence => f.write_str("{-} PipelineSequence"),
        NodeKind::Recovery { retries } => write!(f, "[o] Recovery({retries} retries)"),
        NodeKind::RoundRobin => f.write_str("[o] RoundRobin"),
        NodeKind::RepeatCycles(n) | NodeKind::RetryUntilSuccessful(n) => {
            let name = if matches!(kind, NodeKind::RepeatCycles(_)) { "RepeatCycles" } else { "RetryUntilSuccessful" };
            if n == NodeKind::FOREVER { write!(f, "-^- {name}(forever)") } else { write!(f, "-^- {name}({n})") }
        }
        NodeKind::KeepRunningUntilFailure => f.write_str("-^- KeepRunningUntilFailure"),
        NodeKind::RunOnce { then_skip } => {
            f.write_str(if then_skip { "-^- RunOnce(then skip)" } else { "-^- RunOnce" })
        }
        NodeKind::TimeLimit(d) => write!(f, "-^- TimeLimit({})", d.get()),
        NodeKind::Delay(d) => write!(f, "-^- Delay({})", d.get()),
        NodeKind::RateController(d) => write!(f, "-^- RateController({})", d.get()),
        NodeKind::Gate(ref leaf) => {
            f.write_str("-^- Gate ")?;
            write_leaf(f, catalog, leaf, values)
        }
        NodeKind::AlwaysSuccess => f.write_str("--> AlwaysSuccess"),
        NodeKind::AlwaysFailure => f.write_str("--> AlwaysFailure"),
        NodeKind::Script(c) => write!(f, "--> Script ({} words)", c.len),
        NodeKind::ScriptCondition(c) => write!(f, "--> ScriptCondition ({} words)", c.len),
        NodeKind::Sleep(d) => write!(f, "--> Sleep({})", d.get()),
        NodeKind::Guard(c) => write!(f, "-^- Guard ({} words)", c.len),
        NodeKind::Precondition { code, otherwise } => {
            write!(f, "-^- Precondition ({} words, else {otherwise:?})", code.len)
        }
        NodeKind::Loop { table, if_empty } => match crate::script::queue(table.words(values)) {
            Some(crate::script::Queue::Literal(l)) => {
                write!(f, "-^- Loop({} elements, if empty {if_empty:?})", l.first().copied().unwrap_or(0))
            }
            Some(crate::script::Queue::Key { queue, .. }) => {
                write!(f, "-^- Loop(queue in slot {queue}, if empty {if_empty:?})")
            }
            None => write!(f, "-^- Loop(if empty {if_empty:?})"),
        },
        NodeKind::ManualSelector { repeat_last } => {
            f.write_str(if repeat_last { "[?] ManualSelector(repeat last)" } else { "[?] ManualSelector" })
        }
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
