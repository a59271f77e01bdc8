//! The deployable image: a tree as bytes, checked end to end before it can run.
//!
//! # Byte layout (format version 4)
//!
//! All fixed-width integers are little-endian.
//!
//! | offset | size | field |
//! |-------:|-----:|-------|
//! | 0      | 4    | magic, the ASCII bytes `BTIM` |
//! | 4      | 2    | format version, `u16` (4, 3 or 2, see below; version 1 is still read) |
//! | 6      | 8    | fingerprint of the behavior set, `u64` (see [`fingerprint`](crate::fingerprint)) |
//! | 14     | 2    | node count `n`, `u16`, at least 1 |
//! | 16     | …    | `n` nodes in pre-order, each [postcard]-encoded as below |
//! | …      | …    | sections (version 2), see below |
//! | end-4  | 4    | CRC-32 (ISO-HDLC, as zlib's `crc32`) of every byte before it, `u32` |
//!
//! A node is encoded as its subtree size (`u16`, itself included) followed by its kind,
//! a varint tag and the tag's fields: the table of tags is in [`wire`].
//!
//! ## Sections
//!
//! Between the last node and the CRC, a version-2 image holds zero or more sections,
//! each a tag byte, the body's length in bytes (a varint `u32`) and the body, in
//! increasing tag order, each tag at most once:
//!
//! | tag | section | body |
//! |----:|---------|------|
//! | 1 | values | the value table of extended leaves: a varint count, then that many varint `u16` |
//! | 2 | names | for tools on the host (behavior and object names); never read by the loader |
//! | 3 | ports | blackboard slots and constants of leaves' ports; the layout is in [`crate::port`] |
//!
//! A leaf's values (grounded arguments, port references) are kept inline when there are
//! at most [`MAX_ARGS`](crate::MAX_ARGS); a leaf with more refers to a range of the
//! value table, so every node keeps its 12 bytes. [`load_with`] decodes the table into
//! storage the caller gives; behaviors read values with
//! [`Context::args`](crate::Context::args).
//!
//! # Versioning
//!
//! The version names the whole layout: header, tags, field order, varint rules,
//! sections, CRC. Any change to any of them — a new node kind or section included —
//! takes the next version; a loader reads exactly the versions it knows and refuses
//! others with [`LoadError::UnsupportedVersion`], so old firmware never misreads a newer
//! image. The magic and the version field stay at offsets 0 and 4 in every version. This
//! build reads versions 1 to 4. It writes the oldest version that has every node of the
//! tree: version 4 for a tree with a kind of BehaviorTree.CPP 3 (tags 41 to 44) or a
//! span that never expires, version 3 for one with script, `Sleep`, `Guard`, `Loop` or
//! `ManualSelector` nodes (tags 34 to 40), version 2 otherwise, so that controllers built
//! before a kind existed keep loading every image they can run. A version-1 image has
//! neither extended leaves nor sections.
//!
//! # Loading
//!
//! [`load`] checks, in this order, and stops at the first fault: the length, the magic,
//! the version, the CRC, the fingerprint against the given behavior set, the node count
//! against the storage, the decoding of every node, the sections (framing, order, the
//! value table against its storage), that no bytes follow the last section, and the tree
//! itself ([`Tree::validate_with`]). What it returns is a [`Tree`] — the only thing the
//! executor accepts.
//!
//! [postcard]: https://docs.rs/postcard

use crate::catalog::Catalog;
use crate::error::LoadError;
#[cfg(feature = "btcpp")]
use crate::node::NodeKind;
use crate::node::{Node, NodeId};
use crate::port::PortTable;
use crate::tree::Tree;

mod encode;
pub mod wire;

pub use encode::{ImageParts, encode, encode_with};

use wire::{WireNode, from_wire};

/// The first four bytes of every image.
pub const MAGIC: [u8; 4] = *b"BTIM";
/// The newest format version this build reads and writes (for trees with the kinds of
/// BehaviorTree.CPP 3).
pub const VERSION: u16 = 4;
/// The version this build writes for trees with scripts and without the kinds of
/// version 4.
pub const VERSION_WITH_SCRIPTS: u16 = 3;
/// The version this build writes for trees without scripts.
pub const VERSION_WITHOUT_SCRIPTS: u16 = 2;
/// The oldest format version this build reads.
pub const OLDEST_VERSION: u16 = 1;
/// Bytes before the first node.
pub const HEADER_LEN: usize = 16;
/// Bytes of the trailing CRC-32.
pub const CRC_LEN: usize = 4;
/// Most bytes one encoded node can take.
pub const MAX_NODE_LEN: usize = 3 + 1 + 3 + 1 + 3 * 3;
/// Most bytes a section's tag and length take.
pub const MAX_SECTION_HEAD_LEN: usize = 1 + 5;

/// Tag of the value table section.
pub const SECTION_VALUES: u8 = 1;
/// Tag of the names section: host tools' names, never read by the loader.
pub const SECTION_NAMES: u8 = 2;
/// Tag of the ports section: blackboard slots and constants ([`crate::port`]).
pub const SECTION_PORTS: u8 = 3;
/// The highest section tag this build knows.
const LAST_SECTION: u8 = SECTION_PORTS;

/// An upper bound on the size of the image of a tree of `nodes` nodes, without sections.
#[must_use]
pub const fn max_image_len(nodes: usize) -> usize {
    HEADER_LEN + nodes * MAX_NODE_LEN + CRC_LEN
}

/// An upper bound on the size of the image of [`ImageParts`] with `nodes` nodes, a value
/// table of `values` entries, and a names section of `names` bytes (0 for none).
#[must_use]
pub const fn max_image_len_with(nodes: usize, values: usize, names: usize) -> usize {
    let values_len = if values == 0 { 0 } else { MAX_SECTION_HEAD_LEN + 3 + 3 * values };
    let names_len = if names == 0 { 0 } else { MAX_SECTION_HEAD_LEN + names };
    max_image_len(nodes) + values_len + names_len
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
    if !(OLDEST_VERSION..=VERSION).contains(&version) {
        return Err(LoadError::UnsupportedVersion { found: version, supported: VERSION });
    }
    let stored = u32_at(bytes, len - CRC_LEN);
    let computed = crc32(bytes.get(..len - CRC_LEN).unwrap_or(&[]));
    if stored != computed {
        return Err(LoadError::CrcMismatch { stored, computed });
    }
    Ok(Header { version, fingerprint: u64_at(bytes, 6), node_count: u16_at(bytes, 14), len })
}

/// Decodes the nodes of a checked image into `storage` (or, without storage, only
/// checks that they decode); returns the bytes after the last node.
fn decode_nodes<'b>(bytes: &'b [u8], header: &Header, mut storage: Option<&mut [Node]>) -> Result<&'b [u8], LoadError> {
    let payload = bytes.get(HEADER_LEN..header.len - CRC_LEN).unwrap_or(&[]);
    let mut rest = payload;
    for i in 0..usize::from(header.node_count) {
        let id = i as NodeId;
        let offset = HEADER_LEN + (payload.len() - rest.len());
        let (wire, tail) = postcard::take_from_bytes::<WireNode>(rest).map_err(|e| match e {
            postcard::Error::DeserializeUnexpectedEnd => {
                LoadError::Truncated { len: header.len, inside_node: Some(id) }
            }
            _ => unsupported(rest, header.version, id).unwrap_or(LoadError::MalformedNode { node: id, offset }),
        })?;
        if !wire.in_version(header.version) {
            return Err(LoadError::MalformedNode { node: id, offset });
        }
        let node = from_wire(id, offset, wire)?;
        if let Some(slot) = storage.as_deref_mut().and_then(|s| s.get_mut(i)) {
            *slot = node;
        }
        rest = tail;
    }
    Ok(rest)
}

/// Why node `id` at the start of `bytes` did not decode, when it is a kind this build
/// leaves out: its tag follows the subtree size.
fn unsupported(bytes: &[u8], version: u16, id: NodeId) -> Option<LoadError> {
    #[cfg(not(feature = "btcpp"))]
    if version >= 2 {
        let (_size, after) = postcard::take_from_bytes::<u16>(bytes).ok()?;
        let (tag, _) = postcard::take_from_bytes::<u32>(after).ok()?;
        // Tags 15 and up: the kinds for BehaviorTree.CPP's and Nav2's nodes.
        return (15..=44)
            .contains(&tag)
            .then_some(LoadError::UnsupportedKind { node: id, kind: crate::tree::LEFT_OUT_KIND });
    }
    let _ = (bytes, version, id);
    None
}

/// One section: its tag, the offset of its head in the image, and its body.
struct Section<'b> {
    tag: u8,
    offset: usize,
    body: &'b [u8],
}

/// Walks the sections in `rest` (the bytes between the last node and the CRC, at
/// `offset` in the image), checking their framing and order, and calls `each` on them.
fn sections<'b>(
    mut rest: &'b [u8],
    mut offset: usize,
    header: &Header,
    mut each: impl FnMut(Section<'b>) -> Result<(), LoadError>,
) -> Result<(), LoadError> {
    if header.version < 2 {
        if !rest.is_empty() {
            return Err(LoadError::TrailingBytes { count: rest.len() });
        }
        return Ok(());
    }
    let mut last = 0u8;
    while let Some((&tag, after_tag)) = rest.split_first() {
        let malformed = LoadError::MalformedSection { tag, offset };
        if tag == 0 || tag > LAST_SECTION {
            return Err(LoadError::UnknownSection { tag, offset });
        }
        if tag <= last {
            return Err(malformed);
        }
        let (len, after_len) = postcard::take_from_bytes::<u32>(after_tag).map_err(|_| malformed)?;
        let len = len as usize;
        if len > after_len.len() {
            return Err(malformed);
        }
        let (body, tail) = after_len.split_at(len);
        each(Section { tag, offset, body })?;
        offset += rest.len() - tail.len();
        rest = tail;
        last = tag;
    }
    Ok(())
}

/// Decodes a value table section's body into `values`; returns the number of values.
fn decode_values(section: &Section<'_>, values: &mut [u16]) -> Result<usize, LoadError> {
    let malformed = LoadError::MalformedSection { tag: section.tag, offset: section.offset };
    let (count, mut rest) = postcard::take_from_bytes::<u32>(section.body).map_err(|_| malformed)?;
    let count = count as usize;
    if count > values.len() {
        return Err(LoadError::TooManyValues { count, capacity: values.len() });
    }
    for slot in values.iter_mut().take(count) {
        let (v, tail) = postcard::take_from_bytes::<u16>(rest).map_err(|_| malformed)?;
        *slot = v;
        rest = tail;
    }
    if !rest.is_empty() {
        return Err(malformed);
    }
    Ok(count)
}

/// Decodes and validates an image into `storage`, for the behavior set `catalog`, with
/// at most `DEPTH` levels. Never panics, whatever `bytes` hold. An image with a value
/// table needs [`load_with`].
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
    load_with(bytes, catalog, storage, &mut [])
}

/// As [`load`], decoding the image's value table (extended leaves' values) into
/// `values`.
///
/// ```
/// use bt_core::{load_with, encode_with, fingerprint, image::ImageParts};
/// use bt_core::{BehaviorInfo, Leaf, Node, NodeKind, Tree};
/// const SET: [BehaviorInfo<'static>; 1] = [BehaviorInfo::action("drive-truck", 4)];
/// let leaf = Leaf::extended(0, 0, 4)?; // its values: the table's entries 0..4
/// let nodes = [Node::new(NodeKind::Action(leaf), 1)];
/// let parts = ImageParts::new(&nodes).values(&[7, 1, 2, 3]);
/// let mut image = vec![0u8; parts.max_len()];
/// let len = encode_with(&parts, fingerprint(&SET), &mut image)?;
///
/// let (mut storage, mut values) = ([Node::EMPTY; 4], [0u16; 8]);
/// let tree: Tree<'_, 4> = load_with(&image[..len], &SET, &mut storage, &mut values)?;
/// assert_eq!(tree.args(&leaf), &[7, 1, 2, 3]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// As [`load`]; [`LoadError::TooManyValues`] when the table does not fit `values`.
pub fn load_with<'s, C: Catalog + ?Sized, const DEPTH: usize>(
    bytes: &[u8],
    catalog: &C,
    storage: &'s mut [Node],
    values: &'s mut [u16],
) -> Result<Tree<'s, DEPTH>, LoadError> {
    let header = read_header(bytes)?;
    let expected = catalog.fingerprint();
    if header.fingerprint != expected {
        return Err(LoadError::ForeignBehaviorSet { image: header.fingerprint, expected });
    }
    if header.node_count == 0 {
        return Err(LoadError::EmptyTree);
    }
    let (count, value_count) = decode_body(bytes, &header, storage, values)?;
    let nodes: &'s [Node] = storage;
    let values: &'s [u16] = values;
    Tree::validate_with(nodes.get(..count).unwrap_or(&[]), values.get(..value_count).unwrap_or(&[]), catalog)
}

/// [`load_with`] for behavior sets whose behaviors declare ports: also reads the image's
/// ports section and checks every leaf against it ([`PortTable::check_leaf`]), and
/// returns the table the behaviors read their ports from. (A separate function so that
/// controllers without ports do not carry the code.)
///
/// # Errors
/// As [`load_with`], and [`LoadError::BadPort`] naming the first leaf whose port values
/// do not fit the section, or [`LoadError::MalformedSection`] for a ports section that
/// does not decode.
pub fn load_with_ports<'s, C: Catalog + ?Sized, const DEPTH: usize>(
    bytes: &'s [u8],
    catalog: &C,
    storage: &'s mut [Node],
    values: &'s mut [u16],
) -> Result<(Tree<'s, DEPTH>, PortTable<'s>), LoadError> {
    let tree: Tree<'s, DEPTH> = load_with(bytes, catalog, storage, values)?;
    let ports = PortTable::of_image(bytes)?;
    for (id, node) in tree.nodes().iter().enumerate() {
        if let Some((_, leaf)) = node.kind().leaf() {
            ports
                .check_leaf(catalog, leaf.behavior(), tree.args(&leaf))
                .map_err(|fault| LoadError::BadPort { node: id as NodeId, fault })?;
        }
        #[cfg(feature = "btcpp")]
        {
            let checked = match *node.kind() {
                NodeKind::Script(code)
                | NodeKind::ScriptCondition(code)
                | NodeKind::Precondition { code, .. }
                | NodeKind::Check { code, .. } => crate::script::check(code.words(tree.values()), &ports),
                // A count read from a slot: the program that reads it.
                NodeKind::Cycles { count, from_slot: true, .. } => {
                    crate::script::check(&[crate::script::op::LOAD, count], &ports)
                }
                NodeKind::Guard(table) => crate::script::check_guard(table.words(tree.values()), &ports),
                NodeKind::Loop { table, .. } => crate::script::check_queue(table.words(tree.values()), &ports),
                _ => Ok(()),
            };
            checked.map_err(|fault| LoadError::BadScript { node: id as NodeId, fault })?;
        }
    }
    Ok((tree, ports))
}

impl<'b> PortTable<'b> {
    /// The ports section of an image (empty when it has none), checked: what a
    /// controller keeps beside the tree to read its leaves' ports. [`load_with`] checks
    /// every leaf against it.
    ///
    /// # Errors
    /// A bad envelope or section framing, or [`LoadError::MalformedSection`] for a
    /// ports section that does not decode.
    pub fn of_image(bytes: &'b [u8]) -> Result<Self, LoadError> {
        match section(bytes, SECTION_PORTS)? {
            None => Ok(PortTable::EMPTY),
            Some(body) => PortTable::parse(body).map_err(|_| {
                let offset = (body.as_ptr() as usize).saturating_sub(bytes.as_ptr() as usize);
                LoadError::MalformedSection { tag: SECTION_PORTS, offset }
            }),
        }
    }
}

/// What [`decode`] found in an image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Decoded {
    /// The envelope.
    pub header: Header,
    /// Nodes written to the storage.
    pub nodes: usize,
    /// Values written to the value storage.
    pub values: usize,
}

/// Decodes an image's nodes and value table without validating the tree or checking
/// the fingerprint: for host tools that must show an image whose behavior set they do
/// not know. A controller uses [`load_with`].
///
/// # Errors
/// The first fault in the envelope, the nodes or the sections, as a [`LoadError`].
pub fn decode(bytes: &[u8], storage: &mut [Node], values: &mut [u16]) -> Result<Decoded, LoadError> {
    let header = read_header(bytes)?;
    let (nodes, values) = decode_body(bytes, &header, storage, values)?;
    Ok(Decoded { header, nodes, values })
}

/// Decodes the nodes and the value table of an image whose envelope checked out;
/// returns how many of each.
fn decode_body(
    bytes: &[u8],
    header: &Header,
    storage: &mut [Node],
    values: &mut [u16],
) -> Result<(usize, usize), LoadError> {
    let count = usize::from(header.node_count);
    if count > storage.len() {
        return Err(LoadError::TooManyNodes { count, capacity: storage.len() });
    }
    let rest = decode_nodes(bytes, header, Some(storage))?;
    let offset = header.len - CRC_LEN - rest.len();
    let mut value_count = 0;
    sections(rest, offset, header, |s| {
        if s.tag == SECTION_VALUES {
            value_count = decode_values(&s, values)?;
        }
        Ok(())
    })?;
    Ok((count, value_count))
}

/// The body of section `tag` of an image, `None` when the image has no such section.
/// Checks the envelope, the nodes' decoding and the sections' framing, not the tree.
///
/// # Errors
/// The first fault found in those, as a [`LoadError`].
pub fn section(bytes: &[u8], tag: u8) -> Result<Option<&[u8]>, LoadError> {
    let header = read_header(bytes)?;
    let rest = decode_nodes(bytes, &header, None)?;
    let offset = header.len - CRC_LEN - rest.len();
    let mut found = None;
    sections(rest, offset, &header, |s| {
        if s.tag == tag {
            found = Some(s.body);
        }
        Ok(())
    })?;
    Ok(found)
}
