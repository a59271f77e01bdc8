//! Errors: one variant per fault, each naming what and where.

use crate::node::{Arity, BehaviorId, LeafError, LeafKind, NodeId};

/// Why an image (or a node array) was refused. One variant per fault.
///
/// [`load`](crate::load) checks, in this order: the envelope's length, magic, version
/// and CRC, the behavior-set fingerprint, the node count, the decoding of each node, the
/// trailing bytes, then the tree's structure and leaves ([`Tree::validate`](crate::Tree::validate)
/// returns only the structural variants).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum LoadError {
    /// The image is shorter than its envelope, or its node payload ends inside a node.
    #[error("image truncated: {}, {}", Count(*.len, "byte", "bytes"), match .inside_node {
        Some(n) => TruncatedAt::Node(*n),
        None => TruncatedAt::Envelope,
    })]
    Truncated {
        /// Length of the image in bytes.
        len: usize,
        /// The node being decoded when the payload ran out, if any.
        inside_node: Option<NodeId>,
    },
    /// The image does not start with [`MAGIC`](crate::image::MAGIC).
    #[error("not a behavior-tree image: starts with {}, expected {} (\"BTIM\")", HexBytes(found), HexBytes(&crate::image::MAGIC))]
    BadMagic {
        /// The first four bytes.
        found: [u8; 4],
    },
    /// The image has a format version this build cannot read.
    #[error(
        "image format version {found} is not supported (this build reads versions {} to {supported})",
        crate::image::OLDEST_VERSION
    )]
    UnsupportedVersion {
        /// Version in the image.
        found: u16,
        /// The newest version this build reads (it reads every version from
        /// [`OLDEST_VERSION`](crate::image::OLDEST_VERSION) on).
        supported: u16,
    },
    /// The CRC-32 at the end does not match the bytes before it.
    #[error("image corrupted: stored CRC-32 {stored:#010x}, computed {computed:#010x}")]
    CrcMismatch {
        /// CRC stored in the image.
        stored: u32,
        /// CRC computed over the image.
        computed: u32,
    },
    /// The image was built for a different behavior set.
    #[error("image built for behavior set {image:#018x}, this controller has {expected:#018x}")]
    ForeignBehaviorSet {
        /// Fingerprint in the image.
        image: u64,
        /// Fingerprint of the behavior set given to the loader.
        expected: u64,
    },
    /// More nodes than the storage (or the `u16` node ids) can hold.
    #[error("tree has {}, capacity is {capacity}", Count(*.count, "node", "nodes"))]
    TooManyNodes {
        /// Nodes in the image or array.
        count: usize,
        /// Nodes that fit.
        capacity: usize,
    },
    /// A node's bytes do not decode: an unknown kind tag, a bad varint, too many arguments.
    #[error("node {node} is malformed (bytes from offset {offset} do not decode as a node)")]
    MalformedNode {
        /// Index of the node.
        node: NodeId,
        /// Byte offset of the node in the image.
        offset: usize,
    },
    /// Bytes left between the last node and the CRC (a version-1 image has no sections).
    #[error("{} after the last node", Count(*.count, "unexpected byte", "unexpected bytes"))]
    TrailingBytes {
        /// How many.
        count: usize,
    },
    /// A section tag this build does not know.
    #[error("unknown section {tag} at offset {offset}")]
    UnknownSection {
        /// The tag.
        tag: u8,
        /// Byte offset of the section in the image.
        offset: usize,
    },
    /// A section whose length runs past the end, whose body does not decode, or that
    /// repeats or comes out of order.
    #[error("section {tag} at offset {offset} is malformed")]
    MalformedSection {
        /// The tag.
        tag: u8,
        /// Byte offset of the section in the image.
        offset: usize,
    },
    /// The value table does not fit the value storage.
    #[error("value table has {count} entries, capacity is {capacity}")]
    TooManyValues {
        /// Entries in the image.
        count: usize,
        /// Entries that fit.
        capacity: usize,
    },
    /// A tree needs at least one node.
    #[error("the tree has no nodes")]
    EmptyTree,
    /// A subtree size that does not fit its parent or the array.
    #[error("node {node} claims a subtree of {}, which does not fit inside its parent", Count(usize::from(*.size), "node", "nodes"))]
    SubtreeSizeInconsistent {
        /// Index of the node.
        node: NodeId,
        /// Its stored subtree size.
        size: u16,
    },
    /// A node with a number of children its kind does not allow.
    #[error("node {node} ({kind}) has {}; {}", Count(usize::from(*.children), "child", "children"), match .expected {
        Arity::Leaf => "a leaf has none",
        Arity::One => "a decorator has exactly one",
        Arity::AtLeastOne => "a control node needs at least one",
        Arity::Two => "this kind has exactly two",
        Arity::TwoOrThree => "this kind has two or three",
        Arity::Any => "this kind takes any number",
    })]
    WrongArity {
        /// Index of the node.
        node: NodeId,
        /// Its kind's name.
        kind: &'static str,
        /// How many children it has.
        children: u16,
        /// How many its kind takes.
        expected: Arity,
    },
    /// The tree is deeper than the executor's stack allows.
    #[error("node {node} is deeper than the limit of {}", Count(*.limit, "level", "levels"))]
    DepthOverLimit {
        /// First node found beyond the limit.
        node: NodeId,
        /// The depth limit (root at depth 1).
        limit: usize,
    },
    /// A leaf names a behavior the behavior set does not have.
    #[error("node {node} uses behavior {behavior}, which the behavior set does not have")]
    UnknownBehavior {
        /// Index of the node.
        node: NodeId,
        /// The behavior id.
        behavior: BehaviorId,
    },
    /// A condition node naming an action, or the other way round.
    #[error("node {node} uses behavior {behavior} as {}, but it is declared as {}",
        article(.declared.flip()), article(*.declared))]
    WrongLeafKind {
        /// Index of the node.
        node: NodeId,
        /// The behavior id.
        behavior: BehaviorId,
        /// What the behavior set declares it to be.
        declared: LeafKind,
    },
    /// A node kind this build of bt-core leaves out (the kinds for BehaviorTree.CPP's
    /// and Nav2's nodes, without the `btcpp` feature).
    #[error("node {node} is a {kind}, which this build does not run (bt-core without the `btcpp` feature)")]
    UnsupportedKind {
        /// Index of the node.
        node: NodeId,
        /// Its kind's name.
        kind: &'static str,
    },
    /// A leaf's argument count or a decorator's or parallel's parameter is out of range.
    #[error("node {node}: {fault}")]
    BadArgument {
        /// Index of the node.
        node: NodeId,
        /// What is wrong.
        fault: ArgumentFault,
    },
    /// A leaf's port value names a constant or slot the image's ports section does not
    /// have, or one of another type, or gives an output port a constant.
    #[error("node {node}: {fault}")]
    BadPort {
        /// The leaf.
        node: NodeId,
        /// What is wrong.
        fault: crate::port::PortFault,
    },
    /// A script node's program does not check out against the image's ports section.
    #[error("node {node}: {fault}")]
    BadScript {
        /// The script node.
        node: NodeId,
        /// What is wrong.
        fault: crate::script::ScriptFault,
    },
}

/// What is wrong with a node's arguments or parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ArgumentFault {
    /// The leaf's argument count differs from the behavior's declared arity.
    #[error("behavior {behavior} takes {}, the leaf has {found}", Count(usize::from(*.expected), "argument", "arguments"))]
    Count {
        /// The behavior id.
        behavior: BehaviorId,
        /// Declared arity.
        expected: u8,
        /// Arguments in the leaf.
        found: u16,
    },
    /// An argument is `u16::MAX`, which is reserved.
    #[error("argument {position} is 65535, a reserved value")]
    Reserved {
        /// Position of the argument.
        position: u8,
    },
    /// An extended leaf's values lie (partly) outside the tree's value table.
    #[error("the leaf's values {start}..+{len} lie outside the value table of {table} entries")]
    ValuesOutOfRange {
        /// First value's index in the table.
        start: u16,
        /// Number of values.
        len: u16,
        /// Entries in the table.
        table: u16,
    },
    /// `Repeat`, `Retry` or `Timeout` with a count of zero.
    #[error("`{kind}(0)`: {}", match *.kind {
        "Timeout" => "a timeout must allow at least 1 tick",
        "Retry" => "a Retry must allow at least 1 attempt",
        _ => "a Repeat must run its child at least once",
    })]
    ZeroCount {
        /// The decorator's name.
        kind: &'static str,
    },
    /// A parallel threshold of zero or above the number of children.
    #[error("parallel {which} threshold {threshold} is outside 1..={children}")]
    Threshold {
        /// `success` or `failure`.
        which: &'static str,
        /// The threshold.
        threshold: u16,
        /// Number of children.
        children: u16,
    },
    /// A `ParallelAll` whose `max_failures` exceeds its number of children.
    #[error("ParallelAll max_failures {max_failures} is above its {children} children")]
    MaxFailures {
        /// The threshold.
        max_failures: u16,
        /// Number of children.
        children: u16,
    },
    /// A kind with more children than it can keep track of.
    #[error("{kind} has {children} children, at most {limit} are allowed")]
    TooManyChildren {
        /// The kind's name.
        kind: &'static str,
        /// Number of children.
        children: u16,
        /// The limit.
        limit: u16,
    },
    /// A time span above [`Span::MAX`](crate::Span::MAX).
    #[error("a span of {units} units of `now` is above the limit of 16777215")]
    SpanTooLong {
        /// The span.
        units: u32,
    },
}

impl From<LeafError> for ArgumentFault {
    /// The fault in a decoded leaf: a reserved inline value, or an extended leaf whose
    /// range is malformed (reported as lying outside any table).
    fn from(e: LeafError) -> Self {
        match e {
            LeafError::ReservedValue(p) | LeafError::TooManyArgs(p) => Self::Reserved { position: p as u8 },
            LeafError::BadRange(len, start) => Self::ValuesOutOfRange { start, len, table: 0 },
        }
    }
}

/// Why the [`Builder`](crate::Builder) refused an operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum BuildError {
    /// The caller's node storage is full.
    #[error("node storage is full ({})", Count(*.capacity, "node", "nodes"))]
    Full {
        /// Capacity of the storage.
        capacity: usize,
    },
    /// More open nodes than the builder's depth.
    #[error("tree deeper than the builder's limit of {}", Count(*.limit, "level", "levels"))]
    TooDeep {
        /// The builder's depth limit.
        limit: usize,
    },
    /// `end` without an open control node or decorator.
    #[error("end() without an open node")]
    NothingOpen,
    /// `finish` while nodes are still open.
    #[error("{} still open; close each with end()", Count(*.open, "node is", "nodes are"))]
    Unclosed {
        /// How many.
        open: usize,
    },
    /// A second root, or `finish` before any node.
    #[error("a tree has exactly one root node")]
    NotOneRoot,
    /// `open` with a leaf kind; use `condition` or `action`.
    #[error("open() takes a control node or decorator; leaves are added with condition() or action()")]
    LeafOpened,
    /// `leaf` with a control node or decorator kind; use `open`.
    #[error("leaf() takes a leaf kind; control nodes and decorators are opened with open()")]
    NotALeaf,
    /// A leaf's arguments are not valid.
    #[error(transparent)]
    Leaf(#[from] LeafError),
}

/// Why an image could not be written.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum EncodeError {
    /// The output buffer is too small; [`max_image_len`](crate::image::max_image_len) tells how big.
    #[error("output buffer of {} is too small for the image", Count(*.capacity, "byte", "bytes"))]
    BufferTooSmall {
        /// Size of the given buffer.
        capacity: usize,
    },
    /// More nodes than an image can hold (`u16::MAX`).
    #[error("tree has {count} nodes; an image holds at most 65535")]
    TooManyNodes {
        /// Node count.
        count: usize,
    },
    /// A value table longer than an image can hold (`u16::MAX` entries).
    #[error("value table has {count} entries; an image holds at most 65535")]
    TooManyValues {
        /// Entries.
        count: usize,
    },
}

impl LoadError {
    /// A short, stable identifier of the fault (`"crc-mismatch"`, `"bad-magic"`, ...),
    /// one per variant: for logs and for controllers too small to link `core::fmt`.
    #[must_use]
    pub const fn code(&self) -> &'static str {
        match self {
            Self::Truncated { .. } => "truncated",
            Self::BadMagic { .. } => "bad-magic",
            Self::UnsupportedVersion { .. } => "unsupported-version",
            Self::CrcMismatch { .. } => "crc-mismatch",
            Self::ForeignBehaviorSet { .. } => "foreign-behavior-set",
            Self::TooManyNodes { .. } => "too-many-nodes",
            Self::MalformedNode { .. } => "malformed-node",
            Self::TrailingBytes { .. } => "trailing-bytes",
            Self::UnknownSection { .. } => "unknown-section",
            Self::MalformedSection { .. } => "malformed-section",
            Self::TooManyValues { .. } => "too-many-values",
            Self::EmptyTree => "empty-tree",
            Self::SubtreeSizeInconsistent { .. } => "subtree-size-inconsistent",
            Self::WrongArity { .. } => "wrong-arity",
            Self::DepthOverLimit { .. } => "depth-over-limit",
            Self::UnknownBehavior { .. } => "unknown-behavior",
            Self::WrongLeafKind { .. } => "wrong-leaf-kind",
            Self::BadArgument { .. } => "bad-argument",
            Self::BadPort { .. } => "bad-port",
            Self::BadScript { .. } => "bad-script",
            Self::UnsupportedKind { .. } => "unsupported-kind",
        }
    }

    /// The node the fault was found at, for the variants that have one.
    #[must_use]
    pub const fn node(&self) -> Option<NodeId> {
        match *self {
            Self::Truncated { inside_node, .. } => inside_node,
            Self::MalformedNode { node, .. }
            | Self::SubtreeSizeInconsistent { node, .. }
            | Self::WrongArity { node, .. }
            | Self::DepthOverLimit { node, .. }
            | Self::UnknownBehavior { node, .. }
            | Self::WrongLeafKind { node, .. }
            | Self::BadArgument { node, .. }
            | Self::BadPort { node, .. }
            | Self::BadScript { node, .. }
            | Self::UnsupportedKind { node, .. } => Some(node),
            Self::BadMagic { .. }
            | Self::UnsupportedVersion { .. }
            | Self::CrcMismatch { .. }
            | Self::ForeignBehaviorSet { .. }
            | Self::TooManyNodes { .. }
            | Self::TrailingBytes { .. }
            | Self::UnknownSection { .. }
            | Self::MalformedSection { .. }
            | Self::TooManyValues { .. }
            | Self::EmptyTree => None,
        }
    }
}

/// Bytes as `[47, 49, 46, 38]` (hex), written without `Debug` formatting so that
/// firmware printing a [`LoadError`] does not link core's `Debug` builders.
struct HexBytes<'a>(&'a [u8]);

impl core::fmt::Display for HexBytes<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("[")?;
        for (i, b) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            write!(f, "{b:02x}")?;
        }
        f.write_str("]")
    }
}

enum TruncatedAt {
    Envelope,
    Node(NodeId),
}

impl core::fmt::Display for TruncatedAt {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Envelope => write!(
                f,
                "shorter than the {} bytes of header and CRC",
                crate::image::HEADER_LEN + crate::image::CRC_LEN
            ),
            Self::Node(n) => write!(f, "the payload ends inside node {n}"),
        }
    }
}

/// A count and its noun, singular for 1 (`1 node`, `2 nodes`), without allocating.
pub(crate) struct Count(pub(crate) usize, pub(crate) &'static str, pub(crate) &'static str);

impl core::fmt::Display for Count {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "{} {}", self.0, if self.0 == 1 { self.1 } else { self.2 })
    }
}

fn article(kind: LeafKind) -> &'static str {
    match kind {
        LeafKind::Condition => "a condition",
        LeafKind::Action => "an action",
    }
}

impl LeafKind {
    const fn flip(self) -> Self {
        match self {
            Self::Condition => Self::Action,
            Self::Action => Self::Condition,
        }
    }
}
