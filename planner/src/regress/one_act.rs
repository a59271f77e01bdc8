//! The closure of a regression tree too large for [`super::close`]'s node budget (or
//! for the controller): rules that take the world back by one of the tree's own
//! actions from the states one act of an agent leads to where no rule holds
//! ([`close_one_act`]).
//!
//! Rules regressed through a way back carry all the conditions of the rule they lead
//! to: on a long plan (visitall's 30x30 grid, about 900 conditions in the middle of the
//! plan) one way back costs hundreds of nodes. A *return rule* is `Sequence(pre(u)?,
//! u!)` after all the others, as an undo rule, for a tree action `u` that leads from
//! the disturbed state to one where a rule of the plan holds; unlike an undo rule it
//! need not restore the state exactly (a robot moved out of turn comes back, the cell it
//! visited stays visited). In a plan that leaves a place twice, by different actions, an
//! agent doing the later one during the first visit leads the world where the plan comes
//! only later, without what the plan does in between: one return rule serves that act
//! from every state it can come from.

use std::collections::HashSet;
use std::time::Instant;

use super::{Budget, Policy, Rule, falsifies_own_condition, own_first, successor};
use crate::ground::{ActionId, Grounding, Lit};
use crate::state::State;

/// The return rules may add at most this share (an eighth) of the closure's node budget,
/// or of the tree's nodes where it has more.
pub const ONE_ACT_SHARE: usize = 8;

/// States one act away [`close_one_act`] looks at, at most, per state of the tree's
/// path: a robot on a grid has four moves. Where actions are many (openstacks: an
/// order can be started or a product made from most states) the rules would be scanned
/// for tens of thousands of states for next to no return rule.
pub const STATES_PER_STEP: usize = 4;

/// What [`close_one_act`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OneAct {
    /// States one act from the tree's path where no rule held.
    pub failing: usize,
    /// Return rules added.
    pub rules: usize,
    /// Whether the node budget ran out first.
    pub budget_reached: bool,
}

/// Adds return rules to `policy` (see the module docs): from each state the tree passes
/// through from the initial state, each of the tree's actions an agent can do there,
/// in order; where no rule (nor return rule) holds in the state it leads to, an action
/// that makes true again a fact the act made false (or false again one it made true),
/// the tree's own first, that makes one of its own conditions false, has no
/// conditional effects, forms no cycle with the other return rules in which they could
/// take turns, and leads to a state where a rule of the plan holds.
/// From there the rules reach the goal (each leads to one nearer it; see the module
/// docs of [`crate::regress`]). Stops once the rules would add more than
/// `budget.nodes` planner nodes (each `Sequence`, its conditions and its action), once
/// it has looked at `budget.states` states one act away or [`STATES_PER_STEP`] per
/// state of the path, or at `budget.deadline`.
pub fn close_one_act(g: &Grounding, policy: &mut Policy, budget: &Budget) -> OneAct {
    let mut done = OneAct::default();
    let own = policy.actions();
    let mut seen: HashSet<State> = HashSet::new();
    let mut added = 0;
    let path = policy.path(g, g.init());
    let states = budget.states.min(path.len().saturating_mul(STATES_PER_STEP));
    for s in path {
        for &a in &own {
            let Some(t) = successor(g, a, &s) else { continue };
            if !seen.insert(t.clone()) || policy.next(&t).is_some() || g.goal_holds(&t) {
                continue;
            }
            if seen.len() > states || budget.deadline.is_some_and(|d| Instant::now() >= d) {
                done.budget_reached = true;
                return done;
            }
            done.failing += 1;
            let Some(rule) = return_rule(g, policy, &s, &t, &own) else { continue };
            let cost = 2 + rule.when.len();
            if added + cost > budget.nodes {
                done.budget_reached = true;
                return done;
            }
            added += cost;
            policy.apply(super::groups::Group { rules: vec![rule], undo: true, plan: None });
            done.rules += 1;
        }
    }
    done
}

/// The return rule for `t`, one act from `s` (see [`close_one_act`]), if an action
/// serves.
fn return_rule(g: &Grounding, policy: &Policy, s: &State, t: &State, own: &[ActionId]) -> Option<Rule> {
    let serves = |u: ActionId| -> Option<Rule> {
        let x = g.action(u).filter(|x| x.cond.is_empty() && x.applicable(t))?;
        if !falsifies_own_condition(x) || policy.first(&successor(g, u, t)?).is_none() {
            return None;
        }
        let rule = policy.undo_rule(g, u)?;
        (!policy.returns_take_turns(g, &[], &rule)).then_some(rule)
    };
    let lost = s.iter().filter(|&a| !t.holds(a)).map(|atom| Lit { atom, positive: true });
    let gained = t.iter().filter(|&a| !s.holds(a)).map(|atom| Lit { atom, positive: false });
    let undoing: Vec<ActionId> = lost.chain(gained).flat_map(|l| g.achievers(l).iter().copied()).collect();
    own_first(&undoing, own).find_map(serves)
}

impl Policy {
    /// Adds a way back from a disturbed state as return rules, one group: for each
    /// action of `steps` (a way back found by [`super::close`]'s looks) that no return
    /// or undo rule has yet, `Sequence(pre(u)?, u!)` after all the others. Each must
    /// make one of its own conditions false, have no conditional effects and form no
    /// cycle with the other return rules in which they could take turns. Returns how
    /// many rules were added (0, and nothing added, where one action does not serve);
    /// the caller runs the tree from the disturbed state to see whether they serve.
    ///
    /// A rule regressed through a way back carries all the conditions of the rule it
    /// leads to (175 in philosophers p24, for each of a way back's 24 steps), and serves
    /// the states that meet them all; a return rule carries its action's preconditions
    /// and serves every state where no other rule holds: where an agent did one of a
    /// run of interchangeable steps out of turn (a process activated before the others),
    /// the same few rules lead back from every step of the run.
    pub(super) fn push_returns(&mut self, g: &Grounding, steps: &[ActionId]) -> usize {
        let group = self.group_count();
        let mut rules: Vec<Rule> = Vec::new();
        for &u in steps {
            if self.undo.iter().chain(&rules).any(|r| r.action == u) {
                continue;
            }
            let Some(x) = g.action(u) else { return 0 };
            if !x.cond.is_empty() || !falsifies_own_condition(x) {
                return 0;
            }
            let Some(rule) = self.undo_rule(g, u) else { return 0 };
            if self.returns_take_turns(g, &rules, &rule) {
                return 0;
            }
            rules.push(Rule { group, ..rule });
        }
        let added = rules.len();
        if added > 0 {
            self.apply(super::groups::Group { rules, undo: true, plan: None });
        }
        added
    }

    /// Whether the undo rules with `pending` (rules about to be added with it) and
    /// `extra` could act in turn for ever. They act only
    /// where no rule of a plan holds (from a state where one holds, the rules reach the
    /// goal), and each one's action makes one of its own conditions false, so it acts
    /// again only after another made that condition true: undo rules that repeat need a
    /// cycle of rules, each making true a condition that the next makes false. This
    /// looks for such a cycle through `extra` (the undo rules of [`super::close`], no
    /// two changing a fact in opposite directions, have none).
    fn returns_take_turns(&self, g: &Grounding, pending: &[Rule], extra: &Rule) -> bool {
        let rules: Vec<&Rule> = self.undo.iter().chain(pending).chain(std::iter::once(extra)).collect();
        // `enables(k, j)`: rule k makes true a condition of rule j that j makes false.
        let enables = |k: &Rule, j: &Rule| -> bool {
            let (Some(xk), Some(xj)) = (g.action(k.action), g.action(j.action)) else { return true };
            j.when.iter().any(|l: &Lit| {
                let falsified = if l.positive { xj.del.contains(&l.atom) } else { xj.add.contains(&l.atom) };
                let restored = if l.positive { xk.add.contains(&l.atom) } else { xk.del.contains(&l.atom) };
                falsified && restored
            })
        };
        // A cycle through `extra` exists iff `extra` reaches itself: the other rules had
        // none before.
        let last = rules.len() - 1;
        let mut stack = vec![last];
        let mut reached = vec![false; rules.len()];
        while let Some(k) = stack.pop() {
            for (j, r) in rules.iter().enumerate() {
                if enables(rules[k], r) {
                    if j == last {
                        return true;
                    }
                    if !reached[j] {
                        reached[j] = true;
                        stack.push(j);
                    }
                }
            }
        }
        false
    }
}

#[cfg(test)]
pub(crate) mod star {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

    use super::*;
    use crate::guide::Trace;
    use crate::pddl::{parse_domain, parse_problem};

    /// Visitall's domain (IPC 2011) on a star: the robot starts in the middle and must
    /// visit three cells around it, so every plan leaves the middle three times.
    pub(crate) const DOMAIN: &str = "(define (domain grid-visit-all) (:requirements :typing)
        (:types place - object)
        (:predicates (connected ?x ?y - place) (at-robot ?x - place) (visited ?x - place))
        (:action move :parameters (?curpos ?nextpos - place)
          :precondition (and (at-robot ?curpos) (connected ?curpos ?nextpos))
          :effect (and (at-robot ?nextpos) (not (at-robot ?curpos)) (visited ?nextpos))))";
    pub(crate) const STAR: &str = "(define (problem star) (:domain grid-visit-all)
        (:objects x a b c - place)
        (:init (at-robot x) (visited x) (connected x a) (connected a x) (connected x b)
          (connected b x) (connected x c) (connected c x))
        (:goal (and (visited x) (visited a) (visited b) (visited c))))";

    fn star() -> Grounding {
        let d = parse_domain("domain.pddl", DOMAIN).unwrap();
        Grounding::new(&parse_problem("star.pddl", STAR, &d).unwrap()).unwrap()
    }

    fn named(g: &Grounding, name: &str) -> ActionId {
        (0..g.actions().len()).map(|k| k as ActionId).find(|&a| g.action_name(a) == name).unwrap()
    }

    #[test]
    fn an_agent_taking_the_robot_where_the_plan_comes_later_is_brought_back() {
        let g = star();
        let steps = ["move(x, a)", "move(a, x)", "move(x, b)", "move(b, x)", "move(x, c)"];
        let plan: Vec<ActionId> = steps.iter().map(|s| named(&g, s)).collect();
        let mut policy = Policy::of_trace(&g, &Trace::new(&g, &plan).unwrap());
        // At the start, an agent moves the robot to b (the plan's third step) or c (its
        // fifth): no rule holds there, since a is not visited yet.
        let to_b = successor(&g, named(&g, "move(x, b)"), g.init()).unwrap();
        let to_c = successor(&g, named(&g, "move(x, c)"), g.init()).unwrap();
        let reaches = |p: &Policy, s: &State| p.path(&g, s).last().is_some_and(|l| g.goal_holds(l));
        assert!(!reaches(&policy, &to_b) && !reaches(&policy, &to_c));
        let room = |nodes| Budget { nodes, ..Budget::default() };
        let done = close_one_act(&g, &mut policy, &room(100));
        assert!(done.rules >= 2 && !done.budget_reached, "{done:?}");
        assert!(reaches(&policy, &to_b) && reaches(&policy, &to_c));
        // b to x is the tree's own action; c to x is not, and comes in only for the
        // state no action of the tree leads back from.
        let actions: Vec<String> = policy.undo_rules().iter().map(|r| g.action_name(r.action)).collect();
        assert!(actions.contains(&"move(b, x)".to_string()) && actions.contains(&"move(c, x)".to_string()));
        // The undisturbed path is the plan's.
        assert_eq!(policy.path(&g, g.init()).len(), plan.len() + 1);
        // No room for a rule: none added.
        let mut bare = Policy::of_trace(&g, &Trace::new(&g, &plan).unwrap());
        let none = close_one_act(&g, &mut bare, &room(2));
        assert!(none.rules == 0 && none.budget_reached && bare.undo_rules().is_empty(), "{none:?}");
    }

    #[test]
    fn return_rules_that_could_take_turns_are_refused() {
        let g = star();
        let mut policy = Policy::empty();
        let rule = |name: &str| {
            let u = named(&g, name);
            let mut when = g.action(u).unwrap().pre.clone();
            when.sort_unstable();
            Rule { when, action: u, distance: u32::MAX, group: 0 }
        };
        // a to x, then x to b: a chain, which ends.
        assert!(!policy.returns_take_turns(&g, &[], &rule("move(a, x)")));
        policy.undo.push(rule("move(a, x)"));
        assert!(!policy.returns_take_turns(&g, &[], &rule("move(x, b)")));
        policy.undo.push(rule("move(x, b)"));
        // x to a closes the cycle a, x; b to x the cycle x, b.
        assert!(policy.returns_take_turns(&g, &[], &rule("move(x, a)")));
        assert!(policy.returns_take_turns(&g, &[], &rule("move(b, x)")));
        assert!(!policy.returns_take_turns(&g, &[], &rule("move(c, x)")));
    }
}

#[cfg(test)]
mod ways_back {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]

    use super::*;
    use crate::guide::Trace;
    use crate::pddl::{parse_domain, parse_problem};
    use crate::regress::{Closable, RulesOnly, close};

    /// Six rockets, each armed, then fired; the plan arms them all, then fires them
    /// all (as philosophers p24's plan activates 25 processes, then runs them).
    const DOMAIN: &str = "(define (domain launch) (:requirements :typing)
        (:types rocket - object)
        (:predicates (idle ?r - rocket) (armed ?r - rocket) (fired ?r - rocket))
        (:action arm :parameters (?r - rocket)
          :precondition (idle ?r) :effect (and (armed ?r) (not (idle ?r))))
        (:action fire :parameters (?r - rocket)
          :precondition (armed ?r) :effect (and (fired ?r) (not (armed ?r)))))";
    const SIX: &str = "(define (problem six) (:domain launch)
        (:objects r1 r2 r3 r4 r5 r6 - rocket)
        (:init (idle r1) (idle r2) (idle r3) (idle r4) (idle r5) (idle r6))
        (:goal (and (fired r1) (fired r2) (fired r3) (fired r4) (fired r5) (fired r6))))";

    fn named(g: &Grounding, name: &str) -> ActionId {
        (0..g.actions().len()).map(|k| k as ActionId).find(|&a| g.action_name(a) == name).unwrap()
    }

    /// An agent that arms a rocket out of turn leaves the world where no rule holds
    /// until the plan has armed all the others: a way back of up to five steps, whose
    /// rules, regressed from the rule it leads to, would each carry the whole state.
    /// As return rules (`arm` where the rocket is idle), a few rules serve every such
    /// act from every step, so the closure serves all the states one act from the
    /// tree's path within a budget that regressed ways back exceed.
    #[test]
    fn a_way_back_through_interchangeable_steps_becomes_return_rules() {
        let d = parse_domain("domain.pddl", DOMAIN).unwrap();
        let g = Grounding::new(&parse_problem("six.pddl", SIX, &d).unwrap()).unwrap();
        let names: Vec<String> =
            (1..=6).map(|k| format!("arm(r{k})")).chain((1..=6).map(|k| format!("fire(r{k})"))).collect();
        let plan: Vec<ActionId> = names.iter().map(|s| named(&g, s)).collect();
        let plain = Policy::of_trace(&g, &Trace::new(&g, &plan).unwrap());
        let room = plain.nodes(&g) + 40;
        let mut policy = plain.clone();
        let done = close(&g, &mut policy, &Budget { nodes: room, ..Budget::default() }).unwrap();
        assert!(done.complete && done.returns > 0, "{done}");
        assert!(policy.nodes(&g) <= room, "{} nodes, {room} allowed", policy.nodes(&g));
        // Every state one of the tree's acts leads to from its path: the tree reaches
        // the goal, and undisturbed it still follows the plan.
        let reaches = |s: &State| RulesOnly.run(&g, &policy, s).unwrap().1;
        let mut disturbed = 0;
        for s in plain.path(&g, g.init()) {
            for &a in &plain.actions() {
                if let Some(t) = successor(&g, a, &s) {
                    assert!(reaches(&t), "{} out of turn", g.action_name(a));
                    disturbed += 1;
                }
            }
        }
        assert!(disturbed > 30, "{disturbed}");
        assert_eq!(policy.path(&g, g.init()).len(), plan.len() + 1);
    }
}
