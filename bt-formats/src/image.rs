//! The deployable image of a tree (bt-core's envelope, see [`bt_core::image`]) with
//! what travels with it: the value table of extended leaves, the ports section the
//! controller reads its leaves' constants and blackboard slots from, and the names
//! section ([`Names`]) that only host tools read.
//!
//! ```
//! use bt_core::{BehaviorInfo, Builder, Catalog, Node};
//! use bt_formats::{Names, image::{Image, strip_names}};
//!
//! const SET: [BehaviorInfo<'static>; 1] = [BehaviorInfo::action("MoveTo", 0)];
//! let mut storage = [Node::EMPTY; 1];
//! let mut b = Builder::<4>::new(&mut storage);
//! b.action(0, &[])?;
//! let nodes = b.finish()?;
//! let names = Names::of("a tree that moves", &SET[..], &[]);
//! let named = Image::new(nodes).names(&names).encode(SET.fingerprint())?;
//! let bare = Image::new(nodes).encode(SET.fingerprint())?;
//! assert_eq!(Names::of_image(&named)?.map(|n| n.title), Some("a tree that moves".to_string()));
//! assert_eq!(strip_names(&named)?, bare);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use bt_core::image::{ImageParts, SECTION_PORTS};
use bt_core::port::SlotInfo;
use bt_core::{EncodeError, LoadError, Node};

use crate::constant::Constant;
use crate::names::Names;

/// Why a tree could not be made an image.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ImageError {
    /// The ports section would exceed what a section holds.
    #[error("the ports section: {0}")]
    Ports(bt_core::port::PortFault),
    /// bt-core refused to encode it (too many nodes or values).
    #[error("encoding the image: {0}")]
    Encode(#[from] EncodeError),
    /// The image given does not read.
    #[error(transparent)]
    Load(#[from] LoadError),
}

/// A tree's size as a controller holds it: its image without the names section (the
/// bytes `sim-host deploy --strip-names` sends), and its nodes. The planner's
/// `--max-bytes` and learning's size bound both measure this.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Size {
    /// Bytes of the image without the names section.
    pub bytes: usize,
    /// bt-core nodes.
    pub nodes: usize,
}

/// A tree and what its image holds besides the nodes; [`Image::encode`] writes it.
#[derive(Clone, Copy, Debug, Default)]
pub struct Image<'a> {
    nodes: &'a [Node],
    values: &'a [u16],
    slots: &'a [SlotInfo],
    constants: &'a [Constant],
    names: Option<&'a Names>,
}

impl<'a> Image<'a> {
    /// The nodes alone, in pre-order.
    #[must_use]
    pub const fn new(nodes: &'a [Node]) -> Self {
        Self { nodes, values: &[], slots: &[], constants: &[], names: None }
    }

    /// With the value table of extended leaves (empty: none).
    #[must_use]
    pub const fn values(mut self, values: &'a [u16]) -> Self {
        self.values = values;
        self
    }

    /// With blackboard slots and constants: a ports section, unless both are empty.
    #[must_use]
    pub const fn ports(mut self, slots: &'a [SlotInfo], constants: &'a [Constant]) -> Self {
        self.slots = slots;
        self.constants = constants;
        self
    }

    /// With a names section (its constants are not written: they are the ports').
    #[must_use]
    pub const fn names(mut self, names: &'a Names) -> Self {
        self.names = Some(names);
        self
    }

    /// Its [`Size`]: the image without the names section (the behavior set's
    /// fingerprint is a fixed-width header field, so it does not matter here).
    ///
    /// # Errors
    /// As [`Image::encode`].
    pub fn size(&self) -> Result<Size, ImageError> {
        let bytes = Self { names: None, ..*self }.encode(0)?.len();
        Ok(Size { bytes, nodes: self.nodes.len() })
    }

    /// The image bytes for the behavior set with `fingerprint`.
    ///
    /// # Errors
    /// [`ImageError`] when the tree, its value table or its ports do not fit an image.
    pub fn encode(&self, fingerprint: u64) -> Result<Vec<u8>, ImageError> {
        let ports = self.ports_section()?;
        let names = self.names.map(Names::to_section);
        let mut parts = ImageParts::new(self.nodes).values(self.values);
        if let Some(p) = &ports {
            parts = parts.ports(p);
        }
        if let Some(n) = &names {
            parts = parts.names(n);
        }
        let mut buf = vec![0u8; parts.max_len()];
        let len = bt_core::encode_with(&parts, fingerprint, &mut buf)?;
        buf.truncate(len);
        Ok(buf)
    }

    /// The ports section's body: `None` when there are neither slots nor constants.
    fn ports_section(&self) -> Result<Option<Vec<u8>>, ImageError> {
        if self.constants.is_empty() && self.slots.is_empty() {
            return Ok(None);
        }
        let constants: Vec<bt_core::port::Constant<'_>> = self.constants.iter().map(Constant::as_constant).collect();
        // Counts and slots are at most 3 bytes each, offsets 2, a constant's tag 1 and
        // its value at most 10 bytes or a string's length and bytes.
        let bound = 6
            + 4 * self.slots.len()
            + self.constants.iter().map(|c| 13 + if let Constant::Str(s) = c { s.len() } else { 0 }).sum::<usize>();
        let mut out = vec![0u8; bound];
        let n = bt_core::port::encode_table(self.slots, &constants, &mut out).map_err(ImageError::Ports)?;
        out.truncate(n);
        Ok(Some(out))
    }
}

/// The same image without its names section: what a controller needs and nothing more
/// (it never reads the names). An image without names comes back unchanged.
///
/// # Errors
/// [`ImageError::Load`] with the first fault of the image's envelope, nodes or
/// sections.
pub fn strip_names(bytes: &[u8]) -> Result<Vec<u8>, ImageError> {
    let header = bt_core::image::read_header(bytes)?;
    let mut nodes = vec![Node::EMPTY; usize::from(header.node_count)];
    let mut values = vec![0u16; usize::from(u16::MAX)];
    let decoded = bt_core::image::decode(bytes, &mut nodes, &mut values)?;
    let mut parts = ImageParts::new(&nodes[..decoded.nodes]).values(&values[..decoded.values]);
    let ports = bt_core::image::section(bytes, SECTION_PORTS)?;
    if let Some(p) = ports {
        parts = parts.ports(p);
    }
    let mut buf = vec![0u8; parts.max_len()];
    let len = bt_core::encode_with(&parts, header.fingerprint, &mut buf)?;
    buf.truncate(len);
    Ok(buf)
}

#[cfg(test)]
mod tests {
    use bt_core::port::SlotInfo;
    use bt_core::{Behavior, BehaviorInfo, Catalog, Leaf, NodeKind, PortInfo, PortType};

    use super::*;

    const PORTS: [PortInfo<'static>; 2] =
        [PortInfo::input("goal", PortType::Other, "Pose"), PortInfo::input("speed", PortType::Double, "double")];
    const SET: [Behavior<'static>; 1] = [Behavior::new(BehaviorInfo::action("MoveTo", 2), &PORTS)];

    #[test]
    fn an_image_with_ports_and_names_loads_and_shows_its_leaves_as_written() {
        let nodes = [Node::new(NodeKind::Action(Leaf::with_args(0, &[0x8000, 0]).unwrap()), 1)];
        let slots = [SlotInfo { ty: PortType::Other, initial: None }];
        let constants = [Constant::Double(0.5)];
        let mut names = Names::of("t", &SET[..], &[]);
        names.slots = vec!["target".into()];
        let bytes = Image::new(&nodes).ports(&slots, &constants).names(&names).encode(SET.fingerprint()).unwrap();
        let mut storage = [Node::EMPTY; 1];
        let mut values = [0u16; 0];
        let (tree, table) = bt_core::load_with_ports::<_, 4>(&bytes, &SET[..], &mut storage, &mut values).unwrap();
        assert_eq!(table.constant(0), Some(bt_core::port::Constant::Double(0.5)));
        let read = Names::of_image(&bytes).unwrap().unwrap();
        assert_eq!(read.constants, constants);
        assert_eq!(read.fingerprint(), SET.fingerprint());
        assert_eq!(tree.display(&read).to_string(), "--> MoveTo(goal={target}, speed=0.5)\n");
        // Without names the controller's bytes are the same but for the section and CRC.
        let bare = Image::new(&nodes).ports(&slots, &constants).encode(SET.fingerprint()).unwrap();
        assert_eq!(strip_names(&bytes).unwrap(), bare);
        assert_eq!(strip_names(&bare).unwrap(), bare);
        assert_eq!(Names::of_image(&bare), Ok(None));
        assert!(matches!(Names::of_image(&bytes[..bytes.len() - 1]), Err(crate::NamesError::Image(_))));
    }

    #[test]
    fn too_many_nodes_is_an_error() {
        let nodes = vec![Node::EMPTY; usize::from(u16::MAX) + 1];
        assert!(matches!(Image::new(&nodes).encode(0), Err(ImageError::Encode(EncodeError::TooManyNodes { .. }))));
    }
}
