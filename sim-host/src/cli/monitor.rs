//! `sim-host monitor --port PATH|--tcp HOST:PORT`: the running tree, live.

use std::fmt;
use std::io::{IsTerminal as _, Write};
use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::bail;
use bt_core::{Catalog, Node, NodeKind, NodeStatus, Tree};
use bt_link::Reply;
use bt_link::host::Client;
use crossterm::{cursor, terminal};

use super::link::{self, Io, Line, Target};
use super::{catalogs, output};

/// Most levels a tree may have to be shown.
const DEPTH: usize = 64;

#[derive(clap::Args, Debug)]
#[command(
    long_about = "Connects to a running controller, reads its tree back over the link, \
    and shows it with each node's live status, from the status changes the controller \
    reports as it ticks: redrawn in place on a terminal (the py_trees-style view of \
    `inspect`), one line per tick otherwise. A deployment swapping in a new tree is \
    followed: the new tree is read and drawn.\n\n\
    --trace FILE records the session, one line per status change, tick and swap; the \
    file is written when the session ends (--ticks, or the link closing).",
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
    /// Milliseconds between ticks with --start.
    #[arg(long, default_value_t = 100)]
    pub period: u16,
    /// End after this many ticks (default: until the link closes or Ctrl-C).
    #[arg(long)]
    pub ticks: Option<u32>,
    /// Record the session as a plain trace file.
    #[arg(long, value_name = "FILE")]
    pub trace: Option<PathBuf>,
}

/// The tree the controller runs, with live statuses.
struct Live {
    nodes: Vec<Node>,
    values: Vec<u16>,
    status: Vec<NodeStatus>,
    catalog: Box<dyn Catalog>,
    crc: u32,
}

impl Live {
    fn read(link: &mut Client<Box<dyn Io>>, name: &str, fingerprint: u64) -> anyhow::Result<Self> {
        let image = link.read_image(&mut |_| {}).map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
        // Names from the image's names section when it has one, else from the known
        // behavior set with this fingerprint.
        let (known, header) = catalogs::for_image(std::path::Path::new(name), &image)?;
        if header.fingerprint != fingerprint {
            bail!("{name}: the image read back is for behavior set {:#018x}", header.fingerprint);
        }
        let mut nodes = vec![Node::EMPTY; usize::from(header.node_count)];
        let mut values = vec![0u16; image.len()];
        let tree: Tree<'_, DEPTH> = bt_core::load_with(&image, known.catalog.as_ref(), &mut nodes, &mut values)
            .map_err(|e| anyhow::anyhow!("{name}: the running image read back does not load: {e}"))?;
        let (nodes, values) = (tree.nodes().to_vec(), tree.values().to_vec());
        let status = vec![NodeStatus::Idle; nodes.len()];
        Ok(Self { nodes, values, status, catalog: known.catalog, crc: bt_link::image_crc(&image) })
    }

    /// Lines of the py_trees-style view with status marks.
    fn lines(&self) -> Vec<String> {
        let mut ends: Vec<usize> = Vec::new();
        let mut out = Vec::with_capacity(self.nodes.len());
        for (i, node) in self.nodes.iter().enumerate() {
            while ends.last().is_some_and(|&e| e <= i) {
                ends.pop();
            }
            let mark = match self.status.get(i) {
                Some(NodeStatus::Success) => " [✓]",
                Some(NodeStatus::Failure) => " [✕]",
                Some(NodeStatus::Running) => " [*]",
                _ => "",
            };
            out.push(format!(
                "{}{}{mark}",
                "    ".repeat(ends.len()),
                Label(self.catalog.as_ref(), node.kind(), &self.values)
            ));
            if !matches!(node.kind(), NodeKind::Condition(_) | NodeKind::Action(_)) {
                ends.push(i + usize::from(node.size()));
            }
        }
        out
    }
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

pub fn run(args: &Args) -> anyhow::Result<()> {
    let (mut link, name) = link::open(&args.target, &args.line)?;
    let (info, set) = link::hello(&mut link, &name)?;
    if info.running.is_none() {
        bail!("{name}: the controller runs no tree; deploy one first");
    }
    let mut live = Live::read(&mut link, &name, info.fingerprint)?;
    let mut out = std::io::stdout().lock();
    let tty = std::io::stdout().is_terminal();
    let mut trace = String::new();
    writeln!(out, "controller {name}: behavior set {set}, image {:08x}, {} nodes", live.crc, live.nodes.len())?;
    trace.push_str(&format!("image {:08x} nodes={}\n", live.crc, live.nodes.len()));
    if args.start {
        let tick = link.start(None, args.period, &mut |_| {}).map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
        writeln!(out, "ticking from tick {tick} every {} ms", args.period)?;
    }
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
                trace.push_str(&format!("status {tick} {node} {}\n", status.name()));
            }
            Reply::Tick { tick, status, changes: n, micros } => {
                let root = NodeStatus::from(status);
                trace.push_str(&format!("tick {tick} {} changes={n} us={micros}\n", root.name()));
                if tty {
                    if drawn > 0 {
                        // (`MoveUp(0)` would move one line: terminals read 0 as 1.)
                        crossterm::queue!(out, cursor::MoveUp(drawn as u16))?;
                    }
                    crossterm::queue!(out, terminal::Clear(terminal::ClearType::FromCursorDown))?;
                    writeln!(out, "tick {tick}: {} ({n} changes, {micros} µs)", root.name())?;
                    let lines = live.lines();
                    for l in &lines {
                        writeln!(out, "{l}")?;
                    }
                    drawn = lines.len() + 1;
                    out.flush()?;
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
                writeln!(
                    out,
                    "swap before tick {tick}: image {:08x}, {} nodes ({halted} action(s) of the old tree halted)",
                    image.crc, image.nodes
                )?;
                drawn = 0;
            }
            Reply::Garbled { fault } => {
                trace.push_str(&format!("garbled {}\n", fault.code()));
            }
            _ => {}
        }
    }
    if let Some(path) = &args.trace {
        output::write_whole(path, trace.as_bytes())?;
    }
    Ok(())
}
