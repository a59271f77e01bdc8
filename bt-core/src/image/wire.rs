//! The nodes as the image writes them, and the conversions both ways.
//!
//! A node is encoded as its subtree size (`u16`, itself included) followed by its kind:
//! a varint tag, then the tag's fields. postcard writes every `u16` as a LEB128 varint
//! (1 to 3 bytes) and a list as a varint length followed by its items.
//!
//! | tag | kind | fields |
//! |----:|------|--------|
//! | 0  | `Sequence` | — |
//! | 1  | `Fallback` | — |
//! | 2  | `SequenceWithMemory` | — |
//! | 3  | `FallbackWithMemory` | — |
//! | 4  | `Parallel` | success threshold `u16`, failure threshold `u16` |
//! | 5  | `Inverter` | — |
//! | 6  | `ForceSuccess` | — |
//! | 7  | `ForceFailure` | — |
//! | 8  | `Repeat` | count `u16` |
//! | 9  | `Retry` | attempts `u16` |
//! | 10 | `Timeout` | ticks `u16` |
//! | 11 | `Condition` | behavior id `u16`, values: list of at most 3 `u16` |
//! | 12 | `Action` | behavior id `u16`, values: list of at most 3 `u16` |
//! | 13 | `Condition`, extended (version 2) | behavior id `u16`, then the list `[start, length]` of its values in the value table |
//! | 14 | `Action`, extended (version 2) | behavior id `u16`, then the list `[start, length]` of its values in the value table |
//! | 15 | `SequenceStar` (version 2, as all tags below) | — |
//! | 16 | `IfThenElse` | — |
//! | 17 | `WhileDoElse` | — |
//! | 18 | `ParallelAll` | max failures `u16` |
//! | 19 | `PipelineSequence` | — |
//! | 20 | `Recovery` | retries `u16` |
//! | 21 | `RoundRobin` | — |
//! | 22 | `RepeatCycles` | count `u16` (65535: no limit) |
//! | 23 | `RetryUntilSuccessful` | attempts `u16` (65535: no limit) |
//! | 24 | `KeepRunningUntilFailure` | — |
//! | 25 | `RunOnce` | then skip, one byte 0 or 1 |
//! | 26 | `TimeLimit` | span: low `u16`, high `u16` (at most 255) |
//! | 27 | `Delay` | span as `TimeLimit` |
//! | 28 | `RateController` | span as `TimeLimit` |
//! | 29 | `Gate` | as `Action` |
//! | 30 | `AlwaysSuccess` | — |
//! | 31 | `AlwaysFailure` | — |
//! | 32 | `Parallel` whose skipped children count towards success | as tag 4 |
//! | 33 | `Gate`, extended | as tag 14 |
//! | 34 | `Script` (version 3) | program: start `u16`, length `u16` in the value table |
//! | 35 | `ScriptCondition` (version 3) | as tag 34 |
//! | 36 | `Precondition` (version 3) | program as tag 34, then the `else` status, one byte: 0 Success, 1 Failure, 2 Running, 3 Skipped |
//! | 37 | `Sleep` (version 3) | span as `TimeLimit` |
//! | 38 | `Guard` (version 3) | its table of scripts: start `u16`, length `u16` in the value table |
//! | 39 | `Loop` (version 3) | its queue's table as tag 38, then the `if_empty` status as tag 36's `else` |
//! | 40 | `ManualSelector` (version 3) | repeat the last selection, one byte 0 or 1 |
//! | 41 | `SequenceStarV3` (version 4) | — |
//! | 42 | `ParallelV3` (version 4) | as tag 4 |
//! | 43 | `Cycles` (version 4) | count or slot `u16`, then flags, one byte: 1 from a slot, 2 retry, 4 version 3's loop |
//! | 44 | `Check` (version 4) | program as tag 34, then the status when it does not hold, as tag 36's `else` |
//!
//! A span of `u32::MAX` units ([`Span::NEVER`](crate::Span::NEVER): low and high `0xFFFF`) never expires;
//! an image with one is version 4, so that older loaders refuse it by its version.
//!
//! A tree of the cube task (19 nodes) takes about 70 bytes of payload.

use serde::{Deserialize, Serialize};

use crate::error::LoadError;
use crate::node::{Leaf, LeafError, Node, NodeId, NodeKind, Span};

#[derive(Serialize, Deserialize)]
pub(super) struct WireNode {
    size: u16,
    kind: WireKind,
}

impl WireNode {
    /// The oldest image version that has this node's tag.
    pub(super) fn since(&self) -> u16 {
        self.kind.since()
    }

    /// Whether an image of `version` may hold this node's tag.
    pub(super) fn in_version(&self, version: u16) -> bool {
        self.kind.in_version(version)
    }
}

#[derive(Serialize, Deserialize)]
struct WireLeaf {
    behavior: u16,
    args: heapless::Vec<u16, { crate::node::MAX_ARGS }>,
}

#[derive(Serialize, Deserialize)]
struct WireSpan {
    lo: u16,
    hi: u16,
}

// Tags are the variant indices: never reorder, only append (with a version bump).
#[derive(Serialize, Deserialize)]
enum WireKind {
    Sequence,
    Fallback,
    SequenceWithMemory,
    FallbackWithMemory,
    Parallel {
        success_threshold: u16,
        failure_threshold: u16,
    },
    Inverter,
    ForceSuccess,
    ForceFailure,
    Repeat(u16),
    Retry(u16),
    Timeout(u16),
    Condition(WireLeaf),
    Action(WireLeaf),
    // Version 2: extended leaves, `args` being the start and length of their values in
    // the value table (the same wire struct, so that no second decoder is linked).
    ConditionExt(WireLeaf),
    ActionExt(WireLeaf),
    // Version 2: the kinds for BehaviorTree.CPP's and Nav2's nodes.
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    SequenceStar,
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    IfThenElse,
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    WhileDoElse,
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    ParallelAll {
        max_failures: u16,
    },
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    PipelineSequence,
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    Recovery {
        retries: u16,
    },
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    RoundRobin,
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    RepeatCycles(u16),
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    RetryUntilSuccessful(u16),
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    KeepRunningUntilFailure,
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    RunOnce {
        then_skip: bool,
    },
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    TimeLimit(WireSpan),
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    Delay(WireSpan),
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    RateController(WireSpan),
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    Gate(WireLeaf),
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    AlwaysSuccess,
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    AlwaysFailure,
    /// A `Parallel` whose skipped children count towards success.
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    ParallelCountSkipped {
        success_threshold: u16,
        failure_threshold: u16,
    },
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    GateExt(WireLeaf),
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    Script(WireCode),
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    ScriptCondition(WireCode),
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    Precondition(WireCode, u8),
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    Sleep(WireSpan),
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    Guard(WireCode),
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    Loop(WireCode, u8),
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    ManualSelector {
        repeat_last: bool,
    },
    // Version 4: the kinds of BehaviorTree.CPP 3.
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    SequenceStarV3,
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    ParallelV3 {
        success_threshold: u16,
        failure_threshold: u16,
    },
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    Cycles(u16, u8),
    #[cfg_attr(not(feature = "btcpp"), serde(skip_deserializing))]
    Check(WireCode, u8),
}

/// `Cycles` flags (tag 43).
const CYCLES_FROM_SLOT: u8 = 1;
const CYCLES_RETRY: u8 = 2;
const CYCLES_V3: u8 = 4;

#[derive(Serialize, Deserialize)]
struct WireCode {
    start: u16,
    len: u16,
}

impl WireKind {
    /// The oldest version with this tag (and its fields): version 1 has tags 0 to 12,
    /// version 2 up to 33, version 3 up to 40, version 4 up to 44 and spans that never
    /// expire.
    fn since(&self) -> u16 {
        match self {
            _ if self.in_version_1() => 1,
            Self::TimeLimit(d) | Self::Delay(d) | Self::RateController(d) if d.never() => 4,
            Self::Sleep(d) if d.never() => 4,
            Self::Script(_)
            | Self::ScriptCondition(_)
            | Self::Precondition(..)
            | Self::Sleep(_)
            | Self::Guard(_)
            | Self::Loop(..)
            | Self::ManualSelector { .. } => 3,
            Self::SequenceStarV3 | Self::ParallelV3 { .. } | Self::Cycles(..) | Self::Check(..) => 4,
            _ => 2,
        }
    }

    /// Whether version `version` has this tag. Without the `btcpp` feature only the
    /// tags of versions 1 and 2 decode at all: the test is then the one of those two,
    /// which keeps the firmware's loader small.
    fn in_version(&self, version: u16) -> bool {
        if cfg!(feature = "btcpp") { self.since() <= version } else { version >= 2 || self.in_version_1() }
    }

    /// Whether it is one of version 1's tags, 0 to 12.
    const fn in_version_1(&self) -> bool {
        matches!(
            self,
            Self::Sequence
                | Self::Fallback
                | Self::SequenceWithMemory
                | Self::FallbackWithMemory
                | Self::Parallel { .. }
                | Self::Inverter
                | Self::ForceSuccess
                | Self::ForceFailure
                | Self::Repeat(_)
                | Self::Retry(_)
                | Self::Timeout(_)
                | Self::Condition(_)
                | Self::Action(_)
        )
    }
}

impl WireSpan {
    /// Whether it is [`Span::NEVER`].
    const fn never(&self) -> bool {
        self.lo == u16::MAX && self.hi == u16::MAX
    }
}

fn span(d: Span) -> WireSpan {
    let units = d.get();
    WireSpan { lo: units as u16, hi: (units >> 16) as u16 }
}

pub(super) fn to_wire(node: &Node) -> WireNode {
    let kind = match node.kind() {
        NodeKind::Sequence => WireKind::Sequence,
        NodeKind::Fallback => WireKind::Fallback,
        NodeKind::SequenceWithMemory => WireKind::SequenceWithMemory,
        NodeKind::FallbackWithMemory => WireKind::FallbackWithMemory,
        &NodeKind::Parallel { success_threshold, failure_threshold, count_skipped: false } => {
            WireKind::Parallel { success_threshold, failure_threshold }
        }
        &NodeKind::Parallel { success_threshold, failure_threshold, count_skipped: true } => {
            WireKind::ParallelCountSkipped { success_threshold, failure_threshold }
        }
        NodeKind::Inverter => WireKind::Inverter,
        NodeKind::ForceSuccess => WireKind::ForceSuccess,
        NodeKind::ForceFailure => WireKind::ForceFailure,
        &NodeKind::Repeat(n) => WireKind::Repeat(n),
        &NodeKind::Retry(n) => WireKind::Retry(n),
        &NodeKind::Timeout(n) => WireKind::Timeout(n),
        NodeKind::Condition(l) => match wire_leaf(l) {
            Ok(w) => WireKind::Condition(w),
            Err(x) => WireKind::ConditionExt(x),
        },
        NodeKind::Action(l) => match wire_leaf(l) {
            Ok(w) => WireKind::Action(w),
            Err(x) => WireKind::ActionExt(x),
        },
        NodeKind::SequenceStar => WireKind::SequenceStar,
        NodeKind::IfThenElse => WireKind::IfThenElse,
        NodeKind::WhileDoElse => WireKind::WhileDoElse,
        &NodeKind::ParallelAll { max_failures } => WireKind::ParallelAll { max_failures },
        NodeKind::PipelineSequence => WireKind::PipelineSequence,
        &NodeKind::Recovery { retries } => WireKind::Recovery { retries },
        NodeKind::RoundRobin => WireKind::RoundRobin,
        &NodeKind::RepeatCycles(n) => WireKind::RepeatCycles(n),
        &NodeKind::RetryUntilSuccessful(n) => WireKind::RetryUntilSuccessful(n),
        NodeKind::KeepRunningUntilFailure => WireKind::KeepRunningUntilFailure,
        &NodeKind::RunOnce { then_skip } => WireKind::RunOnce { then_skip },
        &NodeKind::TimeLimit(d) => WireKind::TimeLimit(span(d)),
        &NodeKind::Delay(d) => WireKind::Delay(span(d)),
        &NodeKind::RateController(d) => WireKind::RateController(span(d)),
        NodeKind::Gate(l) => match wire_leaf(l) {
            Ok(w) => WireKind::Gate(w),
            Err(x) => WireKind::GateExt(x),
        },
        NodeKind::AlwaysSuccess => WireKind::AlwaysSuccess,
        NodeKind::AlwaysFailure => WireKind::AlwaysFailure,
        NodeKind::Script(c) => WireKind::Script(WireCode { start: c.start, len: c.len }),
        NodeKind::ScriptCondition(c) => WireKind::ScriptCondition(WireCode { start: c.start, len: c.len }),
        &NodeKind::Sleep(d) => WireKind::Sleep(span(d)),
        NodeKind::Guard(c) => WireKind::Guard(WireCode { start: c.start, len: c.len }),
        NodeKind::Precondition { code, otherwise } => {
            WireKind::Precondition(WireCode { start: code.start, len: code.len }, status_byte(*otherwise))
        }
        NodeKind::Loop { table, if_empty } => {
            WireKind::Loop(WireCode { start: table.start, len: table.len }, status_byte(*if_empty))
        }
        &NodeKind::ManualSelector { repeat_last } => WireKind::ManualSelector { repeat_last },
        NodeKind::SequenceStarV3 => WireKind::SequenceStarV3,
        &NodeKind::ParallelV3 { success_threshold, failure_threshold } => {
            WireKind::ParallelV3 { success_threshold, failure_threshold }
        }
        &NodeKind::Cycles { count, from_slot, retry, v3 } => {
            let flag = |on: bool, bit: u8| if on { bit } else { 0 };
            WireKind::Cycles(count, flag(from_slot, CYCLES_FROM_SLOT) | flag(retry, CYCLES_RETRY) | flag(v3, CYCLES_V3))
        }
        NodeKind::Check { code, otherwise } => {
            WireKind::Check(WireCode { start: code.start, len: code.len }, status_byte(*otherwise))
        }
    };
    WireNode { size: node.size(), kind }
}

/// A status written in a node (tags 36 and 39).
const fn status_byte(s: crate::Status) -> u8 {
    match s {
        crate::Status::Success => 0,
        crate::Status::Failure => 1,
        crate::Status::Running => 2,
        crate::Status::Skipped => 3,
    }
}

/// The status of a byte [`status_byte`] wrote.
#[cfg(feature = "btcpp")]
const fn byte_status(b: u8) -> Option<crate::Status> {
    Some(match b {
        0 => crate::Status::Success,
        1 => crate::Status::Failure,
        2 => crate::Status::Running,
        3 => crate::Status::Skipped,
        _ => return None,
    })
}

/// A leaf's wire form: inline (`Ok`), or extended (`Err`, with start and length).
fn wire_leaf(l: &Leaf) -> Result<WireLeaf, WireLeaf> {
    let wire =
        |args: &[u16]| WireLeaf { behavior: l.behavior(), args: heapless::Vec::from_slice(args).unwrap_or_default() };
    match l.range() {
        Some((start, len)) => Err(wire(&[start, len])),
        None => Ok(wire(l.args())),
    }
}

#[cfg(feature = "btcpp")]
fn from_span(id: NodeId, d: WireSpan) -> Result<Span, LoadError> {
    if d.never() {
        return Ok(Span::NEVER);
    }
    let units = u32::from(d.hi) << 16 | u32::from(d.lo);
    Span::new(units)
        .ok_or(LoadError::BadArgument { node: id, fault: crate::error::ArgumentFault::SpanTooLong { units } })
}

/// An inline leaf of node `id`.
fn leaf_of(id: NodeId, l: WireLeaf) -> Result<Leaf, LoadError> {
    Leaf::with_args(l.behavior, &l.args).map_err(|e| LoadError::BadArgument { node: id, fault: e.into() })
}

/// An extended leaf of node `id`: its args are the start and length of its values.
fn extended_of(id: NodeId, l: WireLeaf) -> Result<Leaf, LoadError> {
    let fault = |e: LeafError| LoadError::BadArgument { node: id, fault: e.into() };
    match *l.args {
        [start, len] => Leaf::extended(l.behavior, start, len).map_err(fault),
        _ => Err(fault(LeafError::TooManyArgs(l.args.len()))),
    }
}

/// Node `id`, decoded at `offset` in the image.
pub(super) fn from_wire(id: NodeId, offset: usize, w: WireNode) -> Result<Node, LoadError> {
    let kind = match w.kind {
        WireKind::Sequence => NodeKind::Sequence,
        WireKind::Fallback => NodeKind::Fallback,
        WireKind::SequenceWithMemory => NodeKind::SequenceWithMemory,
        WireKind::FallbackWithMemory => NodeKind::FallbackWithMemory,
        WireKind::Parallel { success_threshold, failure_threshold } => {
            NodeKind::Parallel { success_threshold, failure_threshold, count_skipped: false }
        }
        WireKind::Inverter => NodeKind::Inverter,
        WireKind::ForceSuccess => NodeKind::ForceSuccess,
        WireKind::ForceFailure => NodeKind::ForceFailure,
        WireKind::Repeat(n) => NodeKind::Repeat(n),
        WireKind::Retry(n) => NodeKind::Retry(n),
        WireKind::Timeout(n) => NodeKind::Timeout(n),
        WireKind::Condition(l) => NodeKind::Condition(leaf_of(id, l)?),
        WireKind::Action(l) => NodeKind::Action(leaf_of(id, l)?),
        WireKind::ConditionExt(l) => NodeKind::Condition(extended_of(id, l)?),
        WireKind::ActionExt(l) => NodeKind::Action(extended_of(id, l)?),
        #[cfg(feature = "btcpp")]
        other => from_wire_btcpp(id, offset, other)?,
        // Without the feature these tags do not decode (see `decode_nodes`).
        #[cfg(not(feature = "btcpp"))]
        _ => return Err(LoadError::MalformedNode { node: id, offset }),
    };
    Ok(Node::new(kind, w.size))
}

/// The kinds for BehaviorTree.CPP's and Nav2's nodes (tags 15 and up).
#[cfg(feature = "btcpp")]
fn from_wire_btcpp(id: NodeId, offset: usize, kind: WireKind) -> Result<NodeKind, LoadError> {
    Ok(match kind {
        WireKind::ParallelCountSkipped { success_threshold, failure_threshold } => {
            NodeKind::Parallel { success_threshold, failure_threshold, count_skipped: true }
        }
        WireKind::SequenceStar => NodeKind::SequenceStar,
        WireKind::IfThenElse => NodeKind::IfThenElse,
        WireKind::WhileDoElse => NodeKind::WhileDoElse,
        WireKind::ParallelAll { max_failures } => NodeKind::ParallelAll { max_failures },
        WireKind::PipelineSequence => NodeKind::PipelineSequence,
        WireKind::Recovery { retries } => NodeKind::Recovery { retries },
        WireKind::RoundRobin => NodeKind::RoundRobin,
        WireKind::RepeatCycles(n) => NodeKind::RepeatCycles(n),
        WireKind::RetryUntilSuccessful(n) => NodeKind::RetryUntilSuccessful(n),
        WireKind::KeepRunningUntilFailure => NodeKind::KeepRunningUntilFailure,
        WireKind::RunOnce { then_skip } => NodeKind::RunOnce { then_skip },
        WireKind::TimeLimit(d) => NodeKind::TimeLimit(from_span(id, d)?),
        WireKind::Delay(d) => NodeKind::Delay(from_span(id, d)?),
        WireKind::RateController(d) => NodeKind::RateController(from_span(id, d)?),
        WireKind::Gate(l) => NodeKind::Gate(leaf_of(id, l)?),
        WireKind::GateExt(l) => NodeKind::Gate(extended_of(id, l)?),
        WireKind::AlwaysSuccess => NodeKind::AlwaysSuccess,
        WireKind::AlwaysFailure => NodeKind::AlwaysFailure,
        WireKind::Script(c) => NodeKind::Script(crate::node::Code { start: c.start, len: c.len }),
        WireKind::ScriptCondition(c) => NodeKind::ScriptCondition(crate::node::Code { start: c.start, len: c.len }),
        WireKind::Sleep(s) => NodeKind::Sleep(from_span(id, s)?),
        WireKind::Guard(c) => NodeKind::Guard(crate::node::Code { start: c.start, len: c.len }),
        WireKind::Precondition(c, otherwise) => NodeKind::Precondition {
            code: crate::node::Code { start: c.start, len: c.len },
            otherwise: byte_status(otherwise).ok_or(LoadError::MalformedNode { node: id, offset })?,
        },
        WireKind::Loop(c, if_empty) => NodeKind::Loop {
            table: crate::node::Code { start: c.start, len: c.len },
            if_empty: byte_status(if_empty).ok_or(LoadError::MalformedNode { node: id, offset })?,
        },
        WireKind::ManualSelector { repeat_last } => NodeKind::ManualSelector { repeat_last },
        WireKind::SequenceStarV3 => NodeKind::SequenceStarV3,
        WireKind::ParallelV3 { success_threshold, failure_threshold } => {
            NodeKind::ParallelV3 { success_threshold, failure_threshold }
        }
        WireKind::Cycles(count, flags) => {
            if flags & !(CYCLES_FROM_SLOT | CYCLES_RETRY | CYCLES_V3) != 0 {
                return Err(LoadError::MalformedNode { node: id, offset });
            }
            NodeKind::Cycles {
                count,
                from_slot: flags & CYCLES_FROM_SLOT != 0,
                retry: flags & CYCLES_RETRY != 0,
                v3: flags & CYCLES_V3 != 0,
            }
        }
        WireKind::Check(c, otherwise) => NodeKind::Check {
            code: crate::node::Code { start: c.start, len: c.len },
            otherwise: byte_status(otherwise).ok_or(LoadError::MalformedNode { node: id, offset })?,
        },
        // The kinds of version 1 and the extended leaves: `from_wire`.
        WireKind::Sequence
        | WireKind::Fallback
        | WireKind::SequenceWithMemory
        | WireKind::FallbackWithMemory
        | WireKind::Parallel { .. }
        | WireKind::Inverter
        | WireKind::ForceSuccess
        | WireKind::ForceFailure
        | WireKind::Repeat(_)
        | WireKind::Retry(_)
        | WireKind::Timeout(_)
        | WireKind::Condition(_)
        | WireKind::Action(_)
        | WireKind::ConditionExt(_)
        | WireKind::ActionExt(_) => return Err(LoadError::MalformedNode { node: id, offset }),
    })
}
