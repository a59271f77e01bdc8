//! `sim-host groot2 --port PATH|--tcp HOST:PORT [--listen PORT]`: a running controller
//! in Groot2, live, across hot swaps.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::bail;
use bt_link::host::{LinkError, Verdict};
use btcpp::groot2::uuid_text;
use sim_host::groot2::{DEFAULT_PORT, Event, Listen, Server, Watch};
use sim_host::session;
use sim_host::text::count;

use super::deploy::Checked;
use super::link::{self, Line, Target};
use super::output::{self, out};
use super::watch::{Live, Recording};

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

/// The note about a tree's names, on stderr, once a session.
fn note(running: &Live, noted: &mut bool) -> anyhow::Result<()> {
    if let Some(n) = &running.note
        && !*noted
    {
        *noted = true;
        output::stderr(format!("note: {n}\n").as_bytes())?;
    }
    Ok(())
}

/// What happened on the Groot2 socket, as a line.
fn event_line(e: &Event) -> String {
    match e {
        Event::Connected => "Groot2 connected\n".to_string(),
        Event::Gone => "Groot2 gone (no request for 5 s)\n".to_string(),
        Event::Fault(f) => format!("Groot2 socket: {f}\n"),
    }
}

fn say_events(server: &Server) -> anyhow::Result<()> {
    for e in server.events() {
        out!("{}", event_line(&e))?;
    }
    Ok(())
}

/// Tells Groot2's comings and goings on stderr (for commands whose stdout is their own).
///
/// # Errors
/// stderr failing.
pub fn tell_events(server: &Server) -> anyhow::Result<()> {
    for e in server.events() {
        output::stderr(event_line(&e).as_bytes())?;
    }
    Ok(())
}

/// After a run: serves its last state on for `linger` seconds, or until Ctrl-C, having
/// said so.
///
/// # Errors
/// stderr failing.
pub fn hold(server: &Server, linger: Option<u64>, trees: usize) -> anyhow::Result<()> {
    let how = linger.map_or_else(|| "until Ctrl-C".to_string(), |s| format!("for {}", count(s, "second")));
    output::stderr(
        format!("Groot2: the run is over ({} served); its last state stays up {how}\n", count(trees, "tree"))
            .as_bytes(),
    )?;
    let until = linger.map(|s| Instant::now() + Duration::from_secs(s));
    while until.is_none_or(|t| Instant::now() < t) {
        std::thread::sleep(Duration::from_millis(100));
        tell_events(server)?;
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
    // What the controller reports while the bridge asks it something waits in the
    // session, in order.
    let mut running = Live::read(&mut link, &name, info.fingerprint)?;
    // Said once: the names Groot2 gets are ids.
    let mut noted = false;
    note(&running, &mut noted)?;
    let server = Server::start(&listen, &running.log_tree("Groot2")?)?;
    let mut record = Recording::new(None, args.period);
    let mut lines = Vec::new();
    record.tree(&mut lines, 0, &running)?;
    out!(
        "controller {name}: behavior set {set}, image {:08x}, {}\n\
         Groot2: connect to port {} of this machine ({}); tree UUID {}\n",
        running.crc,
        count(running.nodes.len(), "node"),
        listen.port,
        server.listen(),
        uuid_text(&server.uuid())
    )?;
    if let Some((path, Checked { image, .. })) = &next {
        match link.deploy(image, args.at_tick).map_err(|e| anyhow::anyhow!("{name}: {e}"))? {
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
        let tick = link.start(None, args.period).map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
        out!("ticking from tick {tick} every {} ms\n", args.period)?;
    }
    let mut ticks = 0u32;
    loop {
        say_events(&server)?;
        let event = match link.next(Instant::now() + Duration::from_millis(200)) {
            Ok(event) => event,
            Err(LinkError::Timeout { .. }) => continue,
            Err(LinkError::Closed) => break,
            Err(e) => bail!("{name}: {e}"),
        };
        record.event(&event);
        match event {
            session::Event::Tick { changes, .. } => {
                for (node, status) in changes {
                    server.change(usize::from(node), status);
                }
                ticks += 1;
                if args.ticks.is_some_and(|t| ticks >= t) {
                    break;
                }
            }
            session::Event::Stopped { changes, .. } => {
                for (node, status) in changes {
                    server.change(usize::from(node), status);
                }
            }
            session::Event::Swapped { tick, image, halted, changes } => {
                // The old tree's halts, then the new tree under a new UUID; the new
                // tree's changes wait in the session meanwhile.
                for (node, status) in changes {
                    server.change(usize::from(node), status);
                }
                running = Live::read(&mut link, &name, info.fingerprint)?;
                note(&running, &mut noted)?;
                record.tree(&mut lines, tick, &running)?;
                let uuid = server.swap(&running.log_tree("Groot2")?);
                out!(
                    "swap before tick {tick}: image {:08x}, {} ({} of the old tree halted); \
                     Groot2 gets it as tree UUID {}\n",
                    image.crc,
                    count(image.nodes, "node"),
                    count(halted, "action"),
                    uuid_text(&uuid)
                )?;
            }
            session::Event::Garbled(_) | session::Event::Lost { .. } => {}
        }
    }
    say_events(&server)?;
    record.finish(&mut lines, args.trace.as_deref())?;
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
        hold(server, self.groot2_linger, watch.served().len())
    }
}
