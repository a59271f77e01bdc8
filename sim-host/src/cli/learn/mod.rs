//! `sim-host learn`: GP runs of Styrud et al. over brick tasks or a PDDL problem x variants x
//! seeds, each written to its own folder; or the commands that make them one by one.

mod args;
mod folders;
mod progress;

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context as _;
use gp::Evaluation;
use rayon::prelude::*;
use sim_host::learn::{self, RunOutcome, RunSpec};
use sim_host::text::count;

use super::output::{self, out};

pub use args::Args;
use progress::Progress;

pub const LONG_ABOUT: &str = "Learns behavior trees with the genetic programming of Styrud et al. \
(Styrud et al.): population 16, Table I's operators and selection, one episode per new tree \
(episodes counted as unique simulations), and the planner's tree as baseline in the variants \
that use it.\n\n\
What is learned: the four brick tasks of Styrud et al. (--task; fitness of Eq. (1)/(2) in the \
symbolic or physics world), or any PDDL problem the planner reads (--domain D.pddl --problem \
P.pddl), in the symbolic STRIPS world: the leaves are the problem's grounded conditions and \
actions, and the fitness is\n  \
F = -(100 per goal literal not holding at the end + 0.1 per node + 0.1 per tick\n        \
+ 50 if the root failed + 10 at the tick limit).\n\
With --disturb RATE, before a tick and with that chance (at most 3 times an episode), an \
external agent undoes the robot's last action or does one of the tree's actions (as in bench-pddl), and \
a tree's fitness is its mean over --disturb-episodes seeded episodes (the same ones for every \
tree), so that the learned tree is reactive rather than a lucky plan.\n\n\
--max-bytes N and --max-nodes N bound the learned tree as a controller holds it (its image \
without the names section; for PDDL, in the leaf contract `learn` writes): random trees and \
offspring over the bound are refused before they are simulated, so no tree of the run, the \
best included, is ever over it. A PDDL baseline's closure over disturbances is cut to fit, as \
plan --max-bytes does; a baseline over the bound even so is an error (--variant none learns \
without it). Default: no bound.\n\n\
Variants: none (no baseline), baseline (inserted and kept), boost-crossover and boost-all \
(its fitness raised to the population's best while crossover, or crossover and mutation, \
parents are chosen), nokeep (inserted in the first population only).\n\n\
--islands K evolves K populations at once on all cores, each with the whole generation \
budget: every --migration-interval generations each sends its best to the next, an island \
whose best has not improved for --stagnation generations starts again, and --stop-at F ends \
the run once the best reaches F. The result depends on the seed only, not on the threads.\n\n\
Each run writes OUT/<task>-<variant>-<world>-seed<N>/ with run.txt (everything needed to repeat \
it), curve.csv (generation,episodes,best_fitness,best_length), and the best tree as best.bt \
(image), best.txt, best.tokens and best.xml; a PDDL run also keeps domain.pddl and \
problem.pddl. The same run gives the same folder, byte for byte, on any machine.\n\n\
Spreading runs: --list prints one self-contained command per run (pipe it to GNU parallel); \
--index I makes only the I-th (a Slurm job array). Any number of processes may write into one \
OUT; the same run is never made twice at once (a lock per run), and a run interrupted midway \
leaves only a hidden .<run>-XXXXXX folder that plot ignores and the next learn of that run \
removes.\n\n\
Default generations (the reference's): symbolic tower 200, croissant 1000, balance 300, \
blocking 1000; physics tower 200, croissant 1000, balance 800, blocking 300; PDDL 200. At most \
100000 generations and 10000 runs per command.";

pub fn run(args: &Args) -> anyhow::Result<()> {
    let specs = args::grid(args)?;
    if args.list {
        let mut list = String::new();
        for spec in &specs {
            list.push_str(&args::command(args, spec));
            list.push('\n');
        }
        output::stdout(list.as_bytes())?;
        return Ok(());
    }
    let specs: Vec<RunSpec> = match args.index {
        None => specs,
        Some(i) => match specs.get(i) {
            Some(s) => vec![s.clone()],
            None => anyhow::bail!(
                "--index {i}: the grid has {}, numbered 0 to {}",
                count(specs.len(), "run"),
                specs.len().saturating_sub(1)
            ),
        },
    };
    std::fs::create_dir_all(&args.out).with_context(|| format!("cannot create {}", args.out.display()))?;
    // Refuse before any work: an existing run folder is someone's result.
    if !args.force
        && let Some(s) = specs.iter().find(|s| args.out.join(s.folder()).exists())
    {
        anyhow::bail!("{} exists; pass --force to replace it", args.out.join(s.folder()).display());
    }
    // Several runs: one per worker, each sequential inside (cheapest for µs episodes).
    // One run: its episodes (or islands) in parallel.
    let evaluation = if specs.len() > 1 { Evaluation::Sequential } else { Evaluation::Parallel };
    let progress = Progress::new(&specs);
    let start = Instant::now();
    let results: Vec<anyhow::Result<(RunOutcome, PathBuf)>> = specs
        .par_iter()
        .map(|spec| {
            let name = spec.folder();
            let claim = folders::claim(&args.out, &name)?;
            if !args.force && args.out.join(&name).exists() {
                anyhow::bail!("{} exists; pass --force to replace it", args.out.join(&name).display());
            }
            let removed = folders::remove_temporaries(&args.out, &name, &claim)?;
            if removed > 0 {
                progress.note(&format!("{name}: removed {} of an interrupted run", count(removed, "temporary folder")));
            }
            let bar = progress.start(spec);
            let outcome = learn::learn(spec, evaluation, |row| bar.row(row))?;
            let folder = folders::write_folder(&args.out, &outcome, args.force, &claim)?;
            drop(claim);
            progress.done(&bar, &outcome);
            Ok((outcome, folder))
        })
        .collect();
    progress.finish();
    let mut episodes = 0u64;
    let mut outcomes = Vec::new();
    let mut first_error = None;
    for r in results {
        match r {
            Ok((o, folder)) => {
                episodes += o.episodes;
                outcomes.push((o, folder));
            }
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    let secs = start.elapsed().as_secs_f64();
    let mut table = String::new();
    if !outcomes.is_empty() {
        table = format!(
            "{:<12} {:<24} {:<9} {:>5} {:>9} {:>12} {:>9} {:>8}  folder\n",
            "task", "variant", "world", "seed", "episodes", "best", "planner", "seconds"
        );
    }
    for (o, folder) in &outcomes {
        table.push_str(&format!(
            "{:<12} {:<24} {:<9} {:>5} {:>9} {:>12.3} {:>9.3} {:>8.2}  {}\n",
            o.spec.subject.label(),
            o.spec.variant_label(),
            o.spec.subject.world_name(),
            o.spec.seed,
            o.episodes,
            o.best.fitness,
            o.planner_fitness,
            o.seconds,
            folder.display()
        ));
    }
    output::stdout(table.as_bytes())?;
    if let Some(e) = first_error {
        return Err(e);
    }
    out!(
        "{}, {} in {secs:.2} s: {:.0} episodes/s on {}\nplot them: sim-host plot {}\n",
        count(outcomes.len(), "run"),
        count(episodes, "episode"),
        episodes as f64 / secs.max(1e-9),
        count(rayon::current_num_threads(), "thread"),
        args.out.display()
    )?;
    Ok(())
}
