//! How reliably, and how fast, learning gives a solved tree: the island model against
//! single populations, on the brick tasks, seed by seed.
//!
//! ```text
//! cargo bench -p sim-host --bench solve -- [symbolic|physics] [TASK,...] [options]
//!   --seeds A..B          seeds (default 1..20)
//!   --islands K           islands (default 8); --interval N, --stagnation N (0: never)
//!   --plain V,...         also single populations of these variants (none, baseline, ...)
//!   --plain-factor F      single populations get F x the reference generations
//!                         (default: K, about the islands' whole episode budget)
//!   --islands-known MED,WORST
//!                         skip the island runs: their median and worst time to solve
//!                         (seconds) from an earlier run, for the equal-time counts
//!                         of single populations (long physics comparisons)
//! ```
//!
//! Every run stops as soon as it reaches the solved level of its task (tower > -3,
//! croissant > -4, balance > -1, blocking > -2, as in Styrud et al.'s figures). For each run
//! it prints whether it solved the task, the wall time and episodes to the solved level
//! (or to the end of the budget), then per mode: seeds solved, median and worst time to
//! solve, and for single populations how many solved within the reference budget
//! (equal generations), within F x (about equal episodes) and within the islands'
//! median and worst time (equal wall time). Runs go one after another, each using
//! every core (islands in parallel; a single population's episodes in parallel).
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use std::time::Instant;

use gp::islands::{self, IslandParams};
use gp::{Alphabet, Params, Variant};
use planner::duplo::Task;
use sim_host::learn;
use worlds::WorldKind;

/// The solved level of each task: better than this fitness.
fn solved_level(task: Task) -> f64 {
    match task {
        Task::Tower => -3.0,
        Task::Croissant => -4.0,
        Task::Balance => -1.0,
        Task::Blocking => -2.0,
    }
}

#[derive(Clone, Copy)]
struct Outcome {
    solved: bool,
    seconds: f64,
    episodes: u64,
    /// Generation at which it was solved (per island for islands).
    generation: Option<u32>,
}

fn run_one(
    task: Task,
    world: WorldKind,
    variant: Variant,
    seed: u64,
    generations: u32,
    setup: IslandParams,
) -> Outcome {
    let baseline = variant.uses_baseline().then(|| learn::planner_tree(task, false).unwrap());
    let params = Params { generations, ..Params::new(seed, variant, baseline) };
    let alphabet = Alphabet::from_catalog(&task.spec()).unwrap();
    let start = Instant::now();
    let r = match world {
        WorldKind::Symbolic => {
            let f = learn::symbolic(task).unwrap();
            islands::run(alphabet, &f, params, setup, |_| {}).unwrap()
        }
        WorldKind::Physics => {
            let f = learn::physics(task).unwrap();
            islands::run(alphabet, &f, params, setup, |_| {}).unwrap()
        }
    };
    let seconds = start.elapsed().as_secs_f64();
    // Solved: strictly better than the level (the stop is at the next 0.1 step).
    let solved = r.best.fitness > solved_level(task);
    Outcome { solved, seconds, episodes: r.episodes, generation: r.reached.map(|x| x.generation) }
}

fn quantiles(mut xs: Vec<f64>) -> (f64, f64) {
    if xs.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    xs.sort_by(f64::total_cmp);
    let n = xs.len();
    let median = if n % 2 == 1 { xs[n / 2] } else { (xs[n / 2 - 1] + xs[n / 2]) / 2.0 };
    (median, xs[n - 1])
}

/// The island runs of `task`, one per seed, printed; their median and worst time to solve.
fn islands_runs(task: Task, world: WorldKind, seeds: &[u64], budget: u32, setup: IslandParams, k: usize) -> (f64, f64) {
    let mut isl = Vec::new();
    for &seed in seeds {
        let o = run_one(task, world, Variant::Baseline, seed, budget, setup);
        println!(
            "  islands  seed {seed:>3}: {} in {:>7.3} s, {:>8} episodes",
            if o.solved { "solved" } else { "FAILED" },
            o.seconds,
            o.episodes
        );
        isl.push(o);
    }
    let solved: Vec<f64> = isl.iter().filter(|o| o.solved).map(|o| o.seconds).collect();
    let (med, worst) = quantiles(solved.clone());
    let (_, worst_all) = quantiles(isl.iter().map(|o| o.seconds).collect());
    println!(
        "  islands (baseline, {k}): {}/{} solved; time to solve median {med:.3} s, worst {worst:.3} s \
         (worst run {worst_all:.3} s); episodes median {:.0}",
        solved.len(),
        isl.len(),
        quantiles(isl.iter().map(|o| o.episodes as f64).collect()).0
    );
    (med, worst)
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).filter(|a| a != "--bench").collect();
    let mut take = |flag: &str| -> Option<String> {
        let i = args.iter().position(|a| a == flag)?;
        let v = args.get(i + 1).cloned();
        args.drain(i..(i + 2).min(args.len()));
        v
    };
    let seeds: Vec<u64> = take("--seeds")
        .map(|s| {
            let (a, b) = s.split_once("..").expect("--seeds A..B");
            (a.parse().unwrap()..=b.parse().unwrap()).collect()
        })
        .unwrap_or_else(|| (1..=20).collect());
    let defaults = IslandParams::default();
    let k: usize = take("--islands").map_or(defaults.islands, |s| s.parse().unwrap());
    let interval: u32 = take("--interval").map_or(defaults.migration_interval, |s| s.parse().unwrap());
    let stagnation: u32 = take("--stagnation").map_or(defaults.stagnation.unwrap_or(0), |s| s.parse().unwrap());
    let plain: Vec<Variant> =
        take("--plain").map(|s| s.split(',').map(|v| v.parse().unwrap()).collect()).unwrap_or_default();
    let factor: u32 = take("--plain-factor").map_or(k as u32, |s| s.parse().unwrap());
    let known: Option<(f64, f64)> = take("--islands-known").map(|s| {
        let (m, w) = s.split_once(',').expect("--islands-known MED,WORST");
        (m.parse().unwrap(), w.parse().unwrap())
    });
    let world = if args.iter().any(|a| a == "physics") { WorldKind::Physics } else { WorldKind::Symbolic };
    let tasks: Vec<Task> = args
        .iter()
        .filter(|a| !matches!(a.as_str(), "symbolic" | "physics"))
        .flat_map(|a| a.split(',').map(|t| Task::from_name(t).unwrap_or_else(|| panic!("unknown task `{t}`"))))
        .collect();
    let tasks = if tasks.is_empty() { Task::ALL.to_vec() } else { tasks };
    println!(
        "world {}, islands {k}, migration every {interval}, restart after {stagnation}, seeds {}..{}, {} threads",
        world.name(),
        seeds[0],
        seeds[seeds.len() - 1],
        rayon::current_num_threads()
    );
    for task in tasks {
        let budget = learn::default_generations(task, world);
        let level = solved_level(task);
        let setup = IslandParams {
            islands: k,
            migration_interval: interval,
            stagnation: (stagnation > 0).then_some(stagnation),
            stop_at: Some(level + 1e-9),
        };
        println!("\n{} ({} generations per island, solved above {level})", task.name(), budget);
        let (med, worst) = match known {
            Some(times) => {
                println!(
                    "  islands: not run; median and worst time to solve {:.3} s, {:.3} s as given",
                    times.0, times.1
                );
                times
            }
            None => islands_runs(task, world, &seeds, budget, setup, k),
        };
        for &variant in &plain {
            let single = IslandParams { islands: 1, migration_interval: 50, stagnation: None, stop_at: setup.stop_at };
            let mut outs = Vec::new();
            for &seed in &seeds {
                let o = run_one(task, world, variant, seed, budget * factor, single);
                println!(
                    "  {:<8} seed {seed:>3}: {} in {:>7.3} s, {:>8} episodes, generation {}",
                    variant.name(),
                    if o.solved { "solved" } else { "failed" },
                    o.seconds,
                    o.episodes,
                    o.generation.map_or("-".into(), |g| g.to_string())
                );
                outs.push(o);
            }
            let within = |gens: u32| outs.iter().filter(|o| o.solved && o.generation.is_some_and(|g| g < gens)).count();
            let in_time = |t: f64| outs.iter().filter(|o| o.solved && o.seconds <= t).count();
            let times: Vec<f64> = outs.iter().filter(|o| o.solved).map(|o| o.seconds).collect();
            let (pm, pw) = quantiles(times.clone());
            println!(
                "  single {}: solved {}/{n} at {budget} generations, {}/{n} at {} ({factor}x, about the islands' \
                 episodes); within the islands' median time {}/{n}, worst time {}/{n}; time to solve median \
                 {pm:.3} s, worst {pw:.3} s",
                variant.name(),
                within(budget),
                times.len(),
                budget * factor,
                in_time(med),
                in_time(worst),
                n = outs.len()
            );
        }
    }
}
