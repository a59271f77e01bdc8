//! Closing a regression tree over disturbances ([`close`]), or the rules in front of
//! another tree ([`close_with`]): see the docs of [`crate::regress`].

use std::collections::HashSet;
use std::time::Instant;

use super::way_back::way_back;
use super::{Policy, successor};
use crate::PlanError;
use crate::ground::{ActionId, Grounding};
use crate::guide::Trace;
use crate::state::State;

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
    /// Undo rules added ([`Policy::undo_rules`]).
    pub undo: usize,
    /// States where the tree failed and no plan reaches the goal.
    pub dead_ends: usize,
    /// States where the tree failed and the search for a plan ran out of its time.
    pub given_up: usize,
    /// States where the tree failed and the only way back found was too long to add
    /// (more than an eighth of the node budget).
    pub too_long: usize,
    /// Whether every state within [`MAX_DISTURBANCES`] was looked at (false: a budget
    /// ran out first).
    pub complete: bool,
    /// Which budget ran out first, when one did.
    pub stopped: Option<Stop>,
    /// Whether rules of a backchained tree's own plan went in front of it with no plan
    /// added ([`close_with`] looks with them there; the tree alone did worse).
    pub own_rules: bool,
    /// Whether the closure of a backchained tree was left out and the tree kept as it
    /// was, without the rules: the closure reached its node budget, or left out a way
    /// back that was too long, or was cut short by its time or states and its rules did
    /// worse under disturbances than the tree alone.
    pub kept: bool,
    /// Whether this is the closure of a tree over its node budget, over one act only
    /// ([`super::close_one_act`]): [`Closed::states`] counts the states one act from the
    /// tree's path where it failed, [`Closed::undo`] the rules back added for them.
    pub one_act: bool,
}

/// The budget that ended a closure early ([`Closed::stopped`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// [`Budget::plans`].
    Plans,
    /// [`Budget::states`].
    States,
    /// [`Budget::nodes`]: the tree's size.
    Nodes,
    /// [`Budget::deadline`].
    Deadline,
}

impl Stop {
    /// Whether the closure stopped for the work it may do (its time or the states it
    /// may look at), not for the tree's size: every rule it added is a way back from a
    /// disturbed state, and the rules it would have added next are for states further
    /// from the tree's path.
    #[must_use]
    pub fn out_of_work(self) -> bool {
        matches!(self, Self::States | Self::Deadline)
    }
}

impl std::fmt::Display for Closed {
    /// `closed over disturbances: 3 plans added from 120 states (2 dead ends), budget
    /// reached` (counts in words).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use crate::wording::count;
        if self.one_act {
            write!(
                f,
                "closed over one act of disturbance: {} back by one action, for {} one act from the tree's path where it failed",
                count(self.undo, "rule"),
                count(self.states, "state")
            )?;
            return if self.complete { Ok(()) } else { write!(f, ", budget reached") };
        }
        write!(
            f,
            "closed over disturbances: {} added from {} looked at",
            count(self.plans, "plan"),
            count(self.states, "state")
        )?;
        if self.undo > 0 {
            write!(f, ", {}", count(self.undo, "undo rule"))?;
        }
        if self.dead_ends > 0 {
            write!(f, " ({} with no plan)", count(self.dead_ends, "state"))?;
        }
        if self.given_up > 0 {
            write!(f, " ({} where no plan was found in time)", count(self.given_up, "state"))?;
        }
        if self.too_long > 0 {
            write!(f, " ({} whose way back was too long to add)", count(self.too_long, "state"))?;
        }
        if self.own_rules {
            write!(f, ", the rules of the tree's own plan put in front of it")?;
        }
        if !self.complete {
            write!(f, ", budget reached")?;
        }
        if self.kept {
            write!(f, ": the tree is kept as it was")?;
        }
        Ok(())
    }
}

/// A way back whose rules would grow the tree by more than this share of the node
/// budget (an eighth) is not taken, so that a few states whose only ways back are long
/// (a new plan of 134 steps in ged, about 1,000 nodes of rules each) do not use up
/// the nodes meant for all the others.
const WAY_BACK_SHARE: usize = 8;

/// A tree a closure grows: the policy's rules first, then whatever the tree does where
/// none of them holds. For a regression tree that is nothing (the tree fails there);
/// the offline planner puts a backchained tree behind them (a guided one, or one of
/// Algorithm 1 with `--close-backchained`).
pub trait Closable {
    /// The states the tree passes through from `s` (`s` first, each one after an
    /// action completed), and whether it reaches the goal.
    ///
    /// # Errors
    /// When the tree cannot be run.
    fn run(&mut self, g: &Grounding, policy: &Policy, s: &State) -> Result<(Vec<State>, bool), PlanError>;
    /// The distinct actions of the whole tree (the disturbances [`close`] tries).
    fn actions(&self, policy: &Policy) -> Vec<ActionId>;
    /// Planner nodes of the whole tree.
    fn nodes(&self, g: &Grounding, policy: &Policy) -> usize;
}

/// The regression tree alone: its rules, and Failure where none holds.
#[derive(Clone, Copy, Debug, Default)]
pub struct RulesOnly;

impl Closable for RulesOnly {
    fn run(&mut self, g: &Grounding, policy: &Policy, s: &State) -> Result<(Vec<State>, bool), PlanError> {
        let path = policy.path(g, s);
        let reached = path.last().is_some_and(|l| g.goal_holds(l));
        Ok((path, reached))
    }

    fn actions(&self, policy: &Policy) -> Vec<ActionId> {
        policy.actions()
    }

    fn nodes(&self, g: &Grounding, policy: &Policy) -> usize {
        policy.nodes(g)
    }
}

/// Closes `policy` over disturbances from the initial state (see the module docs).
///
/// # Errors
/// None: a search that runs out of time counts in [`Closed::given_up`], and a budget
/// that runs out ends the closure early ([`Closed::complete`] false); the `Result` is
/// [`close_with`]'s.
pub fn close(g: &Grounding, policy: &mut Policy, budget: &Budget) -> Result<Closed, PlanError> {
    close_with(g, policy, &mut RulesOnly, budget)
}

/// [`close`] for the tree `tree` makes of `policy`: where the tree (not only the
/// rules) fails from a state a disturbance leads to, rules are added in front.
///
/// # Errors
/// From [`Closable::run`].
pub fn close_with(
    g: &Grounding,
    policy: &mut Policy,
    tree: &mut dyn Closable,
    budget: &Budget,
) -> Result<Closed, PlanError> {
    let mut done = Closed::default();
    let mut ever: HashSet<State> = HashSet::new();
    // Rules added in a pass can change the tree's path (a nearer rule takes over), and
    // with it the states disturbances lead to: passes until one adds nothing.
    loop {
        let added = done.plans + done.undo;
        if !pass(g, policy, tree, budget, &mut done, &mut ever)? {
            return Ok(done);
        }
        if done.plans + done.undo == added {
            done.complete = true;
            return Ok(done);
        }
    }
}

/// One pass of [`close_with`]: false when a budget ran out.
fn pass(
    g: &Grounding,
    policy: &mut Policy,
    tree: &mut dyn Closable,
    budget: &Budget,
    done: &mut Closed,
    ever: &mut HashSet<State>,
) -> Result<bool, PlanError> {
    let mut seen: HashSet<State> = HashSet::new();
    // The states to disturb, by how many disturbances led there, each with how many
    // of `acts` were tried on it. `acts` is the tree's actions, in the order they came:
    // a way back can bring new ones, which an agent can then do in every state looked
    // at before, nearest the initial state first.
    let mut levels: Vec<Vec<(State, usize)>> = vec![Vec::new(); MAX_DISTURBANCES as usize];
    for s in tree.run(g, policy, g.init())?.0 {
        if seen.insert(s.clone()) {
            levels[0].push((s, 0));
        }
    }
    let mut acts = tree.actions(policy);
    // The tree's size, counted again whenever rules are added.
    let mut size = tree.nodes(g, policy);
    let over = |d: &Closed, size: usize| {
        if d.plans >= budget.plans {
            Some(Stop::Plans)
        } else if d.states >= budget.states {
            Some(Stop::States)
        } else if size >= budget.nodes {
            Some(Stop::Nodes)
        } else {
            budget.deadline.is_some_and(|t| Instant::now() >= t).then_some(Stop::Deadline)
        }
    };
    'scan: loop {
        for depth in 0..levels.len() {
            for k in 0..levels[depth].len() {
                while levels[depth][k].1 < acts.len() {
                    let a = acts[levels[depth][k].1];
                    levels[depth][k].1 += 1;
                    let Some(t) = successor(g, a, &levels[depth][k].0) else { continue };
                    if !seen.insert(t.clone()) {
                        continue;
                    }
                    if let Some(stop) = over(done, size) {
                        done.stopped = Some(stop);
                        return Ok(false);
                    }
                    if ever.insert(t.clone()) {
                        done.states += 1;
                    }
                    let (mut path, mut reached) = tree.run(g, policy, &t)?;
                    let mut added = false;
                    // The tree's size with a way back's rules, counted once.
                    let mut grown = None;
                    if !reached {
                        let own = tree.actions(policy);
                        if policy.push_undo(g, &levels[depth][k].0, &t, &own) {
                            let (undone, ok) = tree.run(g, policy, &t)?;
                            if ok {
                                done.undo += 1;
                                (path, reached) = (undone, true);
                            } else {
                                policy.pop_undo();
                            }
                        }
                        if !reached {
                            let back = way_back(g, policy, &levels[depth][k].0, &t, &own, budget, done);
                            let Some((steps, rule)) = back else { continue };
                            let Some(trace) = Trace::from_state(g, &t, &steps) else { continue };
                            let before = policy.clone();
                            policy.add_path(g, &trace, &rule);
                            let nodes = tree.nodes(g, policy);
                            if nodes.saturating_sub(size) > budget.nodes / WAY_BACK_SHARE {
                                // One hard state would use up the nodes meant for many.
                                *policy = before;
                                done.too_long += 1;
                                continue;
                            }
                            grown = Some(nodes);
                            done.plans += 1;
                            path = tree.run(g, policy, &t)?.0;
                        }
                        size = grown.unwrap_or_else(|| tree.nodes(g, policy));
                        added = true;
                    }
                    if let Some(level) = levels.get_mut(depth + 1) {
                        level.push((t, 0));
                        for p in path {
                            if seen.insert(p.clone()) {
                                level.push((p, 0));
                            }
                        }
                    }
                    let grown = acts.len();
                    if added {
                        for x in tree.actions(policy) {
                            if !acts.contains(&x) {
                                acts.push(x);
                            }
                        }
                    }
                    if acts.len() > grown {
                        // New actions: first in the states looked at before.
                        continue 'scan;
                    }
                }
            }
        }
        return Ok(true);
    }
}
