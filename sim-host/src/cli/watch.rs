//! What `monitor` and `blend` share on top of the session's events: the running tree with
//! live statuses ([`Live`]) and the session's record (`--trace`, `--btlog`,
//! [`Recording`]).

use std::fmt;
use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::bail;
use bt_core::{Catalog, Node, NodeKind, NodeStatus, Tree};
use btcpp::btlog::replay::status as btlog_status;
use btcpp::btlog::{LogTree, LogWriter};
use sim_host::session::{self, Event, Session};
use sim_host::text::count;

use super::link::Io;
use super::{catalogs, output};
use planner::DEPTH;

/// The tree the controller runs, with live statuses.
pub struct Live {
    /// Its nodes.
    pub nodes: Vec<Node>,
    /// Its value table.
    pub values: Vec<u16>,
    /// Each node's last status reported.
    pub status: Vec<NodeStatus>,
    /// Names: from the image's names section, else the known behavior set's.
    pub catalog: Box<dyn Catalog>,
    /// The CRC-32 naming the image on the link.
    pub crc: u32,
    /// What to say about the names (none in the image, and the set unknown: ids).
    pub note: Option<String>,
}

impl Live {
    /// A tree the host knows (it deployed it), every node Idle.
    pub fn new(nodes: Vec<Node>, values: Vec<u16>, catalog: Box<dyn Catalog>, crc: u32) -> Self {
        let status = vec![NodeStatus::Idle; nodes.len()];
        Self { nodes, values, status, catalog, crc, note: None }
    }

    /// The running tree read back from the controller, named from the image's names
    /// section when it has one, else from the known behavior set with its fingerprint.
    pub fn read(link: &mut Session<Box<dyn Io>>, name: &str, fingerprint: u64) -> anyhow::Result<Self> {
        let image = link.read_image().map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
        let (known, header) = catalogs::for_image(Path::new(name), &image)?;
        if header.fingerprint != fingerprint {
            bail!("{name}: the image read back is for behavior set {:#018x}", header.fingerprint);
        }
        let mut nodes = vec![Node::EMPTY; usize::from(header.node_count)];
        let mut values = vec![0u16; image.len()];
        let tree: Tree<'_, DEPTH> = bt_core::load_with(&image, known.catalog.as_ref(), &mut nodes, &mut values)
            .map_err(|e| anyhow::anyhow!("{name}: the running image read back does not load: {e}"))?;
        let (nodes, values) = (tree.nodes().to_vec(), tree.values().to_vec());
        Ok(Self { note: known.note, ..Self::new(nodes, values, known.catalog, bt_link::image_crc(&image)) })
    }

    /// The tree as BehaviorTree.CPP instantiates it (for Groot2), `what` naming the
    /// option that needs it.
    ///
    /// # Errors
    /// A kind BehaviorTree.CPP has no equivalent for.
    pub fn log_tree(&self, what: &str) -> anyhow::Result<LogTree> {
        LogTree::with_values(&self.nodes, &self.values, self.catalog.as_ref())
            .map_err(|e| anyhow::anyhow!("{what}: image {:08x}: {e}", self.crc))
    }

    /// Lines of the py_trees-style view with status marks.
    pub fn lines(&self) -> Vec<String> {
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

/// A status's letter in one-line views: `I`, `S`, `F`, `R`.
pub fn letter(s: NodeStatus) -> char {
    match s {
        NodeStatus::Idle => 'I',
        NodeStatus::Success => 'S',
        NodeStatus::Failure => 'F',
        NodeStatus::Running => 'R',
    }
}

/// A Groot2 replay log being recorded.
struct Groot {
    writer: LogWriter,
    /// BehaviorTree.CPP's uid of each bt-core node.
    uid: Vec<Option<u16>>,
}

impl Groot {
    /// A log of `live`'s tree, its clock starting at `usec`.
    fn new(live: &Live, usec: i64) -> anyhow::Result<Self> {
        let tree = live.log_tree("--btlog").map_err(|e| anyhow::anyhow!("{e}; record it with --trace instead"))?;
        let mut uid = vec![None; live.nodes.len()];
        for n in &tree.nodes {
            if let Some(slot) = n.core.and_then(|c| uid.get_mut(c)) {
                *slot = Some(n.uid);
            }
        }
        Ok(Self { writer: LogWriter::new(&tree, usec), uid })
    }

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

/// A session's record: the plain trace (`--trace`: one line per status change, tick and
/// swap) and the Groot2 replay logs (`--btlog`: one file per tree, tick × period on the
/// log's clock). Both are written when the session ends.
pub struct Recording {
    trace: String,
    btlog: Option<PathBuf>,
    groot: Option<Groot>,
    logs_written: u32,
    period_ms: u16,
}

impl Recording {
    /// A record of a session ticking every `period_ms`, with a Groot2 log when `btlog`
    /// names one.
    pub fn new(btlog: Option<&Path>, period_ms: u16) -> Self {
        Self { trace: String::new(), btlog: btlog.map(Path::to_path_buf), groot: None, logs_written: 0, period_ms }
    }

    fn usec(&self, tick: u32) -> i64 {
        i64::from(tick) * i64::from(self.period_ms) * 1000
    }

    /// The tree `live` runs from tick `tick` on: `image` line in the trace; with
    /// `--btlog`, the log of the tree before it is written and a new one begins.
    pub fn tree(&mut self, out: &mut impl Write, tick: u32, live: &Live) -> anyhow::Result<()> {
        if self.trace.is_empty() {
            self.trace.push_str(&format!("image {:08x} nodes={}\n", live.crc, live.nodes.len()));
        }
        if let Some(path) = self.btlog.clone() {
            if let Some(g) = self.groot.take() {
                self.logs_written += 1;
                write_log(out, &path, self.logs_written, g)?;
            }
            self.groot = Some(Groot::new(live, self.usec(tick))?);
        }
        Ok(())
    }

    /// Records an event: its status changes, then the tick, swap or stop.
    pub fn event(&mut self, event: &Event) {
        let changes = match event {
            Event::Tick { tick, changes, .. }
            | Event::Swapped { tick, changes, .. }
            | Event::Stopped { tick, changes } => Some((*tick, changes)),
            Event::Garbled(_) | Event::Lost { .. } => None,
        };
        if let Some((tick, changes)) = changes {
            let usec = self.usec(tick);
            for &(node, status) in changes {
                if let Some(g) = &mut self.groot {
                    g.change(usec, node, status);
                }
                self.trace.push_str(&format!("status {tick} {node} {}\n", status.name()));
            }
        }
        let line = match event {
            Event::Tick { tick, root, changes, micros } => {
                format!("tick {tick} {} changes={} us={micros}", NodeStatus::from(*root).name(), changes.len())
            }
            Event::Swapped { tick, image, halted, .. } => {
                format!("swap {tick} image={:08x} nodes={} halted={halted}", image.crc, image.nodes)
            }
            Event::Stopped { tick, changes } => format!("stop {tick} changes={}", changes.len()),
            Event::Garbled(fault) => format!("garbled {}", fault.code()),
            Event::Lost { tick, frames } => format!("lost {tick} frames={frames}"),
        };
        self.trace.push_str(&line);
        self.trace.push('\n');
    }

    /// A line of the caller's own in the trace (`blend`'s expansions).
    pub fn note(&mut self, line: &str) {
        self.trace.push_str(line);
        self.trace.push('\n');
    }

    /// Writes the trace to `trace` (if given) and the last tree's replay log.
    pub fn finish(mut self, out: &mut impl Write, trace: Option<&Path>) -> anyhow::Result<()> {
        if let Some(path) = trace {
            output::write_whole(path, self.trace.as_bytes())?;
        }
        if let (Some(path), Some(g)) = (self.btlog.take(), self.groot.take()) {
            write_log(out, &path, self.logs_written + 1, g)?;
        }
        Ok(())
    }
}

fn write_log(out: &mut impl Write, path: &Path, n: u32, g: Groot) -> anyhow::Result<()> {
    let file = numbered(path, n);
    let bytes = g.writer.into_bytes();
    output::write_file(&file, &bytes, output::Content::Binary("a replay log"))?;
    writeln!(out, "btlog {} ({}; open it in Groot2)", file.display(), count(bytes.len(), "byte"))?;
    Ok(())
}

/// Applies an event's status changes to the tree they belong to.
pub fn apply(live: &mut Live, event: &Event) {
    match event {
        Event::Tick { changes, .. } | Event::Swapped { changes, .. } | Event::Stopped { changes, .. } => {
            session::apply(&mut live.status, changes);
        }
        Event::Garbled(_) | Event::Lost { .. } => {}
    }
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
