//! `sim-host monitor --port PATH|--tcp HOST:PORT`: the running tree, live.

use std::io::{IsTerminal as _, Write};
use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::bail;
use bt_core::NodeStatus;
use crossterm::{cursor, terminal};
use sim_host::session::Event;
use sim_host::text::count;

use super::link::{self, Line, Target};
use super::output;
use super::watch::{self, Live, Recording};

#[derive(clap::Args, Debug)]
#[command(
    long_about = "Connects to a running controller, reads its tree back over the link, \
    and shows it with each node's live status, from the status changes the controller \
    reports as it ticks: redrawn in place on a terminal (the py_trees-style view of \
    `inspect`), one line per tick otherwise. A deployment swapping in a new tree is \
    followed: the new tree is read and drawn.\n\n\
    --trace FILE records the session, one line per status change, tick and swap; the \
    file is written when the session ends (--ticks, or the link closing).\n\n\
    --btlog FILE.btlog records it as a Groot2 replay log (BehaviorTree.CPP's FileLogger2 \
    format): the tree as Groot2 numbers it, then every status change the controller \
    reported, back to Idle included, at tick × --period on the log's clock. A log holds \
    one tree, so each tree swapped in gets its own file: FILE-2.btlog, FILE-3.btlog, ...",
    after_help = "Examples:\n  sim-host monitor --tcp 127.0.0.1:4321 --start          # QEMU\n  \
    sim-host monitor --port /dev/ttyACM0 --ticks 600 --trace run.txt"
)]
pub struct Args {
    #[command(flatten)]
    pub target: Target,
    #[command(flatten)]
    pub line: Line,
    /// Start the controller ticking (every --period ms) before watching.
    #[arg(long)]
    pub start: bool,
    /// Milliseconds between ticks with --start (0: back to back). The tree's clock
    /// (what Timeout and Delay measure) advances by this much per tick.
    #[arg(long, default_value_t = 100)]
    pub period: u16,
    /// End after this many ticks (default: until the link closes or Ctrl-C).
    #[arg(long)]
    pub ticks: Option<u32>,
    /// Record the session as a plain trace file.
    #[arg(long, value_name = "FILE")]
    pub trace: Option<PathBuf>,
    /// Record the session as a Groot2 replay log (one file per tree; see above).
    #[arg(long, value_name = "FILE.btlog")]
    pub btlog: Option<PathBuf>,
}

/// Writes what `out` gathered to stdout and empties it.
fn flush(out: &mut Vec<u8>) -> Result<(), output::WriteError> {
    if !out.is_empty() {
        output::stdout(out)?;
        out.clear();
    }
    Ok(())
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let (mut link, name) = link::open(&args.target, &args.line)?;
    let (info, set) = link::hello(&mut link, &name)?;
    if info.running.is_none() {
        bail!("{name}: the controller runs no tree; deploy one first");
    }
    let mut live = Live::read(&mut link, &name, info.fingerprint)?;
    let mut record = Recording::new(args.btlog.as_deref(), args.period);
    // Lines are gathered here and written through `output` after each event, so a
    // closed or full stdout is an error like anywhere else (a broken pipe ends quietly).
    let mut out: Vec<u8> = Vec::new();
    let tty = std::io::stdout().is_terminal();
    writeln!(
        out,
        "controller {name}: behavior set {set}, image {:08x}, {}",
        live.crc,
        count(live.nodes.len(), "node")
    )?;
    record.tree(&mut out, 0, &live)?;
    if args.start {
        let tick = link.start(None, args.period).map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
        writeln!(out, "ticking from tick {tick} every {} ms", args.period)?;
    }
    flush(&mut out)?;
    let mut drawn = 0usize;
    let mut ticks = 0u32;
    loop {
        let event = match link.next(Instant::now() + Duration::from_secs(3600)) {
            Ok(e) => e,
            Err(bt_link::host::LinkError::Closed) => break,
            Err(e) => bail!("{name}: {e}"),
        };
        record.event(&event);
        watch::apply(&mut live, &event);
        match event {
            Event::Tick { tick, root, changes, micros } => {
                let root = NodeStatus::from(root);
                if tty {
                    if drawn > 0 {
                        // (`MoveUp(0)` would move one line: terminals read 0 as 1.)
                        crossterm::queue!(out, cursor::MoveUp(drawn as u16))?;
                    }
                    crossterm::queue!(out, terminal::Clear(terminal::ClearType::FromCursorDown))?;
                    writeln!(out, "tick {tick}: {} ({}, {micros} µs)", root.name(), count(changes.len(), "change"))?;
                    let lines = live.lines();
                    for l in &lines {
                        writeln!(out, "{l}")?;
                    }
                    drawn = lines.len() + 1;
                } else {
                    let list: Vec<String> = changes.iter().map(|(n, s)| format!("{n}:{}", watch::letter(*s))).collect();
                    let list = if list.is_empty() { "-".to_string() } else { list.join(" ") };
                    writeln!(out, "tick {tick} {} {list}", root.name())?;
                }
                ticks += 1;
                if args.ticks.is_some_and(|t| ticks >= t) {
                    break;
                }
            }
            Event::Swapped { tick, image, halted, .. } => {
                live = Live::read(&mut link, &name, info.fingerprint)?;
                record.tree(&mut out, tick, &live)?;
                writeln!(
                    out,
                    "swap before tick {tick}: image {:08x}, {} ({} of the old tree halted)",
                    image.crc,
                    count(image.nodes, "node"),
                    count(halted, "action")
                )?;
                drawn = 0;
            }
            Event::Lost { tick, frames } => {
                writeln!(
                    out,
                    "tick {tick}: the controller dropped {} its link could not carry; statuses may be stale \
                     until their nodes change",
                    count(frames, "status frame")
                )?;
                drawn = 0;
            }
            Event::Stopped { .. } | Event::Garbled(_) => {}
        }
        flush(&mut out)?;
    }
    record.finish(&mut out, args.trace.as_deref())?;
    flush(&mut out)?;
    Ok(())
}
