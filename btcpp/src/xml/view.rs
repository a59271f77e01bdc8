//! An imported tree as the renderers and writers see it: its behavior set, with leaf
//! values shown as the document wrote them (`goal={goal}`, `speed=0.5`).

use std::fmt;

use bt_core::{BehaviorId, BehaviorInfo, Catalog, Leaf, PortInfo, PortValue};

use crate::xml::lower::Imported;
use crate::xml::write::{NoPorts, XmlError, XmlOptions, to_xml_with};

impl Catalog for Imported {
    fn len(&self) -> usize {
        self.catalog.len()
    }

    fn info(&self, id: BehaviorId) -> Option<BehaviorInfo<'_>> {
        self.catalog.info(id)
    }

    fn port(&self, id: BehaviorId, position: usize) -> Option<PortInfo<'_>> {
        self.catalog.port(id, position)
    }

    fn fingerprint(&self) -> u64 {
        self.fingerprint
    }

    /// `ID(port=value, ...)`, unset ports left out.
    fn write_leaf(&self, f: &mut fmt::Formatter<'_>, leaf: &Leaf) -> fmt::Result {
        let b = leaf.behavior();
        match self.info(b) {
            Some(info) => f.write_str(info.name)?,
            None => write!(f, "#{b}")?,
        }
        let mut first = true;
        for (pos, &v) in self.leaf_values(leaf).iter().enumerate() {
            if PortValue::from_u16(v) == PortValue::Unset {
                continue;
            }
            f.write_str(if first { "(" } else { ", " })?;
            first = false;
            if let Some(p) = self.port(b, pos) {
                write!(f, "{}=", p.name)?;
            }
            self.write_arg(f, b, pos, v)?;
        }
        if !first {
            f.write_str(")")?;
        }
        Ok(())
    }

    /// A constant as written, a slot as `{key}`.
    fn write_arg(&self, f: &mut fmt::Formatter<'_>, behavior: BehaviorId, position: usize, value: u16) -> fmt::Result {
        if self.port(behavior, position).is_none() {
            return write!(f, "{value}");
        }
        match PortValue::from_u16(value) {
            PortValue::Constant(i) => match self.constants.get(usize::from(i)) {
                Some(c) => f.write_str(&c.text()),
                None => write!(f, "#const{i}"),
            },
            PortValue::Slot(i) => match self.slots.get(usize::from(i)) {
                Some(s) => write!(f, "{{{}}}", s.name),
                None => write!(f, "{{#slot{i}}}"),
            },
            PortValue::Unset => Ok(()),
        }
    }
}

/// Why an imported tree could not be made an image.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ImageError {
    /// The tree uses what this image format cannot hold.
    #[error("{0}")]
    Unsupported(String),
    /// bt-core refused to encode it.
    #[error("encoding the image: {0}")]
    Encode(#[from] bt_core::EncodeError),
}

impl Imported {
    /// The image a controller loads.
    ///
    /// # Errors
    /// [`ImageError`] when the tree does not fit an image.
    pub fn image(&self) -> Result<Vec<u8>, ImageError> {
        if !self.constants.is_empty() || !self.slots.is_empty() || !self.values.is_empty() {
            return Err(ImageError::Unsupported(
                "port constants and blackboard slots need image format 2, which this build does not write yet".into(),
            ));
        }
        let mut buf = vec![0u8; bt_core::image::max_image_len(self.nodes.len())];
        let len = bt_core::encode(&self.nodes, self.fingerprint, &mut buf)?;
        buf.truncate(len);
        Ok(buf)
    }

    /// The tree as BehaviorTree.CPP XML: one tree (SubTrees expanded), every behavior
    /// of the set declared, node names and `_uid`s kept. Importing it gives the same
    /// nodes, values, constants, slots and fingerprint.
    ///
    /// # Errors
    /// [`XmlError`] for kinds without a BehaviorTree.CPP equivalent.
    pub fn to_xml(&self) -> Result<String, XmlError> {
        let names: Vec<Option<String>> = self.meta.iter().map(|m| m.name.clone()).collect();
        let uids: Vec<u16> = self.meta.iter().map(|m| m.uid).collect();
        let options =
            XmlOptions { values: &self.values, all_behaviors: true, names: &names, uids: &uids, tree_id: &self.main };
        to_xml_with(&self.nodes, self, &NoPorts, &options)
    }
}
