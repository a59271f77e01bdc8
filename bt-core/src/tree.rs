//! The validated tree: the only thing the executor accepts.

use crate::catalog::Catalog;
use crate::error::{ArgumentFault, LoadError};
use crate::node::{Arity, Leaf, Node, NodeId, NodeKind};

/// A node array that passed validation against a behavior set, with a depth of at most
/// `DEPTH` levels (the root is level 1).
///
/// Made only by [`Tree::validate`] or [`load`](crate::load). Whatever it holds, the
/// executor cannot panic or index out of bounds on it: subtree sizes nest, every kind
/// has the children it needs, parameters are in range, every leaf names a behavior of
/// the set with the declared kind and arity, and the depth fits the executor's stack.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tree<'a, const DEPTH: usize> {
    nodes: &'a [Node],
    values: &'a [u16],
    depth: u16,
}

#[derive(Clone, Copy)]
struct Open {
    node: NodeId,
    end: usize,
    children: u16,
}

impl<'a, const DEPTH: usize> Tree<'a, DEPTH> {
    /// Checks `nodes` against `catalog` and the depth limit. One pass, no recursion.
    /// The tree has no value table: an extended leaf is refused
    /// ([`Tree::validate_with`] takes one).
    ///
    /// # Errors
    /// The first fault found, as a structural [`LoadError`] naming the node.
    pub fn validate<C: Catalog + ?Sized>(nodes: &'a [Node], catalog: &C) -> Result<Self, LoadError> {
        Self::validate_with(nodes, &[], catalog)
    }

    /// Checks `nodes`, whose extended leaves take their values from `values`, against
    /// `catalog` and the depth limit. One pass, no recursion.
    ///
    /// # Errors
    /// The first fault found, as a structural [`LoadError`] naming the node; an extended
    /// leaf whose range leaves `values` is [`ArgumentFault::ValuesOutOfRange`].
    pub fn validate_with<C: Catalog + ?Sized>(
        nodes: &'a [Node],
        values: &'a [u16],
        catalog: &C,
    ) -> Result<Self, LoadError> {
        let Some(root) = nodes.first() else {
            return Err(LoadError::EmptyTree);
        };
        if nodes.len() > usize::from(u16::MAX) {
            return Err(LoadError::TooManyNodes { count: nodes.len(), capacity: usize::from(u16::MAX) });
        }
        if usize::from(root.size()) != nodes.len() {
            return Err(LoadError::SubtreeSizeInconsistent { node: 0, size: root.size() });
        }
        let mut open: heapless::Vec<Open, DEPTH> = heapless::Vec::new();
        let mut depth = 0usize;
        for (i, node) in nodes.iter().enumerate() {
            let id = i as NodeId; // nodes.len() <= u16::MAX, checked above
            while let Some(top) = open.last().copied() {
                if top.end > i {
                    break;
                }
                open.pop();
                check_children(nodes, top)?;
            }
            let end = i + usize::from(node.size());
            if node.size() == 0 {
                return Err(LoadError::SubtreeSizeInconsistent { node: id, size: 0 });
            }
            if let Some(parent) = open.last_mut() {
                if end > parent.end {
                    return Err(LoadError::SubtreeSizeInconsistent { node: id, size: node.size() });
                }
                parent.children = parent.children.saturating_add(1);
            }
            if open.push(Open { node: id, end, children: 0 }).is_err() {
                return Err(LoadError::DepthOverLimit { node: id, limit: DEPTH });
            }
            depth = depth.max(open.len());
            check_node(id, node, values.len(), catalog)?;
        }
        while let Some(top) = open.pop() {
            check_children(nodes, top)?;
        }
        Ok(Self { nodes, values, depth: depth as u16 })
    }

    /// The nodes, in pre-order.
    #[inline(always)]
    #[must_use]
    pub fn nodes(&self) -> &'a [Node] {
        self.nodes
    }

    /// The value table extended leaves take their values from (often empty).
    #[inline(always)]
    #[must_use]
    pub fn values(&self) -> &'a [u16] {
        self.values
    }

    /// The values of `leaf`, inline or from the value table.
    #[must_use]
    pub fn args<'l>(&self, leaf: &'l Leaf) -> &'l [u16]
    where
        'a: 'l,
    {
        leaf.args_in(self.values)
    }

    /// Number of nodes (at least one).
    #[must_use]
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Always false: a valid tree has a root.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Levels from the root to the deepest leaf, both included.
    #[must_use]
    pub fn depth(&self) -> usize {
        usize::from(self.depth)
    }

    /// Node `id`.
    #[must_use]
    pub fn node(&self, id: NodeId) -> Option<&'a Node> {
        self.nodes.get(usize::from(id))
    }

    /// The children of node `id`, in order.
    #[must_use]
    pub fn children(&self, id: NodeId) -> Children<'a> {
        children(self.nodes, id)
    }

    /// The parent of node `id` (`None` for the root). Walks the array; for tools, not
    /// for the tick path.
    #[must_use]
    pub fn parent(&self, id: NodeId) -> Option<NodeId> {
        let target = usize::from(id);
        let mut best = None;
        for (i, n) in self.nodes.iter().enumerate().take(target) {
            if i + usize::from(n.size()) > target {
                best = Some(i as NodeId);
            }
        }
        best
    }
}

/// The children of a node in a pre-order array.
#[derive(Clone, Debug)]
pub struct Children<'a> {
    nodes: &'a [Node],
    next: usize,
    end: usize,
}

impl Iterator for Children<'_> {
    type Item = NodeId;

    fn next(&mut self) -> Option<NodeId> {
        if self.next >= self.end {
            return None;
        }
        let id = self.next;
        let size = self.nodes.get(id)?.size();
        self.next = id + usize::from(size).max(1);
        Some(id as NodeId)
    }
}

/// The children of node `id` of `nodes`, by subtree sizes (an empty iterator past the end).
#[must_use]
pub fn children(nodes: &[Node], id: NodeId) -> Children<'_> {
    let i = usize::from(id);
    let end = nodes.get(i).map_or(i, |n| (i + usize::from(n.size())).min(nodes.len()));
    Children { nodes, next: i + 1, end }
}

/// Most children of a `RoundRobin`: it counts failed children in one byte of its state.
#[cfg(feature = "btcpp")]
pub(crate) const ROUND_ROBIN_CHILDREN: u16 = 255;

/// Most children of a `ManualSelector`: the behavior set chooses one by a `u8`
/// ([`BehaviorSet::select`](crate::BehaviorSet::select)).
#[cfg(feature = "btcpp")]
pub(crate) const MANUAL_SELECTOR_CHILDREN: u16 = u8::MAX as u16;

/// Whether this build runs `kind`: all kinds with the `btcpp` feature, without it the
/// papers' (a `Parallel` only if it does not count skipped children).
#[inline(always)]
fn supported(kind: &NodeKind) -> bool {
    crate::exec::BTCPP || (kind.family().is_papers() && !matches!(kind, NodeKind::Parallel { count_skipped: true, .. }))
}

/// What [`LoadError::UnsupportedKind`] calls a kind that a build without the `btcpp`
/// feature leaves out. Not its name: the names would cost a controller's flash for an
/// error it reports by code (the host that sent the tree knows what node it is).
pub(crate) const LEFT_OUT_KIND: &str = "BehaviorTree.CPP or Nav2 kind";

/// [`NodeKind::name`] for errors, once in the program rather than inlined at each one.
#[inline(never)]
fn name(kind: &NodeKind) -> &'static str {
    if supported(kind) { kind.name() } else { LEFT_OUT_KIND }
}

fn check_node<C: Catalog + ?Sized>(id: NodeId, node: &Node, values: usize, catalog: &C) -> Result<(), LoadError> {
    let zero = |kind| Err(LoadError::BadArgument { node: id, fault: ArgumentFault::ZeroCount { kind } });
    // A range of the value table that leaves it (a leaf's values, a script's program).
    let out_of_range = |start, len| LoadError::BadArgument {
        node: id,
        fault: ArgumentFault::ValuesOutOfRange { start, len, table: values.min(usize::from(u16::MAX)) as u16 },
    };
    if !supported(node.kind()) {
        return Err(LoadError::UnsupportedKind { node: id, kind: LEFT_OUT_KIND });
    }
    match node.kind() {
        NodeKind::Repeat(0) => zero("Repeat"),
        NodeKind::Retry(0) => zero("Retry"),
        NodeKind::Timeout(0) => zero("Timeout"),
        NodeKind::Condition(leaf) | NodeKind::Action(leaf) | NodeKind::Gate(leaf) => {
            // A gate's behavior is declared as an action (see `NodeKind::Gate`).
            let used = if matches!(node.kind(), NodeKind::Condition(_)) {
                crate::LeafKind::Condition
            } else {
                crate::LeafKind::Action
            };
            let behavior = leaf.behavior();
            let Some(info) = catalog.info(behavior) else {
                return Err(LoadError::UnknownBehavior { node: id, behavior });
            };
            if info.kind != used {
                return Err(LoadError::WrongLeafKind { node: id, behavior, declared: info.kind });
            }
            if let Some((start, len)) = leaf.range()
                && usize::from(start) + usize::from(len) > values
            {
                return Err(out_of_range(start, len));
            }
            let found = leaf.argc() as u16; // at most u16::MAX by construction
            if found != u16::from(info.arity) {
                return Err(LoadError::BadArgument {
                    node: id,
                    fault: ArgumentFault::Count { behavior, expected: info.arity, found },
                });
            }
            Ok(())
        }
        NodeKind::Script(code)
        | NodeKind::ScriptCondition(code)
        | NodeKind::Precondition { code, .. }
        | NodeKind::Guard(code)
        | NodeKind::Loop { table: code, .. }
        | NodeKind::Check { code, .. }
            if code.len == 0 || usize::from(code.start) + usize::from(code.len) > values =>
        {
            Err(out_of_range(code.start, code.len))
        }
        _ => Ok(()),
    }
}

fn check_children(nodes: &[Node], open: Open) -> Result<(), LoadError> {
    let Some(node) = nodes.get(usize::from(open.node)) else {
        return Err(LoadError::SubtreeSizeInconsistent { node: open.node, size: 0 });
    };
    let kind = node.kind();
    let children = open.children;
    let expected = kind.arity();
    let ok = match expected {
        Arity::Leaf => children == 0,
        Arity::One => children == 1,
        Arity::AtLeastOne => children >= 1,
        Arity::Two => children == 2,
        Arity::TwoOrThree => children == 2 || children == 3,
        Arity::Any => true,
    };
    if !ok {
        return Err(LoadError::WrongArity { node: open.node, kind: name(kind), children, expected });
    }
    let bad = |fault| Err(LoadError::BadArgument { node: open.node, fault });
    match *kind {
        NodeKind::Parallel { success_threshold, failure_threshold, .. }
        | NodeKind::ParallelV3 { success_threshold, failure_threshold } => {
            for (which, threshold) in [("success", success_threshold), ("failure", failure_threshold)] {
                if threshold == 0 || threshold > children {
                    return bad(ArgumentFault::Threshold { which, threshold, children });
                }
            }
        }
        #[cfg(feature = "btcpp")]
        NodeKind::ParallelAll { max_failures } if max_failures > children => {
            return bad(ArgumentFault::MaxFailures { max_failures, children });
        }
        #[cfg(feature = "btcpp")]
        NodeKind::RoundRobin if children > ROUND_ROBIN_CHILDREN => {
            return bad(ArgumentFault::TooManyChildren { kind: "RoundRobin", children, limit: ROUND_ROBIN_CHILDREN });
        }
        #[cfg(feature = "btcpp")]
        NodeKind::ManualSelector { .. } if children > MANUAL_SELECTOR_CHILDREN => {
            return bad(ArgumentFault::TooManyChildren {
                kind: "ManualSelector",
                children,
                limit: MANUAL_SELECTOR_CHILDREN,
            });
        }
        _ => {}
    }
    Ok(())
}
