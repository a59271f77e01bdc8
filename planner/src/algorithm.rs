//! The steps of Algorithm 1 of Colledanchise et al. 2019 on the planner's tree: `atomic_bt` and
//! `expand` (ExpandTree, lines 13-23), `conflict` (line 11), `increase_priority`
//! (line 12) and `condition_to_expand` (GetConditionToExpand, lines 24-30).
//!
//! Decisions where the paper leaves room, in the paper's words:
//!
//! * **Atomic BT** (Fig. 2): `Fallback(c, Sequence(pre..., a)...)`, one Sequence per
//!   achieving action in domain order, preconditions in the order written; an action
//!   without (non-static) preconditions stands alone instead of in a one-child
//!   Sequence.
//! * **Conflict**, both ways: the new subtree has a conflict when an action that
//!   executes before it — an action inside a left sibling of any Sequence on its path
//!   from the root — may falsify one of its preconditions (the conditions of its
//!   Sequences) and nothing executed after that action re-establishes it for sure; and
//!   when the new subtree itself may falsify a condition that the part executed before
//!   it established for sure (a reactive Sequence re-checks that condition on the next
//!   tick, re-achieves it, and the two parts undo each other forever). What a subtree
//!   may and must make true is summarised bottom-up: an action makes its effects true
//!   (conditional effects count as "may"); a condition that succeeded holds; a
//!   Sequence composes its children left to right; a Fallback may do what any child
//!   may, and must do what all children must. Moving the subtree left resolves both:
//!   at the left end of the top Sequence nothing executes before it.
//! * **IncreasePriority**: the subtree moves one place left in its Sequence; when it is
//!   already leftmost, it moves *up a level*: into the nearest Sequence above its
//!   parent, immediately left of the child that contains it (a Fallback above is passed
//!   through: putting the subtree into a Fallback would make it an alternative, not a
//!   prerequisite). The expanded condition stays where it was, as the guard of the
//!   action that needs it (Fig. 4 keeps `τ ⊆ CollFree` before `MoveTo`), and counts as
//!   expanded. Moving stops at the first conflict-free position; at the left end of
//!   the top Sequence nothing executes before the subtree, so the loop always ends.

use crate::ground::{ActionId, Grounding, Lit};
use crate::refine::{Refinement, achieving_actions};
use crate::state::State;
use crate::tree::{Flat, Kind, PlanNode, PlanTree};
use crate::variables::{Choice, StateVariables};
use bt_core::NodeStatus;

/// The atomic BT of `lit`'s achievers as a new detached subtree; `condition` becomes
/// its first child. Returns the Fallback.
pub fn atomic_bt(tree: &mut PlanTree, g: &Grounding, condition: PlanNode, lit: Lit, actions: &[ActionId]) -> PlanNode {
    let rows: Vec<(ActionId, Vec<Lit>)> = actions
        .iter()
        .map(|&a| {
            // The action's preconditions, then the condition of the conditional
            // effect that achieves `lit`, if that is how it does.
            let mut pre: Vec<Lit> = g.action(a).map_or_else(Vec::new, |x| x.pre.clone());
            if let Some(extra) = g.action(a).and_then(|x| x.achieving_condition(lit)) {
                for &l in extra {
                    if !pre.contains(&l) {
                        pre.push(l);
                    }
                }
            }
            (a, pre)
        })
        .collect();
    atomic_bt_of(tree, condition, &rows)
}

/// The atomic BT with the given achievers and the order of their preconditions.
fn atomic_bt_of(tree: &mut PlanTree, condition: PlanNode, rows: &[(ActionId, Vec<Lit>)]) -> PlanNode {
    let fallback = tree.add(Kind::Fallback);
    tree.push_child(fallback, condition);
    for (a, pre) in rows {
        tree.push_step(fallback, pre, *a);
    }
    fallback
}

/// ExpandTree with achievers chosen by the caller (a plan's guidance): each is an
/// action, its preconditions in the order to check them, and the plan step it comes
/// from. Returns the new subtree and the actions used.
pub fn expand_with(
    tree: &mut PlanTree,
    condition: PlanNode,
    lit: Lit,
    choices: &[Choice],
) -> (PlanNode, Vec<ActionId>) {
    let _ = lit;
    let rows: Vec<(ActionId, Vec<Lit>)> = choices.iter().map(|c| (c.0, c.1.clone())).collect();
    let placeholder = tree.add(Kind::Sequence);
    tree.replace(condition, placeholder);
    let fallback = atomic_bt_of(tree, condition, &rows);
    tree.replace(placeholder, fallback);
    (fallback, rows.iter().map(|r| r.0).collect())
}

/// ExpandTree with a step and its siblings over state variables
/// ([`crate::variables::Variables::choices`]): the preconditions the siblings (the
/// achievers of the first one's template) share are checked once, before a Fallback of
/// the rest of each and its action, then the other achievers (actions that set the
/// state variables) with the rest of theirs:
/// `Fallback(c?, Sequence(shared?.., Fallback(Sequence(own?.., a)..)))`. Returns the
/// new subtree and the actions used.
pub fn expand_shared(
    tree: &mut PlanTree,
    g: &Grounding,
    condition: PlanNode,
    choices: &[Choice],
) -> (PlanNode, Vec<ActionId>) {
    let template = |a: ActionId| g.action(a).map(|x| x.template);
    let Some(first) = choices.first() else { return (condition, Vec::new()) };
    let shared: Vec<Lit> = first
        .1
        .iter()
        .copied()
        .filter(|l| choices.iter().filter(|c| template(c.0) == template(first.0)).all(|c| c.1.contains(l)))
        .collect();
    let placeholder = tree.add(Kind::Sequence);
    tree.replace(condition, placeholder);
    let outer = tree.add(Kind::Fallback);
    tree.push_child(outer, condition);
    let seq = tree.add(Kind::Sequence);
    for &p in &shared {
        let c = tree.add(Kind::Condition(p));
        tree.push_child(seq, c);
    }
    let inner = tree.add(Kind::Fallback);
    for (a, pre, _) in choices {
        let own: Vec<Lit> = pre.iter().copied().filter(|l| !shared.contains(l)).collect();
        tree.push_step(inner, &own, *a);
    }
    tree.push_child(seq, inner);
    tree.push_child(outer, seq);
    tree.replace(placeholder, outer);
    (outer, choices.iter().map(|c| c.0).collect())
}

/// ExpandTree: replaces the condition node `condition` by its atomic BT. Returns the
/// new subtree and the actions used, or `None` when no action achieves it.
pub fn expand(
    tree: &mut PlanTree,
    g: &Grounding,
    condition: PlanNode,
    state: &State,
    how: Refinement,
) -> Option<(PlanNode, Vec<ActionId>)> {
    let Kind::Condition(lit) = tree.kind(condition) else { return None };
    let actions = achieving_actions(g, lit, state, how);
    if actions.is_empty() {
        return None;
    }
    let placeholder = tree.add(Kind::Sequence);
    tree.replace(condition, placeholder);
    let fallback = atomic_bt(tree, g, condition, lit, &actions);
    tree.replace(placeholder, fallback);
    Some((fallback, actions))
}

/// Literals in the order they were added (one removed and added again goes last), with
/// constant-time membership and removal: the summary of everything executed before a
/// subtree holds hundreds of literals in a long plan, and each subtree composed into it
/// removes only the few its effects undo.
#[derive(Clone, Debug, Default)]
struct Lits {
    /// The literals in order; `None` where one was removed.
    order: Vec<Option<Lit>>,
    /// Where each literal present is in `order`.
    at: std::collections::HashMap<Lit, usize, foldhash::fast::FixedState>,
}

impl Lits {
    fn contains(&self, l: &Lit) -> bool {
        self.at.contains_key(l)
    }

    fn insert(&mut self, l: Lit) {
        if !self.at.contains_key(&l) {
            self.at.insert(l, self.order.len());
            self.order.push(Some(l));
        }
    }

    fn remove(&mut self, l: &Lit) {
        if let Some(i) = self.at.remove(l)
            && let Some(slot) = self.order.get_mut(i)
        {
            *slot = None;
        }
    }

    fn iter(&self) -> impl Iterator<Item = &Lit> {
        self.order.iter().flatten()
    }

    fn retain(&mut self, keep: impl Fn(&Lit) -> bool) {
        for slot in &mut self.order {
            if let Some(l) = slot
                && !keep(l)
            {
                self.at.remove(l);
                *slot = None;
            }
        }
    }
}

impl FromIterator<Lit> for Lits {
    fn from_iter<I: IntoIterator<Item = Lit>>(iter: I) -> Self {
        let mut out = Self::default();
        for l in iter {
            out.insert(l);
        }
        out
    }
}

/// A literal set with "may" and "must" parts, as described in the module docs.
#[derive(Clone, Debug, Default)]
struct Summary {
    must: Lits,
    may: Lits,
}

fn then(acc: &mut Summary, next: &Summary) {
    // What `next` may undo is no longer sure, and what it surely undoes no longer
    // possible.
    for l in next.may.iter() {
        acc.must.remove(&l.negated());
    }
    for l in next.must.iter() {
        acc.may.remove(&l.negated());
    }
    for &l in next.must.iter() {
        acc.must.insert(l);
    }
    for &l in next.may.iter() {
        acc.may.insert(l);
    }
}

fn summary(tree: &PlanTree, g: &Grounding, n: PlanNode) -> Summary {
    let order = tree.preorder(n);
    let mut sums: std::collections::HashMap<PlanNode, Summary, foldhash::fast::FixedState> =
        std::collections::HashMap::default();
    for &x in order.iter().rev() {
        let s = match tree.kind(x) {
            Kind::Condition(l) => Summary { must: std::iter::once(l).collect(), may: Lits::default() },
            Kind::Action(a) => match g.action(a) {
                Some(x) => Summary { must: x.must_effects().collect(), may: x.may_effects().collect() },
                None => Summary::default(),
            },
            Kind::Sequence => {
                let mut acc = Summary::default();
                for c in tree.children(x) {
                    if let Some(s) = sums.remove(c) {
                        then(&mut acc, &s);
                    }
                }
                acc
            }
            Kind::Fallback => {
                let mut acc: Option<Summary> = None;
                for c in tree.children(x) {
                    let Some(s) = sums.remove(c) else { continue };
                    acc = Some(match acc {
                        None => s,
                        Some(mut a) => {
                            a.must.retain(|l| s.must.contains(l));
                            for &l in s.may.iter() {
                                a.may.insert(l);
                            }
                            a
                        }
                    });
                }
                acc.unwrap_or_default()
            }
        };
        sums.insert(x, s);
    }
    sums.remove(&n).unwrap_or_default()
}

/// The subtrees that execute before `n`: left siblings of `n`'s path in every Sequence
/// from the root down, in execution order.
fn executed_before(tree: &PlanTree, n: PlanNode) -> Vec<PlanNode> {
    let mut path = vec![n];
    let mut x = n;
    while let Some(p) = tree.parent(x) {
        path.push(p);
        x = p;
    }
    path.reverse();
    let mut out = Vec::new();
    for w in path.windows(2) {
        let (p, c) = (w[0], w[1]);
        if tree.kind(p) == Kind::Sequence {
            for &s in tree.children(p) {
                if s == c {
                    break;
                }
                out.push(s);
            }
        }
    }
    out
}

/// The preconditions of a new subtree: the conditions of its Sequences.
fn preconditions(tree: &PlanTree, n: PlanNode) -> Vec<Lit> {
    let mut out = Vec::new();
    for &alt in tree.children(n).iter().skip(1) {
        if tree.kind(alt) != Kind::Sequence {
            continue;
        }
        for &c in tree.children(alt) {
            let lit = match tree.kind(c) {
                Kind::Condition(l) => Some(l),
                Kind::Fallback => tree.children(c).first().and_then(|&f| match tree.kind(f) {
                    Kind::Condition(l) => Some(l),
                    _ => None,
                }),
                _ => None,
            };
            if let Some(l) = lit
                && !out.contains(&l)
            {
                out.push(l);
            }
        }
    }
    out
}

/// A conflict: `precondition` of the new subtree may be falsified by `by`, which
/// executes before it; or (`by_new_subtree`) `by`, inside the new subtree, may falsify
/// `precondition`, a condition established before the new subtree.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Conflict {
    /// The condition undone.
    pub precondition: Lit,
    /// The action that undoes it.
    pub by: ActionId,
    /// Whether `by` is in the new subtree (the second side of the test).
    pub by_new_subtree: bool,
}

/// Conflict(T) for the subtree `n` (see the module docs), or `None`.
#[must_use]
pub fn conflict(tree: &PlanTree, g: &Grounding, n: PlanNode) -> Option<Conflict> {
    conflict_with(tree, g, n, None)
}

/// [`conflict`], and with state variables (guided backchaining that does not pin them,
/// [`crate::variables`]) three cases left out: a value of a state variable never
/// conflicts (a Fallback of sibling rows serves every value); nothing conflicts in a
/// subtree `Fallback(c?, ...)` whose condition `c` the part before it establishes for
/// sure (the subtree succeeds at `c` there); and a precondition undone only by actions
/// that make `c` true does not conflict either (a second subtree for `started(o)`
/// after the first one started `o`).
#[must_use]
pub fn conflict_with(
    tree: &PlanTree,
    g: &Grounding,
    n: PlanNode,
    variables: Option<&StateVariables>,
) -> Option<Conflict> {
    let before = executed_before(tree, n);
    if before.is_empty() {
        return None;
    }
    let mut acc = Summary::default();
    for &b in &before {
        then(&mut acc, &summary(tree, g, b));
    }
    let is_value = |l: Lit| variables.is_some_and(|v| v.is_value(g, l));
    let own_condition = match tree.children(n).first().map(|&c| tree.kind(c)) {
        Some(Kind::Condition(c)) if variables.is_some() && tree.kind(n) == Kind::Fallback => Some(c),
        _ => None,
    };
    if own_condition.is_some_and(|c| acc.must.contains(&c)) {
        return None;
    }
    let pre = preconditions(tree, n);
    let undoing = |nodes: &mut dyn Iterator<Item = PlanNode>, undo: Lit| {
        nodes
            .filter_map(|x| match tree.kind(x) {
                Kind::Action(a) if g.action(a).is_some_and(|ga| ga.achieves(undo)) => Some(a),
                _ => None,
            })
            .collect::<Vec<_>>()
    };
    let harmful = |p: Lit| {
        let Some(c) = own_condition else { return true };
        let mut all = before.iter().flat_map(|&b| tree.preorder(b));
        undoing(&mut all, p.negated()).iter().any(|&a| !g.action(a).is_some_and(|x| x.achieves(c)))
    };
    if let Some(precondition) = pre.into_iter().find(|&p| !is_value(p) && acc.may.contains(&p.negated()) && harmful(p))
    {
        let mut all = before.iter().flat_map(|&b| tree.preorder(b));
        let by = undoing(&mut all, precondition.negated()).pop()?;
        return Some(Conflict { precondition, by, by_new_subtree: false });
    }
    let own = summary(tree, g, n);
    let established =
        acc.must.iter().find(|&&l| !is_value(l) && own.may.contains(&l.negated()) && !own.must.contains(&l))?;
    let by = *undoing(&mut tree.preorder(n).into_iter(), established.negated()).first()?;
    Some(Conflict { precondition: *established, by, by_new_subtree: true })
}

/// Where one step of IncreasePriority took the subtree.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Move {
    /// One place left in its Sequence.
    Left,
    /// Up a level, left of the branch that contained it.
    Up,
}

/// Leaves a guard copy of the expanded condition in the subtree's slot (the first time
/// a subtree moves). Returns the guard.
pub fn leave_guard(tree: &mut PlanTree, n: PlanNode) -> Option<PlanNode> {
    let first = *tree.children(n).first()?;
    let kind = tree.kind(first);
    let parent = tree.parent(n)?;
    let i = tree.index_in_parent(n)?;
    let guard = tree.add(kind);
    tree.insert(parent, i + 1, guard);
    Some(guard)
}

/// One step of IncreasePriority for subtree `n`, or `None` when it is already at the
/// left end of the top Sequence.
pub fn increase_priority(tree: &mut PlanTree, n: PlanNode) -> Option<Move> {
    let parent = tree.parent(n)?;
    let i = tree.index_in_parent(n)?;
    if tree.kind(parent) == Kind::Sequence && i > 0 {
        tree.detach(n);
        tree.insert(parent, i - 1, n);
        return Some(Move::Left);
    }
    // Up a level: the nearest Sequence above `parent`, left of the branch holding `n`.
    let mut branch = parent;
    let mut above = tree.parent(parent)?;
    while tree.kind(above) != Kind::Sequence {
        branch = above;
        above = tree.parent(above)?;
    }
    let at = tree.index_in_parent(branch)?;
    tree.detach(n);
    tree.insert(above, at, n);
    Some(Move::Up)
}

/// GetConditionToExpand: the conditions that returned Failure on the last tick and were
/// not expanded before, breadth-first (by depth, then left to right). `statuses` are the
/// bt-core nodes' statuses after that tick.
#[must_use]
pub fn conditions_to_expand(tree: &PlanTree, flat: &Flat, statuses: &[NodeStatus], expanded: &[bool]) -> Vec<PlanNode> {
    let mut found: Vec<(u16, u32, PlanNode)> = Vec::new();
    for (i, &n) in flat.of.iter().enumerate() {
        if flat.top.get(n as usize) != Some(&(i as u32)) || expanded.get(n as usize).copied().unwrap_or(false) {
            continue;
        }
        if !matches!(tree.kind(n), Kind::Condition(_)) {
            continue;
        }
        if statuses.get(i) == Some(&NodeStatus::Failure) {
            found.push((flat.depth[i], i as u32, n));
        }
    }
    found.sort_unstable();
    found.into_iter().map(|f| f.2).collect()
}
