//! `sim-host blend --domain D.pddl --problem P.pddl --port PATH|--tcp HOST:PORT`:
//! blended planning and acting with the tree growing on the controller
//! ([`sim_host::blend`]).

use std::path::PathBuf;
use std::sync::Arc;

use anyhow::{Context as _, bail};
use bt_core::{Catalog as _, Node};
use planner::{Options, PddlCatalog, Planner, Refinement};
use sim_host::blend::narrate::Narrator;
use sim_host::blend::{self, Blend, End, Listener, Step, Summary};
use sim_host::input::{self, Limit};
use sim_host::text::count;

use btcpp::btlog::LogTree;
use btcpp::groot2::uuid_text;
use sim_host::groot2::{Listen, Server};

use super::groot2::{hold, tell_events};
use super::link::{self, Line, Target};
use super::output;
use super::plan::RefinementArg;
use super::watch::{Live, Recording};

pub const LONG_ABOUT: &str = "Blended planning and acting on a controller (Colledanchise, \
Almeida, Ögren, ICRA 2019, Algorithm 1 at run time): the controller starts with a tree that \
is only the goal and acts on it; whenever the root fails, the host expands the failed \
condition with the planner (its atomic BT, Fig. 2; conflicts resolved by IncreasePriority, \
Fig. 4), keeping everything built before, and sends the grown tree, which the controller \
swaps in between two ticks. The controller never stops acting: while the host plans, it \
ticks on with the old tree.\n\n\
The host names the tick each tree swaps in at: it lets the controller run at most --lead \
ticks past the last tick it has read, and a tree grown after tick T fails swaps in before \
tick T + 1 + --lead. What the controller does is thus the same whatever planning and the \
link take (if they take longer than --lead ticks, the controller waits at that tick).\n\n\
What the host knows of the world is what the controller reports: the status of every \
condition it ticked. The planner refines free parameters (--refinement cheapest) on a \
belief made of the problem's initial state, the effects of the actions that succeeded and \
every condition reported since; a condition that reports what no action that ran explains \
is told as a change of the world.\n\n\
The session ends when the root succeeds, --ticks run out, or a condition cannot be expanded \
(exit code 2 with the reason); the controller then ticks on to the tick it was granted and \
stops. --trace writes the status stream with each expansion, --btlog one Groot2 replay log \
per tree, as `monitor` does.";

#[derive(clap::Args, Debug)]
#[command(
    long_about = LONG_ABOUT,
    after_help = "Examples:\n  sim-host blend --domain planner/domains/cube-sphere/domain.pddl \\\n      \
    --problem planner/domains/cube-sphere/problem.pddl --tcp 127.0.0.1:4321          # QEMU\n  \
    sim-host blend --domain d.pddl --problem p.pddl --port /dev/ttyACM0 --tree start.bt --ticks 600"
)]
pub struct Args {
    /// The PDDL domain file.
    #[arg(long, value_name = "D.pddl")]
    pub domain: PathBuf,
    /// The PDDL problem file: its goal is the first tree, its initial state the host's
    /// first belief.
    #[arg(long, value_name = "P.pddl")]
    pub problem: PathBuf,
    #[command(flatten)]
    pub target: Target,
    #[command(flatten)]
    pub line: Line,
    /// Start from the tree that is only the goal (the default).
    #[arg(long, conflicts_with = "tree")]
    pub from_goal: bool,
    /// Start from this tree image instead (made for the problem's behavior set, of
    /// Sequences, Fallbacks and leaves): its conditions heading a Fallback count as
    /// expanded.
    #[arg(long, value_name = "T.bt")]
    pub tree: Option<PathBuf>,
    /// Milliseconds between ticks. The tree's clock (what Timeout and Delay measure)
    /// advances by this much per tick.
    #[arg(long, default_value_t = 100)]
    pub period: u16,
    /// Ticks the controller may run past the last tick the host has read: a grown tree
    /// swaps in this many ticks after the tick that failed, plus one.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(0..=1000))]
    pub lead: u32,
    /// End after this many ticks.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub ticks: Option<u32>,
    /// How the planner binds free action parameters.
    #[arg(long, value_enum, default_value_t = RefinementArg::Cheapest)]
    pub refinement: RefinementArg,
    /// Record the session as a plain trace file: status changes, ticks, expansions,
    /// swaps.
    #[arg(long, value_name = "FILE")]
    pub trace: Option<PathBuf>,
    /// Record the session as Groot2 replay logs, one per tree (FILE, FILE-2, ...).
    #[arg(long, value_name = "FILE.btlog")]
    pub btlog: Option<PathBuf>,
    /// Serve the session to Groot2 live, on PORT or HOST:PORT (1667 when none is given;
    /// the publish socket takes the next port): each grown tree under a new tree UUID,
    /// with the statuses the controller reports.
    #[arg(long, value_name = "[HOST:]PORT", num_args = 0..=1, default_missing_value = "1667")]
    pub groot2: Option<String>,
    /// With --groot2: how long to go on serving the last tree after the session ends, in
    /// seconds (default: until Ctrl-C).
    #[arg(long, value_name = "SECONDS", requires = "groot2")]
    pub groot2_linger: Option<u64>,
}

/// Narration to stdout as it happens, the session's record, and Groot2.
struct Shown<'a> {
    narrator: Narrator<'a>,
    record: Recording,
    catalog: &'a PddlCatalog,
    out: Vec<u8>,
    /// With --groot2: where to listen until the first tree, then the server.
    groot2: Groot2,
}

/// `--groot2`: off, waiting for the first tree, or serving the trees so far.
enum Groot2 {
    Off,
    Listen(Listen),
    Serving { server: Server, trees: usize },
}

impl Groot2 {
    /// Serves the tree that runs from now on: the first one, or a grown one under a new UUID.
    fn tree(&mut self, tree: &LogTree, out: &mut Vec<u8>) -> anyhow::Result<()> {
        match self {
            Self::Off => {}
            Self::Listen(listen) => {
                let server = Server::start(listen, tree)?;
                out.extend(
                    format!(
                        "Groot2: connect to port {} of this machine ({}); tree UUID {}\n",
                        listen.port,
                        server.listen(),
                        uuid_text(&server.uuid())
                    )
                    .bytes(),
                );
                *self = Self::Serving { server, trees: 1 };
            }
            Self::Serving { server, trees } => {
                let uuid = server.swap(tree);
                *trees += 1;
                out.extend(format!("Groot2: the grown tree is served as tree UUID {}\n", uuid_text(&uuid)).bytes());
            }
        }
        Ok(())
    }

    /// Passes an event's status changes on.
    fn event(&self, event: &sim_host::session::Event) -> anyhow::Result<()> {
        use sim_host::session::Event;
        if let Self::Serving { server, .. } = self {
            if let Event::Tick { changes, .. } | Event::Swapped { changes, .. } | Event::Stopped { changes, .. } = event
            {
                for &(node, status) in changes {
                    server.change(usize::from(node), status);
                }
            }
            tell_events(server)?;
        }
        Ok(())
    }
}

impl Listener for Shown<'_> {
    fn step(&mut self, step: Step<'_>) -> anyhow::Result<()> {
        self.narrator.step(step)?;
        match step {
            Step::Tree { tick, nodes, values, image, .. } => {
                let live = Live::new(nodes.to_vec(), values.to_vec(), Box::new(self.catalog.clone()), image.crc);
                self.record.tree(&mut self.out, tick, &live)?;
                if !matches!(self.groot2, Groot2::Off) {
                    self.groot2.tree(&live.log_tree("--groot2")?, &mut self.out)?;
                }
            }
            Step::Event { event, .. } => {
                self.record.event(event);
                self.groot2.event(event)?;
            }
            Step::Expanded { grown, .. } => self.record.note(&format!(
                "expand {} `{}` nodes={} image={:08x} bytes={} swap_at={}",
                grown.failed_at,
                grown.expansion.condition,
                grown.expansion.nodes,
                grown.image.crc,
                grown.image.len,
                grown.swap_at
            )),
            _ => {}
        }
        let text = self.narrator.take_text();
        output::stdout(text.as_bytes())?;
        if !self.out.is_empty() {
            output::stdout(&self.out)?;
            self.out.clear();
        }
        Ok(())
    }
}

fn read(path: &std::path::Path) -> anyhow::Result<String> {
    Ok(input::read_text(path, Limit::PDDL)?)
}

/// The tree of `--tree`, for the problem's behavior set.
fn given_tree(path: &std::path::Path, catalog: &PddlCatalog) -> anyhow::Result<(Vec<Node>, Vec<u16>)> {
    let bytes = input::read(path, Limit::IMAGE)?;
    let header = bt_core::image::read_header(&bytes).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    if header.fingerprint != catalog.fingerprint() {
        bail!(
            "{}: made for behavior set {:#018x}, the problem's is {:#018x}",
            path.display(),
            header.fingerprint,
            catalog.fingerprint()
        );
    }
    let mut nodes = vec![Node::EMPTY; usize::from(header.node_count)];
    let mut values = vec![0u16; bytes.len()];
    let tree: bt_core::Tree<'_, { planner::DEPTH }> = bt_core::load_with(&bytes, catalog, &mut nodes, &mut values)
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    Ok((tree.nodes().to_vec(), tree.values().to_vec()))
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let (dpath, ppath) = (&args.domain, &args.problem);
    let (domain, dwarn) = planner::pddl::read_domain(&dpath.display().to_string(), &read(dpath)?)?;
    let (problem, pwarn) = planner::pddl::read_problem(&ppath.display().to_string(), &read(ppath)?, &domain)?;
    for w in dwarn.iter().chain(&pwarn) {
        output::stderr(format!("{w}\n").as_bytes())?;
    }
    let g =
        Arc::new(planner::ground::Grounding::new(&problem).with_context(|| format!("grounding {}", ppath.display()))?);
    let catalog = PddlCatalog::new(&problem);
    let options = Options {
        refinement: match args.refinement {
            RefinementArg::Cheapest => Refinement::Cheapest,
            RefinementArg::All => Refinement::All,
        },
        ..Options::default()
    };
    let planner = match &args.tree {
        None => Planner::new(g.clone(), options)?,
        Some(path) => {
            let (nodes, values) = given_tree(path, &catalog)?;
            Planner::from_nodes(g.clone(), &nodes, &values, options).with_context(|| path.display().to_string())?
        }
    };
    let (mut link, name) = link::open(&args.target, &args.line)?;
    let (info, set) = link::hello(&mut link, &name)?;
    if info.fingerprint != catalog.fingerprint() {
        bail!(
            "the controller at {name} runs behavior set {set}; {} has {:#018x}",
            ppath.display(),
            catalog.fingerprint()
        );
    }
    output::stdout(
        format!(
            "controller {name}: link protocol {}, behavior set {set}; images of at most {}\n\
             goal: {}. Ticks {}; a grown tree swaps in {} after the tick that failed.\n\n",
            info.version,
            count(info.image_capacity, "byte"),
            g.goal().iter().map(|&l| g.lit_name(l)).collect::<Vec<_>>().join(", "),
            if args.period == 0 { "back to back".to_string() } else { format!("every {} ms", args.period) },
            count(args.lead + 1, "tick")
        )
        .as_bytes(),
    )?;
    let groot2 = match &args.groot2 {
        None => Groot2::Off,
        Some(listen) => Groot2::Listen(Listen::parse(listen).map_err(|e| anyhow::anyhow!("--groot2: {e}"))?),
    };
    let mut shown = Shown {
        narrator: Narrator::new(&catalog, g.clone()),
        record: Recording::new(args.btlog.as_deref(), args.period),
        catalog: &catalog,
        out: Vec::new(),
        groot2,
    };
    let setup = Blend { planner, catalog: catalog.clone(), period_ms: args.period, lead: args.lead, ticks: args.ticks };
    let result = blend::run(&mut link, info.image_capacity, setup, &mut shown);
    // The record is written whatever happened: it is what shows why.
    let Shown { record, mut out, groot2, .. } = shown;
    record.finish(&mut out, args.trace.as_deref())?;
    output::stdout(&out)?;
    let summary = result.map_err(|e| e.context(name.clone()))?;
    output::stdout(summarize(&summary, args).as_bytes())?;
    if let Groot2::Serving { server, trees } = &groot2 {
        hold(server, args.groot2_linger, *trees)?;
    }
    match summary.end {
        End::Unexpandable { tick, error } => bail!("tick {tick}: the planner cannot expand the tree: {error}"),
        End::Refused { tick, reason } => bail!("tick {tick}: the grown tree: {reason}"),
        End::Goal(_) | End::Ticks => {}
    }
    Ok(())
}

/// The closing lines: how it ended, expansions, swaps, halts, planning and link figures.
fn summarize(s: &Summary, args: &Args) -> String {
    let verdict = match &s.end {
        End::Goal(t) => format!("goal reached at tick {t}, {} after the first", count(t - s.first_tick, "tick")),
        End::Ticks => format!("stopped after {} without reaching the goal", count(args.ticks.unwrap_or(0), "tick")),
        End::Unexpandable { tick, .. } => format!("stuck at tick {tick}: a condition cannot be expanded"),
        End::Refused { tick, .. } => format!("stuck at tick {tick}: the grown tree cannot go to the controller"),
    };
    let mut text = format!(
        "\nsummary: {verdict}; {}, each swapped in at the tick named; {} halted by the tree, {} by swaps; \
         the tree has {}; the controller stopped before tick {}\n",
        count(s.grown.len(), "expansion"),
        count(s.halts, "action"),
        s.swap_halts,
        count(s.nodes.len(), "node"),
        s.stopped_at
    );
    if !s.grown.is_empty() {
        let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
        let planning: Vec<f64> = s.grown.iter().map(|g| ms(g.planning)).collect();
        let sending: Vec<f64> = s.grown.iter().map(|g| ms(g.sending)).collect();
        let (lo, hi, mean) = spread(&planning);
        let (slo, shi, _) = spread(&sending);
        let bytes: u64 = s.grown.iter().map(|g| u64::from(g.image.len)).sum();
        // On the host's clock, from reading the failed tick (the report's way to the
        // host not counted): the swap tick is due (lead + 1) periods after the failed one.
        let allowed = u64::from(args.lead + 1) * u64::from(args.period);
        let late = s.grown.iter().filter(|g| ms(g.planning) + ms(g.sending) > allowed as f64).count();
        let timing = if args.period == 0 {
            String::new()
        } else {
            format!(" ({allowed} ms): {late} of them took longer to plan and send")
        };
        text.push_str(&format!(
            "         planning per expansion {lo:.2}-{hi:.2} ms (mean {mean:.2} ms); the grown trees sent \
             ({} of images) in {slo:.1}-{shi:.1} ms each; each swap {} after the failed tick{timing}\n",
            count(bytes, "byte"),
            count(args.lead + 1, "tick"),
        ));
    }
    text.push_str(&format!(
        "         the link: {} sent, {} received; the controller waited for the host (at the last tick \
         granted) {}\n",
        count(s.bytes.0, "byte"),
        count(s.bytes.1, "byte"),
        count(s.waits, "time")
    ));
    text
}

/// Least, greatest and mean.
fn spread(v: &[f64]) -> (f64, f64, f64) {
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(0.0, f64::max);
    (lo, hi, v.iter().sum::<f64>() / v.len().max(1) as f64)
}
