//! The nesting against the rules side by side, and against the halves.
#![allow(clippy::unwrap_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;

use proptest::prelude::*;

use super::{Cost, halves, push_with};
use crate::ground::{ActionId, Grounding, Lit};
use crate::guide::Trace;
use crate::pddl::{parse_domain, parse_problem};
use crate::regress::{Budget, Policy, Rule, close};
use crate::state::State;
use crate::tree::{Kind, PlanNode, PlanTree};

/// What a reactive tree of Sequences, Fallbacks, conditions and actions returns in
/// a state: an action ticked stands for Running.
#[derive(Debug, PartialEq, Eq)]
enum Tick {
    Success,
    Failure,
    Act(ActionId),
}

fn tick(t: &PlanTree, n: PlanNode, s: &State) -> Tick {
    match t.kind(n) {
        Kind::Condition(l) if l.holds(s) => Tick::Success,
        Kind::Condition(_) => Tick::Failure,
        Kind::Action(a) => Tick::Act(a),
        Kind::Sequence => {
            t.children(n).iter().map(|&c| tick(t, c, s)).find(|r| *r != Tick::Success).unwrap_or(Tick::Success)
        }
        Kind::Fallback => {
            t.children(n).iter().map(|&c| tick(t, c, s)).find(|r| *r != Tick::Failure).unwrap_or(Tick::Failure)
        }
    }
}

/// What the rules side by side do: the first that holds acts.
fn flat(rules: &[Rule], s: &State) -> Tick {
    rules.iter().find(|r| r.holds(s)).map_or(Tick::Failure, |r| Tick::Act(r.action))
}

fn condition(l: Lit) -> Cost {
    if l.positive { Cost { bytes: 3, nodes: 1 } } else { Cost { bytes: 5, nodes: 2 } }
}

fn action(_: ActionId) -> Cost {
    Cost { bytes: 4, nodes: 1 }
}

/// The cost of `t`'s nodes under `condition` and `action`.
fn cost_of(t: &PlanTree, n: PlanNode) -> Cost {
    match t.kind(n) {
        Kind::Condition(l) => condition(l),
        Kind::Action(a) => action(a),
        _ => Cost::control(t.children(n).iter().fold(Cost::default(), |s, &c| s + cost_of(t, c))),
    }
}

/// Rules as a plan's regression makes them: each differs from the one before in a
/// few literals.
fn rules() -> impl Strategy<Value = Vec<Rule>> {
    let step = (prop::collection::vec(0..10u32, 0..3), prop::collection::vec((0..10u32, any::<bool>()), 0..3));
    (prop::collection::vec((0..10u32, any::<bool>()), 1..6), prop::collection::vec(step, 0..50)).prop_map(
        |(first, steps)| {
            let mut when: Vec<Lit> = Vec::new();
            let put = |when: &mut Vec<Lit>, (atom, positive): (u32, bool)| {
                when.retain(|l| l.atom != atom);
                when.push(Lit { atom, positive });
            };
            for l in first {
                put(&mut when, l);
            }
            let mut out = Vec::new();
            for (k, (drop, add)) in std::iter::once((Vec::new(), Vec::new())).chain(steps).enumerate() {
                when.retain(|l| !drop.contains(&l.atom));
                for l in add {
                    put(&mut when, l);
                }
                let mut sorted = when.clone();
                sorted.sort_unstable();
                out.push(Rule { when: sorted, action: k as ActionId, distance: k as u32 + 1, group: 0 });
            }
            out
        },
    )
}

proptest! {
    /// The nesting ticks exactly as the rules side by side do, in every state of
    /// their atoms, and is never larger than the halves'.
    #[test]
    fn the_cheapest_nesting_ticks_as_the_rules_side_by_side(rules in rules()) {
        let refs: Vec<&Rule> = rules.iter().collect();
        let mut nested = PlanTree::with_root(Kind::Fallback);
        let root = nested.root();
        push_with(&mut nested, root, &refs, &condition, &action);
        let mut by_halves = PlanTree::with_root(Kind::Fallback);
        halves(&mut by_halves, root, &refs, &[]);
        for bits in 0..1u32 << 10 {
            let mut s = State::new(10);
            for atom in 0..10 {
                s.set(atom, bits & (1 << atom) != 0);
            }
            prop_assert_eq!(tick(&nested, root, &s), flat(&rules, &s), "state {:010b}", bits);
        }
        prop_assert!(cost_of(&nested, root) <= cost_of(&by_halves, root));
    }
}

/// The IPC fixtures' regression trees, closed over disturbances: each ticks as its
/// rules side by side do (from states where a rule holds), and its image is no
/// larger than the one the halves make.
#[test]
fn fixture_trees_tick_as_their_rules_and_are_no_larger_than_halves() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/ipc");
    let mut looked = 0;
    let mut dirs: Vec<_> = std::fs::read_dir(&root).unwrap().map(|e| e.unwrap().path()).collect();
    dirs.sort();
    for dir in dirs.iter().filter(|d| d.join("domain.pddl").exists()) {
        let d = std::fs::read_to_string(dir.join("domain.pddl")).unwrap();
        let mut files: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
        files.sort();
        for file in files.iter().filter(|f| f.extension().is_some_and(|e| e == "pddl") && !f.ends_with("domain.pddl")) {
            let p = std::fs::read_to_string(file).unwrap();
            let name = file.display().to_string();
            let problem = parse_domain("domain.pddl", &d).and_then(|d| parse_problem(&name, &p, &d)).unwrap();
            let g = Grounding::new(&problem).unwrap();
            let plan = crate::search::gbfs(&g, &crate::search::SearchOptions::default()).unwrap().plan;
            let mut policy = Policy::of_trace(&g, &Trace::new(&g, &plan).unwrap());
            close(&g, &mut policy, &Budget { nodes: 2_000, ..Budget::default() }).unwrap();
            let tree = policy.tree(&g);
            let mut by_halves = PlanTree::with_root(Kind::Fallback);
            let top = by_halves.root();
            by_halves.graft(top, &PlanTree::from_goal(g.goal()));
            let all: Vec<&Rule> = policy.rules().iter().chain(policy.undo_rules()).collect();
            halves(&mut by_halves, top, &all, &[]);
            let bytes = |t: &PlanTree| {
                let f = t.flatten(&g).unwrap();
                crate::offline::fit::size_of(&f.nodes, &f.values).unwrap().bytes
            };
            assert!(bytes(&tree) <= bytes(&by_halves), "{name}: {} > {}", bytes(&tree), bytes(&by_halves));
            // States where each rule holds, the others' atoms as the initial state has them.
            let goal = |s: &State| g.goal_holds(s);
            for r in &all {
                let mut s = g.init().clone();
                for l in &r.when {
                    s.set(l.atom, l.positive);
                }
                let want = if goal(&s) { Tick::Success } else { flat(policy.rules(), &s) };
                let want = if want == Tick::Failure { flat(policy.undo_rules(), &s) } else { want };
                assert_eq!(tick(&tree, tree.root(), &s), want, "{name}");
                looked += 1;
            }
        }
    }
    assert!(looked > 100, "{looked} states looked at");
}
