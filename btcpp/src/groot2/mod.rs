//! Groot2's live protocol, as BehaviorTree.CPP 4.10's `Groot2Publisher` serves it, with
//! no sockets: [`Publisher`] turns a tree and its status changes into the replies Groot2
//! gets, request by request. A server (sim-host's, over ZeroMQ) passes it the parts of
//! each request and sends back the parts it returns.
//!
//! # The protocol (version 2)
//!
//! Groot2 connects a ZeroMQ REQ socket to the publisher's REP socket (port 1667 by
//! default) and subscribes to its PUB socket (the next port). A request is a multipart
//! message: a 6-byte header — protocol (2), request type (one ASCII byte), a request id
//! (`u32` little-endian) — and, for some types, one more part. A reply starts with a
//! 22-byte header: the request's header with the protocol set to 2, then the tree's
//! 16-byte UUID, which changes when the tree does; then the reply's parts. A refused
//! request gets the two parts `error` and a message instead.
//!
//! | type | request | reply |
//! |---|---|---|
//! | `T` | FULLTREE | the tree XML, as [`LogTree::xml`] writes it (what `FileLogger2` writes) |
//! | `S` | STATUS | 3 bytes per node: uid (`u16` LE), status (0 Idle, 1 Running, 2 Success, 3 Failure; 10 + X: Idle after X) |
//! | `B` | BLACKBOARD, with `;`-separated board names | MessagePack of `{name: board}` for each name the tree has |
//! | `r` | TOGGLE_RECORDING, with `start` or `stop` | `start`: the time, microseconds since 1970, as decimal text |
//! | `t` | GET_TRANSITIONS | 9 bytes per transition since the last call: microseconds since `start` (6 bytes LE), uid, new status |
//! | `D` | HOOKS_DUMP | the hooks as JSON: `[]` here |
//! | `A`, `X` | REMOVE_ALL_HOOKS, DISABLE_ALL_HOOKS | the header only |
//! | `I`, `R`, `U` | HOOK_INSERT, HOOK_REMOVE, BREAKPOINT_UNLOCK | refused: `Request not recognized` |
//!
//! Any other type is refused with `Request not recognized`, a first part that is not 6
//! bytes with `wrong request header`, a BLACKBOARD or TOGGLE_RECORDING without exactly
//! two parts with `must be 2 parts message` — BehaviorTree.CPP's own replies. As in
//! BehaviorTree.CPP the protocol byte of a request is not checked, and the reply says 2.
//!
//! Hooks and breakpoints would stop the controller's tick before a node: this side of
//! the link cannot, so they are refused as BehaviorTree.CPP refuses a request it does not
//! know (as its releases before 4.4 refused recording). A publisher without hooks has
//! none to dump, remove or disable, so those requests succeed. The heartbeat rule
//! (BehaviorTree.CPP disables every hook when no request came for 5 s) therefore
//! disables nothing; [`Publisher::connected`] applies it to tell whether a client is
//! there.
//!
//! Blackboards: a controller reports no blackboard values, so each board named is given
//! as BehaviorTree.CPP gives an empty one (`nil`); a name the tree does not have is left
//! out, and a request naming none of its boards gets `nil`.

use std::collections::{BTreeSet, VecDeque};
use std::fmt::Write as _;

use bt_core::NodeStatus;

use crate::btlog::LogTree;
use crate::btlog::replay::status;

/// The protocol version this module speaks (`kProtocolID`).
pub const PROTOCOL: u8 = 2;
/// Bytes of a request header.
pub const REQUEST_HEADER: usize = 6;
/// Bytes of a reply header.
pub const REPLY_HEADER: usize = REQUEST_HEADER + 16;
/// Transitions kept while recording: older ones are dropped first, as BehaviorTree.CPP
/// drops them.
pub const MAX_TRANSITIONS: usize = 1000;
/// Microseconds without a request after which the client counts as gone (BehaviorTree.CPP's
/// default `max_heartbeat_delay`, 5000 ms).
pub const HEARTBEAT_USEC: i64 = 5_000_000;
/// The name BehaviorTree.CPP gives a refused request of a type it does not serve.
pub const NOT_RECOGNIZED: &str = "Request not recognized";

/// A request's type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RequestType {
    /// `T`: the tree.
    FullTree,
    /// `S`: every node's status.
    Status,
    /// `B`: blackboards.
    Blackboard,
    /// `I`: insert a hook (a breakpoint, or a status to return instead).
    HookInsert,
    /// `R`: remove a hook.
    HookRemove,
    /// `N`: a breakpoint was reached (published, never requested).
    BreakpointReached,
    /// `U`: release a breakpoint.
    BreakpointUnlock,
    /// `D`: the hooks, as JSON.
    HooksDump,
    /// `A`: remove every hook.
    RemoveAllHooks,
    /// `X`: disable every hook.
    DisableAllHooks,
    /// `r`: start or stop recording transitions.
    ToggleRecording,
    /// `t`: the transitions recorded since the last call.
    GetTransitions,
}

impl RequestType {
    /// Every type, in the protocol header's order.
    pub const ALL: [Self; 12] = [
        Self::FullTree,
        Self::Status,
        Self::Blackboard,
        Self::HookInsert,
        Self::HookRemove,
        Self::BreakpointReached,
        Self::BreakpointUnlock,
        Self::HooksDump,
        Self::RemoveAllHooks,
        Self::DisableAllHooks,
        Self::ToggleRecording,
        Self::GetTransitions,
    ];

    /// Its byte on the wire.
    #[must_use]
    pub const fn byte(self) -> u8 {
        match self {
            Self::FullTree => b'T',
            Self::Status => b'S',
            Self::Blackboard => b'B',
            Self::HookInsert => b'I',
            Self::HookRemove => b'R',
            Self::BreakpointReached => b'N',
            Self::BreakpointUnlock => b'U',
            Self::HooksDump => b'D',
            Self::RemoveAllHooks => b'A',
            Self::DisableAllHooks => b'X',
            Self::ToggleRecording => b'r',
            Self::GetTransitions => b't',
        }
    }

    /// The type of a byte, if it is one.
    #[must_use]
    pub fn of(byte: u8) -> Option<Self> {
        Self::ALL.into_iter().find(|t| t.byte() == byte)
    }
}

/// A request header: protocol, type byte, request id.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Header {
    /// The protocol byte as sent.
    pub protocol: u8,
    /// The type byte as sent (see [`RequestType::of`]).
    pub kind: u8,
    /// The request's id.
    pub id: u32,
}

impl Header {
    /// The header of `part`, which must be exactly [`REQUEST_HEADER`] bytes.
    #[must_use]
    pub fn parse(part: &[u8]) -> Option<Self> {
        let &[protocol, kind, a, b, c, d] = part else { return None };
        Some(Self { protocol, kind, id: u32::from_le_bytes([a, b, c, d]) })
    }

    /// Its 6 bytes.
    #[must_use]
    pub fn bytes(self) -> [u8; REQUEST_HEADER] {
        let id = self.id.to_le_bytes();
        [self.protocol, self.kind, id[0], id[1], id[2], id[3]]
    }
}

/// The parts of BehaviorTree.CPP's error reply: `error`, then the message.
#[must_use]
pub fn error_reply(message: &str) -> Vec<Vec<u8>> {
    vec![b"error".to_vec(), message.as_bytes().to_vec()]
}

/// BehaviorTree.CPP's status byte of a bt-core status.
#[must_use]
pub const fn status_code(s: NodeStatus) -> u8 {
    match s {
        NodeStatus::Idle => status::IDLE,
        NodeStatus::Running => status::RUNNING,
        NodeStatus::Success => status::SUCCESS,
        NodeStatus::Failure => status::FAILURE,
    }
}

/// One tree served to Groot2: its XML, its status buffer, and the transitions recorded.
#[derive(Clone, Debug)]
pub struct Publisher {
    uuid: [u8; 16],
    xml: String,
    /// STATUS's payload: uid and status byte per node, in BehaviorTree.CPP's order.
    buffer: Vec<u8>,
    /// Per uid (index uid - 1): the offset of its status byte in `buffer`, and its
    /// status (0 to 3).
    nodes: Vec<(usize, u8)>,
    /// The uid of each bt-core node (none for nodes BehaviorTree.CPP does not have, such
    /// as a guard of scripted attributes).
    core_uid: Vec<Option<u16>>,
    /// The blackboards' names: the main tree's ID, then each SubTree instance's path.
    boards: Vec<String>,
    /// When recording started (microseconds), if it is on.
    recording: Option<i64>,
    transitions: VecDeque<[u8; 9]>,
    last_request: Option<i64>,
}

impl Publisher {
    /// A publisher of `tree` under `uuid`, every node Idle.
    #[must_use]
    pub fn new(tree: &LogTree, uuid: [u8; 16]) -> Self {
        let mut p = Self {
            uuid,
            xml: String::new(),
            buffer: Vec::new(),
            nodes: Vec::new(),
            core_uid: Vec::new(),
            boards: Vec::new(),
            recording: None,
            transitions: VecDeque::new(),
            last_request: None,
        };
        p.load(tree);
        p
    }

    /// Serves `tree` from now on under `uuid`, every node Idle: Groot2 sees the new
    /// UUID in its next reply and asks for the tree again. Recording stays as it was;
    /// the old tree's transitions not yet fetched are dropped (their uids would name
    /// the new tree's nodes).
    pub fn swap(&mut self, tree: &LogTree, uuid: [u8; 16]) {
        self.uuid = uuid;
        self.transitions.clear();
        self.load(tree);
    }

    fn load(&mut self, tree: &LogTree) {
        self.xml = tree.xml();
        let order = status_order(tree);
        self.buffer = Vec::with_capacity(3 * order.len());
        self.nodes = vec![(0, status::IDLE); tree.nodes.len()];
        for i in order {
            let uid = tree.nodes[i].uid;
            self.buffer.extend_from_slice(&uid.to_le_bytes());
            if let Some(slot) = usize::from(uid).checked_sub(1).and_then(|k| self.nodes.get_mut(k)) {
                *slot = (self.buffer.len(), status::IDLE);
            }
            self.buffer.push(status::IDLE);
        }
        let cores = tree.nodes.iter().filter_map(|n| n.core).max().map_or(0, |m| m + 1);
        self.core_uid = vec![None; cores];
        for n in &tree.nodes {
            if let Some(slot) = n.core.and_then(|c| self.core_uid.get_mut(c)) {
                *slot = Some(n.uid);
            }
        }
        self.boards = std::iter::once(tree.main.clone())
            .chain(tree.nodes.iter().filter_map(|n| n.subtree.as_ref().map(|(_, instance)| instance.clone())))
            .collect();
    }

    /// The tree's UUID.
    #[must_use]
    pub const fn uuid(&self) -> [u8; 16] {
        self.uuid
    }

    /// The tree's XML (FULLTREE's payload).
    #[must_use]
    pub fn xml(&self) -> &str {
        &self.xml
    }

    /// STATUS's payload.
    #[must_use]
    pub fn status_buffer(&self) -> &[u8] {
        &self.buffer
    }

    /// The uid BehaviorTree.CPP gives bt-core node `core`, if it has the node.
    #[must_use]
    pub fn uid(&self, core: usize) -> Option<u16> {
        self.core_uid.get(core).copied().flatten()
    }

    /// bt-core node `core` changed to `new` at `usec` microseconds.
    pub fn change(&mut self, core: usize, new: NodeStatus, usec: i64) {
        if let Some(uid) = self.uid(core) {
            self.set(uid, status_code(new), usec);
        }
    }

    /// Node `uid` changed to `new` (BehaviorTree.CPP's status byte, 0 to 4) at `usec`
    /// microseconds. A change to the status it has is none; an unknown uid is ignored.
    pub fn set(&mut self, uid: u16, new: u8, usec: i64) {
        let Some((at, current)) = usize::from(uid).checked_sub(1).and_then(|k| self.nodes.get_mut(k)) else {
            return;
        };
        if *current == new {
            return;
        }
        let shown = if new == status::IDLE { 10 + *current } else { new };
        *current = new;
        if let Some(b) = self.buffer.get_mut(*at) {
            *b = shown;
        }
        if let Some(start) = self.recording {
            let delta = u64::try_from(usec.saturating_sub(start)).unwrap_or(0).to_le_bytes();
            let u = uid.to_le_bytes();
            let t = [delta[0], delta[1], delta[2], delta[3], delta[4], delta[5], u[0], u[1], new];
            self.transitions.push_back(t);
            while self.transitions.len() > MAX_TRANSITIONS {
                self.transitions.pop_front();
            }
        }
    }

    /// Whether a client asked anything within the heartbeat delay before `usec`.
    #[must_use]
    pub fn connected(&self, usec: i64) -> bool {
        self.last_request.is_some_and(|t| usec.saturating_sub(t) < HEARTBEAT_USEC)
    }

    /// Whether transitions are being recorded.
    #[must_use]
    pub const fn recording(&self) -> bool {
        self.recording.is_some()
    }

    /// The reply to the request of `parts`, received at `usec` microseconds since
    /// 1970 (TOGGLE_RECORDING's reply tells that time, as BehaviorTree.CPP does).
    pub fn handle<P: AsRef<[u8]>>(&mut self, parts: &[P], usec: i64) -> Vec<Vec<u8>> {
        self.last_request = Some(usec);
        let Some(header) = parts.first().and_then(|p| Header::parse(p.as_ref())) else {
            return error_reply("wrong request header");
        };
        let mut reply_header = Header { protocol: PROTOCOL, ..header }.bytes().to_vec();
        reply_header.extend_from_slice(&self.uuid);
        let second = parts.get(1).map(AsRef::as_ref);
        let two_parts = parts.len() == 2;
        let payload: Option<Vec<u8>> = match RequestType::of(header.kind) {
            Some(RequestType::FullTree) => Some(self.xml.as_bytes().to_vec()),
            Some(RequestType::Status) => Some(self.buffer.clone()),
            Some(RequestType::Blackboard) => match second {
                Some(names) if two_parts => Some(self.blackboards(names)),
                _ => return error_reply("must be 2 parts message"),
            },
            Some(RequestType::ToggleRecording) => match second {
                Some(b"start") if two_parts => {
                    self.recording = Some(usec);
                    self.transitions.clear();
                    Some(usec.to_string().into_bytes())
                }
                Some(b"stop") if two_parts => {
                    self.recording = None;
                    None
                }
                Some(_) if two_parts => None,
                _ => return error_reply("must be 2 parts message"),
            },
            Some(RequestType::GetTransitions) => Some(self.transitions.drain(..).flatten().collect()),
            Some(RequestType::HooksDump) => Some(b"[]".to_vec()),
            Some(RequestType::RemoveAllHooks | RequestType::DisableAllHooks) => None,
            Some(
                RequestType::HookInsert
                | RequestType::HookRemove
                | RequestType::BreakpointUnlock
                | RequestType::BreakpointReached,
            )
            | None => return error_reply(NOT_RECOGNIZED),
        };
        let mut reply = vec![reply_header];
        reply.extend(payload);
        reply
    }

    /// BLACKBOARD's payload for the `;`-separated `names`: a MessagePack map from each
    /// name the tree has (in byte order, once each, as nlohmann's JSON object keeps
    /// keys) to `nil`, a board without entries (and `ROOT`, the main tree's board, when a
    /// SubTree's is named); `nil` alone when no name is the tree's.
    fn blackboards(&self, names: &[u8]) -> Vec<u8> {
        let mut wanted: BTreeSet<&[u8]> =
            names.split(|&b| b == b';').filter(|n| self.boards.iter().any(|b| b.as_bytes() == *n)).collect();
        // A SubTree's board hangs off the main tree's, which BehaviorTree.CPP then adds as
        // `ROOT`.
        if self.boards.iter().skip(1).any(|b| wanted.contains(b.as_bytes())) {
            wanted.insert(b"ROOT");
        }
        let mut out = Vec::new();
        if wanted.is_empty() {
            let _ = rmp::encode::write_nil(&mut out);
            return out;
        }
        let _ = rmp::encode::write_map_len(&mut out, u32::try_from(wanted.len()).unwrap_or(u32::MAX));
        for name in wanted {
            let _ = rmp::encode::write_str(&mut out, &String::from_utf8_lossy(name));
            let _ = rmp::encode::write_nil(&mut out);
        }
        out
    }
}

/// The order of BehaviorTree.CPP's status buffer, as indices into [`LogTree::nodes`]:
/// the main tree's nodes in creation order, then each SubTree instance's nodes (a
/// SubTree node belongs to the tree that holds it), the instances in creation order.
#[must_use]
pub fn status_order(tree: &LogTree) -> Vec<usize> {
    let mut roots: Vec<usize> = Vec::new();
    if !tree.nodes.is_empty() {
        roots.push(0);
    }
    roots.extend(tree.nodes.iter().filter(|n| n.subtree.is_some()).filter_map(|n| n.children.first().copied()));
    let mut out = Vec::with_capacity(tree.nodes.len());
    let mut stack: Vec<usize> = Vec::new();
    for root in roots {
        stack.push(root);
        while let Some(i) = stack.pop() {
            let Some(n) = tree.nodes.get(i) else { continue };
            out.push(i);
            if n.subtree.is_none() {
                stack.extend(n.children.iter().rev());
            }
        }
    }
    out
}

/// A 16-byte UUID as text, `xxxxxxxx-xxxx-...`, for messages.
#[must_use]
pub fn uuid_text(uuid: &[u8; 16]) -> String {
    let mut s = String::with_capacity(36);
    for (i, b) in uuid.iter().enumerate() {
        if matches!(i, 4 | 6 | 8 | 10) {
            s.push('-');
        }
        let _ = write!(s, "{b:02x}");
    }
    s
}

#[cfg(test)]
mod tests;
