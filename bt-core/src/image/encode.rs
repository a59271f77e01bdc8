//! Writing an image: the nodes, their value table and the optional sections, with the
//! header and the CRC (the layout is in [the module docs](super)).

use serde::Serialize;

use super::wire::to_wire;
use super::{
    CRC_LEN, HEADER_LEN, MAGIC, MAX_SECTION_HEAD_LEN, SECTION_NAMES, SECTION_PORTS, SECTION_VALUES,
    VERSION_WITHOUT_SCRIPTS, crc32, max_image_len_with,
};
use crate::error::EncodeError;
use crate::node::Node;

/// What an image holds besides its fingerprint: the nodes, the value table of their
/// extended leaves, and an optional names section for host tools.
///
/// ```
/// use bt_core::image::ImageParts;
/// # let nodes = [bt_core::Node::EMPTY];
/// let parts = ImageParts::new(&nodes).values(&[4, 5, 6, 7]).names(b"cube");
/// assert_eq!(parts.nodes.len(), 1);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct ImageParts<'a> {
    /// The nodes, in pre-order.
    pub nodes: &'a [Node],
    /// The value table (empty: no values section).
    pub values: &'a [u16],
    /// The names section's body (`None`: no names section).
    pub names: Option<&'a [u8]>,
    /// The ports section's body (`None`: no ports section), as
    /// [`port::encode_table`](crate::port::encode_table) writes it.
    pub ports: Option<&'a [u8]>,
}

impl<'a> ImageParts<'a> {
    /// Just the nodes.
    #[must_use]
    pub const fn new(nodes: &'a [Node]) -> Self {
        Self { nodes, values: &[], names: None, ports: None }
    }

    /// With a ports section.
    #[must_use]
    pub const fn ports(mut self, ports: &'a [u8]) -> Self {
        self.ports = Some(ports);
        self
    }

    /// With a value table.
    #[must_use]
    pub const fn values(mut self, values: &'a [u16]) -> Self {
        self.values = values;
        self
    }

    /// With a names section.
    #[must_use]
    pub const fn names(mut self, names: &'a [u8]) -> Self {
        self.names = Some(names);
        self
    }

    /// An upper bound on the size of their image.
    #[must_use]
    pub fn max_len(&self) -> usize {
        max_image_len_with(self.nodes.len(), self.values.len(), self.names.map_or(0, <[u8]>::len))
            + self.ports.map_or(0, |p| MAX_SECTION_HEAD_LEN + p.len())
    }
}

/// Writes the image of `nodes` for the behavior set with `fingerprint` into `out`;
/// returns the image length. Any node array is written as given: [`load`](super::load) validates.
/// The nodes may not have extended leaves: [`encode_with`] writes their value table.
///
/// # Errors
/// [`EncodeError::BufferTooSmall`] (nothing meaningful is left in `out`), or
/// [`EncodeError::TooManyNodes`].
pub fn encode(nodes: &[Node], fingerprint: u64, out: &mut [u8]) -> Result<usize, EncodeError> {
    encode_with(&ImageParts::new(nodes), fingerprint, out)
}

/// Writes the image of `parts` for the behavior set with `fingerprint` into `out`;
/// returns the image length. [`ImageParts::max_len`] bounds the size.
///
/// # Errors
/// [`EncodeError::BufferTooSmall`] (nothing meaningful is left in `out`),
/// [`EncodeError::TooManyNodes`] or [`EncodeError::TooManyValues`].
pub fn encode_with(parts: &ImageParts<'_>, fingerprint: u64, out: &mut [u8]) -> Result<usize, EncodeError> {
    let nodes = parts.nodes;
    let count = u16::try_from(nodes.len()).map_err(|_| EncodeError::TooManyNodes { count: nodes.len() })?;
    if parts.values.len() > usize::from(u16::MAX) {
        return Err(EncodeError::TooManyValues { count: parts.values.len() });
    }
    let capacity = out.len();
    let too_small = EncodeError::BufferTooSmall { capacity };
    let (header, body) = out.split_at_mut_checked(HEADER_LEN).ok_or(too_small)?;
    header.get_mut(0..4).ok_or(too_small)?.copy_from_slice(&MAGIC);
    header.get_mut(6..14).ok_or(too_small)?.copy_from_slice(&fingerprint.to_le_bytes());
    header.get_mut(14..16).ok_or(too_small)?.copy_from_slice(&count.to_le_bytes());
    let mut w = Writer { buf: body, used: 0, too_small };
    // The oldest version that has every node's tag (see `WireKind::since`).
    let mut version = VERSION_WITHOUT_SCRIPTS;
    for node in nodes {
        let wire = to_wire(node);
        version = version.max(wire.since());
        w.put(&wire)?;
    }
    header.get_mut(4..6).ok_or(too_small)?.copy_from_slice(&version.to_le_bytes());
    if !parts.values.is_empty() {
        // The body's length first: the count and the values, each a varint.
        let len = varint_len(parts.values.len() as u32)
            + parts.values.iter().map(|&v| varint_len(u32::from(v))).sum::<usize>();
        w.put(&SECTION_VALUES)?;
        w.put(&(len as u32))?;
        w.put(&(parts.values.len() as u32))?;
        for v in parts.values {
            w.put(v)?;
        }
    }
    if let Some(names) = parts.names {
        w.put(&SECTION_NAMES)?;
        w.put(&u32::try_from(names.len()).map_err(|_| too_small)?)?;
        w.bytes(names)?;
    }
    if let Some(ports) = parts.ports {
        w.put(&SECTION_PORTS)?;
        w.put(&u32::try_from(ports.len()).map_err(|_| too_small)?)?;
        w.bytes(ports)?;
    }
    let payload_end = HEADER_LEN + w.used;
    let crc = crc32(out.get(..payload_end).ok_or(too_small)?);
    out.get_mut(payload_end..payload_end + CRC_LEN).ok_or(too_small)?.copy_from_slice(&crc.to_le_bytes());
    Ok(payload_end + CRC_LEN)
}

/// Bytes of `v` as a LEB128 varint.
const fn varint_len(v: u32) -> usize {
    match v {
        0..0x80 => 1,
        0x80..0x4000 => 2,
        0x4000..0x20_0000 => 3,
        0x20_0000..0x1000_0000 => 4,
        _ => 5,
    }
}

struct Writer<'o> {
    buf: &'o mut [u8],
    used: usize,
    too_small: EncodeError,
}

impl Writer<'_> {
    fn put<T: Serialize>(&mut self, value: &T) -> Result<(), EncodeError> {
        let rest = self.buf.get_mut(self.used..).ok_or(self.too_small)?;
        let written = postcard::to_slice(value, rest).map_err(|_| self.too_small)?;
        self.used += written.len();
        Ok(())
    }

    fn bytes(&mut self, bytes: &[u8]) -> Result<(), EncodeError> {
        let end = self.used + bytes.len();
        self.buf.get_mut(self.used..end).ok_or(self.too_small)?.copy_from_slice(bytes);
        self.used = end;
        Ok(())
    }
}
