//! `sim-host learn`: GP runs of seed 003 over tasks x variants x seeds, each written to
//! its own folder.

use std::io::IsTerminal as _;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

use anyhow::{Context as _, bail};
use gp::{Evaluation, Variant};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use planner::duplo::Task;
use rayon::prelude::*;
use sim_host::learn::{self, RunOutcome, RunSpec};
use sim_host::scenario::WorldKind;

use super::output::{self, out};
use super::scenario::World;
use sim_host::text::count;

pub const LONG_ABOUT: &str = "Learns behavior trees for the brick tasks of seed 003 (Styrud et \
al.) with its genetic programming: population 16, Table I's operators and selection, the \
fitness of Eq. (1)/(2) from one episode per new tree (episodes counted as unique \
simulations), and the planner's tree as baseline in the variants that use it.\n\n\
Variants: none (no baseline), baseline (inserted and kept), boost-crossover and boost-all \
(its fitness raised to the population's best while crossover, or crossover and mutation, \
parents are chosen).\n\n\
Each run writes DIR/<task>-<variant>-<world>-seed<N>/ with run.txt (everything needed to \
repeat it), curve.csv (generation,episodes,best_fitness,best_length), and the best tree as \
best.bt (image), best.txt and best.tokens. Runs are independent: spread them over machines \
(one process per task x variant x seed) and merge the folders for `sim-host plot`.\n\n\
Default generations (the reference's): symbolic tower 200, croissant 1000, balance 300, \
blocking 1000; physics tower 200, croissant 1000, balance 800, blocking 300.";

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Tasks: tower, croissant, balance, blocking, a comma list, or `all`.
    #[arg(long = "task", alias = "tasks", value_name = "TASKS", value_parser = parse_tasks)]
    pub tasks: TaskList,
    /// Variants: none, baseline, boost-crossover, boost-all, a comma list, or `all`.
    #[arg(long = "variant", alias = "variants", value_name = "VARIANTS", default_value = "baseline", value_parser = parse_variants)]
    pub variants: VariantList,
    /// Where episodes run.
    #[arg(long, value_enum, default_value_t = World::Symbolic)]
    pub world: World,
    /// Seeds: `1..5` (inclusive), `3`, or `1,4,7`.
    #[arg(long, default_value = "1..5", value_parser = parse_seeds)]
    pub seeds: SeedList,
    /// Generations per run (default: the reference's for the task and world).
    #[arg(long)]
    pub generations: Option<u32>,
    /// The folder the run folders go into (created if missing).
    #[arg(long)]
    pub out: PathBuf,
    /// Replace run folders that already exist.
    #[arg(long)]
    pub force: bool,
}

#[derive(Clone, Debug)]
pub struct TaskList(pub Vec<Task>);
#[derive(Clone, Debug)]
pub struct VariantList(pub Vec<Variant>);
#[derive(Clone, Debug)]
pub struct SeedList(pub Vec<u64>);

fn parse_tasks(s: &str) -> Result<TaskList, String> {
    if s == "all" {
        return Ok(TaskList(Task::ALL.to_vec()));
    }
    s.split(',')
        .map(|t| {
            Task::from_name(t.trim())
                .ok_or_else(|| format!("unknown task `{t}` (tower, croissant, balance, blocking, all)"))
        })
        .collect::<Result<_, _>>()
        .map(TaskList)
}

fn parse_variants(s: &str) -> Result<VariantList, String> {
    if s == "all" {
        return Ok(VariantList(Variant::ALL.to_vec()));
    }
    s.split(',')
        .map(|v| v.trim().parse::<Variant>().map_err(|e| e.to_string()))
        .collect::<Result<_, _>>()
        .map(VariantList)
}

fn parse_seeds(s: &str) -> Result<SeedList, String> {
    let num = |t: &str| t.trim().parse::<u64>().map_err(|_| format!("`{t}` is not a seed (a whole number)"));
    let seeds: Vec<u64> = if let Some((a, b)) = s.split_once("..") {
        let (a, b) = (num(a)?, num(b.trim_start_matches('='))?);
        if a > b {
            return Err(format!("empty seed range `{s}`: the first seed is larger than the last"));
        }
        if b - a >= 10_000 {
            return Err(format!("seed range `{s}` has more than 10000 seeds"));
        }
        (a..=b).collect()
    } else {
        s.split(',').map(num).collect::<Result<_, _>>()?
    };
    Ok(SeedList(seeds))
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let world = WorldKind::from(args.world);
    if args.generations == Some(0) {
        bail!("--generations must be at least 1");
    }
    let mut specs = Vec::new();
    for &task in &args.tasks.0 {
        for &variant in &args.variants.0 {
            for &seed in &args.seeds.0 {
                let generations = args.generations.unwrap_or_else(|| learn::default_generations(task, world));
                specs.push(RunSpec { task, variant, world, seed, generations });
            }
        }
    }
    std::fs::create_dir_all(&args.out).with_context(|| format!("cannot create {}", args.out.display()))?;
    // Refuse before any work: an existing run folder is someone's result.
    if !args.force
        && let Some(s) = specs.iter().find(|s| args.out.join(s.folder()).exists())
    {
        bail!("{} exists; pass --force to replace it", args.out.join(s.folder()).display());
    }
    // Several runs: one per worker, each sequential inside (cheapest for µs episodes).
    // One run: its episodes in parallel.
    let evaluation = if specs.len() > 1 { Evaluation::Sequential } else { Evaluation::Parallel };
    let progress = Progress::new(&specs);
    let start = Instant::now();
    let results: Vec<anyhow::Result<(RunOutcome, PathBuf)>> = specs
        .par_iter()
        .map(|&spec| {
            let bar = progress.start(&spec);
            let outcome = learn::learn(spec, evaluation, |row| bar.row(row))?;
            let folder = write_folder(&args.out, &outcome, args.force)?;
            progress.done(&bar, &outcome);
            Ok((outcome, folder))
        })
        .collect();
    progress.finish();
    let mut episodes = 0u64;
    let mut outcomes = Vec::new();
    for r in results {
        let (o, folder) = r?;
        episodes += o.result.episodes;
        outcomes.push((o, folder));
    }
    let secs = start.elapsed().as_secs_f64();
    let mut table = format!(
        "{:<10} {:<16} {:<9} {:>5} {:>9} {:>12} {:>9}  folder\n",
        "task", "variant", "world", "seed", "episodes", "best", "planner"
    );
    for (o, folder) in &outcomes {
        table.push_str(&format!(
            "{:<10} {:<16} {:<9} {:>5} {:>9} {:>12.3} {:>9.3}  {}\n",
            o.spec.task.name(),
            o.spec.variant.name(),
            o.spec.world.name(),
            o.spec.seed,
            o.result.episodes,
            o.result.best.fitness,
            o.planner_fitness,
            folder.display()
        ));
    }
    output::stdout(table.as_bytes())?;
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

/// Writes a run's folder whole: into a temporary folder beside it, then renamed.
fn write_folder(out: &Path, run: &RunOutcome, force: bool) -> anyhow::Result<PathBuf> {
    let folder = out.join(run.spec.folder());
    let tmp = tempfile::Builder::new()
        .prefix(&format!(".{}-", run.spec.folder()))
        .tempdir_in(out)
        .with_context(|| format!("cannot write into {}", out.display()))?;
    for (name, bytes) in learn::folder_files(run)? {
        output::write_whole(&tmp.path().join(name), &bytes)?;
    }
    if force && folder.exists() {
        std::fs::remove_dir_all(&folder).with_context(|| format!("cannot replace {}", folder.display()))?;
    }
    let tmp = tmp.keep();
    std::fs::rename(&tmp, &folder).with_context(|| format!("cannot write {}", folder.display()))?;
    Ok(folder)
}

/// Progress: a bar per running run and one for the whole, on a terminal; otherwise a
/// line per finished run.
struct Progress {
    multi: Option<MultiProgress>,
    total: Option<ProgressBar>,
    lock: Mutex<()>,
}

struct RunBar {
    bar: Option<ProgressBar>,
}

impl RunBar {
    fn row(&self, row: &gp::GenerationLog) {
        if let Some(b) = &self.bar {
            b.set_position(u64::from(row.generation) + 1);
            b.set_message(format!("{}, best {:.3}", count(row.episodes, "episode"), row.best_fitness));
        }
    }
}

impl Progress {
    fn new(specs: &[RunSpec]) -> Self {
        if !std::io::stderr().is_terminal() {
            return Self { multi: None, total: None, lock: Mutex::new(()) };
        }
        let multi = MultiProgress::with_draw_target(ProgressDrawTarget::stderr());
        let total = multi.add(ProgressBar::new(specs.len() as u64));
        total.set_style(
            ProgressStyle::with_template("runs {pos}/{len} {wide_bar} {elapsed}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        Self { multi: Some(multi), total: Some(total), lock: Mutex::new(()) }
    }

    fn start(&self, spec: &RunSpec) -> RunBar {
        let Some(multi) = &self.multi else { return RunBar { bar: None } };
        let bar = multi.add(ProgressBar::new(u64::from(spec.generations)));
        bar.set_style(
            ProgressStyle::with_template("{prefix:<34} gen {pos:>4}/{len} {bar:20} {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        bar.set_prefix(spec.folder());
        RunBar { bar: Some(bar) }
    }

    fn done(&self, bar: &RunBar, o: &RunOutcome) {
        if let Some(b) = &bar.bar {
            b.finish_and_clear();
        }
        match &self.total {
            Some(t) => t.inc(1),
            None => {
                let _guard = self.lock.lock();
                // Progress only: a closed or full stderr does not stop the runs.
                let _ = output::stderr(
                    format!(
                        "done {}: {}, best {:.3} (planner {:.3}), {:.1} s\n",
                        o.spec.folder(),
                        count(o.result.episodes, "episode"),
                        o.result.best.fitness,
                        o.planner_fitness,
                        o.seconds
                    )
                    .as_bytes(),
                );
            }
        }
    }

    fn finish(&self) {
        if let Some(t) = &self.total {
            t.finish_and_clear();
        }
    }
}
