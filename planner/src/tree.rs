//! The tree the planner grows: an arena of nodes with stable ids, edited in place by
//! `expand` and `increase_priority`, and flattened into the pre-order array bt-core
//! ticks.
//!
//! Negative conditions: a condition `not p` is written as `Inverter(Condition p)` in
//! the bt-core tree (the pair counts as one condition for the planner).

use bt_core::{Leaf, Node, NodeKind};

use crate::PlanError;
use crate::ground::{ActionId, Grounding, Lit};

/// Why a leaf could not be made: none in the behavior set, or a value table full.
fn no_leaf(call: Option<(u16, &[u16])>, name: impl Fn() -> String) -> PlanError {
    match call {
        Some((_, args)) if args.len() > bt_core::MAX_ARGS => PlanError::TooManyValues { limit: usize::from(u16::MAX) },
        _ => PlanError::NoLeaf { condition: name() },
    }
}

/// The leaf of a call under the PDDL contract: inline up to [`bt_core::MAX_ARGS`]
/// values, else extended, its values in `values` (a run of values already in the
/// table is shared).
fn leaf_of(
    call: (u16, &[u16]),
    values: &mut Vec<u16>,
    runs: &mut std::collections::HashMap<Vec<u16>, u16>,
) -> Option<Leaf> {
    let (behavior, args) = call;
    if args.len() <= bt_core::MAX_ARGS {
        return Leaf::with_args(behavior, args).ok();
    }
    let start = match runs.get(args) {
        Some(&s) => s,
        None => {
            let s = u16::try_from(values.len()).ok()?;
            if values.len() + args.len() > usize::from(u16::MAX) {
                return None;
            }
            values.extend_from_slice(args);
            runs.insert(args.to_vec(), s);
            s
        }
    };
    Leaf::extended(behavior, start, u16::try_from(args.len()).ok()?).ok()
}

/// Id of a planner node; stable across edits.
pub type PlanNode = u32;
const NONE: u32 = u32::MAX;

/// The most levels of a tree the host tools make, load and run ([`bt_formats::DEPTH`]):
/// the planner emits no deeper tree. Re-exported as `planner::DEPTH`.
pub const DEPTH: usize = bt_formats::DEPTH;

/// What a planner node is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Reactive sequence.
    Sequence,
    /// Reactive fallback.
    Fallback,
    /// A condition (a literal).
    Condition(Lit),
    /// A ground action.
    Action(ActionId),
}

#[derive(Clone, Debug)]
struct Slot {
    kind: Kind,
    parent: u32,
    children: Vec<PlanNode>,
}

/// The planner's editable tree.
#[derive(Clone, Debug)]
pub struct PlanTree {
    slots: Vec<Slot>,
    root: PlanNode,
}

/// A flattened tree: the bt-core nodes and the maps between the two numberings.
#[derive(Clone, Debug, Default)]
pub struct Flat {
    /// The bt-core pre-order array.
    pub nodes: Vec<Node>,
    /// Planner node → index of its (top) bt-core node.
    pub top: Vec<u32>,
    /// bt-core index → planner node (both nodes of an inverted condition map to it).
    pub of: Vec<PlanNode>,
    /// Depth of each bt-core node (root 0).
    pub depth: Vec<u16>,
    /// The value table of the extended leaves (those with more than
    /// [`bt_core::MAX_ARGS`] values; empty when there are none).
    pub values: Vec<u16>,
}

impl PlanTree {
    /// The initial tree of Algorithm 1 (lines 1-3): the goal condition alone, or a
    /// Sequence of the goal conditions in order.
    #[must_use]
    pub fn from_goal(goal: &[Lit]) -> Self {
        let mut t = Self { slots: Vec::new(), root: 0 };
        if let [single] = goal {
            t.root = t.add(Kind::Condition(*single));
        } else {
            t.root = t.add(Kind::Sequence);
            for &g in goal {
                let c = t.add(Kind::Condition(g));
                t.push_child(t.root, c);
            }
        }
        t
    }

    /// A tree of one node of `kind` (its root); grow it with [`PlanTree::add`] and
    /// [`PlanTree::push_child`].
    #[must_use]
    pub fn with_root(kind: Kind) -> Self {
        let mut t = Self { slots: Vec::new(), root: 0 };
        t.root = t.add(kind);
        t
    }

    /// The initial tree with the goal conditions always under a Sequence, even a
    /// single one ([`crate::Options::goal_sequence`]).
    #[must_use]
    pub fn goal_sequence(goal: &[Lit]) -> Self {
        let mut t = Self { slots: Vec::new(), root: 0 };
        t.root = t.add(Kind::Sequence);
        for &g in goal {
            let c = t.add(Kind::Condition(g));
            t.push_child(t.root, c);
        }
        t
    }

    /// A new detached node.
    pub fn add(&mut self, kind: Kind) -> PlanNode {
        self.slots.push(Slot { kind, parent: NONE, children: Vec::new() });
        (self.slots.len() - 1) as PlanNode
    }

    /// Appends `child` (detached) to `parent`'s children.
    pub fn push_child(&mut self, parent: PlanNode, child: PlanNode) {
        self.slots[child as usize].parent = parent;
        self.slots[parent as usize].children.push(child);
    }

    /// A step and the conditions it needs, detached: `Sequence(when?.., action)`, or the
    /// action alone when `when` is empty (a row of an atomic BT, a rule).
    pub fn step(&mut self, when: &[Lit], action: ActionId) -> PlanNode {
        let act = self.add(Kind::Action(action));
        if when.is_empty() {
            return act;
        }
        let seq = self.add(Kind::Sequence);
        for &l in when {
            let c = self.add(Kind::Condition(l));
            self.push_child(seq, c);
        }
        self.push_child(seq, act);
        seq
    }

    /// Appends [`PlanTree::step`]`(when, action)` to `parent`.
    pub fn push_step(&mut self, parent: PlanNode, when: &[Lit], action: ActionId) {
        let s = self.step(when, action);
        self.push_child(parent, s);
    }

    /// The root.
    #[must_use]
    pub fn root(&self) -> PlanNode {
        self.root
    }

    /// Number of planner nodes ever made (ids run below it).
    #[must_use]
    pub fn capacity(&self) -> usize {
        self.slots.len()
    }

    /// The node's kind.
    #[must_use]
    pub fn kind(&self, n: PlanNode) -> Kind {
        self.slots[n as usize].kind
    }

    /// The node's parent (`None` for the root or a detached node).
    #[must_use]
    pub fn parent(&self, n: PlanNode) -> Option<PlanNode> {
        let p = self.slots[n as usize].parent;
        (p != NONE).then_some(p)
    }

    /// The node's children.
    #[must_use]
    pub fn children(&self, n: PlanNode) -> &[PlanNode] {
        &self.slots[n as usize].children
    }

    /// Index of `n` among its parent's children.
    #[must_use]
    pub fn index_in_parent(&self, n: PlanNode) -> Option<usize> {
        let p = self.parent(n)?;
        self.children(p).iter().position(|&c| c == n)
    }

    /// Puts `new` (detached) where `old` is, leaving `old` detached.
    pub fn replace(&mut self, old: PlanNode, new: PlanNode) {
        match self.parent(old) {
            None => self.root = new,
            Some(p) => {
                if let Some(i) = self.index_in_parent(old) {
                    self.slots[p as usize].children[i] = new;
                }
                self.slots[new as usize].parent = p;
            }
        }
        self.slots[old as usize].parent = NONE;
    }

    /// Detaches `n` from its parent.
    pub fn detach(&mut self, n: PlanNode) {
        if let (Some(p), Some(i)) = (self.parent(n), self.index_in_parent(n)) {
            self.slots[p as usize].children.remove(i);
        }
        self.slots[n as usize].parent = NONE;
    }

    /// Inserts `n` (detached) as child `index` of `parent`.
    pub fn insert(&mut self, parent: PlanNode, index: usize, n: PlanNode) {
        let c = &mut self.slots[parent as usize].children;
        c.insert(index.min(c.len()), n);
        self.slots[n as usize].parent = parent;
    }

    /// Copies `other` (from its root) in as the last child of `parent`; returns the
    /// copy's root.
    pub fn graft(&mut self, parent: PlanNode, other: &PlanTree) -> PlanNode {
        self.graft_from(parent, other, other.root)
    }

    /// Copies `other`'s subtree under `from` in as the last child of `parent`; returns
    /// the copy's root.
    pub fn graft_from(&mut self, parent: PlanNode, other: &PlanTree, from: PlanNode) -> PlanNode {
        let mut copy = vec![NONE; other.slots.len()];
        for n in other.preorder(from) {
            let c = self.add(other.kind(n));
            copy[n as usize] = c;
            let up = if n == from { parent } else { other.parent(n).map_or(parent, |p| copy[p as usize]) };
            self.push_child(up, c);
        }
        copy[from as usize]
    }

    /// The action of a row of an atomic BT: `n` itself if it is an action, the last
    /// child of a Sequence `n` if that is one.
    #[must_use]
    pub fn row_action(&self, n: PlanNode) -> Option<ActionId> {
        let last = match self.kind(n) {
            Kind::Sequence => *self.children(n).last()?,
            _ => n,
        };
        match self.kind(last) {
            Kind::Action(a) => Some(a),
            _ => None,
        }
    }

    /// The nodes of the subtree at `n` in pre-order.
    #[must_use]
    pub fn preorder(&self, n: PlanNode) -> Vec<PlanNode> {
        let mut out = Vec::new();
        let mut stack = vec![n];
        while let Some(x) = stack.pop() {
            out.push(x);
            stack.extend(self.children(x).iter().rev());
        }
        out
    }

    /// The planner's tree of a bt-core tree made of the kinds it grows (Sequence,
    /// Fallback, conditions, `Inverter(Condition)` for a negative one, actions), its
    /// leaves read under `grounding`'s PDDL contract; `values` is the tree's value table.
    /// The inverse of [`PlanTree::flatten`].
    ///
    /// # Errors
    /// [`PlanError::InvalidTree`] naming the node: another kind, a leaf that is no
    /// condition or action of the problem, sizes that do not nest.
    pub fn from_nodes(g: &Grounding, nodes: &[Node], values: &[u16]) -> Result<Self, PlanError> {
        let bad = |i: usize, why: String| PlanError::InvalidTree(format!("node {i}: {why}"));
        let mut t = Self { slots: Vec::new(), root: 0 };
        // Open control nodes: (planner node, index past its subtree).
        let mut open: Vec<(PlanNode, usize)> = Vec::new();
        let mut alternatives = Vec::new();
        let mut i = 0;
        while let Some(node) = nodes.get(i) {
            while open.last().is_some_and(|&(_, end)| end <= i) {
                open.pop();
            }
            let end = i + usize::from(node.size());
            if node.size() == 0 || end > nodes.len() || open.last().is_some_and(|&(_, e)| end > e) {
                return Err(bad(i, "subtree sizes do not nest".into()));
            }
            let (kind, step) = match node.kind() {
                NodeKind::Sequence => (Kind::Sequence, 1),
                NodeKind::Fallback => (Kind::Fallback, 1),
                NodeKind::Inverter => match nodes.get(i + 1).map(Node::kind) {
                    Some(NodeKind::Condition(leaf)) if node.size() == 2 => {
                        let atom = g.leaf_atom_of(leaf, leaf.args_in(values));
                        let atom = atom.ok_or_else(|| bad(i + 1, "not a condition of this problem".into()))?;
                        (Kind::Condition(Lit { atom, positive: false }), 2)
                    }
                    _ => return Err(bad(i, "an Inverter over something other than a condition".into())),
                },
                NodeKind::Condition(leaf) => {
                    let atom = g.leaf_atom_of(leaf, leaf.args_in(values));
                    (
                        Kind::Condition(Lit {
                            atom: atom.ok_or_else(|| bad(i, "not a condition of this problem".into()))?,
                            positive: true,
                        }),
                        1,
                    )
                }
                NodeKind::Action(leaf) => {
                    g.leaf_actions_of(leaf, leaf.args_in(values), &mut alternatives);
                    let a = alternatives.first().copied();
                    (Kind::Action(a.ok_or_else(|| bad(i, "not an action of this problem".into()))?), 1)
                }
                other => {
                    return Err(bad(
                        i,
                        format!("a {}: the planner grows only Sequence, Fallback and leaves", other.name()),
                    ));
                }
            };
            let n = t.add(kind);
            match open.last() {
                Some(&(parent, _)) => t.push_child(parent, n),
                None if i == 0 => t.root = n,
                None => return Err(bad(i, "a second root".into())),
            }
            if matches!(kind, Kind::Sequence | Kind::Fallback) {
                open.push((n, end));
            }
            i += step;
        }
        if t.slots.is_empty() {
            return Err(PlanError::InvalidTree("the tree has no node".into()));
        }
        Ok(t)
    }

    /// Flattens the tree into bt-core nodes with `grounding`'s leaves.
    ///
    /// # Errors
    /// [`PlanError::NoLeaf`] for an atom or action without a leaf,
    /// [`PlanError::TreeTooLarge`] beyond `u16` nodes or [`DEPTH`] levels.
    pub fn flatten(&self, g: &Grounding) -> Result<Flat, PlanError> {
        let order = self.preorder(self.root);

        // Flat sizes, children before parents.
        let mut size = vec![0u32; self.slots.len()];
        for &n in order.iter().rev() {
            let own = match self.kind(n) {
                Kind::Condition(l) if !l.positive => 2,
                _ => 1,
            };
            size[n as usize] = own + self.children(n).iter().map(|&c| size[c as usize]).sum::<u32>();
        }
        let total = size[self.root as usize] as usize;
        if total > usize::from(u16::MAX) {
            return Err(PlanError::TooManyNodes { nodes: total, limit: usize::from(u16::MAX) });
        }
        let mut flat = Flat {
            nodes: Vec::with_capacity(total),
            top: vec![NONE; self.slots.len()],
            of: Vec::with_capacity(total),
            depth: Vec::with_capacity(total),
            values: Vec::new(),
        };
        let mut runs = std::collections::HashMap::new();
        let mut depth_of = vec![0u16; self.slots.len()];
        for &n in &order {
            let d = self.parent(n).map_or(0, |p| depth_of[p as usize] + 1);
            depth_of[n as usize] = d;
            // Levels down to this node, root included; a negative condition is two
            // nodes (Inverter over Condition). A tree of exactly DEPTH levels is fine.
            let negative = matches!(self.kind(n), Kind::Condition(l) if !l.positive);
            let levels = usize::from(d) + 1 + usize::from(negative);
            if levels > DEPTH {
                return Err(PlanError::TooDeep { levels, limit: DEPTH });
            }
            flat.top[n as usize] = flat.nodes.len() as u32;
            let s = size[n as usize] as u16;
            match self.kind(n) {
                Kind::Sequence => flat.nodes.push(Node::new(NodeKind::Sequence, s)),
                Kind::Fallback => flat.nodes.push(Node::new(NodeKind::Fallback, s)),
                Kind::Condition(l) => {
                    let leaf = match g.condition_call(l.atom) {
                        Some(call) => leaf_of(call, &mut flat.values, &mut runs),
                        None => g.condition_leaf(l.atom),
                    }
                    .ok_or_else(|| no_leaf(g.condition_call(l.atom), || g.lit_name(l)))?;
                    if !l.positive {
                        flat.nodes.push(Node::new(NodeKind::Inverter, 2));
                        flat.of.push(n);
                        flat.depth.push(d);
                    }
                    flat.nodes.push(Node::new(NodeKind::Condition(leaf), 1));
                }
                Kind::Action(a) => {
                    let leaf = match g.action_call(a) {
                        Some(call) => leaf_of(call, &mut flat.values, &mut runs),
                        None => g.action_leaf(a),
                    }
                    .ok_or_else(|| no_leaf(g.action_call(a), || g.action_name(a)))?;
                    flat.nodes.push(Node::new(NodeKind::Action(leaf), 1));
                }
            }
            flat.of.push(n);
            flat.depth.push(d + u16::from(negative));
        }
        Ok(flat)
    }
}
