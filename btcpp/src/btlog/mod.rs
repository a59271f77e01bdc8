//! Groot2 replay logs: the `.btlog` files BehaviorTree.CPP's `FileLogger2` writes.
//!
//! # Format (`BTCPP4-FileLogger2`, protocol 1)
//!
//! | bytes | what |
//! |---|---|
//! | 18 | the ASCII text `BTCPP4-FileLogger2` |
//! | 1 | protocol version, 1 |
//! | 4 | length `n` of the XML, `i32` little-endian |
//! | `n` | the tree as XML: every `<BehaviorTree>` instance with each node's `name`, `_uid` and ports (SubTree nodes with `_fullpath`), then `<TreeNodesModel>` of every registered node type |
//! | 8 | the first timestamp, microseconds, `i64` little-endian |
//! | 9 each | transitions: microseconds since the first timestamp (6 bytes, little-endian), the node's uid (`u16` little-endian), its new status (1 byte: 0 Idle, 1 Running, 2 Success, 3 Failure) |
//!
//! Every status change of every node is a transition, the changes back to Idle
//! included, in the order the nodes made them ([`replay`]).
//!
//! Logs written here take their timestamps from the simulated clock, so the same run
//! gives the same bytes; the first timestamp is the clock's start.

pub mod replay;
pub mod run;
pub mod stdmap;
pub mod tree;

use std::fmt::Write as _;

use crate::kinds;
use crate::xml::write::escape;

pub use replay::{Leaves, Replay, Ticking};
pub use run::{Mismatch, RunLog, status_of};
pub use tree::{LogTree, NotExpressible};

/// The first bytes of every log.
pub const MAGIC: &[u8; 18] = b"BTCPP4-FileLogger2";

/// The models of BehaviorTree.CPP's built-in nodes as 4.10.0 writes them (recorded by
/// `btcpp/tools/record-builtin-models.sh`).
const BUILTIN_MODELS: &str = include_str!("builtin-models.xml");

/// The built-in model entries: (ID, the entry's lines).
fn builtin_models() -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = Vec::new();
    let body = BUILTIN_MODELS
        .split_once("<TreeNodesModel>\n")
        .and_then(|(_, rest)| rest.split_once("    </TreeNodesModel>"))
        .map_or("", |(b, _)| b);
    for line in body.lines() {
        let starts_entry = line.starts_with("        <") && !line.starts_with("        </");
        if starts_entry {
            let id = line.split("ID=\"").nth(1).and_then(|r| r.split('"').next()).unwrap_or("").to_string();
            out.push((id, String::new()));
        }
        if let Some((_, text)) = out.last_mut() {
            text.push_str(line);
            text.push('\n');
        }
    }
    out
}

impl LogTree {
    /// The XML BehaviorTree.CPP's FileLogger2 writes for this tree (tinyxml2's layout:
    /// four spaces per level, attributes in BehaviorTree.CPP's order).
    #[must_use]
    pub fn xml(&self) -> String {
        let mut o = String::from("<root BTCPP_format=\"4\">\n");
        // One <BehaviorTree> per instance: the main tree, then each SubTree node's.
        let mut roots: Vec<(String, String, usize)> = Vec::new();
        if !self.nodes.is_empty() {
            roots.push((self.main.clone(), String::new(), 0));
        }
        for n in &self.nodes {
            if let (Some((_, instance)), Some(&child)) = (&n.subtree, n.children.first()) {
                roots.push((n.name.clone(), instance.clone(), child));
            }
        }
        for (id, path, root) in roots {
            let _ = writeln!(o, "    <BehaviorTree ID=\"{}\" _fullpath=\"{}\">", escape(&id), escape(&path));
            self.node_xml(root, 2, &mut o);
            o.push_str("    </BehaviorTree>\n");
        }
        o.push_str("    <TreeNodesModel>\n");
        let mut entries = builtin_models();
        // The node types the factory does not register itself, when the tree has them:
        // Nav2's (a Nav2 factory registers every plugin; the log of one without Nav2
        // lists the nodes it has) and ManualSelector, which a program registers to load
        // a tree with one.
        for entry in kinds::TABLE {
            let Some(text) = entry.log_model else { continue };
            if self.nodes.iter().any(|n| n.element == entry.id && n.subtree.is_none()) {
                entries.push((entry.id.to_string(), text.to_string()));
            }
        }
        for m in &self.models {
            if entries.iter().any(|(id, _)| *id == m.id) {
                continue;
            }
            let mut text = format!("        <{} ID=\"{}\"", m.tag, escape(&m.id));
            if m.ports.is_empty() {
                text.push_str("/>\n");
            } else {
                text.push_str(">\n");
                for name in stdmap::order(m.ports.iter().map(|p| p.1.as_str())) {
                    let Some((tag, _, ty, default)) = m.ports.iter().find(|p| p.1 == name) else { continue };
                    let _ = write!(text, "            <{tag} name=\"{}\" type=\"{}\"", escape(&name), escape(ty));
                    if let Some(d) = default {
                        let _ = write!(text, " default=\"{}\"", escape(d));
                    }
                    text.push_str("/>\n");
                }
                let _ = writeln!(text, "        </{}>", m.tag);
            }
            entries.push((m.id.clone(), text));
        }
        entries.sort_by(|a, b| a.0.as_bytes().cmp(b.0.as_bytes()));
        for (_, text) in entries {
            o.push_str(&text);
        }
        o.push_str("    </TreeNodesModel>\n</root>\n");
        o
    }

    fn node_xml(&self, i: usize, depth: usize, o: &mut String) {
        let n = &self.nodes[i];
        let pad = "    ".repeat(depth);
        let _ = write!(o, "{pad}<{}", n.element);
        match &n.subtree {
            Some((path, _)) => {
                let _ = write!(o, " ID=\"{}\" _fullpath=\"{}\"", escape(&n.name), escape(path));
            }
            None => {
                let _ = write!(o, " name=\"{}\"", escape(&n.name));
            }
        }
        let _ = write!(o, " _uid=\"{}\"", n.uid);
        for (k, v) in &n.attrs {
            let _ = write!(o, " {k}=\"{}\"", escape(v));
        }
        if n.children.is_empty() || n.subtree.is_some() {
            o.push_str("/>\n");
            return;
        }
        o.push_str(">\n");
        for &c in &n.children {
            self.node_xml(c, depth + 1, o);
        }
        let _ = writeln!(o, "{pad}</{}>", n.element);
    }
}

/// A `.btlog` being written: the header, then transitions as they come.
#[derive(Clone, Debug)]
pub struct LogWriter {
    bytes: Vec<u8>,
    first_usec: i64,
}

impl LogWriter {
    /// A log of `tree` whose clock starts at `first_usec` microseconds.
    #[must_use]
    pub fn new(tree: &LogTree, first_usec: i64) -> Self {
        let xml = tree.xml();
        let mut bytes = Vec::with_capacity(64 + xml.len());
        bytes.extend_from_slice(MAGIC);
        bytes.push(1);
        bytes.extend_from_slice(&i32::try_from(xml.len()).unwrap_or(i32::MAX).to_le_bytes());
        bytes.extend_from_slice(xml.as_bytes());
        bytes.extend_from_slice(&first_usec.to_le_bytes());
        Self { bytes, first_usec }
    }

    /// Node `uid` changed to `status` at `usec` microseconds (same clock as the first
    /// timestamp).
    pub fn transition(&mut self, usec: i64, uid: u16, status: u8) {
        let delta = u64::try_from(usec.saturating_sub(self.first_usec)).unwrap_or(0);
        self.bytes.extend_from_slice(&delta.to_le_bytes()[..6]);
        self.bytes.extend_from_slice(&uid.to_le_bytes());
        self.bytes.push(status);
    }

    /// The log's bytes.
    #[must_use]
    pub fn bytes(&self) -> &[u8] {
        &self.bytes
    }

    /// The log's bytes, taken.
    #[must_use]
    pub fn into_bytes(self) -> Vec<u8> {
        self.bytes
    }
}

/// A `.btlog` read back.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Log {
    /// The XML.
    pub xml: String,
    /// The first timestamp (microseconds).
    pub first_usec: i64,
    /// Transitions: microseconds since the first timestamp, uid, status.
    pub transitions: Vec<(u64, u16, u8)>,
}

/// Why bytes are not a `.btlog`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum LogError {
    /// Not `BTCPP4-FileLogger2` protocol 1.
    #[error("not a BehaviorTree.CPP FileLogger2 log (protocol 1)")]
    NotALog,
    /// Shorter than its header says.
    #[error("log truncated at byte {0}")]
    Truncated(usize),
    /// Transition records that do not fill 9 bytes each.
    #[error("{0} bytes after the last whole transition")]
    Partial(usize),
}

impl Log {
    /// Parses a log.
    ///
    /// # Errors
    /// [`LogError`].
    pub fn parse(bytes: &[u8]) -> Result<Self, LogError> {
        if bytes.len() < 19 || &bytes[..18] != MAGIC || bytes[18] != 1 {
            return Err(LogError::NotALog);
        }
        let take = |at: usize, n: usize| bytes.get(at..at + n).ok_or(LogError::Truncated(bytes.len()));
        let len = usize::try_from(i32::from_le_bytes(take(19, 4)?.try_into().map_err(|_| LogError::NotALog)?))
            .map_err(|_| LogError::NotALog)?;
        let xml = String::from_utf8_lossy(take(23, len)?).into_owned();
        let first_usec = i64::from_le_bytes(take(23 + len, 8)?.try_into().map_err(|_| LogError::NotALog)?);
        let rest = &bytes[31 + len..];
        if !rest.len().is_multiple_of(9) {
            return Err(LogError::Partial(rest.len() % 9));
        }
        let transitions = rest
            .chunks_exact(9)
            .map(|c| {
                let mut t = [0u8; 8];
                t[..6].copy_from_slice(&c[..6]);
                (u64::from_le_bytes(t), u16::from_le_bytes([c[6], c[7]]), c[8])
            })
            .collect();
        Ok(Self { xml, first_usec, transitions })
    }
}
