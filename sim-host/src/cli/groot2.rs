//! `sim-host groot2 --port PATH|--tcp HOST:PORT [--listen PORT]`: a running controller
//! in Groot2, live, across hot swaps.

use std::collections::VecDeque;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::bail;
use bt_core::NodeStatus;
use bt_link::host::{LinkError, Verdict};
use bt_link::{Reply, WireStatus};
use btcpp::groot2::uuid_text;
use sim_host::groot2::{DEFAULT_PORT, Event, Listen, Server, Watch};
use sim_host::text::count;

use super::deploy::Checked;
use super::link::{self, Line, Running, Target};
use super::output::{self, out};

#[derive(clap::Args, Debug)]
#[command(
    long_about = "Serves a running controller's tree to Groot2, live: attaches to the controller \
    over its link (as `monitor` does), reads its tree back, and answers Groot2 as \
    BehaviorTree.CPP 4.10's Groot2Publisher does, from the status changes the controller \
    reports as it ticks. In Groot2, connect to this machine on --listen's port (1667, \
    with the publish socket on 1668).\n\n\
    Served: the tree (with its node models, numbered as `export` and `.btlog` files \
    number it), every node's status, recording and the transitions recorded, blackboards \
    (empty: a controller reports no values). Refused: breakpoints and hooks, which would \
    have to stop the controller's tick (Groot2 is told `Request not recognized`, as \
    BehaviorTree.CPP tells it for a request it does not serve).\n\n\
    When a deployment swaps a new tree in (--deploy here, since the link has one host), \
    the new tree is served under a new tree UUID and Groot2 loads it, instead of losing \
    the connection as with BehaviorTree.CPP's `setNewTree()`.\n\n\
    The controller does not tell the statuses it had before the bridge attached: every \
    node shows Idle until it changes (use --start on a stopped controller to see it \
    from the first tick).",
    after_help = "Examples:\n  sim-host groot2 --tcp 127.0.0.1:4321 --start      # QEMU; Groot2: localhost 1667\n  \
    sim-host groot2 --port /dev/ttyACM0 --deploy b.bt --at-tick 300 --listen 127.0.0.1:1667"
)]
pub struct Args {
    #[command(flatten)]
    pub target: Target,
    #[command(flatten)]
    pub line: Line,
    /// Where Groot2 connects: PORT (every interface, as BehaviorTree.CPP listens) or
    /// HOST:PORT; the publish socket takes the next port.
    #[arg(long, value_name = "[HOST:]PORT", default_value_t = DEFAULT_PORT.to_string())]
    pub listen: String,
    /// Start the controller ticking (every --period ms) once Groot2 can connect.
    #[arg(long)]
    pub start: bool,
    /// Milliseconds between ticks with --start (0: back to back).
    #[arg(long, default_value_t = 100)]
    pub period: u16,
    /// Deploy this image while serving (before --start starts the controller): it
    /// swaps in at --at-tick (default: the next tick), and Groot2 is given the new tree.
    #[arg(long, value_name = "IMAGE")]
    pub deploy: Option<PathBuf>,
    /// With --deploy: the tick to swap the new tree in before.
    #[arg(long, value_name = "TICK", requires = "deploy")]
    pub at_tick: Option<u32>,
    /// End after this many ticks (default: until the link closes or Ctrl-C).
    #[arg(long)]
    pub ticks: Option<u32>,
    /// Record the session as a plain trace file, as `monitor --trace` does (written
    /// when the session ends: end it with --ticks).
    #[arg(long, value_name = "FILE")]
    pub trace: Option<PathBuf>,
}

/// A reply of the controller's stream, kept for later.
enum Seen {
    Status { tick: u32, node: u16, status: NodeStatus },
    Tick { tick: u32, status: WireStatus, changes: u16, micros: u32 },
    Swapped { tick: u32, crc: u32, nodes: u16, halted: u16 },
    Garbled(&'static str),
}

impl Seen {
    fn of(reply: &Reply<'_>) -> Option<Self> {
        Some(match *reply {
            Reply::Status { tick, node, status } => Self::Status { tick, node, status: NodeStatus::from(status) },
            Reply::Tick { tick, status, changes, micros } => Self::Tick { tick, status, changes, micros },
            Reply::Swapped { tick, image, halted } => {
                Self::Swapped { tick, crc: image.crc, nodes: image.nodes, halted }
            }
            Reply::Garbled { fault } => Self::Garbled(fault.code()),
            _ => return None,
        })
    }
}

/// The note about a tree's names, on stderr, once a session.
fn note(running: &Running, noted: &mut bool) -> anyhow::Result<()> {
    if let Some(n) = &running.note
        && !*noted
    {
        *noted = true;
        output::stderr(format!("note: {n}\n").as_bytes())?;
    }
    Ok(())
}

fn say_events(server: &Server) -> anyhow::Result<()> {
    for e in server.events() {
        match e {
            Event::Connected => out!("Groot2 connected\n")?,
            Event::Gone => out!("Groot2 gone (no request for 5 s)\n")?,
            Event::Fault(f) => out!("Groot2 socket: {f}\n")?,
        }
    }
    Ok(())
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let listen = Listen::parse(&args.listen).map_err(|e| anyhow::anyhow!("--listen: {e}"))?;
    let file = args.deploy.as_deref().map(Checked::read).transpose()?;
    let (mut link, name) = link::open(&args.target, &args.line)?;
    let (info, set) = link::hello(&mut link, &name)?;
    if info.running.is_none() {
        bail!("{name}: the controller runs no tree; deploy one first");
    }
    let next = match (&args.deploy, file) {
        (Some(path), Some(file)) => Some((path, Checked::check(path, file, false, &info, &set, &name)?)),
        _ => None,
    };
    // What the controller reports while the bridge asks it something is kept, in order.
    let mut queue: VecDeque<Seen> = VecDeque::new();
    let mut keep = |r: &Reply<'_>| queue.extend(Seen::of(r));
    let mut running = Running::read(&mut link, &name, info.fingerprint, &mut keep)?;
    // Said once: the names Groot2 gets are ids.
    let mut noted = false;
    note(&running, &mut noted)?;
    let server = Server::start(&listen, &running.log_tree("Groot2")?)?;
    let mut trace = String::new();
    let _ = writeln!(trace, "image {:08x} nodes={}", running.crc, running.nodes.len());
    out!(
        "controller {name}: behavior set {set}, image {:08x}, {}\n\
         Groot2: connect to port {} of this machine ({}); tree UUID {}\n",
        running.crc,
        count(running.nodes.len(), "node"),
        listen.port,
        server.listen(),
        uuid_text(&server.uuid())
    )?;
    let mut keep = |r: &Reply<'_>| queue.extend(Seen::of(r));
    if let Some((path, Checked { image, .. })) = &next {
        match link.deploy(image, args.at_tick, &mut keep).map_err(|e| anyhow::anyhow!("{name}: {e}"))? {
            Verdict::Accepted { swap_at, .. } => {
                let when = swap_at.map_or_else(|| "at the next tick".to_string(), |t| format!("before tick {t}"));
                out!("deployed {}: swaps in {when}\n", path.display())?;
            }
            Verdict::Rejected(fault) => {
                bail!("the controller at {name} rejected {}: {}", path.display(), link::describe(&fault))
            }
        }
    }
    if args.start {
        let tick = link.start(None, args.period, &mut keep).map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
        out!("ticking from tick {tick} every {} ms\n", args.period)?;
    }
    let mut ticks = 0u32;
    'session: loop {
        while let Some(seen) = queue.pop_front() {
            match seen {
                Seen::Status { tick, node, status } => {
                    server.change(usize::from(node), status);
                    let _ = writeln!(trace, "status {tick} {node} {}", status.name());
                }
                Seen::Tick { tick, status, changes, micros } => {
                    let _ = writeln!(trace, "tick {tick} {} changes={changes} us={micros}", status.name());
                    ticks += 1;
                    if args.ticks.is_some_and(|t| ticks >= t) {
                        break 'session;
                    }
                }
                Seen::Swapped { tick, crc, nodes, halted } => {
                    let _ = writeln!(trace, "swap {tick} image={crc:08x} nodes={nodes} halted={halted}");
                    // The new tree's changes come after Swapped: they wait in the queue.
                    let mut keep = |r: &Reply<'_>| queue.extend(Seen::of(r));
                    running = Running::read(&mut link, &name, info.fingerprint, &mut keep)?;
                    note(&running, &mut noted)?;
                    let uuid = server.swap(&running.log_tree("Groot2")?);
                    out!(
                        "swap before tick {tick}: image {crc:08x}, {} ({} of the old tree halted); \
                         Groot2 gets it as tree UUID {}\n",
                        count(nodes, "node"),
                        count(halted, "action"),
                        uuid_text(&uuid)
                    )?;
                }
                Seen::Garbled(code) => {
                    let _ = writeln!(trace, "garbled {code}");
                }
            }
        }
        say_events(&server)?;
        match link.next(Instant::now() + Duration::from_millis(200), "status") {
            Ok(reply) => queue.extend(Seen::of(&reply)),
            Err(LinkError::Timeout { .. }) => {}
            Err(LinkError::Closed) => break,
            Err(e) => bail!("{name}: {e}"),
        }
    }
    say_events(&server)?;
    if let Some(path) = &args.trace {
        output::write_whole(path, trace.as_bytes())?;
    }
    out!("{} watched\n", count(ticks, "tick"))?;
    Ok(())
}

/// `--groot2 [PORT]` and its pacing, for runs the host simulates.
#[derive(clap::Args, Debug)]
pub struct Serve {
    /// Serve the run to Groot2 as it runs, on PORT or HOST:PORT (1667 when none is
    /// given; the publish socket takes the next port). Each tree the run makes (the
    /// planner's expansions) is served under a new tree UUID.
    #[arg(long, value_name = "[HOST:]PORT", num_args = 0..=1, default_missing_value = "1667")]
    pub groot2: Option<String>,
    /// With --groot2: one tick per tick of the simulated clock (100 ms), the default.
    #[arg(long, requires = "groot2", conflicts_with = "period")]
    pub realtime: bool,
    /// With --groot2: milliseconds between ticks instead (0: as fast as the run goes).
    #[arg(long, value_name = "MS", requires = "groot2")]
    pub period: Option<u64>,
    /// With --groot2: how long to go on serving the last tree and its statuses after the
    /// run ends, in seconds (default: until Ctrl-C).
    #[arg(long, value_name = "SECONDS", requires = "groot2")]
    pub groot2_linger: Option<u64>,
}

impl Serve {
    /// The watch to run with: off without --groot2; else listening, having said where.
    ///
    /// # Errors
    /// A bad address or a port that cannot be listened on.
    pub fn watch(&self) -> anyhow::Result<Watch> {
        let Some(listen) = &self.groot2 else { return Ok(Watch::off()) };
        let listen = Listen::parse(listen).map_err(|e| anyhow::anyhow!("--groot2: {e}"))?;
        let ms = self.period.unwrap_or(u64::from(sim_host::episode::TICK_MS));
        let watch = Watch::new(&listen, Duration::from_millis(ms))?;
        output::stderr(
            format!("Groot2: connect to port {} of this machine ({}); {ms} ms a tick\n", listen.port, listen)
                .as_bytes(),
        )?;
        Ok(watch)
    }

    /// After the run: a tree Groot2 could not be given is an error; otherwise the last
    /// state is served on for --groot2-linger seconds, or until Ctrl-C.
    ///
    /// # Errors
    /// A tree with a kind BehaviorTree.CPP does not have, or stderr failing.
    pub fn finish(&self, watch: &Watch) -> anyhow::Result<()> {
        let Some(server) = watch.server() else { return Ok(()) };
        if let Some(e) = watch.error() {
            bail!("{e}");
        }
        let trees = watch.served().len();
        let linger =
            self.groot2_linger.map_or_else(|| "until Ctrl-C".to_string(), |s| format!("for {}", count(s, "second")));
        output::stderr(
            format!("Groot2: the run is over ({} served); its last state stays up {linger}\n", count(trees, "tree"))
                .as_bytes(),
        )?;
        let until = self.groot2_linger.map(|s| Instant::now() + Duration::from_secs(s));
        while until.is_none_or(|t| Instant::now() < t) {
            std::thread::sleep(Duration::from_millis(100));
            for e in server.events() {
                let line = match e {
                    Event::Connected => "Groot2 connected\n".to_string(),
                    Event::Gone => "Groot2 gone (no request for 5 s)\n".to_string(),
                    Event::Fault(f) => format!("Groot2 socket: {f}\n"),
                };
                output::stderr(line.as_bytes())?;
            }
        }
        Ok(())
    }
}
