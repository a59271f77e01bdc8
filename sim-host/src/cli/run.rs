//! `sim-host run --task T --world W [--tree FILE] [--svg FILE]`: one episode of a tree.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail};
use bt_core::{Catalog as _, Node, Tree};
use planner::DEPTH;
use planner::duplo::{Mode, Spec, Task};
use sim_host::episode::{End, Episode, Runner, TICK_MS, Trace};
use sim_host::physics::PhysicsBrickWorld;
use sim_host::picture;
use sim_host::symbolic::SymbolicBrickWorld;
use sim_host::world::BrickWorld;
use worlds::WorldKind;
use worlds::record::LeafCalls;

use sim_host::input::{self, Limit};
use sim_host::text::count;

use super::catalogs;
use super::output::{self, Content, Target};

/// The long help of `sim-host run` (set on the subcommand in `cli/mod.rs`).
pub const LONG_ABOUT: &str = "Runs one episode of a behavior tree on one of the four brick tasks of \
    Styrud et al. and prints the outcome and the fitness of Eq. (1)/(2).\n\n\
    Tasks:\n  \
      tower      stack three 2x2 bricks and press them together (the planner solves it)\n  \
      croissant  three bricks in a U, a long brick across the middle one; placing the\n             \
                 side bricks fails once the long brick lies at y = 0\n  \
      balance    lift an unbalanced long brick one brick high: it tips on the narrow\n             \
                 brick 1 and needs the wide brick 2 as base\n  \
      blocking   a Tower-of-Hanoi-like shuffle: brick 2 (with a cone) blocks the spot\n             \
                 of bricks 0 and 1, which block its own\n\n\
    Worlds: `symbolic` is the fast state machine GP learns in (30 ticks); `physics` is the\n\
    rapier3d world (200 ticks at 10 Hz). An episode ends at the first root Failure, after\n\
    root Success on two consecutive ticks, or at the tick limit (timeout).\n\n\
    Fitness = -cost, cost = 0.1 per node (control nodes included)\n  \
      + 1000 per metre each brick ends beyond 0.4 mm from its goal\n  \
      + 50 if the episode ended in Failure + 10 if it ran to the tick limit\n  \
      + 100 if a brick is still held at the end (balance only).\n\n\
    The tree FILE is an image (starts with `BTIM`, as `sim-host plan`/`learn` write) or\n\
    text in the token notation of Styrud et al., e.g.\n  \
      s( f( 0 on 1? put 0 on 1! ) apply force 0! )\n\
    with leaves named exactly as the task's behaviors: `picked 0?`, `1 on 0?`,\n\
    `0 at pos (0.0, 0.05, 0.0)?`, `pick 0!`, `place on 1!`, `put 0 at (0.0, 0.0, 0.0)!`, ...\n\
    (docs/brick-tasks.md lists them per task).\n\n\
    With --domain D.pddl --problem P.pddl instead of --task: runs the tree (the planner's, \
    or a FILE that `learn` wrote: best.bt or best.tokens) in the problem's symbolic STRIPS \
    world, once, or with --disturb RATE over --episodes seeded episodes in which external \
    agents undo the robot's last action or do one of the tree's actions (as in bench-pddl), and prints how often it reached the goal, its ticks and its \
    fitness (the fitness `learn` uses for PDDL problems).";

#[derive(clap::Args, Debug)]
#[command(after_help = "Example: sim-host run --task tower --tree tower.txt --svg tower.svg")]
pub struct Args {
    /// The task: tower, croissant, balance or blocking.
    #[arg(long, value_parser = parse_task, required_unless_present = "domain", conflicts_with = "domain")]
    pub task: Option<Task>,
    /// The PDDL options: run episodes of a PDDL problem in its STRIPS world instead.
    #[command(flatten)]
    pub strips: super::run_strips::Args,
    /// The world that plays the episode.
    #[arg(long, default_value_t = WorldKind::Symbolic, value_parser = super::scenario::world_parser(
        "The fast symbolic world of Styrud et al.: exact, 30 ticks, microseconds per episode",
        "The rapier3d physics world: 200 ticks at 10 Hz",
    ))]
    pub world: WorldKind,
    /// The tree: an image file or token text [default: the planner's tree for the task].
    #[arg(long, value_name = "FILE")]
    pub tree: Option<PathBuf>,
    /// Also draw the episode as an SVG picture: paths over the table, heights against
    /// ticks, the tree's statuses tick by tick (written whole or not at all; `-` writes
    /// it to stdout and the report to stderr).
    #[arg(long, value_name = "FILE", value_parser = Target::parse)]
    pub svg: Option<Target>,
    /// Write the run as a Groot2 replay log (BehaviorTree.CPP's FileLogger2 format;
    /// tick k at k x 100 ms of simulated time).
    #[arg(long, value_name = "FILE.btlog")]
    pub btlog: Option<PathBuf>,
    #[command(flatten)]
    pub serve: super::groot2::Serve,
}

/// Microseconds of simulated time per tick (10 Hz) in replay logs.
const TICK_USEC: i64 = TICK_MS as i64 * 1000;

fn parse_task(s: &str) -> Result<Task, String> {
    Task::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = Task::ALL.iter().map(|t| t.name()).collect();
        format!("unknown task `{s}` (tasks: {})", names.join(", "))
    })
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let Some(task) = args.task else {
        if args.serve.groot2.is_some() {
            bail!("--groot2 serves brick-task episodes and scenarios; not runs of a PDDL problem (--domain)");
        }
        return super::run_strips::run(&args.strips, args.tree.as_deref());
    };
    let spec = task.spec();
    let (nodes, source) = match &args.tree {
        Some(path) => (read_tree(path, &spec)?, path.display().to_string()),
        None => (planner_tree(&spec)?, "the planner's tree".to_string()),
    };
    let tree: Tree<'_, DEPTH> =
        Tree::validate(&nodes, &spec).map_err(|e| anyhow!("{source}: not a valid tree for this task: {e}"))?;
    match args.world {
        WorldKind::Symbolic => episode(SymbolicBrickWorld::new(&spec)?, tree, &source, args),
        WorldKind::Physics => episode(PhysicsBrickWorld::new(&spec)?, tree, &source, args),
    }
}

/// The tree to run when no `--tree` is given.
fn planner_tree(spec: &Spec) -> anyhow::Result<Vec<Node>> {
    let plan = planner::duplo::plan(spec.task).map_err(|e| anyhow!("planning the {} task: {e}", spec.task.name()))?;
    Ok(plan.nodes)
}

/// Reads an image (`BTIM…`) or token text, each within its size limit.
fn read_tree(path: &Path, spec: &Spec) -> anyhow::Result<Vec<Node>> {
    let bytes = input::read(path, Limit::TOKENS)?;
    if bytes.starts_with(&bt_core::image::MAGIC) {
        if bytes.len() as u64 > Limit::IMAGE.bytes {
            return Err(input::InputError::TooLarge { path: path.display().to_string(), limit: Limit::IMAGE }.into());
        }
        let header = bt_core::image::read_header(&bytes).map_err(|e| anyhow!("{}: {e}", path.display()))?;
        if header.fingerprint != spec.fingerprint() {
            bail!("{}: {}", path.display(), foreign(header.fingerprint, spec));
        }
        let mut storage = vec![Node::EMPTY; usize::from(header.node_count)];
        let tree: Tree<'_, DEPTH> =
            bt_core::load(&bytes, spec, &mut storage).map_err(|e| anyhow!("{}: {e}", path.display()))?;
        let n = tree.len();
        storage.truncate(n);
        return Ok(storage);
    }
    let text = input::text(path, bytes)
        .map_err(|e| anyhow!("{e}; neither a tree image (no `BTIM` at the start) nor token text"))?;
    bt_formats::tokens::parse(&text, spec).map_err(|e| match e.at() {
        Some(_) => anyhow!("{}:{e}", path.display()),
        None => anyhow!("{}: {e}", path.display()),
    })
}

/// Whose an image of another behavior set is, when this binary knows.
fn foreign(fingerprint: u64, spec: &Spec) -> String {
    let task = spec.task.name();
    match catalogs::by_fingerprint(fingerprint) {
        Some(known) => match Task::ALL.into_iter().find(|t| t.spec().fingerprint() == fingerprint) {
            Some(other) => format!(
                "an image for the {} task's behaviors, not the {task} task's; run it with --task {}",
                other.name(),
                other.name()
            ),
            None => format!("an image for {}, not for the {task} task: `run` plays brick tasks only", known.name),
        },
        None => format!(
            "an image for behavior set {fingerprint:#018x}, not the {task} task's ({:#018x}); this binary \
             knows no behavior set with that fingerprint",
            spec.fingerprint()
        ),
    }
}

/// Runs one episode in `world` and reports it.
fn episode<W: BrickWorld>(world: W, tree: Tree<'_, DEPTH>, source: &str, args: &Args) -> anyhow::Result<()> {
    let spec = world.spec().clone();
    let mut runner = Runner::new(world)?;
    let mut watch = args.serve.watch()?;
    watch.names(std::sync::Arc::new(spec.clone()));
    // The trace for pictures, and the leaf calls of every tick for the replay log.
    let mut rec = ((Trace::default(), LeafCalls::default()), &mut watch);
    let e = runner.run_recorded(tree, &mut rec).map_err(|err| anyhow!("{source}: {err}"))?;
    let ((trace, calls), _) = rec;
    let log = match &args.btlog {
        Some(_) => {
            let log_tree = btcpp::btlog::LogTree::new(tree.nodes(), &spec)
                .map_err(|err| anyhow!("{source}: no replay log: {err}"))?;
            let mut log = btcpp::btlog::RunLog::new(&log_tree, 0);
            // The episode gives bt-core `now` = k x TICK_MS on its tick k (from 0).
            for (k, (_, calls)) in calls.ticks.iter().enumerate() {
                let k = u32::try_from(k).unwrap_or(u32::MAX);
                let calls: Vec<(usize, u8)> =
                    calls.iter().map(|&(n, s)| (usize::from(n), btcpp::btlog::status_of(s))).collect();
                log.tick(k, i64::from(k) * TICK_USEC, k.saturating_mul(TICK_MS), &calls)
                    .map_err(|err| anyhow!("{source}: replay log: {err}"))?;
            }
            Some(log.into_bytes())
        }
        None => None,
    };
    let mut out = String::new();
    let mode = match spec.mode {
        Mode::Default => "default",
        Mode::Croissant => "croissant",
        Mode::Balance => "balance",
        Mode::Blocking => "blocking",
    };
    let _ = writeln!(out, "task     {} ({mode} mode), {} world", spec.task.name(), args.world.name());
    let _ = writeln!(out, "tree     {source}: {}, depth {}", count(tree.len(), "node"), tree.depth());
    let _ = writeln!(out, "\nthe tree, with each node's status after the last tick:");
    let _ = write!(out, "{}", tree.display(&spec).with_states(runner.states()));
    out.push('\n');
    report(&mut out, &spec, &e, runner.tick_limit());
    // The picture first: if it cannot be written, nothing is printed as if all went well.
    if let Some(target) = &args.svg {
        let doc = picture::svg(&picture::Run {
            spec: &spec,
            nodes: tree.nodes(),
            trace: &trace,
            episode: &e,
            world: args.world.name(),
        });
        output::write(target, doc.as_bytes(), Content::Text)?;
        if let Target::File(path) = target {
            let _ = writeln!(out, "picture  {}", path.display());
        }
    }
    if let (Some(path), Some(bytes)) = (&args.btlog, &log) {
        output::write_file(path, bytes, Content::Binary("a replay log"))?;
        let _ = writeln!(out, "btlog    {} ({}; open it in Groot2)", path.display(), count(bytes.len(), "byte"));
    }
    if args.svg == Some(Target::Stdout) {
        // The picture took stdout: the report goes to stderr.
        output::stderr(out.as_bytes())?;
    } else {
        output::stdout(out.as_bytes())?;
    }
    args.serve.finish(&watch)
}

fn report(out: &mut String, spec: &Spec, e: &Episode, limit: u32) {
    let how = match e.end {
        End::Success => "Success: the root succeeded on two consecutive ticks",
        End::Failure => "Failure: the root failed",
        End::Timeout => "Timeout: neither Failure nor Success twice in a row",
    };
    let limit_note = if e.timed_out && e.end != End::Timeout { " (the tick limit: timeout too)" } else { "" };
    let _ = writeln!(out, "outcome  {how}, after {} of {}{limit_note}", e.ticks, count(limit, "tick"));
    for (b, p) in e.positions().iter().enumerate() {
        let at = fmt_pos(*p);
        match spec.goal.get(b).copied().flatten() {
            Some(g) => {
                let d = distance_mm(*p, g);
                let _ = writeln!(
                    out,
                    "brick {b}  at {at}  goal {}  off {d:.1} mm  cost {:.3}",
                    fmt_pos(g),
                    e.fitness.distance.get(b).copied().unwrap_or(0.0)
                );
            }
            None => {
                let _ = writeln!(out, "brick {b}  at {at}  (no goal)");
            }
        }
    }
    let held = e.held.map_or_else(|| "nothing".to_string(), |b| format!("brick {b}"));
    let _ = writeln!(out, "held     {held}");
    let _ = writeln!(out, "fitness  {:.3}  {}", e.fitness.value(), e.fitness.terms_text("  "));
}

fn fmt_pos(p: [f32; 3]) -> String {
    format!("({:7.4}, {:7.4}, {:7.4})", p[0], p[1], p[2])
}

fn distance_mm(a: [f32; 3], b: [f32; 3]) -> f64 {
    let d = |i: usize| f64::from(a[i]) - f64::from(b[i]);
    (d(0) * d(0) + d(1) * d(1) + d(2) * d(2)).sqrt() * 1000.0
}
