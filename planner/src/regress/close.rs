//! Closing a regression tree over disturbances ([`close`]), or the rules in front of
//! another tree ([`close_with`]): see the docs of [`crate::regress`].

use std::collections::{HashSet, VecDeque};
use std::time::Instant;

use super::way_back::{near_way_back, way_back};
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
    /// States where the tree failed, each given a way back (a plan to the goal, or to a
    /// state where one of the tree's rules holds) and its rules.
    pub plans: usize,
    /// Undo rules added ([`Policy::undo_rules`]).
    pub undo: usize,
    /// Of [`Closed::plans`], the ways back added as return rules (each action's
    /// preconditions only, after all the other rules), where those take no more nodes
    /// than the way's rules regressed from the rule it leads to.
    pub returns: usize,
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
        if self.returns > 0 {
            write!(f, ", {} as return rules", self.returns)?;
        }
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
///
/// The states where the tree fails are served depth by depth, in two rounds at each
/// depth: first those with a way back that needs no new plan ([`near_way_back`]: a few
/// actions, or the tree's own plan rejoined); then, in the order they were met, those
/// that need a new plan to the goal, whose search takes many times longer and whose
/// rules take many more nodes. So a few such states (in openstacks, a machine set up
/// out of turn from the initial state: a new plan of a hundred steps each) do not use up
/// the time and the nodes that would have served many states a few of the plan's steps
/// away (an order started out of turn), and the rules still come nearest the tree's
/// path first, the order in which a closure that does not fit is cut.
///
/// With a deadline, a state whose first look found a way back all the same (one
/// farther from the goal than the tree was) is not left for later but takes it at once
/// ([`serve`]).
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
    // States whose only ways back need a new plan, with their depth and the state the
    // disturbance came from: served at the end of their depth.
    let mut later: VecDeque<(usize, State, State)> = VecDeque::new();
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
                    let from = levels[depth][k].0.clone();
                    match serve(g, policy, tree, budget, done, (&from, &t), &mut size, Look::Near)? {
                        Served::Later => later.push_back((depth, from, t)),
                        Served::Not => {}
                        Served::Path(path, added) => {
                            follow(&mut levels, &mut seen, depth, t, path);
                            if added && more_actions(&mut acts, tree.actions(policy)) {
                                // New actions: first in the states looked at before.
                                continue 'scan;
                            }
                        }
                    }
                }
            }
            // This depth's states that need a new plan, before the next depth's.
            let Some(i) = later.iter().position(|l| l.0 <= depth) else { continue };
            let Some((depth, from, t)) = later.remove(i) else { continue };
            if let Some(stop) = over(done, size) {
                done.stopped = Some(stop);
                return Ok(false);
            }
            let served = serve(g, policy, tree, budget, done, (&from, &t), &mut size, Look::Any)?;
            if let Served::Path(path, added) = served {
                follow(&mut levels, &mut seen, depth, t, path);
                if added {
                    more_actions(&mut acts, tree.actions(policy));
                }
            }
            continue 'scan;
        }
        return Ok(true);
    }
}

/// Puts `t`, a state `depth` disturbances led to, and the states the tree passes
/// through from it into the next level, where there is one.
fn follow(levels: &mut [Vec<(State, usize)>], seen: &mut HashSet<State>, depth: usize, t: State, path: Vec<State>) {
    if let Some(level) = levels.get_mut(depth + 1) {
        level.push((t, 0));
        for p in path {
            if seen.insert(p.clone()) {
                level.push((p, 0));
            }
        }
    }
}

/// Appends to `acts` those of `now` it does not have; whether there were any.
fn more_actions(acts: &mut Vec<ActionId>, now: Vec<ActionId>) -> bool {
    let before = acts.len();
    for x in now {
        if !acts.contains(&x) {
            acts.push(x);
        }
    }
    acts.len() > before
}

/// What [`serve`] did for a state a disturbance led to.
enum Served {
    /// The tree reaches the goal from it, or does after the rules added: the states
    /// it passes through, and whether rules were added.
    Path(Vec<State>, bool),
    /// The tree fails there and its only ways back need a new plan: left for later.
    Later,
    /// The tree fails there and no way back was added (none, or too long).
    Not,
}

/// How [`serve`] looks for a way back where neither the tree nor an undo rule serves.
#[derive(Clone, Copy)]
enum Look {
    /// Only for one that needs no new plan ([`near_way_back`]).
    Near,
    /// For any, a new plan too ([`way_back`]).
    Any,
}

/// Serves `t`, the state a disturbance led to from `s`: where the tree fails from it,
/// adds an undo rule or the rules of a way back (found as `look` says), and counts what
/// it did in `done` and the tree's `size`.
#[allow(clippy::too_many_arguments)]
fn serve(
    g: &Grounding,
    policy: &mut Policy,
    tree: &mut dyn Closable,
    budget: &Budget,
    done: &mut Closed,
    (s, t): (&State, &State),
    size: &mut usize,
    look: Look,
) -> Result<Served, PlanError> {
    let (path, reached) = tree.run(g, policy, t)?;
    if reached {
        return Ok(Served::Path(path, false));
    }
    let own = tree.actions(policy);
    if policy.push_undo(g, s, t, &own) {
        let (undone, ok) = tree.run(g, policy, t)?;
        if ok {
            done.undo += 1;
            *size = tree.nodes(g, policy);
            return Ok(Served::Path(undone, true));
        }
        policy.pop_undo();
    }
    let back = match look {
        Look::Near => match near_way_back(g, policy, s, t, &own, budget) {
            Ok(way) => Some(way),
            // With a deadline, a way back found is taken at once: served later, the
            // search for a new plan that might be cheaper would get a small share of the
            // time left ([`way_back`]), while the way found needs no search and adds few
            // rules, after which many of the states met next need no look at all.
            Err(known) if budget.deadline.is_some() && known.is_some() => known,
            Err(_) => return Ok(Served::Later),
        },
        Look::Any => way_back(g, policy, s, t, &own, budget, done),
    };
    let Some((steps, rule)) = back else { return Ok(Served::Not) };
    let Some(trace) = Trace::from_state(g, t, &steps) else { return Ok(Served::Not) };
    // The way's steps as return rules, where the tree then reaches the goal from `t`.
    let mut returns = policy.clone();
    let returned = if returns.push_returns(g, &steps) > 0 {
        let (path, reached) = tree.run(g, &returns, t)?;
        reached.then(|| (tree.nodes(g, &returns), path))
    } else {
        None
    };
    let mut regressed = policy.clone();
    regressed.add_path(g, &trace, &rule);
    let regressed_nodes = tree.nodes(g, &regressed);
    // The return rules where they take no more nodes than the way's regressed rules.
    let (chosen, nodes, path) = match returned {
        Some((nodes, path)) if nodes <= regressed_nodes => (returns, nodes, Some(path)),
        _ => (regressed, regressed_nodes, None),
    };
    if nodes.saturating_sub(*size) > budget.nodes / WAY_BACK_SHARE {
        // One hard state would use up the nodes meant for many.
        done.too_long += 1;
        return Ok(Served::Not);
    }
    *policy = chosen;
    *size = nodes;
    done.plans += 1;
    done.returns += usize::from(path.is_some());
    let path = match path {
        Some(path) => path,
        None => tree.run(g, policy, t)?.0,
    };
    Ok(Served::Path(path, true))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]

    use std::path::Path;

    use super::*;
    use crate::pddl::{parse_domain, parse_problem};
    use crate::regress::way_back::Way;

    fn fixture(domain: &str, problem: &str) -> Grounding {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/ipc");
        let d = std::fs::read_to_string(dir.join(domain)).unwrap();
        let p = std::fs::read_to_string(dir.join(problem)).unwrap();
        Grounding::new(&parse_domain(domain, &d).and_then(|d| parse_problem(problem, &p, &d)).unwrap()).unwrap()
    }

    /// A state one of the tree's actions leads to from the tree's path, where the tree
    /// fails, no undo rule serves, and the first look finds a way back all the same but
    /// none that is no farther from the goal: the state the disturbance came from, it,
    /// and the way the look found.
    fn left_for_later(g: &Grounding, policy: &Policy) -> Option<(State, State, Way)> {
        let own = policy.actions();
        for s in policy.path(g, g.init()) {
            for &a in &own {
                let Some(t) = successor(g, a, &s) else { continue };
                if RulesOnly.run(g, policy, &t).ok()?.1 {
                    continue;
                }
                let mut undone = policy.clone();
                if undone.push_undo(g, &s, &t, &own) && RulesOnly.run(g, &undone, &t).ok()?.1 {
                    continue;
                }
                if let Err(Some(known)) = near_way_back(g, policy, &s, &t, &own, &Budget::default()) {
                    return Some((s, t, known));
                }
            }
        }
        None
    }

    #[test]
    fn with_a_deadline_a_state_whose_first_look_found_a_way_back_takes_it_at_once() {
        let g = fixture("psr-middle/domain.pddl", "psr-middle/p01-s17-n2-l2-f30.pddl");
        let plan = crate::search::gbfs(&g, &crate::search::SearchOptions::default()).unwrap().plan;
        let plain = Policy::of_trace(&g, &Trace::new(&g, &plan).unwrap());
        let (s, t, (steps, _)) = left_for_later(&g, &plain).expect("no state whose only near way back is farther");
        let serve_with = |budget: &Budget| {
            let mut policy = plain.clone();
            let mut done = Closed::default();
            let mut size = RulesOnly.nodes(&g, &policy);
            let served = serve(&g, &mut policy, &mut RulesOnly, budget, &mut done, (&s, &t), &mut size, Look::Near);
            (served.unwrap(), policy, done)
        };
        // Without a deadline: left for later.
        let (served, policy, done) = serve_with(&Budget::default());
        assert!(matches!(served, Served::Later), "not left for later");
        assert_eq!((policy.rules(), done.plans), (plain.rules(), 0));
        // With a deadline (one far off, so that no search is cut): the way taken at once.
        let far =
            Budget { deadline: Some(Instant::now() + std::time::Duration::from_secs(3_600)), ..Budget::default() };
        let (served, policy, done) = serve_with(&far);
        assert!(matches!(served, Served::Path(_, true)));
        assert_eq!(done.plans, 1, "{done}");
        let (path, reached) = RulesOnly.run(&g, &policy, &t).unwrap();
        assert!(reached);
        assert_eq!(Trace::from_state(&g, &t, &steps).unwrap().state(steps.len()), path.get(steps.len()));
    }
}
