//! Regression trees closed over disturbances (`planner::regress::close`): on IPC
//! fixtures where the plain regression tree fails after an external agent does one of
//! its actions, the closed tree handles every such state and still reaches the goal.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;
use std::sync::Arc;

use planner::coverage::{self, Settings};
use planner::ground::{Grounding, Lit};
use planner::guide::Trace;
use planner::pddl::{parse_domain, parse_problem};
use planner::regress::{self, Budget, Policy};
use planner::search::{self, SearchOptions};
use planner::state::State;
use planner::strips::{self, StripsWorld};
use planner::{Options, PddlCatalog};

/// A problem written here, not read from the fixtures.
fn problem_of(domain: &str, problem: &str) -> planner::model::Problem {
    parse_domain("domain.pddl", domain).and_then(|d| parse_problem("problem.pddl", problem, &d)).unwrap()
}

fn grounding(domain: &str, problem: &str) -> (Arc<Grounding>, Arc<PddlCatalog>) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/ipc");
    let dtext = std::fs::read_to_string(dir.join(domain)).unwrap();
    let ptext = std::fs::read_to_string(dir.join(problem)).unwrap();
    let p = parse_domain(domain, &dtext).and_then(|d| parse_problem(problem, &ptext, &d)).unwrap();
    (Arc::new(Grounding::new(&p).unwrap()), Arc::new(PddlCatalog::new(&p)))
}

/// The states one of the tree's actions leads to from a state the tree passes through
/// from the initial state, and whether the tree has a rule (or the goal) there.
fn one_disturbance_away(g: &Grounding, policy: &Policy) -> Vec<(State, bool)> {
    let mut out = Vec::new();
    for s in policy.path(g, g.init()) {
        for a in policy.actions() {
            let x = g.action(a).unwrap();
            if x.applicable(&s) {
                let mut t = s.clone();
                x.apply(&mut t);
                let covered = g.goal_holds(&t) || policy.next(&t).is_some();
                out.push((t, covered));
            }
        }
    }
    out
}

fn plain_policy(g: &Grounding) -> Policy {
    let found = search::gbfs(g, &SearchOptions::default()).unwrap();
    Policy::of_trace(g, &Trace::new(g, &found.plan).unwrap())
}

#[test]
fn the_closed_tree_has_a_rule_wherever_one_disturbance_leads() {
    let (g, _) = grounding("assembly/domain.pddl", "assembly/prob01.pddl");
    let mut policy = plain_policy(&g);
    let before = one_disturbance_away(&g, &policy);
    assert!(before.iter().any(|(_, covered)| !covered), "the plain tree already covers every state");
    let closed = regress::close(&g, &mut policy, &Budget::default()).unwrap();
    assert!(closed.plans > 0, "{closed}");
    for (t, covered) in one_disturbance_away(&g, &policy) {
        if !covered {
            // Only where no plan exists.
            assert!(search::gbfs_from(&g, &t, &SearchOptions::default()).is_err(), "{closed}");
        }
    }
    // From every such state, the tree's path ends at the goal, never in a loop.
    for (t, covered) in one_disturbance_away(&g, &policy) {
        if covered {
            let path = policy.path(&g, &t);
            assert!(g.goal_holds(path.last().unwrap()), "a path stopped short of the goal");
        }
    }
}

#[test]
fn rules_are_ordered_by_distance_and_none_is_preempted_by_an_earlier_one() {
    let (g, _) = grounding("assembly/domain.pddl", "assembly/prob01.pddl");
    let mut policy = plain_policy(&g);
    regress::close(&g, &mut policy, &Budget::default()).unwrap();
    let rules = policy.rules();
    assert!(rules.windows(2).all(|w| w[0].distance <= w[1].distance));
    for (i, r) in rules.iter().enumerate() {
        for earlier in &rules[..i] {
            assert!(!earlier.when.iter().all(|l| r.when.contains(l)), "a rule can never be the first to hold");
        }
    }
}

#[test]
fn disturbed_episodes_of_the_planned_tree_reach_the_goal() {
    // The planner closes its regression trees; the bench's disturbed episodes (undo
    // the last action, or do one of the tree's actions) then all reach the goal here,
    // where the plain regression tree of the same plan failed most of them.
    let (g, c) = grounding("assembly/domain.pddl", "assembly/prob01.pddl");
    let plan = planner::plan(g.clone(), c.clone(), Options::default()).unwrap();
    assert_eq!(plan.method, planner::Made::Regression, "this fixture no longer needs the regression tree");
    let settings = Settings { episodes: 40, ..Settings::default() };
    let ticks = plan.goal_ticks.unwrap();
    let d = coverage::disturbed(&plan.nodes, &plan.values, c.as_ref(), &g, ticks, &settings).unwrap();
    assert_eq!((d.reached, d.episodes, d.dead_ends), (40, 40, 0));

    let plain = plain_policy(&g).tree(&g).flatten(&g).unwrap();
    let plain_d = coverage::disturbed(&plain.nodes, &plain.values, c.as_ref(), &g, ticks, &settings).unwrap();
    // Assembly's actions can be undone: a failed episode is the tree's, not a dead end.
    assert_eq!(plain_d.dead_ends, 0);
    assert!(plain_d.reached < 40, "the plain tree reaches the goal in every episode too: the test shows nothing");
}

/// The states at most `depth` actions (any) from the initial state.
fn near_init(g: &Grounding, depth: usize) -> Vec<State> {
    let mut out = vec![g.init().clone()];
    let mut layer = out.clone();
    for _ in 0..depth {
        let mut next = Vec::new();
        for s in &layer {
            for x in g.actions() {
                if x.applicable(s) {
                    let mut t = s.clone();
                    x.apply(&mut t);
                    if !out.contains(&t) {
                        out.push(t.clone());
                        next.push(t);
                    }
                }
            }
        }
        layer = next;
    }
    out
}

#[test]
fn the_factored_tree_starts_the_first_rule_that_holds() {
    // `Policy::tree` checks the conditions neighbouring rules share once; ticked, it
    // must do what the rules side by side do: start the action of the first that holds.
    let (g, c) = grounding("assembly/domain.pddl", "assembly/prob01.pddl");
    let mut policy = plain_policy(&g);
    regress::close(&g, &mut policy, &Budget::default()).unwrap();
    let flat_rules: usize = policy.rules().iter().map(|r| if r.when.is_empty() { 1 } else { 2 + r.when.len() }).sum();
    let tree = policy.tree(&g);
    assert!(policy.nodes(&g) < flat_rules, "nothing shared: the test shows nothing");
    // `nodes` counts the rules nested by halves; the tree's own nesting is smaller.
    assert!(tree.preorder(tree.root()).len() <= policy.nodes(&g));
    let flat = tree.flatten(&g).unwrap();
    let mut states = Vec::new();
    let mut started_some = 0;
    let mut undone = 0;
    for s in near_init(&g, 3).into_iter().chain(policy.path(&g, g.init())) {
        let mut world = StripsWorld::new(g.clone());
        world.set_state(s.clone());
        strips::run_to_goal(
            (&flat.nodes, &flat.values),
            c.as_ref(),
            &mut world,
            1,
            strips::Ends::RANDOM,
            (),
            &mut states,
        )
        .unwrap();
        let started: Vec<u32> = (0..g.actions().len() as u32).filter(|&a| world.starts(a) > 0).collect();
        let expected: Vec<u32> =
            if g.goal_holds(&s) { Vec::new() } else { policy.next(&s).map(|r| r.action).into_iter().collect() };
        assert_eq!(started, expected);
        started_some += usize::from(!expected.is_empty());
        undone += usize::from(!g.goal_holds(&s) && policy.first(&s).is_none() && !expected.is_empty());
    }
    assert!(started_some > 10, "too few states with a rule: {started_some}");
    assert!(undone > 0, "no state where only an undo rule holds: the undo rules are not tested");
}

#[test]
fn a_guided_tree_gets_rules_in_front_where_it_fails_after_disturbances() {
    let (g, c) = grounding("transport-sat08-strips/domain.pddl", "transport-sat08-strips/p01.pddl");
    let plain = planner::plan(g.clone(), c.clone(), Options { close_nodes: 0, ..Options::default() }).unwrap();
    assert_eq!(plain.method, planner::Made::SearchGuided, "this fixture no longer makes a guided tree");
    assert!(plain.closed.is_none(), "closed with no nodes to close it");
    // Guided trees are closed by default (only Algorithm 1's need --close-backchained).
    let closed = planner::plan(g.clone(), c.clone(), Options::default()).unwrap();
    assert_eq!(closed.method, planner::Made::SearchGuided);
    let report = closed.closed.unwrap();
    assert!(report.plans > 0, "{report}");
    // The guided tree is still there, whole: a child of the new root, after the rules
    // (and before the undo rules, if any).
    assert!(closed.nodes.len() > plain.nodes.len());
    // (Leaves with more than three arguments number their values differently.)
    let resolved = |nodes: &[bt_core::Node], values: &[u16]| -> Vec<(String, u16, Vec<u16>)> {
        nodes
            .iter()
            .map(|n| {
                let leaf = n.kind().leaf();
                let args = leaf.map(|(_, l)| l.args_in(values).to_vec()).unwrap_or_default();
                (n.kind().name().to_string(), n.size(), args)
            })
            .collect()
    };
    let (whole, guided) = (resolved(&closed.nodes, &closed.values), resolved(&plain.nodes, &plain.values));
    assert!(whole.windows(guided.len()).any(|w| w == guided.as_slice()), "the guided tree is not in the closed one");
    let settings = Settings { episodes: 40, ..Settings::default() };
    let run = |p: &planner::Plan<PddlCatalog>| {
        coverage::disturbed(&p.nodes, &p.values, c.as_ref(), &g, p.goal_ticks.unwrap(), &settings).unwrap()
    };
    let (before, after) = (run(&plain), run(&closed));
    assert!(before.reached < 40, "the guided tree reaches the goal in every episode: the test shows nothing");
    assert!(after.reached > before.reached, "{before} -> {after}");
}

/// A door that, once shut, cannot be opened: shutting it before going in leaves no way
/// to the goal.
const DOOR_DOMAIN: &str = "(define (domain door) (:requirements :strips)
  (:predicates (open) (inside) (shut) (done))
  (:action enter :precondition (open) :effect (inside))
  (:action close :precondition (open) :effect (and (shut) (not (open))))
  (:action finish :precondition (and (inside) (shut)) :effect (done)))";
const DOOR_PROBLEM: &str = "(define (problem p) (:domain door) (:init (open)) (:goal (done)))";

#[test]
fn a_disturbance_that_leaves_no_plan_is_counted_as_a_dead_end() {
    let p = problem_of(DOOR_DOMAIN, DOOR_PROBLEM);
    let (g, c) = (Arc::new(Grounding::new(&p).unwrap()), PddlCatalog::new(&p));
    let plan = planner::plan(g.clone(), Arc::new(c.clone()), Options::default()).unwrap();
    let settings = Settings { episodes: 40, rate: 1.0, ..Settings::default() };
    let d = coverage::disturbed(&plan.nodes, &plan.values, &c, &g, plan.goal_ticks.unwrap(), &settings).unwrap();
    assert!(d.dead_ends > 0, "{d}");
    // Every failure here is an agent shutting the door on the robot.
    assert_eq!(d.reached + d.dead_ends, d.episodes, "{d}");
    assert_eq!(d.recoverable(), d.reached);
    assert!(d.to_string().ends_with(&format!("({} dead end{})", d.dead_ends, if d.dead_ends == 1 { "" } else { "s" })));
}

#[test]
fn a_disturbed_state_is_led_back_to_the_rules_it_left() {
    // Where a disturbance leaves the plain regression tree without a rule, a short
    // search on the unmet conditions of its rules leads back to one of them, usually
    // long before the goal (a new plan to the goal would add a rule per step).
    let (g, _) = grounding("openstacks-sat08-adl/domain.pddl", "openstacks-sat08-adl/p01.pddl");
    let policy = plain_policy(&g);
    let own = policy.actions();
    let (mut uncovered, mut midway, mut beyond_two) = (0, 0, 0);
    for (t, covered) in one_disturbance_away(&g, &policy) {
        if covered {
            continue;
        }
        uncovered += 1;
        let (path, rule) = policy.rejoin(&g, &t, &own, None).expect("no way back to the rules");
        let trace = Trace::from_state(&g, &t, &path).expect("the path is not applicable");
        let end = trace.state(path.len()).unwrap();
        assert!(rule.when.iter().all(|l| l.holds(end)), "the rule does not hold where the path ends");
        if rule.distance > 0 {
            assert_eq!(policy.first(end), Some(&rule), "not the first rule that holds there");
            midway += 1;
            beyond_two += usize::from(path.len() > 2);
        }
    }
    eprintln!("{uncovered} uncovered, {midway} led back to a rule, {beyond_two} of them more than two steps away");
    assert!(uncovered > 0, "the plain tree covers every state: the test shows nothing");
    assert!(midway > 0 && beyond_two > 0);
}

/// The fixtures whose tree Algorithm 1 or guided backchaining makes.
const BACKCHAINED: [(&str, &str); 7] = [
    ("blocks/domain.pddl", "blocks/probBLOCKS-4-0.pddl"),
    ("gripper/domain.pddl", "gripper/prob01.pddl"),
    ("miconic/domain.pddl", "miconic/s1-0.pddl"),
    ("satellite/domain.pddl", "satellite/p01-pfile1.pddl"),
    ("scanalyzer-08-strips/domain.pddl", "scanalyzer-08-strips/p22.pddl"),
    ("storage/domain.pddl", "storage/p01.pddl"),
    ("transport-sat08-strips/domain.pddl", "transport-sat08-strips/p01.pddl"),
];

#[test]
fn a_closed_backchained_tree_reaches_the_goal_wherever_one_disturbance_leads() {
    // `--close-backchained` looks at the states one of the tree's actions leads to from
    // its path; from each, the tree it returns (not only the one it looked with) must
    // reach the goal wherever a plan exists.
    let mut looked = 0;
    for (domain, problem) in BACKCHAINED {
        let (g, c) = grounding(domain, problem);
        let p = planner::plan(g.clone(), c.clone(), Options { close_backchained: true, ..Options::default() }).unwrap();
        if p.method == planner::Made::Regression {
            continue;
        }
        let mut actions = Vec::new();
        let mut buf = Vec::new();
        for n in &p.nodes {
            if let bt_core::NodeKind::Action(leaf) = n.kind() {
                g.leaf_actions_of(leaf, leaf.args_in(&p.values), &mut buf);
                actions.extend_from_slice(&buf);
            }
        }
        let path = Trace::new(&g, &p.executed).unwrap();
        let mut states = Vec::new();
        for i in 0..=p.executed.len() {
            for &a in &actions {
                let x = g.action(a).unwrap();
                let s = path.state(i).unwrap();
                if !x.applicable(s) {
                    continue;
                }
                let mut t = s.clone();
                x.apply(&mut t);
                let mut world = StripsWorld::new(g.clone());
                world.set_state(t.clone());
                let verdict = strips::run_to_goal(
                    (&p.nodes, &p.values),
                    c.as_ref(),
                    &mut world,
                    coverage::episode_ticks(p.goal_ticks.unwrap()),
                    strips::Ends::DETERMINISTIC,
                    (),
                    &mut states,
                )
                .unwrap();
                looked += 1;
                if !verdict.reached() {
                    assert!(
                        search::gbfs_from(&g, &t, &SearchOptions::default()).is_err(),
                        "{problem}: the tree fails after {} out of turn at step {i}",
                        g.action_name(a)
                    );
                }
            }
        }
    }
    assert!(looked > 50, "too few states looked at: {looked}");
}

#[test]
fn a_backchained_tree_whose_closure_runs_out_of_budget_is_kept_as_it_was() {
    let (g, c) = grounding("transport-sat08-strips/domain.pddl", "transport-sat08-strips/p01.pddl");
    let plain = planner::plan(g.clone(), c.clone(), Options { close_nodes: 0, ..Options::default() }).unwrap();
    // Room for the tree and a few rules, not for the rules of every disturbed state.
    let options = Options { close_nodes: plain.nodes.len() + 20, ..Options::default() };
    let p = planner::plan(g.clone(), c.clone(), options).unwrap();
    let report = p.closed.unwrap();
    assert!(!report.complete && report.kept, "{report}");
    assert!(report.to_string().ends_with("budget reached: the tree is kept as it was"), "{report}");
    assert_eq!(p.nodes, plain.nodes);
    // With room enough, the rules go in front.
    let roomy = planner::plan(g.clone(), c.clone(), Options::default()).unwrap();
    assert!(roomy.closed.unwrap().complete && roomy.nodes.len() > plain.nodes.len());
}

/// A line of three places and a stamp that, once used, is used for good.
const STAMP_DOMAIN: &str = "(define (domain stamp) (:requirements :strips)
  (:predicates (at0) (at1) (at2) (blank) (stamped) (done))
  (:action go01 :precondition (at0) :effect (and (at1) (not (at0))))
  (:action go12 :precondition (at1) :effect (and (at2) (not (at1))))
  (:action stamp :precondition (blank) :effect (and (stamped) (not (blank))))
  (:action finish :precondition (and (at2) (stamped)) :effect (done)))";
const STAMP_PROBLEM: &str = "(define (problem p) (:domain stamp) (:init (at0) (blank)) (:goal (done)))";

#[test]
fn a_plan_resumes_without_the_step_a_disturbance_did_out_of_turn() {
    let g = Grounding::new(&problem_of(STAMP_DOMAIN, STAMP_PROBLEM)).unwrap();
    let id = |name: &str| (0..g.actions().len() as u32).find(|&a| g.action_name(a) == name).unwrap();
    let plan = [id("go01"), id("go12"), id("stamp"), id("finish")];
    let policy = Policy::of_trace(&g, &Trace::new(&g, &plan).unwrap());
    // The agent stamps at the start: every rule but the last needs a blank stamp.
    let mut t = g.init().clone();
    g.action(id("stamp")).unwrap().apply(&mut t);
    assert_eq!(policy.first(&t), None);
    // The plan's rest without the stamp, up to where the rule that finishes holds.
    // The tree was 4 steps from the goal before the agent stamped.
    let (resumed, rule) = policy.resume(&g, &t, 4, &policy.actions()).expect("the plan's rest reaches the goal");
    let names: Vec<String> = resumed.iter().map(|&a| g.action_name(a)).collect();
    assert_eq!(names, ["go01", "go12"]);
    assert_eq!((g.action_name(rule.action), rule.distance), ("finish".to_string(), 1));
    // Stamped a step later, the same rule is one step away.
    let mut u = g.init().clone();
    for a in [id("go01"), id("stamp")] {
        g.action(a).unwrap().apply(&mut u);
    }
    assert_eq!(policy.first(&u), None);
    let (resumed, rule) = policy.resume(&g, &u, 3, &policy.actions()).unwrap();
    assert_eq!(resumed.iter().map(|&a| g.action_name(a)).collect::<Vec<_>>(), ["go12"]);
    assert_eq!(rule.distance, 1);
    // Nowhere (no place, no stamp), no rest of the plan reaches the goal.
    let mut w = g.init().clone();
    w.clear();
    assert_eq!(policy.resume(&g, &w, 4, &policy.actions()), None);
}

/// Orders that each take a stack: the one the world starts with, or one opened.
const STACKS_DOMAIN: &str = "(define (domain stacks) (:requirements :strips)
  (:predicates (stack) (no-stack) (waiting-a) (waiting-b) (started-a) (started-b) (done))
  (:action open :precondition (no-stack) :effect (and (stack) (not (no-stack))))
  (:action start-a :precondition (and (stack) (waiting-a))
    :effect (and (started-a) (no-stack) (not (stack)) (not (waiting-a))))
  (:action start-b :precondition (and (stack) (waiting-b))
    :effect (and (started-b) (no-stack) (not (stack)) (not (waiting-b))))
  (:action finish :precondition (and (started-a) (started-b)) :effect (done)))";
const STACKS_PROBLEM: &str =
    "(define (problem p) (:domain stacks) (:init (stack) (waiting-a) (waiting-b)) (:goal (done)))";

#[test]
fn a_plan_resumes_with_the_step_that_makes_its_next_one_possible_again() {
    // An agent starts order b out of turn on the stack the plan meant for a: the
    // plan's next step cannot be done, but is one of the tree's actions away (a stack
    // opened), and b's own turn is then left out.
    let g = Grounding::new(&problem_of(STACKS_DOMAIN, STACKS_PROBLEM)).unwrap();
    let id = |name: &str| (0..g.actions().len() as u32).find(|&a| g.action_name(a) == name).unwrap();
    let plan = [id("start-a"), id("open"), id("start-b"), id("finish")];
    let policy = Policy::of_trace(&g, &Trace::new(&g, &plan).unwrap());
    let mut t = g.init().clone();
    g.action(id("start-b")).unwrap().apply(&mut t);
    assert_eq!(policy.first(&t), None);
    let (resumed, rule) = policy.resume(&g, &t, 4, &policy.actions()).expect("the plan's rest reaches the goal");
    let names: Vec<String> = resumed.iter().map(|&a| g.action_name(a)).collect();
    assert_eq!(names, ["open", "start-a"]);
    assert_eq!((g.action_name(rule.action), rule.distance), ("finish".to_string(), 1));
    // The closed tree reaches the goal from there by that way.
    let mut closed = policy.clone();
    regress::close(&g, &mut closed, &Budget::default()).unwrap();
    let path = closed.path(&g, &t);
    assert!(g.goal_holds(path.last().unwrap()), "{} states", path.len());
    assert_eq!(path.len(), 4);
}

#[test]
fn one_undo_rule_puts_back_what_an_agent_did_out_of_turn_wherever_it_did_it() {
    // Gripper: an agent that picks up a ball the robot will carry later, or drops one
    // it carries, leaves a state off the plan; the action that undoes it, as a rule
    // after all the others, serves every state on the path it can happen in.
    let (g, _) = grounding("gripper/domain.pddl", "gripper/prob01.pddl");
    let mut policy = plain_policy(&g);
    let closed = regress::close(&g, &mut policy, &Budget::default()).unwrap();
    assert!(closed.complete, "{closed}");
    let undo = policy.undo_rules();
    assert!(!undo.is_empty(), "{closed}");
    assert_eq!(closed.undo, undo.len());
    let mut served = 0;
    for (t, covered) in one_disturbance_away(&g, &policy) {
        assert!(covered, "{closed}");
        let path = policy.path(&g, &t);
        assert!(g.goal_holds(path.last().unwrap()), "a path stopped short of the goal");
        if policy.first(&t).is_none() && !g.goal_holds(&t) {
            let r = policy.next(&t).unwrap();
            assert!(undo.contains(r));
            served += 1;
        }
    }
    assert!(served > undo.len(), "{served} states served by {} undo rules", undo.len());
}

/// Lamps: l1 goes on while l2 is still off, then l2; switching a lamp off needs
/// nothing (so `off` does not make one of its own conditions false, and as an undo rule
/// it could act where it changes nothing).
const LAMP_DOMAIN: &str = "(define (domain lamps) (:requirements :negative-preconditions)
  (:predicates (lit ?l))
  (:constants l1 l2)
  (:action first :precondition (and (not (lit l1)) (not (lit l2))) :effect (lit l1))
  (:action second :precondition (not (lit l2)) :effect (lit l2))
  (:action off :parameters (?l) :effect (not (lit ?l))))";
const LAMP_PROBLEM: &str = "(define (problem two) (:domain lamps)
  (:init) (:goal (and (lit l1) (lit l2))))";

#[test]
fn undo_rules_never_take_turns() {
    // Lamps: the agent switching l2 on first is undone by switching it off, which
    // needs nothing: no undo rule, a way back instead.
    let g = Grounding::new(&problem_of(LAMP_DOMAIN, LAMP_PROBLEM)).unwrap();
    let mut policy = plain_policy(&g);
    let closed = regress::close(&g, &mut policy, &Budget::default()).unwrap();
    assert!(closed.complete && closed.plans > 0, "{closed}");
    assert!(policy.undo_rules().is_empty(), "{closed}");
    // Each undo rule's action makes one of its own conditions false, and no rules
    // form a cycle, each making true a condition of the next that the next makes false
    // (here, without that check, blocks would get rules that stack and unstack one
    // block, transport and assembly similar pairs): from any state they act a bounded
    // number of times before a rule of a plan holds.
    for (d, p) in [
        ("blocks/domain.pddl", "blocks/probBLOCKS-4-0.pddl"),
        ("transport-sat08-strips/domain.pddl", "transport-sat08-strips/p01.pddl"),
        ("assembly/domain.pddl", "assembly/prob01.pddl"),
    ] {
        let (g, _) = grounding(d, p);
        let mut policy = plain_policy(&g);
        let closed = regress::close(&g, &mut policy, &Budget::default()).unwrap();
        let undo = policy.undo_rules();
        assert!(!undo.is_empty(), "{d}: {closed}");
        for r in undo {
            let x = g.action(r.action).unwrap();
            let falsified = |l: &Lit| if l.positive { x.del.contains(&l.atom) } else { x.add.contains(&l.atom) };
            assert!(r.when.iter().any(falsified), "{d}: {} can act twice", g.action_name(r.action));
        }
        // `enables[k]`: the rules j whose condition, made false by j, rule k makes true.
        let enables: Vec<Vec<usize>> = undo
            .iter()
            .map(|k| {
                let xk = g.action(k.action).unwrap();
                (0..undo.len())
                    .filter(|&j| {
                        let xj = g.action(undo[j].action).unwrap();
                        undo[j].when.iter().any(|l| {
                            if l.positive {
                                xj.del.contains(&l.atom) && xk.add.contains(&l.atom)
                            } else {
                                xj.add.contains(&l.atom) && xk.del.contains(&l.atom)
                            }
                        })
                    })
                    .collect()
            })
            .collect();
        // No cycle: repeatedly take out the rules no remaining rule enables.
        let mut left: Vec<usize> = (0..undo.len()).collect();
        while let Some(free) = left.iter().position(|&j| !left.iter().any(|&k| enables[k].contains(&j))) {
            left.remove(free);
        }
        let names: Vec<String> = left.iter().map(|&k| g.action_name(undo[k].action)).collect();
        assert!(left.is_empty(), "{d}: undo rules that can take turns: {names:?}");
    }
}

/// Inspections: a visit to a site on a day inspects every vehicle parked there that
/// day, and uses the day up. Vehicle `v1` is at `north` on day 1 and `south` on day 2,
/// `v2` at `north` on day 1 and `east` on day 3: one visit (day 1, north) does both.
const INSPECT_DOMAIN: &str = "
(define (domain inspect)
  (:requirements :adl :typing :conditional-effects)
  (:types vehicle day site)
  (:predicates (inspected ?v - vehicle) (free ?d - day) (parked ?v - vehicle ?d - day ?s - site))
  (:action visit
    :parameters (?d - day ?s - site)
    :precondition (free ?d)
    :effect (and (not (free ?d))
                 (forall (?v - vehicle) (when (parked ?v ?d ?s) (inspected ?v))))))";

const INSPECT_PROBLEM: &str = "
(define (problem two)
  (:domain inspect)
  (:objects v1 v2 - vehicle d1 d2 d3 - day north south east - site)
  (:init (free d1) (free d2) (free d3)
         (parked v1 d1 north) (parked v2 d1 north) (parked v1 d2 south) (parked v2 d3 east))
  (:goal (and (inspected v1) (inspected v2))))";

#[test]
fn a_guided_tree_redoes_the_step_behind_a_condition_it_only_checked() {
    let p = problem_of(INSPECT_DOMAIN, INSPECT_PROBLEM);
    let (g, c) = (Arc::new(Grounding::new(&p).unwrap()), Arc::new(PddlCatalog::new(&p)));
    // Not closed over disturbances (no nodes for it): the checks alone do this.
    let options = Options { method: planner::Method::Search, close_nodes: 0, ..Options::default() };
    let plan = planner::plan(g.clone(), c.clone(), options).unwrap();
    assert_eq!(plan.method, planner::Made::SearchGuided);
    assert!(plan.closed.is_none());
    // Undisturbed: the one visit.
    let names: Vec<String> = plan.executed.iter().map(|&a| g.action_name(a)).collect();
    assert_eq!(names, ["visit(d1, north)"]);
    // Backchaining expanded one goal condition with that visit and only checks the
    // other, which the visit made true on the way: the check got the visit too.
    assert_eq!(plan.covered, 1, "{}", bt_formats::ascii::to_ascii_with(&plan.nodes, &plan.values, c.as_ref()).unwrap());
    // An agent inspects either vehicle on its other day: the planned visit is still
    // needed for the other one, and the tree makes it whichever vehicle it expanded.
    let mut states = Vec::new();
    for other in ["visit(d2, south)", "visit(d3, east)"] {
        let a = (0..g.actions().len() as u32).find(|&a| g.action_name(a) == other).unwrap();
        let mut s = g.init().clone();
        g.action(a).unwrap().apply(&mut s);
        let mut world = StripsWorld::new(g.clone());
        world.set_state(s);
        let verdict = strips::run_to_goal(
            (&plan.nodes, &plan.values),
            c.as_ref(),
            &mut world,
            100,
            strips::Ends::DETERMINISTIC,
            (),
            &mut states,
        )
        .unwrap();
        assert!(verdict.reached(), "after {other}: {verdict:?}");
        let done: Vec<String> = world.executed().iter().map(|&a| g.action_name(a)).collect();
        assert_eq!(done, ["visit(d1, north)"], "after {other}");
    }
}

#[test]
fn a_way_back_too_long_for_its_share_of_the_budget_is_left_out() {
    // Room for three plain trees: the rules of a few long ways back would fill it
    // before the closure has looked at every state; left out, the budget serves the
    // states with short ways back, and the closure looks at every state.
    let (g, _) = grounding("gripper/domain.pddl", "gripper/prob01.pddl");
    let mut policy = plain_policy(&g);
    let size = policy.nodes(&g);
    let budget = Budget { nodes: 3 * size, ..Budget::default() };
    let closed = regress::close(&g, &mut policy, &budget).unwrap();
    assert!(closed.too_long > 0, "{closed}");
    assert!(closed.complete, "{closed}");
    assert!(closed.to_string().contains("whose way back was too long to add"), "{closed}");
    assert!(policy.nodes(&g) < budget.nodes, "{closed}: {} nodes", policy.nodes(&g));
}
