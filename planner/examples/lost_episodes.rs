//! Why a tree loses disturbed episodes: plans one PDDL problem as `bench-pddl` does
//! (its default options; the deadline counts from after grounding), runs the benchmark's seeded disturbed episodes
//! ([`planner::coverage::Settings`]'s defaults: 20, seed 1) and, for each episode that
//! does not reach the goal, prints every act of the agents: where on the plan it came
//! (the step of the undisturbed path, or `off` the path), what it did (`undo`, or the
//! action done out of turn), whether the tree, run undisturbed, reaches the goal from
//! the state before and after it, and how long a plan from the state after it is
//! (greedy best-first search with h_FF, 5 s at most: not the shortest, an upper bound).
//!
//! `cargo run --release -p planner --example lost_episodes -- DOMAIN PROBLEM [SECONDS]`
//!
//! SECONDS is the planning deadline (10, `bench-pddl --timeout`'s default; 0: none, so
//! the tree does not depend on the machine's load).

use std::sync::Arc;
use std::time::{Duration, Instant};

use planner::coverage::{Settings, episode_ticks};
use planner::ground::Grounding;
use planner::guide::Trace;
use planner::pddl::{parse_domain, parse_problem};
use planner::search::{SearchOptions, gbfs_from};
use planner::state::State;
use planner::strips::{self, StripsWorld, disturb::tree_actions};
use planner::{Options, PddlCatalog};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [domain, problem, rest @ ..] = args.as_slice() else {
        return Err("usage: lost_episodes DOMAIN PROBLEM [SECONDS]".into());
    };
    let seconds: f64 = rest.first().map_or(Ok(10.0), |s| s.parse())?;
    let d = parse_domain(domain, &std::fs::read_to_string(domain)?)?;
    let p = parse_problem(problem, &std::fs::read_to_string(problem)?, &d)?;
    let g = Arc::new(Grounding::new(&p)?);
    let c = Arc::new(PddlCatalog::new(&p));
    let deadline = (seconds > 0.0).then(|| Instant::now() + Duration::from_secs_f64(seconds));
    let plan = planner::plan(g.clone(), c.clone(), Options { deadline, ..Options::default() })?;
    println!("{:?} tree, {}", plan.method, plan.fit);
    if let Some(closed) = plan.closed {
        println!("{closed}");
    }
    let trace = Trace::new(&g, &plan.executed).ok_or("the tree's plan does not apply")?;
    let path: Vec<State> = (0..=plan.executed.len()).filter_map(|i| trace.state(i).cloned()).collect();
    let tree = (&plan.nodes[..], &plan.values[..]);
    let ticks = episode_ticks(plan.goal_ticks.unwrap_or(0));
    let ends = strips::Ends { on_loop: false, failures: 2 };
    let mut states = Vec::new();
    let mut reaches = |s: &State| -> Result<bool, planner::PlanError> {
        let mut w = StripsWorld::new(g.clone());
        w.set_state(s.clone());
        Ok(strips::run_to_goal(tree, c.as_ref(), &mut w, ticks, ends, (), &mut states)?.reached())
    };
    let settings = Settings::default();
    let helpers = tree_actions(&plan.nodes, &plan.values, &g);
    let mut reached = 0;
    for e in 0..settings.episodes {
        let mut world = StripsWorld::new(g.clone());
        let mut agents = settings.disturbance().agents(helpers.clone(), e);
        let mut run_states = Vec::new();
        if strips::run_to_goal(tree, c.as_ref(), &mut world, ticks, ends, &mut agents, &mut run_states)?.reached() {
            reached += 1;
            continue;
        }
        println!("episode {e}: lost");
        for (before, after) in agents.changes() {
            let step = path.iter().position(|s| s == before).map_or_else(|| "off".to_string(), |i| i.to_string());
            let done_out_of_turn = helpers.iter().find(|&&a| {
                g.action(a).is_some_and(|x| {
                    let mut s = before.clone();
                    x.applicable(before) && {
                        g.apply(x, &mut s);
                        &s == after
                    }
                })
            });
            let act = done_out_of_turn.map_or_else(|| "undo".to_string(), |&a| g.action_name(a));
            let search =
                SearchOptions { deadline: Some(Instant::now() + Duration::from_secs(5)), ..Default::default() };
            let plan_from =
                gbfs_from(&g, after, &search).map_or_else(|_| "none found".into(), |f| f.plan.len().to_string());
            println!(
                "  step {step:>4}  {act:40} tree reaches the goal before: {}, after: {}; a plan from after: {plan_from} steps",
                reaches(before)?,
                reaches(after)?
            );
        }
    }
    println!("reached the goal in {reached} of {} disturbed episodes", settings.episodes);
    Ok(())
}
