//! The last resort for a plan that guided backchaining could not turn into a tree
//! that reaches the goal: a tree built by regressing the goal through the plan, and
//! made robust to disturbances by regressing more plans.
//!
//! With `C_n` the goal and `C_{i-1}` what must hold before step `i` for the rest of
//! the plan to reach the goal (`C_i` without what action `a_i` achieves, plus its
//! preconditions and the conditions of the conditional effects it relies on), the
//! tree is
//!
//! ```text
//! Fallback( C_n?,  Sequence(C_{n-1}?, a_n),  ...,  Sequence(C_0?, a_1) )
//! ```
//!
//! Ticked, it does the step after the latest `C_i` that holds: from the initial state
//! it executes the plan; when an external change undoes a step it goes back, when one
//! does a step for it it skips ahead (the reactivity of Problem 1 in seed 000, for
//! the states the plan passes through). It is flat: its depth does not grow with the
//! plan's length.
//!
//! # Rules, and why the tree always progresses
//!
//! Each `Sequence(C_{i-1}?, a_i)` is a *rule* with a *distance*: the actions from it to
//! the goal, `n - i + 1`. Rules of several plans (from different states) go into one
//! Fallback ordered by distance, nearest the goal first. In a state where the first
//! rule that holds has distance `d`, its action leads to a state where the next rule of
//! its own plan holds, whose distance is `d - 1`: the first rule that holds there is at
//! least as near. Undisturbed, every tick that completes an action brings the tree
//! strictly nearer the goal, so it cannot oscillate, whatever plans were merged. A rule
//! that an earlier one with fewer conditions always pre-empts is left out.
//!
//! # Closing the tree over disturbances
//!
//! An external agent that undoes a step returns the world to a state the tree already
//! handled; one that does one of the tree's actions for it can move the world off the
//! plan, where no rule may hold and the tree fails. [`close`] finds those states: from
//! every state the tree passes through, it applies each of the tree's actions that is
//! applicable, and where the tree would fail it plans from that state (greedy
//! best-first search) and adds the new plan's rules, up to [`MAX_DISTURBANCES`]
//! disturbances deep, within a budget of plans, nodes and time (the tree is correct at
//! every point, so running out of budget leaves a tree that is only less robust).

use std::collections::HashSet;
use std::time::Instant;

use crate::PlanError;
use crate::ground::{ActionId, Grounding, Lit};
use crate::guide::Trace;
use crate::search::{self, SearchOptions};
use crate::state::State;
use crate::tree::{Kind, PlanTree};
fn add(set: &mut Vec<Lit>, l: Lit) {
    if !set.contains(&l) {
        set.push(l);
    }
}

/// The regressed conditions `C_0 .. C_n` of a trace.
#[must_use]
pub fn conditions(g: &Grounding, trace: &Trace) -> Vec<Vec<Lit>> {
    conditions_to(g, trace, g.goal())
}

/// The conditions `C_0 .. C_n` of a trace regressed from `target` (`C_n`) instead of
/// the goal.
#[must_use]
pub fn conditions_to(g: &Grounding, trace: &Trace, target: &[Lit]) -> Vec<Vec<Lit>> {
    let n = trace.plan().len();
    let mut out = vec![Vec::new(); n + 1];
    let mut c: Vec<Lit> = target.to_vec();
    out[n].clone_from(&c);
    for i in (1..=n).rev() {
        let Some(a) = g.action(trace.plan()[i - 1]) else { continue };
        let Some(before) = trace.state(i - 1) else { continue };
        let mut prev: Vec<Lit> = Vec::new();
        for &l in &c {
            if a.must_effects().any(|e| e == l) {
                continue;
            }
            // A conditional effect that made `l` true here: keep its condition.
            if let Some(cond) = a.cond.iter().find(|k| {
                k.when.iter().all(|w| w.holds(before))
                    && if l.positive { k.add.contains(&l.atom) } else { k.del.contains(&l.atom) }
            }) {
                for &w in &cond.when {
                    add(&mut prev, w);
                }
                continue;
            }
            add(&mut prev, l);
            // A conditional effect that would undo `l` did not fire: keep it so.
            for k in &a.cond {
                let undoes = if l.positive { k.del.contains(&l.atom) } else { k.add.contains(&l.atom) };
                if undoes && let Some(off) = k.when.iter().find(|w| !w.holds(before)) {
                    add(&mut prev, off.negated());
                }
            }
        }
        for &p in &a.pre {
            add(&mut prev, p);
        }
        out[i - 1].clone_from(&prev);
        c = prev;
    }
    out
}

/// The regression tree of a trace (see the module docs).
#[must_use]
pub fn tree(g: &Grounding, trace: &Trace) -> PlanTree {
    Policy::of_trace(g, trace).tree(g)
}

/// Most disturbances in a row [`close`] follows from the tree's path.
pub const MAX_DISTURBANCES: u32 = 3;

/// The budget of [`close`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Budget {
    /// Most plans added.
    pub plans: usize,
    /// Most states looked at.
    pub states: usize,
    /// Stop adding rules once the tree has this many planner nodes.
    pub nodes: usize,
    /// Stop at this instant.
    pub deadline: Option<Instant>,
}

impl Default for Budget {
    fn default() -> Self {
        Self { plans: 1_024, states: 20_000, nodes: 8_192, deadline: None }
    }
}

/// What [`close`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Closed {
    /// States looked at.
    pub states: usize,
    /// States where the tree failed, each given a plan and its rules.
    pub plans: usize,
    /// States where the tree failed and no plan reaches the goal.
    pub dead_ends: usize,
    /// Whether every state within [`MAX_DISTURBANCES`] was looked at (false: a budget
    /// ran out first).
    pub complete: bool,
}

impl std::fmt::Display for Closed {
    /// `closed over disturbances: 3 plans added from 120 states (2 dead ends), budget
    /// reached` (counts in words).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use crate::wording::count;
        write!(
            f,
            "closed over disturbances: {} added from {} looked at",
            count(self.plans, "plan"),
            count(self.states, "state")
        )?;
        if self.dead_ends > 0 {
            write!(f, " ({} with no plan)", count(self.dead_ends, "state"))?;
        }
        if !self.complete {
            write!(f, ", budget reached")?;
        }
        Ok(())
    }
}

/// One rule of a regression tree: where every literal of `when` holds, do `action`,
/// `distance` actions from the goal (this one included).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rule {
    /// The conditions, sorted.
    pub when: Vec<Lit>,
    /// The action.
    pub action: ActionId,
    /// Actions to the goal, this one included.
    pub distance: u32,
}

impl Rule {
    fn holds(&self, s: &State) -> bool {
        self.when.iter().all(|l| l.holds(s))
    }

    /// The goal as a rule's target: its conditions, at distance 0.
    fn goal(g: &Grounding) -> Self {
        let mut when = g.goal().to_vec();
        when.sort_unstable();
        Self { when, action: 0, distance: 0 }
    }
}

/// The state action `a` leads to from `s`, when it is applicable there.
fn successor(g: &Grounding, a: ActionId, s: &State) -> Option<State> {
    let x = g.action(a).filter(|x| x.applicable(s))?;
    let mut t = s.clone();
    x.apply(&mut t);
    Some(t)
}

/// The rules of a regression tree, nearest the goal first (see the module docs).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Policy {
    rules: Vec<Rule>,
}

fn subset(a: &[Lit], b: &[Lit]) -> bool {
    a.iter().all(|l| b.binary_search(l).is_ok())
}

impl Policy {
    /// The rules of one plan to the goal.
    #[must_use]
    pub fn of_trace(g: &Grounding, trace: &Trace) -> Self {
        let mut p = Self { rules: Vec::new() };
        p.add_trace(g, trace);
        p
    }

    /// The rules, nearest the goal first.
    #[must_use]
    pub fn rules(&self) -> &[Rule] {
        &self.rules
    }

    /// Adds the rules of a plan to the goal; returns how many were kept.
    pub fn add_trace(&mut self, g: &Grounding, trace: &Trace) -> usize {
        self.add_path(g, trace, &Rule::goal(g))
    }

    /// Inserts `rule` after every rule at most as far from the goal, unless one of those
    /// always pre-empts it; drops the later rules it always pre-empts.
    fn insert(&mut self, rule: Rule) -> bool {
        let at = self.rules.partition_point(|r| r.distance <= rule.distance);
        if self.rules[..at].iter().any(|r| subset(&r.when, &rule.when)) {
            return false;
        }
        let mut k = at;
        while k < self.rules.len() {
            if subset(&rule.when, &self.rules[k].when) {
                self.rules.remove(k);
            } else {
                k += 1;
            }
        }
        self.rules.insert(at, rule);
        true
    }

    /// The first rule that holds in `s`.
    #[must_use]
    pub fn first(&self, s: &State) -> Option<&Rule> {
        self.rules.iter().find(|r| r.holds(s))
    }

    /// The states the tree passes through from `s` until the goal (`s` included), or
    /// until no rule holds.
    #[must_use]
    pub fn path(&self, g: &Grounding, s: &State) -> Vec<State> {
        let mut out = vec![s.clone()];
        let mut cur = s.clone();
        // Distances fall by at least one a step (see the module docs); the limit only
        // guards against a grounding whose actions break that.
        let limit = self.max_distance() as usize + 1;
        while !g.goal_holds(&cur) && out.len() <= limit {
            let Some(next) = self.first(&cur).and_then(|r| successor(g, r.action, &cur)) else { break };
            out.push(next.clone());
            cur = next;
        }
        out
    }

    fn max_distance(&self) -> u32 {
        self.rules.iter().map(|r| r.distance).max().unwrap_or(0)
    }

    /// The distinct actions of the rules, in rule order.
    #[must_use]
    pub fn actions(&self) -> Vec<ActionId> {
        let mut out: Vec<ActionId> = Vec::new();
        for r in &self.rules {
            if !out.contains(&r.action) {
                out.push(r.action);
            }
        }
        out
    }

    /// Adds the rules of `trace`, a path to a state where `rule` holds (its conditions
    /// regressed through the path); returns how many were kept.
    fn add_path(&mut self, g: &Grounding, trace: &Trace, rule: &Rule) -> usize {
        let cs = conditions_to(g, trace, &rule.when);
        let n = trace.plan().len();
        let mut kept = 0;
        // Nearest the target first, so that equal rules keep the path's last use.
        for i in (1..=n).rev() {
            let mut when = cs[i - 1].clone();
            when.sort_unstable();
            let distance = rule.distance + (n - i + 1) as u32;
            if self.insert(Rule { when, action: trace.plan()[i - 1], distance }) {
                kept += 1;
            }
        }
        kept
    }

    /// Planner nodes of [`Policy::tree`].
    #[must_use]
    pub fn nodes(&self, g: &Grounding) -> usize {
        let goal = if g.goal().len() == 1 { 1 } else { 1 + g.goal().len() };
        1 + goal + self.rules.iter().map(|r| if r.when.is_empty() { 1 } else { 2 + r.when.len() }).sum::<usize>()
    }

    /// The tree: `Fallback(goal?, Sequence(when?, action), ...)`.
    #[must_use]
    pub fn tree(&self, g: &Grounding) -> PlanTree {
        let mut t = PlanTree::with_root(Kind::Fallback);
        let root = t.root();
        let goal = if let [single] = g.goal() {
            t.add(Kind::Condition(*single))
        } else {
            let s = t.add(Kind::Sequence);
            for &l in g.goal() {
                let c = t.add(Kind::Condition(l));
                t.push_child(s, c);
            }
            s
        };
        t.push_child(root, goal);
        for r in &self.rules {
            let act = t.add(Kind::Action(r.action));
            if r.when.is_empty() {
                t.push_child(root, act);
                continue;
            }
            let seq = t.add(Kind::Sequence);
            for &l in &r.when {
                let c = t.add(Kind::Condition(l));
                t.push_child(seq, c);
            }
            t.push_child(seq, act);
            t.push_child(root, seq);
        }
        t
    }
}

/// Closes `policy` over disturbances from the initial state (see the module docs).
///
/// # Errors
/// None today: a search that fails or times out ends the closure early
/// ([`Closed::complete`] false); the `Result` keeps room for a caller's stop.
pub fn close(g: &Grounding, policy: &mut Policy, budget: &Budget) -> Result<Closed, PlanError> {
    let mut done = Closed::default();
    let mut ever: HashSet<State> = HashSet::new();
    // Rules added in a pass can change the tree's path (a nearer rule takes over), and
    // with it the states disturbances lead to: passes until one adds nothing.
    loop {
        let plans = done.plans;
        if !pass(g, policy, budget, &mut done, &mut ever) {
            return Ok(done);
        }
        if done.plans == plans {
            done.complete = true;
            return Ok(done);
        }
    }
}

/// One pass of [`close`]: false when a budget ran out.
fn pass(g: &Grounding, policy: &mut Policy, budget: &Budget, done: &mut Closed, ever: &mut HashSet<State>) -> bool {
    let mut seen: HashSet<State> = HashSet::new();
    let mut frontier: Vec<State> = Vec::new();
    for s in policy.path(g, g.init()) {
        if seen.insert(s.clone()) {
            frontier.push(s);
        }
    }
    let over = |d: &Closed, p: &Policy| {
        d.plans >= budget.plans
            || d.states >= budget.states
            || p.nodes(g) >= budget.nodes
            || budget.deadline.is_some_and(|t| Instant::now() >= t)
    };
    for _ in 0..MAX_DISTURBANCES {
        let mut next = Vec::new();
        for s in &frontier {
            for a in policy.actions() {
                let Some(t) = successor(g, a, s) else { continue };
                if !seen.insert(t.clone()) {
                    continue;
                }
                if over(done, policy) {
                    return false;
                }
                if ever.insert(t.clone()) {
                    done.states += 1;
                }
                if !g.goal_holds(&t) && policy.first(&t).is_none() {
                    if let Some((path, rule)) = repair(g, policy, &t) {
                        if let Some(trace) = Trace::from_state(g, &t, &path) {
                            policy.add_path(g, &trace, &rule);
                            done.plans += 1;
                        }
                    } else {
                        let options = SearchOptions { deadline: budget.deadline, ..SearchOptions::default() };
                        match search::gbfs_from(g, &t, &options) {
                            Ok(found) => {
                                let Some(trace) = Trace::from_state(g, &t, &found.plan) else { continue };
                                policy.add_trace(g, &trace);
                                done.plans += 1;
                            }
                            Err(PlanError::NoPlan(_)) => {
                                done.dead_ends += 1;
                                continue;
                            }
                            Err(_) => return false,
                        }
                    }
                }
                next.push(t.clone());
                for p in policy.path(g, &t) {
                    if seen.insert(p.clone()) {
                        next.push(p);
                    }
                }
            }
        }
        frontier = next;
    }
    true
}

/// Deepest path [`repair`] looks for.
const REPAIR_DEPTH: usize = 2;
/// Most states [`repair`] looks at.
const REPAIR_STATES: usize = 4_000;

/// The shortest path (at most [`REPAIR_DEPTH`] actions) from `t` to a state where a
/// rule holds, and that rule (for the goal, its conditions at distance 0): with the
/// tree's own actions if they can (a tree with fewer distinct actions gives an external
/// agent fewer to do), else with any. Breadth first, actions in a fixed order, so the
/// result is deterministic.
fn repair(g: &Grounding, policy: &Policy, t: &State) -> Option<(Vec<ActionId>, Rule)> {
    let own = policy.actions();
    repair_with(g, policy, t, &own).or_else(|| {
        let all: Vec<ActionId> = (0..g.actions().len() as ActionId).collect();
        repair_with(g, policy, t, &all)
    })
}

fn repair_with(g: &Grounding, policy: &Policy, t: &State, actions: &[ActionId]) -> Option<(Vec<ActionId>, Rule)> {
    let mut layer: Vec<(State, Vec<ActionId>)> = vec![(t.clone(), Vec::new())];
    let mut seen: HashSet<State> = HashSet::new();
    seen.insert(t.clone());
    for _ in 0..REPAIR_DEPTH {
        let mut next = Vec::new();
        for (s, path) in &layer {
            for &id in actions {
                let Some(u) = successor(g, id, s) else { continue };
                if !seen.insert(u.clone()) {
                    continue;
                }
                let mut p = path.clone();
                p.push(id);
                if g.goal_holds(&u) {
                    return Some((p, Rule::goal(g)));
                }
                if let Some(r) = policy.first(&u) {
                    return Some((p, r.clone()));
                }
                if seen.len() >= REPAIR_STATES {
                    return None;
                }
                next.push((u, p));
            }
        }
        layer = next;
    }
    None
}
