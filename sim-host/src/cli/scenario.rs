//! `sim-host scenario <name> [--world symbolic|physics] [--seed N] [--svg FILE]`,
//! `sim-host scenario --list`, and the demo `sim-host` runs without arguments.

use std::path::PathBuf;

use anyhow::bail;
use sim_host::episode::TICK_MS;
use sim_host::scenario::{self, Scenario};
use worlds::WorldKind;

use super::output::{self, Content, Target, out};

/// A `--world` argument: `symbolic` or `physics`, each with its help line.
pub fn world_parser(
    symbolic: &'static str,
    physics: &'static str,
) -> impl clap::builder::TypedValueParser<Value = WorldKind> {
    use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser as _};
    PossibleValuesParser::new([
        PossibleValue::new(WorldKind::Symbolic.name()).help(symbolic),
        PossibleValue::new(WorldKind::Physics.name()).help(physics),
    ])
    .map(|name| WorldKind::from_name(&name).unwrap_or(WorldKind::Symbolic))
}

/// The help of each world, for `scenario` and `learn`.
pub const WORLDS: (&str, &str) =
    ("Exact and fast: STRIPS semantics, or the reference's brick world", "rapier3d rigid bodies");

pub const LONG_ABOUT: &str = "Runs one of the papers' scenarios and narrates it tick by tick: \
what happens in the world, which actions the tree starts, finishes or halts, and each \
expansion of the tree with the conflicts IncreasePriority resolved.\n\n\
Scenarios (`--list` shows which worlds each runs in):\n  \
cube       Colledanchise et al. 2019 Fig. 1, Examples 1-2: blended planning and acting. The tree grows from \
the goal as the robot acts; the sphere blocks the path and the tree is expanded into the \
arrangement of Fig. 4; agents help (put the cube in the hand) and undo (take it away), and \
the tree copes without new expansions. `--seed N` lets agents act at random instead.\n  \
cellphone  Colledanchise et al. 2019 Section VI: two arms assemble a cellphone, regrasping parts by handing \
them over; a part slips and a co-worker helps.\n  \
tower, croissant, balance, blocking   Styrud et al.'s brick tasks with the planner's tree: the \
tower is built; the other three fail for the physical reason the paper gives.\n\n\
`--svg FILE` draws the run: a top view with every body's path, the goal region, the events \
and expansions where they happened, and the tree at the start, after each expansion and at \
the end, coloured by status.";

#[derive(clap::Args, Debug)]
pub struct Args {
    /// The scenario (see --list).
    #[arg(required_unless_present = "list")]
    pub name: Option<String>,
    /// List the scenarios and the worlds each runs in.
    #[arg(long)]
    pub list: bool,
    /// The world: symbolic or physics (default: physics where the scenario has it).
    #[arg(long, value_parser = world_parser(WORLDS.0, WORLDS.1))]
    pub world: Option<WorldKind>,
    /// Random external agents from this seed (cube scenario) instead of the scripted story.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Draw the run as an SVG picture (`-`: to stdout, the narration then goes to stderr).
    #[arg(long, value_name = "FILE", value_parser = Target::parse)]
    pub svg: Option<Target>,
    /// Write the run as a Groot2 replay log (BehaviorTree.CPP's FileLogger2 format, tick
    /// k at k x 100 ms). A log holds one tree: when the planner expanded the tree during
    /// the run, it covers the ticks of the final tree, after the last expansion.
    #[arg(long, value_name = "FILE.btlog")]
    pub btlog: Option<PathBuf>,
    #[command(flatten)]
    pub serve: super::groot2::Serve,
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    if args.list {
        let mut list = String::new();
        for s in Scenario::ALL {
            let worlds: Vec<&str> = s.worlds().iter().map(|w| w.name()).collect();
            list.push_str(&format!("{:<10} [{}]  {}\n", s.name(), worlds.join(", "), s.about()));
        }
        output::stdout(list.as_bytes())?;
        return Ok(());
    }
    let name = args.name.as_deref().unwrap_or_default();
    let Some(scenario) = Scenario::from_name(name) else {
        let known: Vec<&str> = Scenario::ALL.iter().map(|s| s.name()).collect();
        bail!("unknown scenario `{name}` (scenarios: {})", known.join(", "));
    };
    if args.seed.is_some() && scenario != Scenario::Cube {
        bail!("--seed applies to the cube scenario only (its agents); `{name}` is scripted");
    }
    let world = args.world.unwrap_or(if scenario.worlds().contains(&WorldKind::Physics) {
        WorldKind::Physics
    } else {
        WorldKind::Symbolic
    });
    let mut watch = args.serve.watch()?;
    show(scenario, world, args.seed, args.svg.as_ref(), args.btlog.as_ref(), &mut watch)?;
    args.serve.finish(&watch)
}

/// `sim-host` without arguments: the blended demo in the physics world.
pub fn demo() -> anyhow::Result<()> {
    out!(
        "sim-host: blended planning and acting (Colledanchise, Almeida, Ögren, ICRA 2019).\n\
         A mobile robot must put a cube on a goal region. It starts with a behavior tree that is\n\
         only the goal condition; whenever the tree fails, the planner expands the failed\n\
         condition with the actions that achieve it, and the robot acts on the new tree at once.\n\
         External agents then get in the way and help; watch the tree cope without replanning.\n\
         (Other scenarios: `sim-host scenario --list`; all commands: `sim-host --help`.)\n\n"
    )?;
    show(Scenario::Cube, WorldKind::Physics, None, None, None, &mut sim_host::groot2::Watch::off())
}

/// The replay log of the run's final tree: its ticks after the last expansion.
fn btlog(run: &scenario::Run) -> anyhow::Result<(Vec<u8>, u32, u32)> {
    let record = &run.record;
    let Some(last) = record.snapshots.last() else { anyhow::bail!("the run made no tree") };
    let from = record.expansions.last().map_or(0, |(t, _)| *t);
    let tree = btcpp::btlog::LogTree::new(&last.nodes, run.catalog.as_ref())
        .map_err(|e| anyhow::anyhow!("no replay log: {e}"))?;
    let mut log = btcpp::btlog::RunLog::new(&tree, i64::from((from + 1).saturating_mul(TICK_MS)) * 1000);
    let mut ticks = 0;
    for (tick, calls) in record.leaf_calls.iter().filter(|(t, _)| *t > from) {
        let calls: Vec<(usize, u8)> =
            calls.iter().map(|&(n, s)| (usize::from(n), btcpp::btlog::status_of(s))).collect();
        // The driver gives bt-core `now` = tick x TICK_MS.
        let now = tick.saturating_mul(TICK_MS);
        log.tick(*tick, i64::from(now) * 1000, now, &calls).map_err(|e| anyhow::anyhow!("replay log: {e}"))?;
        ticks += 1;
    }
    Ok((log.into_bytes(), from + 1, ticks))
}

fn show(
    scenario: Scenario,
    world: WorldKind,
    seed: Option<u64>,
    svg: Option<&Target>,
    btlog_path: Option<&PathBuf>,
    watch: &mut sim_host::groot2::Watch,
) -> anyhow::Result<()> {
    let run = match scenario::run_watched(scenario, world, seed, watch) {
        Ok(run) => run,
        Err(e) => {
            // What happened up to the error, then the error (which names the tick).
            if let Some(stopped) = e.downcast_ref::<scenario::Interrupted>() {
                let narration = stopped.narration.as_bytes();
                if svg == Some(&Target::Stdout) { output::stderr(narration)? } else { output::stdout(narration)? }
            }
            return Err(e);
        }
    };
    // The files first: if one cannot be written, nothing is printed as if all went well.
    let mut text = run.narration.clone();
    if let Some(target) = svg {
        let title = format!("sim-host scenario {} ({} world)", scenario.name(), world.name());
        output::write(target, sim_host::picture::scenario::svg(&run, &title).as_bytes(), Content::Text)?;
        if let Target::File(path) = target {
            text.push_str(&format!("picture: {}\n", path.display()));
        }
    }
    if let Some(path) = btlog_path {
        let (bytes, from, ticks) = btlog(&run)?;
        output::write_file(path, &bytes, Content::Binary("a replay log"))?;
        text.push_str(&format!(
            "btlog: {} ({} of the final tree, from tick {from})\n",
            path.display(),
            sim_host::text::count(ticks, "tick")
        ));
    }
    if svg == Some(&Target::Stdout) {
        // The picture took stdout: the narration goes to stderr.
        output::stderr(text.as_bytes())?;
    } else {
        output::stdout(text.as_bytes())?;
    }
    Ok(())
}
