//! `sim-host monitor --port PATH|--tcp HOST:PORT`: the running tree, live.

use std::fmt;
use std::io::{IsTerminal as _, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::bail;
use bt_core::{Catalog, NodeKind, NodeStatus};
use bt_link::Reply;
use bt_link::host::Client;
use btcpp::btlog::LogWriter;
use btcpp::btlog::replay::status as btlog_status;
use crossterm::{cursor, terminal};

use super::link::{self, Io, Line, Running, Target};
use super::output;
use sim_host::text::count;

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

/// The tree the controller runs, with live statuses.
struct Live {
    running: Running,
    status: Vec<NodeStatus>,
}

impl Live {
    fn read(link: &mut Client<Box<dyn Io>>, name: &str, fingerprint: u64) -> anyhow::Result<Self> {
        let running = Running::read(link, name, fingerprint, &mut |_| {})?;
        let status = vec![NodeStatus::Idle; running.nodes.len()];
        Ok(Self { running, status })
    }

    /// A Groot2 replay log of this tree, its clock starting at `usec`.
    fn log(&self, usec: i64) -> anyhow::Result<Groot> {
        let tree =
            self.running.log_tree("--btlog").map_err(|e| anyhow::anyhow!("{e}; record it with --trace instead"))?;
        let mut uid = vec![None; self.running.nodes.len()];
        for n in &tree.nodes {
            if let Some(slot) = n.core.and_then(|c| uid.get_mut(c)) {
                *slot = Some(n.uid);
            }
        }
        Ok(Groot { writer: LogWriter::new(&tree, usec), uid })
    }

    /// Lines of the py_trees-style view with status marks.
    fn lines(&self) -> Vec<String> {
        let mut ends: Vec<usize> = Vec::new();
        let mut out = Vec::with_capacity(self.running.nodes.len());
        let (nodes, values, catalog) = (&self.running.nodes, &self.running.values, self.running.catalog.as_ref());
        for (i, node) in nodes.iter().enumerate() {
            while ends.last().is_some_and(|&e| e <= i) {
                ends.pop();
            }
            let mark = match self.status.get(i) {
                Some(NodeStatus::Success) => " [✓]",
                Some(NodeStatus::Failure) => " [✕]",
                Some(NodeStatus::Running) => " [*]",
                _ => "",
            };
            out.push(format!("{}{}{mark}", "    ".repeat(ends.len()), Label(catalog, node.kind(), values)));
            if !matches!(node.kind(), NodeKind::Condition(_) | NodeKind::Action(_)) {
                ends.push(i + usize::from(node.size()));
            }
        }
        out
    }
}

/// A Groot2 replay log being recorded.
struct Groot {
    writer: LogWriter,
    /// BehaviorTree.CPP's uid of each bt-core node.
    uid: Vec<Option<u16>>,
}

impl Groot {
    fn change(&mut self, usec: i64, node: u16, status: NodeStatus) {
        if let Some(&Some(uid)) = self.uid.get(usize::from(node)) {
            let s = match status {
                NodeStatus::Idle => btlog_status::IDLE,
                NodeStatus::Running => btlog_status::RUNNING,
                NodeStatus::Success => btlog_status::SUCCESS,
                NodeStatus::Failure => btlog_status::FAILURE,
            };
            self.writer.transition(usec, uid, s);
        }
    }
}

/// The file of the `n`th tree's log (from 1): `run.btlog`, `run-2.btlog`, ...
fn numbered(path: &Path, n: u32) -> PathBuf {
    if n <= 1 {
        return path.to_path_buf();
    }
    let stem = path.file_stem().map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let name = match path.extension() {
        Some(ext) => format!("{stem}-{n}.{}", ext.to_string_lossy()),
        None => format!("{stem}-{n}"),
    };
    path.with_file_name(name)
}

struct Label<'a>(&'a dyn Catalog, &'a NodeKind, &'a [u16]);

impl fmt::Display for Label<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        bt_core::render::write_label(f, self.0, self.1, self.2)
    }
}

fn letter(s: NodeStatus) -> char {
    match s {
        NodeStatus::Idle => 'I',
        NodeStatus::Success => 'S',
        NodeStatus::Failure => 'F',
        NodeStatus::Running => 'R',
    }
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
    // Microseconds on the log's clock at tick `t`.
    let usec = |t: u32| i64::from(t) * i64::from(args.period) * 1000;
    let mut groot = match &args.btlog {
        Some(_) => Some(live.log(0)?),
        None => None,
    };
    let mut logs_written: u32 = 0;
    // Lines are gathered here and written through `output` after each message, so a
    // closed or full stdout is an error like anywhere else (a broken pipe ends quietly).
    let mut out: Vec<u8> = Vec::new();
    let tty = std::io::stdout().is_terminal();
    let mut trace = String::new();
    writeln!(
        out,
        "controller {name}: behavior set {set}, image {:08x}, {}",
        live.running.crc,
        count(live.running.nodes.len(), "node")
    )?;
    trace.push_str(&format!("image {:08x} nodes={}\n", live.running.crc, live.running.nodes.len()));
    if args.start {
        let tick = link.start(None, args.period, &mut |_| {}).map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
        writeln!(out, "ticking from tick {tick} every {} ms", args.period)?;
    }
    flush(&mut out)?;
    let mut drawn = 0usize;
    let mut changes: Vec<(u16, NodeStatus)> = Vec::new();
    let mut ticks = 0u32;
    loop {
        let reply = match link.next(Instant::now() + Duration::from_secs(3600), "status") {
            Ok(r) => r,
            Err(bt_link::host::LinkError::Closed) => break,
            Err(e) => bail!("{name}: {e}"),
        };
        match reply {
            Reply::Status { tick, node, status } => {
                let status = NodeStatus::from(status);
                if let Some(s) = live.status.get_mut(usize::from(node)) {
                    *s = status;
                }
                changes.push((node, status));
                if let Some(g) = &mut groot {
                    g.change(usec(tick), node, status);
                }
                trace.push_str(&format!("status {tick} {node} {}\n", status.name()));
            }
            Reply::Tick { tick, status, changes: n, micros } => {
                let root = status;
                trace.push_str(&format!("tick {tick} {} changes={n} us={micros}\n", root.name()));
                if tty {
                    if drawn > 0 {
                        // (`MoveUp(0)` would move one line: terminals read 0 as 1.)
                        crossterm::queue!(out, cursor::MoveUp(drawn as u16))?;
                    }
                    crossterm::queue!(out, terminal::Clear(terminal::ClearType::FromCursorDown))?;
                    writeln!(out, "tick {tick}: {} ({}, {micros} µs)", root.name(), count(n, "change"))?;
                    let lines = live.lines();
                    for l in &lines {
                        writeln!(out, "{l}")?;
                    }
                    drawn = lines.len() + 1;
                } else {
                    let list: Vec<String> = changes.iter().map(|(n, s)| format!("{n}:{}", letter(*s))).collect();
                    let list = if list.is_empty() { "-".to_string() } else { list.join(" ") };
                    writeln!(out, "tick {tick} {} {list}", root.name())?;
                }
                changes.clear();
                ticks += 1;
                if args.ticks.is_some_and(|t| ticks >= t) {
                    break;
                }
            }
            Reply::Swapped { tick, image, halted } => {
                trace.push_str(&format!("swap {tick} image={:08x} nodes={} halted={halted}\n", image.crc, image.nodes));
                live = Live::read(&mut link, &name, info.fingerprint)?;
                if let (Some(path), Some(g)) = (&args.btlog, groot.take()) {
                    logs_written += 1;
                    write_log(&mut out, path, logs_written, g)?;
                    groot = Some(live.log(usec(tick))?);
                }
                writeln!(
                    out,
                    "swap before tick {tick}: image {:08x}, {} ({} of the old tree halted)",
                    image.crc,
                    count(image.nodes, "node"),
                    count(halted, "action")
                )?;
                drawn = 0;
            }
            Reply::Garbled { fault } => {
                trace.push_str(&format!("garbled {}\n", fault.code()));
            }
            _ => {}
        }
        flush(&mut out)?;
    }
    if let Some(path) = &args.trace {
        output::write_whole(path, trace.as_bytes())?;
    }
    if let (Some(path), Some(g)) = (&args.btlog, groot) {
        write_log(&mut out, path, logs_written + 1, g)?;
    }
    flush(&mut out)?;
    Ok(())
}

fn write_log(out: &mut impl Write, path: &Path, n: u32, g: Groot) -> anyhow::Result<()> {
    let file = numbered(path, n);
    let bytes = g.writer.into_bytes();
    output::write_file(&file, &bytes, output::Content::Binary("a replay log"))?;
    writeln!(out, "btlog {} ({}; open it in Groot2)", file.display(), count(bytes.len(), "byte"))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_tree_after_the_first_gets_a_numbered_log() {
        let p = Path::new("/tmp/logs/run.btlog");
        assert_eq!(numbered(p, 1), Path::new("/tmp/logs/run.btlog"));
        assert_eq!(numbered(p, 2), Path::new("/tmp/logs/run-2.btlog"));
        assert_eq!(numbered(Path::new("session"), 3), Path::new("session-3"));
    }
}
