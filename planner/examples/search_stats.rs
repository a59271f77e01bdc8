//! What heuristic search does on one PDDL problem: states expanded and evaluated, the
//! plan's length and the time per evaluation, to compare with Fast Downward's
//! "Expanded"/"Evaluated" lines.
//!
//! `cargo run --release -p planner --example search_stats -- DOMAIN PROBLEM [eager|deferred|landmarks|lama-first] [SECONDS]`
//!
//! `landmarks` prefers the landmark count's helpful actions too, `lama-first` only
//! h_FF's (as Fast Downward's lama-first; the planner's third search).
//! With `landmarks` or `lama-first` it also prints how many landmarks, disjunctive landmarks and
//! orderings were found (Fast Downward prints the same with `lm_rhw(verbosity=debug)`),
//! and with `LANDMARKS=1` in the environment each landmark and those ordered before it.

use std::time::{Duration, Instant};

use planner::ground::Grounding;
use planner::pddl::{parse_domain, parse_problem};
use planner::search::landmarks::Landmarks;
use planner::search::{SearchOptions, gbfs};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [domain, problem, rest @ ..] = args.as_slice() else {
        return Err("usage: search_stats DOMAIN PROBLEM [eager|deferred|landmarks|lama-first] [SECONDS]".into());
    };
    let mode = rest.first().map_or("landmarks", String::as_str);
    let seconds: f64 = rest.get(1).map_or(Ok(30.0), |s| s.parse())?;
    let d = parse_domain(domain, &std::fs::read_to_string(domain)?)?;
    let p = parse_problem(problem, &std::fs::read_to_string(problem)?, &d)?;
    let g = Grounding::new(&p)?;
    let options = SearchOptions {
        deadline: Some(Instant::now() + Duration::from_secs_f64(seconds)),
        lazy: mode != "eager",
        landmarks: mode == "landmarks" || mode == "lama-first",
        landmark_preferred: mode != "lama-first",
        ..SearchOptions::default()
    };
    let fluents = (0..g.atom_count()).filter(|&a| u32::try_from(a).is_ok_and(|a| !g.is_static(a))).count();
    let conditional: usize = g.actions().iter().map(|a| a.cond.len()).sum();
    println!(
        "ground actions {} ({} conditional effects), atoms {} ({} fluents), relaxation size {} ({} relevant to the goal)",
        g.actions().len(),
        conditional,
        g.atom_count(),
        fluents,
        planner::search::Relaxation::new(&g).size(),
        planner::search::Relaxation::new(&g).relevant_size()
    );
    if options.landmarks
        && let Some(lm) = Landmarks::new(&g, options.deadline)
    {
        println!("{} landmarks, {} disjunctive, {} orderings", lm.len(), lm.disjunctive(), lm.orderings());
        if std::env::var_os("LANDMARKS").is_some() {
            for k in 0..lm.len() {
                let before: Vec<String> = lm.before(k).iter().map(|&p| lm.name(&g, p as usize)).collect();
                println!("  {} <- {}", lm.name(&g, k), before.join(", "));
            }
        }
    }
    let start = Instant::now();
    let found = gbfs(&g, &options);
    let t = start.elapsed().as_secs_f64();
    match found {
        Ok(f) => println!(
            "{mode}: plan {} steps, expanded {}, evaluated {}, stored {}, {:.3} s, {:.1} us per evaluation",
            f.plan.len(),
            f.expanded,
            f.evaluated,
            f.stored,
            t,
            t * 1e6 / f.evaluated.max(1) as f64
        ),
        Err(e) => println!("{mode}: {e} after {t:.3} s"),
    }
    Ok(())
}
