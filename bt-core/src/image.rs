//! The deployable image: a tree as bytes, checked end to end before it can run.
//!
//! # Byte layout (format version 1)
//!
//! All fixed-width integers are little-endian.
//!
//! | offset | size | field |
//! |-------:|-----:|-------|
//! | 0      | 4    | magic, the ASCII bytes `BTIM` |
//! | 4      | 2    | format version, `u16` (currently 1) |
//! | 6      | 8    | fingerprint of the behavior set, `u64` (see [`fingerprint`](crate::fingerprint)) |
//! | 14     | 2    | node count `n`, `u16`, at least 1 |
//! | 16     | …    | `n` nodes in pre-order, each [postcard]-encoded as below |
//! | end-4  | 4    | CRC-32 (ISO-HDLC, as zlib's `crc32`) of every byte before it, `u32` |
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
//! | 11 | `Condition` | behavior id `u16`, arguments: list of at most 3 `u16` |
//! | 12 | `Action` | behavior id `u16`, arguments: list of at most 3 `u16` |
//!
//! A tree of the cube task (19 nodes) takes about 70 bytes of payload.
//!
//! # Versioning
//!
//! The version names the whole layout: header, tags, field order, varint rules, CRC.
//! Any change to any of them — a new node kind included — takes the next version; a
//! loader reads exactly the versions it knows and refuses others with
//! [`LoadError::UnsupportedVersion`], so old firmware never misreads a newer image. The
//! magic and the version field stay at offsets 0 and 4 in every version.
//!
//! # Loading
//!
//! [`load`] checks, in this order, and stops at the first fault: the length, the magic,
//! the version, the CRC, the fingerprint against the given behavior set, the node count
//! against the storage, the decoding of every node, that no bytes follow the last node,
//! and the tree itself ([`Tree::validate`]). What it returns is a [`Tree`] — the only
//! thing the executor accepts.
//!
//! [postcard]: https://docs.rs/postcard

use serde::{Deserialize, Serialize};

use crate::catalog::Catalog;
use crate::error::{ArgumentFault, EncodeError, LoadError};
use crate::node::{Leaf, Node, NodeId, NodeKind};
use crate::tree::Tree;

/// The first four bytes of every image.
pub const MAGIC: [u8; 4] = *b"BTIM";
/// The format version this build writes and reads.
pub const VERSION: u16 = 1;
/// Bytes before the first node.
pub const HEADER_LEN: usize = 16;
/// Bytes of the trailing CRC-32.
pub const CRC_LEN: usize = 4;
/// Most bytes one encoded node can take.
pub const MAX_NODE_LEN: usize = 3 + 1 + 3 + 1 + 3 * 3;

/// An upper bound on the size of the image of a tree of `nodes` nodes.
#[must_use]
pub const fn max_image_len(nodes: usize) -> usize {
    HEADER_LEN + nodes * MAX_NODE_LEN + CRC_LEN
}

const CRC32: crc::Crc<u32, crc::NoTable> = crc::Crc::<u32, crc::NoTable>::new(&crc::CRC_32_ISO_HDLC);

/// The CRC-32 the image format uses (ISO-HDLC, as zlib's `crc32`).
#[must_use]
pub fn crc32(bytes: &[u8]) -> u32 {
    CRC32.checksum(bytes)
}

/// The envelope's fields, read by [`read_header`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Header {
    /// Format version.
    pub version: u16,
    /// Fingerprint of the behavior set the tree was built for.
    pub fingerprint: u64,
    /// Number of nodes.
    pub node_count: u16,
    /// Total image length in bytes.
    pub len: usize,
}

#[derive(Serialize, Deserialize)]
struct WireNode {
    size: u16,
    kind: WireKind,
}

#[derive(Serialize, Deserialize)]
struct WireLeaf {
    behavior: u16,
    args: heapless::Vec<u16, { crate::node::MAX_ARGS }>,
}

// Tags are the variant indices: never reorder, only append (with a version bump).
#[derive(Serialize, Deserialize)]
enum WireKind {
    Sequence,
    Fallback,
    SequenceWithMemory,
    FallbackWithMemory,
    Parallel { success_threshold: u16, failure_threshold: u16 },
    Inverter,
    ForceSuccess,
    ForceFailure,
    Repeat(u16),
    Retry(u16),
    Timeout(u16),
    Condition(WireLeaf),
    Action(WireLeaf),
}

fn to_wire(node: &Node) -> WireNode {
    let leaf =
        |l: &Leaf| WireLeaf { behavior: l.behavior(), args: heapless::Vec::from_slice(l.args()).unwrap_or_default() };
    let kind = match node.kind() {
        NodeKind::Sequence => WireKind::Sequence,
        NodeKind::Fallback => WireKind::Fallback,
        NodeKind::SequenceWithMemory => WireKind::SequenceWithMemory,
        NodeKind::FallbackWithMemory => WireKind::FallbackWithMemory,
        &NodeKind::Parallel { success_threshold, failure_threshold } => {
            WireKind::Parallel { success_threshold, failure_threshold }
        }
        NodeKind::Inverter => WireKind::Inverter,
        NodeKind::ForceSuccess => WireKind::ForceSuccess,
        NodeKind::ForceFailure => WireKind::ForceFailure,
        &NodeKind::Repeat(n) => WireKind::Repeat(n),
        &NodeKind::Retry(n) => WireKind::Retry(n),
        &NodeKind::Timeout(n) => WireKind::Timeout(n),
        NodeKind::Condition(l) => WireKind::Condition(leaf(l)),
        NodeKind::Action(l) => WireKind::Action(leaf(l)),
    };
    WireNode { size: node.size(), kind }
}

fn from_wire(id: NodeId, w: WireNode) -> Result<Node, LoadError> {
    let leaf = |l: WireLeaf| {
        Leaf::with_args(l.behavior, &l.args).map_err(|e| {
            let position = match e {
                crate::node::LeafError::ReservedValue(p) => p as u8,
                crate::node::LeafError::TooManyArgs(n) => n as u8,
            };
            LoadError::BadArgument { node: id, fault: ArgumentFault::Reserved { position } }
        })
    };
    let kind = match w.kind {
        WireKind::Sequence => NodeKind::Sequence,
        WireKind::Fallback => NodeKind::Fallback,
        WireKind::SequenceWithMemory => NodeKind::SequenceWithMemory,
        WireKind::FallbackWithMemory => NodeKind::FallbackWithMemory,
        WireKind::Parallel { success_threshold, failure_threshold } => {
            NodeKind::Parallel { success_threshold, failure_threshold }
        }
        WireKind::Inverter => NodeKind::Inverter,
        WireKind::ForceSuccess => NodeKind::ForceSuccess,
        WireKind::ForceFailure => NodeKind::ForceFailure,
        WireKind::Repeat(n) => NodeKind::Repeat(n),
        WireKind::Retry(n) => NodeKind::Retry(n),
        WireKind::Timeout(n) => NodeKind::Timeout(n),
        WireKind::Condition(l) => NodeKind::Condition(leaf(l)?),
        WireKind::Action(l) => NodeKind::Action(leaf(l)?),
    };
    Ok(Node::new(kind, w.size))
}

/// Writes the image of `nodes` for the behavior set with `fingerprint` into `out`;
/// returns the image length. Any node array is written as given: [`load`] validates.
///
/// # Errors
/// [`EncodeError::BufferTooSmall`] (nothing meaningful is left in `out`), or
/// [`EncodeError::TooManyNodes`].
pub fn encode(nodes: &[Node], fingerprint: u64, out: &mut [u8]) -> Result<usize, EncodeError> {
    let count = u16::try_from(nodes.len()).map_err(|_| EncodeError::TooManyNodes { count: nodes.len() })?;
    let capacity = out.len();
    let too_small = EncodeError::BufferTooSmall { capacity };
    let (header, body) = out.split_at_mut_checked(HEADER_LEN).ok_or(too_small)?;
    header.get_mut(0..4).ok_or(too_small)?.copy_from_slice(&MAGIC);
    header.get_mut(4..6).ok_or(too_small)?.copy_from_slice(&VERSION.to_le_bytes());
    header.get_mut(6..14).ok_or(too_small)?.copy_from_slice(&fingerprint.to_le_bytes());
    header.get_mut(14..16).ok_or(too_small)?.copy_from_slice(&count.to_le_bytes());
    let mut used = 0usize;
    for node in nodes {
        let rest = body.get_mut(used..).ok_or(too_small)?;
        let written = postcard::to_slice(&to_wire(node), rest).map_err(|_| too_small)?;
        used += written.len();
    }
    let payload_end = HEADER_LEN + used;
    let crc = crc32(out.get(..payload_end).ok_or(too_small)?);
    out.get_mut(payload_end..payload_end + CRC_LEN).ok_or(too_small)?.copy_from_slice(&crc.to_le_bytes());
    Ok(payload_end + CRC_LEN)
}

fn u16_at(bytes: &[u8], at: usize) -> u16 {
    let mut b = [0u8; 2];
    if let Some(s) = bytes.get(at..at + 2) {
        b.copy_from_slice(s);
    }
    u16::from_le_bytes(b)
}

fn u32_at(bytes: &[u8], at: usize) -> u32 {
    let mut b = [0u8; 4];
    if let Some(s) = bytes.get(at..at + 4) {
        b.copy_from_slice(s);
    }
    u32::from_le_bytes(b)
}

fn u64_at(bytes: &[u8], at: usize) -> u64 {
    let mut b = [0u8; 8];
    if let Some(s) = bytes.get(at..at + 8) {
        b.copy_from_slice(s);
    }
    u64::from_le_bytes(b)
}

/// Checks the envelope (length, magic, version, CRC) and returns its fields; does not
/// decode the nodes.
///
/// # Errors
/// [`LoadError::Truncated`], [`LoadError::BadMagic`], [`LoadError::UnsupportedVersion`]
/// or [`LoadError::CrcMismatch`].
pub fn read_header(bytes: &[u8]) -> Result<Header, LoadError> {
    let len = bytes.len();
    if len < HEADER_LEN + CRC_LEN {
        return Err(LoadError::Truncated { len, inside_node: None });
    }
    let mut magic = [0u8; 4];
    if let Some(m) = bytes.get(0..4) {
        magic.copy_from_slice(m);
    }
    if magic != MAGIC {
        return Err(LoadError::BadMagic { found: magic });
    }
    let version = u16_at(bytes, 4);
    if version != VERSION {
        return Err(LoadError::UnsupportedVersion { found: version, supported: VERSION });
    }
    let stored = u32_at(bytes, len - CRC_LEN);
    let computed = crc32(bytes.get(..len - CRC_LEN).unwrap_or(&[]));
    if stored != computed {
        return Err(LoadError::CrcMismatch { stored, computed });
    }
    Ok(Header { version, fingerprint: u64_at(bytes, 6), node_count: u16_at(bytes, 14), len })
}

/// Decodes and validates an image into `storage`, for the behavior set `catalog`, with
/// at most `DEPTH` levels. Never panics, whatever `bytes` hold.
///
/// ```
/// use bt_core::{load, encode, fingerprint, BehaviorInfo, Builder, Node, Tree, image::max_image_len};
/// const SET: [BehaviorInfo<'static>; 2] =
///     [BehaviorInfo::condition("done?", 0), BehaviorInfo::action("work", 0)];
/// let mut nodes = [Node::EMPTY; 3];
/// let mut b = Builder::<4>::new(&mut nodes);
/// b.fallback()?.condition(0, &[])?.action(1, &[])?.end()?;
/// let nodes = b.finish()?;
///
/// let mut image = [0u8; max_image_len(3)];
/// let len = encode(nodes, fingerprint(&SET), &mut image)?;
///
/// let mut storage = [Node::EMPTY; 16];
/// let tree: Tree<'_, 8> = load(&image[..len], &SET, &mut storage)?;
/// assert_eq!(tree.nodes(), nodes);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// The first fault found, as a [`LoadError`] (see the module docs for the order).
pub fn load<'s, C: Catalog + ?Sized, const DEPTH: usize>(
    bytes: &[u8],
    catalog: &C,
    storage: &'s mut [Node],
) -> Result<Tree<'s, DEPTH>, LoadError> {
    let header = read_header(bytes)?;
    let expected = catalog.fingerprint();
    if header.fingerprint != expected {
        return Err(LoadError::ForeignBehaviorSet { image: header.fingerprint, expected });
    }
    let count = usize::from(header.node_count);
    if count == 0 {
        return Err(LoadError::EmptyTree);
    }
    if count > storage.len() {
        return Err(LoadError::TooManyNodes { count, capacity: storage.len() });
    }
    let payload = bytes.get(HEADER_LEN..header.len - CRC_LEN).unwrap_or(&[]);
    let mut rest = payload;
    for (i, slot) in storage.iter_mut().take(count).enumerate() {
        let id = i as NodeId;
        let offset = HEADER_LEN + (payload.len() - rest.len());
        let (wire, tail) = postcard::take_from_bytes::<WireNode>(rest).map_err(|e| match e {
            postcard::Error::DeserializeUnexpectedEnd => {
                LoadError::Truncated { len: header.len, inside_node: Some(id) }
            }
            _ => LoadError::MalformedNode { node: id, offset },
        })?;
        *slot = from_wire(id, wire)?;
        rest = tail;
    }
    if !rest.is_empty() {
        return Err(LoadError::TrailingBytes { count: rest.len() });
    }
    let nodes: &'s [Node] = storage;
    Tree::validate(nodes.get(..count).unwrap_or(&[]), catalog)
}
