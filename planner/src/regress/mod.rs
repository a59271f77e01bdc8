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
//! does a step for it it skips ahead (the reactivity of Problem 1 in Colledanchise et al. 2019, for
//! the states the plan passes through). The conditions that a run of neighbouring
//! rules share are checked once, in a `Sequence(shared?, Fallback(rules...))` around
//! them, which ticks exactly as the rules side by side do (the regressed conditions of
//! consecutive steps differ in a few literals, so this makes the tree several times
//! smaller); the runs are chosen to make the tree's image small (a dynamic
//! programme over runs of shared conditions, never larger than splitting the rules at
//! their halves).
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
//! applicable, and where the tree would fail it finds a way back to its rules and adds
//! that path's rules (regressed from the rule it leads to), up to [`MAX_DISTURBANCES`]
//! disturbances deep, the states with fewer disturbances first. A new action that a
//! way back brings is tried at once in every state looked at before, the nearest the
//! initial state first (an agent can do it there too). The way back is a path of at
//! most two actions to a state where a rule holds; else the rest of a plan already
//! added without the steps that were done out of turn ([`Policy::resume`]: a step
//! that cannot be done is left out where what it adds holds, or done after the one
//! action of the tree that makes it possible again, such as a stack opened for an
//! order when an agent started another on the one the plan meant for it), taken when
//! it leaves the world no farther from the goal than before the disturbance, with no
//! search; else a longer one found by search on the unmet conditions of the rules
//! ([`Policy::rejoin`]: where a disturbance did a step of a long plan out of turn, the
//! plan's later steps lead back to its rules long before the goal), taken on the same
//! condition; else the cheapest of these ways and a new plan to the goal (greedy
//! best-first search with h_FF), where a way costs its steps to the goal plus one for
//! every action the tree does not have yet, the new plan on a tie, since rules
//! regressed from the goal hold in more states. The states that need a new plan are
//! served after every state as many disturbances deep with a shorter way back: a new
//! plan's search takes many times as long and its rules many more nodes, and a few
//! such states would otherwise use up the time and the nodes meant for many others.
//! The ways back try the tree's own actions before any others, and the cost counts new
//! ones, because a tree with fewer distinct actions gives an external agent fewer to
//! do, and its closure fewer states to look at.
//!
//! Any of these ways back is added as *return rules* instead where they
//! serve: for each of its actions, `Sequence(pre(u)?, u)` after all the other rules
//! (as the undo rules below), where the tree then reaches the goal from the disturbed
//! state, no return rules could take turns, and they take no more nodes than the way's
//! regressed rules, which carry all the conditions of the rule it leads to. A return
//! rule serves every state where no other rule holds: where an agent did one of a run
//! of interchangeable steps out of turn (a process activated before the others), the
//! same few rules lead back from every step of the run.
//!
//! Before any of these, an *undo rule* ([`Policy::undo_rules`]): where the agent's
//! action can be undone by one action (an object picked up out of turn, put back),
//! a rule `Sequence(pre(u)?, u)` after all the others, where the tree would otherwise
//! fail. One such rule serves the disturbance from every state of the tree's path,
//! where the ways back above serve one state each: rules regressed through a way back
//! carry all the conditions of the rule they lead to. Undo rules cannot take turns
//! (see [`Policy::undo_rules`]), and the tree acts on them only where no other rule
//! holds, so the rules' progress argument above is untouched.
//!
//! A tree already over the node budget (a long plan's: visitall's 30x30 grid) gets
//! none of these, only *return rules* ([`close_one_act`]): from the states one act of
//! an agent leads to where no rule holds, one action (the tree's own where one serves)
//! to a state where a rule holds, as a rule after all the others with that action's
//! preconditions. They need not restore the state exactly, and may change a fact in
//! opposite directions, but never form a cycle that could take turns for ever.
//!
//! All within a budget of plans, nodes and time (the tree is correct at every point,
//! so running out of budget leaves a tree that is only less robust); a way back whose
//! rules would take more than an eighth of the node budget is left out, so that a few
//! states with only long ways back do not use up the nodes meant for all the others.
//! [`close_with`] does the same for rules in front of another tree ([`Closable`]), the
//! undo rules behind it: where that tree fails from a state a disturbance leads to,
//! the rules take over.

mod close;
mod factor;
mod groups;
mod one_act;
mod way_back;

pub use close::{Budget, Closable, Closed, MAX_DISTURBANCES, RulesOnly, Stop, close, close_with};

/// Whether `x` makes one of its own preconditions false: a rule with `x`'s
/// preconditions as its conditions acts again only after something else made them true.
fn falsifies_own_condition(x: &GroundAction) -> bool {
    x.pre.iter().any(|l| if l.positive { x.del.contains(&l.atom) } else { x.add.contains(&l.atom) })
}

/// `candidates`, the tree's actions (`own`) among them first: a way back by those gives
/// an agent no new action to do.
fn own_first<'a>(candidates: &'a [ActionId], own: &'a [ActionId]) -> impl Iterator<Item = ActionId> + 'a {
    let (theirs, others) =
        (candidates.iter().filter(|u| own.contains(u)), candidates.iter().filter(|u| !own.contains(u)));
    theirs.chain(others).copied()
}
#[cfg(test)]
pub(crate) use one_act::star as one_act_star;
pub use one_act::{ONE_ACT_SHARE, OneAct, STATES_PER_STEP, close_one_act};

use crate::ground::{ActionId, GroundAction, Grounding, Lit};
use crate::guide::Trace;
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
        // Derived atoms change with the basic ones that support them here.
        if let Some(after) = trace.state(i) {
            c = g.support(after, &c);
        }
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
    /// The addition it came with ([`Policy::group_count`]): 0 for the first plan's.
    group: u32,
}

impl Rule {
    fn holds(&self, s: &State) -> bool {
        self.when.iter().all(|l| l.holds(s))
    }

    /// The goal as a rule's target: its conditions, at distance 0.
    fn goal(g: &Grounding) -> Self {
        let mut when = g.goal().to_vec();
        when.sort_unstable();
        Self { when, action: 0, distance: 0, group: 0 }
    }
}

/// The state action `a` leads to from `s`, when it is applicable there.
fn successor(g: &Grounding, a: ActionId, s: &State) -> Option<State> {
    let x = g.action(a).filter(|x| x.applicable(s))?;
    let mut t = s.clone();
    g.apply(x, &mut t);
    Some(t)
}

/// The rules of a regression tree, nearest the goal first (see the module docs).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Policy {
    rules: Vec<Rule>,
    /// Rules that undo an agent's action, after all the others: each takes the world
    /// back by one action where no rule holds (see [`Policy::undo_rules`]).
    undo: Vec<Rule>,
    /// The plans to the goal whose rules were added, first to last.
    plans: Vec<Vec<ActionId>>,
    /// Every addition of rules, in order: replayed in part by [`Policy::only`].
    log: Vec<groups::Group>,
}

fn subset(a: &[Lit], b: &[Lit]) -> bool {
    a.iter().all(|l| b.binary_search(l).is_ok())
}

impl Policy {
    /// The rules of one plan to the goal.
    #[must_use]
    pub fn of_trace(g: &Grounding, trace: &Trace) -> Self {
        let mut p = Self::empty();
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

    /// The rules that undo an agent's action: `when` is the action's preconditions, and
    /// `distance` is `u32::MAX` (they are not steps of a plan). The tree checks them
    /// after every other rule, so they act only where the tree would otherwise fail:
    /// where an agent did one of the tree's actions out of turn, such as picking up an
    /// object, one rule that puts it back serves every state the disturbance can come
    /// from, where rules regressed through the way back serve one each. Each undo
    /// rule's action makes one of its own conditions false, and no two change a fact
    /// in opposite directions: so they never take turns, and from any state each acts
    /// at most once before a rule holds (or the tree fails).
    #[must_use]
    pub fn undo_rules(&self) -> &[Rule] {
        &self.undo
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

    /// The rule the tree acts on in `s`: the first rule that holds, else the first
    /// undo rule that holds.
    #[must_use]
    pub fn next(&self, s: &State) -> Option<&Rule> {
        self.first(s).or_else(|| self.undo.iter().find(|r| r.holds(s)))
    }

    /// The states the tree passes through from `s` until the goal (`s` included), or
    /// until neither a rule nor an undo rule holds.
    #[must_use]
    pub fn path(&self, g: &Grounding, s: &State) -> Vec<State> {
        let mut out = vec![s.clone()];
        let mut cur = s.clone();
        // Distances fall by at least one a step (see the module docs), and each undo
        // rule acts at most once ([`Policy::push_undo`]); the limit only guards against
        // a grounding whose actions break that.
        let limit = self.max_distance() as usize + 1 + self.undo.len();
        while !g.goal_holds(&cur) && out.len() <= limit {
            let Some(next) = self.next(&cur).and_then(|r| successor(g, r.action, &cur)) else { break };
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
        for r in self.rules.iter().chain(&self.undo) {
            if !out.contains(&r.action) {
                out.push(r.action);
            }
        }
        out
    }

    /// Adds the rules of `trace`, a path to a state where `rule` holds (its conditions
    /// regressed through the path); returns how many were kept.
    fn add_path(&mut self, g: &Grounding, trace: &Trace, rule: &Rule) -> usize {
        let plan = (rule.distance == 0).then(|| trace.plan().to_vec());
        let cs = conditions_to(g, trace, &rule.when);
        let n = trace.plan().len();
        let group = self.group_count();
        // Nearest the target first, so that equal rules keep the path's last use.
        let rules = (1..=n)
            .rev()
            .map(|i| {
                let mut when = cs[i - 1].clone();
                when.sort_unstable();
                let distance = rule.distance + (n - i + 1) as u32;
                Rule { when, action: trace.plan()[i - 1], distance, group }
            })
            .collect();
        self.apply(groups::Group { rules, undo: false, plan })
    }

    /// Planner nodes of the tree with its rules and its undo rules nested by halves
    /// (each apart): quick to count after every addition of the closure over
    /// disturbances, where [`Policy::tree`]'s nesting takes up to a few tens of
    /// milliseconds, and about as many as that tree has (whose image is never larger).
    /// It builds the tree: keep the count while the rules do not change.
    #[must_use]
    pub fn nodes(&self, g: &Grounding) -> usize {
        let t = self.tree_with(g, None, false);
        t.preorder(t.root()).len()
    }

    /// The tree: `Fallback(goal?, Sequence(when?, action), ...)`, the rules in order,
    /// then the undo rules, with the conditions that runs of neighbouring rules share
    /// checked once (in a `Sequence(shared?, Fallback(rules...))` around them), the
    /// runs chosen to make the image small.
    #[must_use]
    pub fn tree(&self, g: &Grounding) -> PlanTree {
        self.tree_with(g, None, true)
    }

    /// [`Policy::tree`] with `base` between the rules and the undo rules.
    /// `cheapest`: nested by [`factor::push`], else by halves ([`Policy::nodes`]).
    fn tree_with(&self, g: &Grounding, base: Option<&PlanTree>, cheapest: bool) -> PlanTree {
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
        if !cheapest {
            factor::halves(&mut t, root, &self.rules.iter().collect::<Vec<_>>(), &[]);
            if let Some(base) = base {
                t.graft(root, base);
            }
            factor::halves(&mut t, root, &self.undo.iter().collect::<Vec<_>>(), &[]);
        } else if let Some(base) = base {
            factor::push(g, &mut t, root, &self.rules.iter().collect::<Vec<_>>());
            t.graft(root, base);
            factor::push(g, &mut t, root, &self.undo.iter().collect::<Vec<_>>());
        } else {
            factor::push(g, &mut t, root, &self.rules.iter().chain(&self.undo).collect::<Vec<_>>());
        }
        t
    }

    /// Adds an undo rule for `t`, a state an agent's action led to from `s`, when one
    /// action `u` (of `own`, the tree's, if one does) leads back to `s` exactly (the
    /// rule's action is `u`, its conditions `u`'s preconditions); the caller checks
    /// that the tree then reaches the goal from `t`, and takes it out again
    /// ([`Policy::pop_undo`]) if not. Returns whether it was added.
    ///
    /// Undo rules never take turns: `u` must make one of its own conditions false (so
    /// it never acts where it would change nothing), have no conditional effects, and
    /// change no fact the other way from an undo rule already there (an agent that puts
    /// an object down, undone by picking it up, where a rule puts it down: the two
    /// could alternate for ever). A fact that only ever changes one way changes at most
    /// once, so from any state each undo rule acts at most once before a rule holds
    /// (or the tree fails).
    fn push_undo(&mut self, g: &Grounding, s: &State, t: &State, own: &[ActionId]) -> bool {
        // The actions that make a fact of `s` that `t` lacks true (or one `t` has
        // false): the tree's own first.
        let lost = s.iter().find(|&a| !t.holds(a)).map(|atom| Lit { atom, positive: true });
        let Some(need) = lost.or_else(|| t.iter().find(|&a| !s.holds(a)).map(|atom| Lit { atom, positive: false }))
        else {
            return false;
        };
        let fits = |u: &ActionId| {
            let Some(x) = g.action(*u) else { return false };
            let against = |r: &Rule| {
                g.action(r.action)
                    .is_none_or(|y| x.add.iter().any(|a| y.del.contains(a)) || x.del.iter().any(|a| y.add.contains(a)))
            };
            falsifies_own_condition(x)
                && x.cond.is_empty()
                && !self.undo.iter().any(against)
                && successor(g, *u, t).as_ref() == Some(s)
        };
        let Some(u) = own_first(g.achievers(need), own).find(fits) else { return false };
        let Some(rule) = self.undo_rule(g, u) else { return false };
        self.apply(groups::Group { rules: vec![rule], undo: true, plan: None });
        true
    }

    /// The rule `Sequence(pre(u)?, u!)` of an undo or return rule, in the next group:
    /// after all the others, so with no distance to the goal.
    fn undo_rule(&self, g: &Grounding, u: ActionId) -> Option<Rule> {
        let mut when = g.action(u)?.pre.clone();
        when.sort_unstable();
        when.dedup();
        Some(Rule { when, action: u, distance: u32::MAX, group: self.group_count() })
    }

    /// Takes out the undo rule added last.
    fn pop_undo(&mut self) {
        self.undo.pop();
        self.log.pop();
    }

    /// The rules in front of `base`, the undo rules behind it: `Fallback(goal?,
    /// rules..., base, undo rules...)`; `base` itself while there are none.
    #[must_use]
    pub fn tree_before(&self, g: &Grounding, base: &PlanTree) -> PlanTree {
        self.before(g, base, true)
    }

    /// A tree that ticks exactly as [`Policy::tree_before`]'s, its rules nested by
    /// halves: quicker to make where the closure runs it after every addition.
    #[must_use]
    pub fn tree_before_by_halves(&self, g: &Grounding, base: &PlanTree) -> PlanTree {
        self.before(g, base, false)
    }

    /// `base` where there are no rules, else [`Policy::tree_with`] around it.
    fn before(&self, g: &Grounding, base: &PlanTree, cheapest: bool) -> PlanTree {
        if self.rules.is_empty() && self.undo.is_empty() {
            return base.clone();
        }
        self.tree_with(g, Some(base), cheapest)
    }

    /// An empty policy (no rules).
    #[must_use]
    pub fn empty() -> Self {
        Self { rules: Vec::new(), undo: Vec::new(), plans: Vec::new(), log: Vec::new() }
    }
}
