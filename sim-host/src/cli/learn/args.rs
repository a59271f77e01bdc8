//! `sim-host learn`'s arguments, their limits, and the grid of runs they make.

use std::path::PathBuf;
use std::sync::Arc;

use anyhow::{Context as _, bail};
use gp::Variant;
use gp::islands::IslandParams;
use planner::duplo::Task;
use sim_host::learn::{self, Disturbance, RunSpec, StripsProblem, Subject};
use sim_host::text::count;
use worlds::WorldKind;

use crate::cli::scenario::{WORLDS, world_parser};

/// Most generations a run may ask for: 100,000 generations keep about 2.7 million
/// trees in the fitness cache (some hundreds of MB).
pub const MAX_GENERATIONS: u32 = 100_000;
/// Most runs one command may make or list.
pub const MAX_RUNS: usize = 10_000;
/// Most islands.
pub const MAX_ISLANDS: usize = 256;
/// Most disturbed episodes per tree.
pub const MAX_EPISODES: u32 = 1000;
/// Most ticks of a PDDL episode.
pub const MAX_TICKS: u32 = 100_000;
/// Generations of a PDDL run when none are given.
pub const PDDL_GENERATIONS: u32 = 200;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Tasks: tower, croissant, balance, blocking, a comma list, or `all`.
    #[arg(long = "task", alias = "tasks", value_name = "TASKS", value_parser = parse_tasks,
          required_unless_present = "domain", conflicts_with = "domain")]
    pub tasks: Option<TaskList>,
    /// A PDDL domain: learn on --problem in the symbolic STRIPS world instead of a brick task.
    #[arg(long, value_name = "D.pddl", requires = "problem")]
    pub domain: Option<PathBuf>,
    /// The PDDL problem (with --domain).
    #[arg(long, value_name = "P.pddl", requires = "domain")]
    pub problem: Option<PathBuf>,
    /// Variants: none, baseline, boost-crossover, boost-all, nokeep, a comma list, or
    /// `all` (the paper's four).
    #[arg(long = "variant", alias = "variants", value_name = "VARIANTS", default_value = "baseline", value_parser = parse_variants)]
    pub variants: VariantList,
    /// Where episodes run (brick tasks; PDDL problems run in the STRIPS world).
    #[arg(long, value_parser = world_parser(WORLDS.0, WORLDS.1))]
    pub world: Option<WorldKind>,
    /// Seeds: `1..5` (inclusive), `3`, or `1,4,7`.
    #[arg(long, default_value = "1..5", value_parser = parse_seeds)]
    pub seeds: SeedList,
    /// Generations per run, at most 100000 (default: the reference's for the task and
    /// world; 200 for PDDL). With --islands, each island's budget.
    #[arg(long)]
    pub generations: Option<u32>,
    /// The folder the run folders go into (created if missing).
    #[arg(long)]
    pub out: PathBuf,
    /// Replace run folders that already exist.
    #[arg(long)]
    pub force: bool,
    /// Evolve K populations at once, with migration and restarts (a solved tree
    /// more often than one population gives).
    #[arg(long, value_name = "K")]
    pub islands: Option<usize>,
    /// With --islands: generations between migrations.
    #[arg(long, value_name = "N", requires = "islands", default_value_t = IslandParams::default().migration_interval)]
    pub migration_interval: u32,
    /// With --islands: restart an island whose best has not improved for N
    /// generations (0: never).
    #[arg(long, value_name = "N", requires = "islands", default_value_t = IslandParams::default().stagnation.unwrap_or(0))]
    pub stagnation: u32,
    /// With --islands: stop as soon as the best fitness reaches F (e.g. -3 for a
    /// solved tower).
    #[arg(long, value_name = "F", requires = "islands", allow_hyphen_values = true)]
    pub stop_at: Option<f64>,
    /// The brick tasks' baseline in the reference's form: the goal Sequence kept at the
    /// root for a single goal (balance: 11 nodes instead of 10).
    #[arg(long)]
    pub goal_sequence: bool,
    /// PDDL: before a tick, with this chance, an external agent undoes the robot's last
    /// action or does one of the tree's actions (at most 3 times an episode).
    #[arg(long, value_name = "RATE", requires = "domain")]
    pub disturb: Option<f64>,
    /// PDDL with --disturb: the seed of the agents.
    #[arg(long, value_name = "N", requires = "disturb", default_value_t = 0)]
    pub disturb_seed: u64,
    /// PDDL with --disturb: disturbed episodes that score each tree.
    #[arg(long, value_name = "E", requires = "disturb", default_value_t = 100)]
    pub disturb_episodes: u32,
    /// PDDL: ticks an episode may last (default: three times the planner's tree's
    /// ticks to the goal, plus 30).
    #[arg(long, value_name = "N", requires = "domain")]
    pub ticks: Option<u32>,
    /// The most bytes the learned tree's image may have as a controller holds it
    /// (without the names section; `deploy --strip-names` sends exactly that). A
    /// validity rule, as the paper's are: random trees and offspring over it are
    /// refused before they are simulated, so no tree of the run is ever over it. A PDDL
    /// baseline's closure over disturbances is cut to fit (as `plan --max-bytes`
    /// does); a baseline over it even so is an error. Default: no bound.
    #[arg(long, value_name = "BYTES")]
    pub max_bytes: Option<usize>,
    /// The most bt-core nodes the learned tree may have, as --max-bytes (random
    /// trees of the first generation have at most this many). Default: no bound.
    #[arg(long, value_name = "NODES")]
    pub max_nodes: Option<usize>,
    /// Print one self-contained command per run (for GNU parallel, a batch
    /// scheduler), and run nothing.
    #[arg(long, conflicts_with = "index")]
    pub list: bool,
    /// Make only run I of the grid (0-based, in --list's order): for Slurm job
    /// arrays (`--index $SLURM_ARRAY_TASK_ID`).
    #[arg(long, value_name = "I")]
    pub index: Option<usize>,
}

#[derive(Clone, Debug)]
pub struct TaskList(pub Vec<Task>);
#[derive(Clone, Debug)]
pub struct VariantList(pub Vec<Variant>);
#[derive(Clone, Debug)]
pub struct SeedList(pub Vec<u64>);

/// Refuses a list that names something twice: the same run would be made twice.
fn unique<T: PartialEq>(items: &[T], what: &str, name: impl Fn(&T) -> String) -> Result<(), String> {
    for (i, x) in items.iter().enumerate() {
        if items[..i].contains(x) {
            return Err(format!("{what} `{}` is given twice; each run is made once, list it once", name(x)));
        }
    }
    Ok(())
}

fn parse_tasks(s: &str) -> Result<TaskList, String> {
    if s == "all" {
        return Ok(TaskList(Task::ALL.to_vec()));
    }
    let tasks: Vec<Task> = s
        .split(',')
        .map(|t| {
            Task::from_name(t.trim())
                .ok_or_else(|| format!("unknown task `{t}` (tower, croissant, balance, blocking, all)"))
        })
        .collect::<Result<_, _>>()?;
    unique(&tasks, "task", |t| t.name().to_string())?;
    Ok(TaskList(tasks))
}

fn parse_variants(s: &str) -> Result<VariantList, String> {
    if s == "all" {
        return Ok(VariantList(Variant::ALL.to_vec()));
    }
    let variants: Vec<Variant> =
        s.split(',').map(|v| v.trim().parse::<Variant>().map_err(|e| e.to_string())).collect::<Result<_, _>>()?;
    unique(&variants, "variant", |v| v.name().to_string())?;
    Ok(VariantList(variants))
}

fn parse_seeds(s: &str) -> Result<SeedList, String> {
    let num = |t: &str| t.trim().parse::<u64>().map_err(|_| format!("`{t}` is not a seed (a whole number)"));
    let seeds: Vec<u64> = if let Some((a, b)) = s.split_once("..") {
        let (a, b) = (num(a)?, num(b.trim_start_matches('='))?);
        if a > b {
            return Err(format!("empty seed range `{s}`: the first seed is larger than the last"));
        }
        if b - a >= MAX_RUNS as u64 {
            return Err(format!("seed range `{s}` has more than {MAX_RUNS} seeds"));
        }
        (a..=b).collect()
    } else {
        s.split(',').map(num).collect::<Result<_, _>>()?
    };
    unique(&seeds, "seed", u64::to_string)?;
    Ok(SeedList(seeds))
}

/// Reads a text file whole, naming it on failure.
fn read_text(path: &PathBuf) -> anyhow::Result<String> {
    std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))
}

/// The runs the arguments ask for, in order: task (or the PDDL problem) x variant x
/// seed, after checking every limit.
pub fn grid(args: &Args) -> anyhow::Result<Vec<RunSpec>> {
    if let Some(g) = args.generations {
        if g == 0 {
            bail!("--generations must be at least 1");
        }
        if g > MAX_GENERATIONS {
            bail!(
                "--generations {g} is over the limit of {MAX_GENERATIONS} (each generation adds up to 32 \
                 trees to the run's fitness cache; 100000 generations hold some hundreds of MB)"
            );
        }
    }
    let islands = match args.islands {
        None => None,
        Some(k) if k == 0 || k > MAX_ISLANDS => bail!("--islands {k}: give 1 to {MAX_ISLANDS} islands"),
        Some(k) => {
            if args.migration_interval == 0 {
                bail!("--migration-interval must be at least 1");
            }
            if let Some(f) = args.stop_at
                && !f.is_finite()
            {
                bail!("--stop-at {f}: give a finite fitness");
            }
            Some(IslandParams {
                islands: k,
                migration_interval: args.migration_interval,
                stagnation: (args.stagnation > 0).then_some(args.stagnation),
                stop_at: args.stop_at,
            })
        }
    };
    let subjects: Vec<(Subject, u32)> = match (&args.tasks, &args.domain, &args.problem) {
        (Some(tasks), _, _) => {
            let world = args.world.unwrap_or(WorldKind::Symbolic);
            tasks
                .0
                .iter()
                .map(|&task| {
                    let generations = args.generations.unwrap_or_else(|| learn::default_generations(task, world));
                    (Subject::Brick { task, world }, generations)
                })
                .collect()
        }
        (None, Some(d), Some(p)) => {
            if args.world.is_some_and(|w| w != WorldKind::Symbolic) {
                bail!("--world physics is for the brick tasks; PDDL problems learn in the symbolic STRIPS world");
            }
            let disturbance = match args.disturb {
                None => None,
                Some(rate) if !(0.0..=1.0).contains(&rate) => {
                    bail!("--disturb {rate}: give a chance per tick between 0 and 1")
                }
                Some(rate) => {
                    if args.disturb_episodes == 0 || args.disturb_episodes > MAX_EPISODES {
                        bail!("--disturb-episodes {}: give 1 to {MAX_EPISODES}", args.disturb_episodes);
                    }
                    Some(Disturbance { rate, seed: args.disturb_seed, episodes: args.disturb_episodes })
                }
            };
            let problem = StripsProblem::new(
                &d.display().to_string(),
                read_text(d)?,
                &p.display().to_string(),
                read_text(p)?,
                args.goal_sequence,
                bound(args)?,
            )?;
            let tick_limit = args.ticks.unwrap_or_else(|| problem.default_tick_limit());
            if tick_limit == 0 || tick_limit > MAX_TICKS {
                bail!("--ticks {tick_limit}: give 1 to {MAX_TICKS}");
            }
            let subject = Subject::Strips { problem: Arc::new(problem), tick_limit, disturbance };
            vec![(subject, args.generations.unwrap_or(PDDL_GENERATIONS))]
        }
        _ => bail!("give --task NAME, or --domain D.pddl --problem P.pddl"),
    };
    let bound = bound(args)?;
    if !bound.is_none() && args.variants.0.iter().any(|v| v.uses_baseline()) {
        for (subject, _) in &subjects {
            check_baseline(args, subject, bound)?;
        }
    }
    let total = subjects.len() * args.variants.0.len() * args.seeds.0.len();
    if total > MAX_RUNS {
        bail!(
            "{} x {} x {} = {}, over the limit of {MAX_RUNS} per command; \
             split the grid (e.g. by --seeds) or spread it with --list",
            count(subjects.len(), "task"),
            count(args.variants.0.len(), "variant"),
            count(args.seeds.0.len(), "seed"),
            count(total, "run")
        );
    }
    let mut specs = Vec::with_capacity(total);
    for (subject, generations) in &subjects {
        for &variant in &args.variants.0 {
            for &seed in &args.seeds.0 {
                specs.push(RunSpec {
                    subject: subject.clone(),
                    variant,
                    seed,
                    generations: *generations,
                    islands,
                    goal_sequence: args.goal_sequence,
                    bound,
                });
            }
        }
    }
    Ok(specs)
}

/// The bound of --max-bytes and --max-nodes, refused where no tree GP makes fits it.
fn bound(args: &Args) -> anyhow::Result<gp::Bound> {
    use bt_core::{Leaf, Node, NodeKind};
    // The smallest tree GP makes: a Sequence over one action (`min_length` 2).
    let smallest = [Node::new(NodeKind::Sequence, 2), Node::new(NodeKind::Action(Leaf::new(0)), 1)];
    let smallest = gp::image_size(&smallest).context("the image of a two-node tree")?;
    if let Some(b) = args.max_bytes
        && b < smallest.bytes
    {
        bail!(
            "--max-bytes {b}: too small for any tree; the smallest GP makes (a Sequence over one action) has an \
             image of {}",
            count(smallest.bytes, "byte")
        );
    }
    if let Some(n) = args.max_nodes
        && n < smallest.nodes
    {
        bail!(
            "--max-nodes {n}: too small for any tree; the smallest GP makes (a Sequence over one action) has 2 nodes"
        );
    }
    Ok(gp::Bound { bytes: args.max_bytes, nodes: args.max_nodes })
}

/// Refuses, before any run, a bound the planner's tree (the baseline) is over.
fn check_baseline(args: &Args, subject: &Subject, bound: gp::Bound) -> anyhow::Result<()> {
    let tree = subject.planner_tree(args.goal_sequence)?;
    let size = subject.size(&tree).context("the image of the planner's tree")?;
    if bound.admits(size) {
        return Ok(());
    }
    let flags: Vec<String> = [("--max-bytes", bound.bytes), ("--max-nodes", bound.nodes)]
        .iter()
        .filter_map(|(flag, v)| v.map(|v| format!("{flag} {v}")))
        .collect();
    let cut = match subject {
        Subject::Strips { problem, .. } if problem.planner_fit().cut == Some(0) => {
            " even with its closure over disturbances left out"
        }
        _ => "",
    };
    bail!(
        "{}: the planner's tree for {} (the baseline) has an image of {} and {}{cut}, over the bound; \
         give a larger one, or --variant none to learn from random trees only",
        flags.join(" "),
        subject.label(),
        count(size.bytes, "byte"),
        count(size.nodes, "node"),
    )
}

/// One self-contained command that makes exactly `spec` into `args.out`.
pub fn command(args: &Args, spec: &RunSpec) -> String {
    let exe = std::env::args().next().unwrap_or_else(|| "sim-host".to_string());
    let mut words: Vec<String> = vec![exe, "learn".into()];
    let mut push = |k: &str, v: String| {
        words.push(k.to_string());
        words.push(v);
    };
    match &spec.subject {
        Subject::Brick { task, world } => {
            push("--task", task.name().into());
            push("--world", world.name().into());
        }
        Subject::Strips { tick_limit, disturbance, .. } => {
            if let (Some(d), Some(p)) = (&args.domain, &args.problem) {
                push("--domain", d.display().to_string());
                push("--problem", p.display().to_string());
            }
            push("--ticks", tick_limit.to_string());
            if let Some(d) = disturbance {
                push("--disturb", d.rate.to_string());
                push("--disturb-seed", d.seed.to_string());
                push("--disturb-episodes", d.episodes.to_string());
            }
        }
    }
    push("--variant", spec.variant.name().into());
    push("--seeds", spec.seed.to_string());
    push("--generations", spec.generations.to_string());
    if let Some(i) = spec.islands {
        push("--islands", i.islands.to_string());
        push("--migration-interval", i.migration_interval.to_string());
        push("--stagnation", i.stagnation.unwrap_or(0).to_string());
        if let Some(f) = i.stop_at {
            push("--stop-at", format!("{f:?}"));
        }
    }
    if let Some(b) = spec.bound.bytes {
        push("--max-bytes", b.to_string());
    }
    if let Some(n) = spec.bound.nodes {
        push("--max-nodes", n.to_string());
    }
    push("--out", args.out.display().to_string());
    if spec.goal_sequence {
        words.push("--goal-sequence".into());
    }
    if args.force {
        words.push("--force".into());
    }
    words.iter().map(|w| shell_word(w)).collect::<Vec<_>>().join(" ")
}

/// A word as a POSIX shell reads it back: bare when safe, else in single quotes.
fn shell_word(w: &str) -> String {
    let safe = !w.is_empty() && w.chars().all(|c| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c));
    if safe { w.to_string() } else { format!("'{}'", w.replace('\'', r"'\''")) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeated_entries_are_refused_by_name() {
        assert!(parse_seeds("1,1,1").unwrap_err().contains("seed `1` is given twice"));
        assert!(parse_tasks("tower,tower").unwrap_err().contains("task `tower` is given twice"));
        assert!(parse_variants("none,none").unwrap_err().contains("variant `none` is given twice"));
        assert_eq!(parse_seeds("3..5").unwrap().0, [3, 4, 5]);
    }

    #[test]
    fn shell_words_read_back() {
        assert_eq!(shell_word("runs/a-1"), "runs/a-1");
        assert_eq!(shell_word("my runs"), "'my runs'");
        assert_eq!(shell_word("it's"), r"'it'\''s'");
        assert_eq!(shell_word(""), "''");
    }
}
