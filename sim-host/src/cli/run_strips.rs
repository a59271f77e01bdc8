//! `sim-host run --domain D --problem P [--tree FILE] [--disturb RATE --episodes N]`:
//! episodes of a tree in a PDDL problem's STRIPS world, with or without external agents.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Context as _, anyhow, bail};
use bt_core::Node;
use sim_host::learn::strips::{StripsEnd, StripsRunner};
use sim_host::learn::{Disturbance, StripsProblem};
use sim_host::text::count;

/// Most episodes one command runs.
const MAX_EPISODES: u32 = 100_000;

#[derive(clap::Args, Debug)]
#[group(id = "pddl")]
pub struct Args {
    /// A PDDL domain (with --problem), instead of --task.
    #[arg(long, value_name = "D.pddl", requires = "problem")]
    pub domain: Option<PathBuf>,
    /// The PDDL problem.
    #[arg(long, value_name = "P.pddl", requires = "domain")]
    pub problem: Option<PathBuf>,
    /// PDDL: before a tick, with this chance, an external agent undoes the robot's last
    /// action or does one of the tree's actions (at most 3 times an episode).
    #[arg(long, value_name = "RATE", requires = "domain")]
    pub disturb: Option<f64>,
    /// PDDL with --disturb: the seed of the agents (episode k uses the agents of seed
    /// and k, as `learn` does).
    #[arg(long, value_name = "N", requires = "disturb", default_value_t = 0)]
    pub disturb_seed: u64,
    /// PDDL with --disturb: how many episodes.
    #[arg(long, value_name = "N", requires = "disturb", default_value_t = 100)]
    pub episodes: u32,
    /// PDDL: ticks an episode may last (default as `learn`'s: three times the planner's
    /// tree's ticks to the goal, plus 30).
    #[arg(long, value_name = "N", requires = "domain")]
    pub ticks: Option<u32>,
}

fn read_text(path: &Path) -> anyhow::Result<String> {
    std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))
}

/// The tree in GP's leaves: an image of the PDDL leaf contract, or token text.
fn read_tree(p: &StripsProblem, path: &Path) -> anyhow::Result<Vec<Node>> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    if bytes.starts_with(&bt_core::image::MAGIC) {
        let header = bt_core::image::read_header(&bytes).map_err(|e| anyhow!("{}: {e}", path.display()))?;
        let mut storage = vec![Node::EMPTY; usize::from(header.node_count)];
        let tree: bt_core::Tree<'_, { sim_host::learn::strips::DEPTH }> =
            bt_core::load(&bytes, p.pddl_catalog(), &mut storage).map_err(|e| anyhow!("{}: {e}", path.display()))?;
        let n = tree.len();
        storage.truncate(n);
        return p.from_pddl(&storage).map_err(|e| anyhow!("{}: {e}", path.display()));
    }
    let text = std::str::from_utf8(&bytes).map_err(|_| {
        anyhow!("{}: neither a tree image (no `BTIM` magic) nor token text (not UTF-8)", path.display())
    })?;
    bt_formats::tokens::parse(text, p.catalog()).map_err(|e| anyhow!("{}: {e}", path.display()))
}

pub fn run(args: &Args, tree: Option<&Path>) -> anyhow::Result<()> {
    let (Some(d), Some(pp)) = (&args.domain, &args.problem) else {
        bail!("give --task NAME, or --domain D.pddl --problem P.pddl");
    };
    let p = StripsProblem::new(
        &d.display().to_string(),
        read_text(d)?,
        &pp.display().to_string(),
        read_text(pp)?,
        false,
        gp::Bound::NONE,
    )?;
    let (nodes, source) = match tree {
        Some(path) => (read_tree(&p, path)?, path.display().to_string()),
        None => (p.planner_tree().to_vec(), "the planner's tree".to_string()),
    };
    let tick_limit = args.ticks.unwrap_or_else(|| p.default_tick_limit());
    if tick_limit == 0 {
        bail!("--ticks must be at least 1");
    }
    let disturbance = match args.disturb {
        None => None,
        Some(rate) if !(0.0..=1.0).contains(&rate) => bail!("--disturb {rate}: give a chance per tick between 0 and 1"),
        Some(_) if args.episodes == 0 || args.episodes > MAX_EPISODES => {
            bail!("--episodes {}: give 1 to {MAX_EPISODES}", args.episodes)
        }
        Some(rate) => Some(Disturbance { rate, seed: args.disturb_seed, episodes: args.episodes }),
    };
    let episodes: Vec<Option<(&Disturbance, u32)>> = match &disturbance {
        None => vec![None],
        Some(d) => (0..d.episodes).map(|k| Some((d, k))).collect(),
    };
    let mut runner = StripsRunner::new(Arc::new(p), tick_limit);
    let mut out = String::new();
    let results = episodes
        .iter()
        .map(|&a| runner.episode(&nodes, a))
        .collect::<anyhow::Result<Vec<_>>>()
        .map_err(|e| anyhow!("{source}: {e}"))?;
    let n = results.len();
    let reached = results.iter().filter(|e| e.goal_reached()).count();
    let mut ticks: Vec<u32> = results.iter().map(|e| e.ticks).collect();
    ticks.sort_unstable();
    let ended = |end: StripsEnd| results.iter().filter(|e| e.end == end).count();
    let acts: u32 = results.iter().map(|e| e.disturbances).sum();
    let fitness = results.iter().map(|e| e.fitness).sum::<f64>() / n as f64;
    let _ = writeln!(out, "problem  {} (domain {})", pp.display(), d.display());
    let _ = writeln!(out, "tree     {source}: {} as learned (a negative condition is one)", count(nodes.len(), "node"));
    match &disturbance {
        None => {
            let _ = writeln!(out, "episodes 1, undisturbed, at most {}", count(tick_limit, "tick"));
        }
        Some(d) => {
            let _ = writeln!(
                out,
                "episodes {n}, agents act before a tick with chance {}, at most {} (seed {}): {}; at most {}",
                d.rate,
                count(d.model().max, "time"),
                d.seed,
                count(acts, "act"),
                count(tick_limit, "tick")
            );
        }
    }
    let _ = writeln!(out, "goal     reached in {reached} of {}", count(n, "episode"));
    let mean = f64::from(ticks.iter().sum::<u32>()) / n as f64;
    let _ =
        writeln!(out, "ticks    mean {mean:.1}, median {}, most {}", ticks[n / 2], ticks.last().copied().unwrap_or(0));
    let _ = writeln!(
        out,
        "ended    success {}, failure {}, timeout {}",
        ended(StripsEnd::Success),
        ended(StripsEnd::Failure),
        ended(StripsEnd::Timeout)
    );
    let _ = writeln!(out, "fitness  {fitness:.3} (mean)");
    super::output::stdout(out.as_bytes())?;
    Ok(())
}
