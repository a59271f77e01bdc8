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
    fn write_leaf(&self, f: &mut fmt::Formatter<'_>, leaf: &Leaf, args: &[u16]) -> fmt::Result {
        let b = leaf.behavior();
        match self.info(b) {
            Some(info) => f.write_str(info.name)?,
            None => write!(f, "#{b}")?,
        }
        let mut first = true;
        for (pos, &v) in args.iter().enumerate() {
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
        let mut parts = bt_core::image::ImageParts::new(&self.nodes).values(&self.values);
        let ports = self.ports_section()?;
        if let Some(p) = &ports {
            parts = parts.ports(p);
        }
        let mut buf = vec![0u8; parts.max_len()];
        let len = bt_core::encode_with(&parts, self.fingerprint, &mut buf)?;
        buf.truncate(len);
        Ok(buf)
    }

    /// The ports section's body: `None` when the tree has no constants and no slots.
    ///
    /// # Errors
    /// [`ImageError::Unsupported`] when it would exceed a section's limits.
    pub fn ports_section(&self) -> Result<Option<Vec<u8>>, ImageError> {
        if self.constants.is_empty() && self.slots.is_empty() {
            return Ok(None);
        }
        let slots: Vec<bt_core::port::SlotInfo> = self.slots.iter().map(|s| s.info).collect();
        let constants: Vec<bt_core::port::Constant<'_>> = self.constants.iter().map(|c| c.as_constant()).collect();
        let bound = 8
            + 8 * slots.len()
            + constants
                .iter()
                .map(|c| {
                    16 + match c {
                        bt_core::port::Constant::Str(s) => s.len(),
                        _ => 0,
                    }
                })
                .sum::<usize>();
        let mut out = vec![0u8; bound];
        let n = bt_core::port::encode_table(&slots, &constants, &mut out)
            .map_err(|e| ImageError::Unsupported(format!("the ports section: {e}")))?;
        out.truncate(n);
        Ok(Some(out))
    }

    /// The tree as BehaviorTree.CPP XML: one tree (SubTrees expanded), every behavior
    /// of the set declared, node names, `_uid`s and the built-ins' parameters as the
    /// document wrote them kept. Importing it gives the same nodes, values, constants,
    /// slots and fingerprint.
    ///
    /// # Errors
    /// [`XmlError`] for kinds without a BehaviorTree.CPP equivalent.
    pub fn to_xml(&self) -> Result<String, XmlError> {
        let names: Vec<Option<String>> = self.meta.iter().map(|m| m.name.clone()).collect();
        let uids: Vec<u16> = self.meta.iter().map(|m| m.uid).collect();
        // Scripts with their keys as the flattened tree names them.
        let flat: Vec<Vec<(String, String)>> =
            self.meta.iter().map(|m| m.flat.clone().unwrap_or_else(|| m.params.clone())).collect();
        // Keys as scripts can name them (a SubTree's local key `MySub::3/x` as `MySub_3_x`),
        // in the ports as in the scripts.
        let mut renamed = self.clone();
        let mut seen = std::collections::BTreeMap::new();
        for (slot, s) in renamed.slots.iter_mut().enumerate() {
            let name = crate::xml::lower::script_name(&s.name).into_owned();
            if let Some(constant) = s.info.initial {
                let value = self.constants.get(usize::from(constant)).map(|c| c.text()).unwrap_or_default();
                return Err(XmlError::StartValue { slot, key: s.name.clone(), value });
            }
            if let Some(first) = seen.insert(name.clone(), s.name.clone()) {
                return Err(XmlError::SameKey { slot, name, first, second: s.name.clone() });
            }
            s.name = name;
        }
        let params: Vec<&[(String, String)]> = flat.iter().map(Vec::as_slice).collect();
        let ids: Vec<&str> = self.meta.iter().map(|m| m.id.as_str()).collect();
        let options = XmlOptions {
            values: &self.values,
            all_behaviors: true,
            names: &names,
            uids: &uids,
            params: &params,
            tree_id: &self.main,
            ids: &ids,
        };
        to_xml_with(&renamed.nodes, &renamed, &NoPorts, &options)
    }
}
