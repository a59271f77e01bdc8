//! An imported tree as the renderers, the writers and the image see it: its behavior
//! set, with leaf values shown as the document wrote them (`goal={goal}`, `speed=0.5`),
//! and its names for the image's names section.

use std::fmt;

use bt_core::{BehaviorId, BehaviorInfo, Catalog, Node, PortInfo, PortTable};
use bt_formats::constant::write_port_value;
use bt_formats::{Image, ImageError, Names, NamesError};

use crate::xml::catalog::{Behavior, XmlCatalog};
use crate::xml::document::Version;
use crate::xml::lower::{Imported, Slot};
use crate::xml::model::{Literal, PortModel};
use crate::xml::write::{XmlError, XmlOptions, to_xml_with};

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

    /// A constant as written, a slot as `{key}`.
    fn write_arg(&self, f: &mut fmt::Formatter<'_>, behavior: BehaviorId, position: usize, value: u16) -> fmt::Result {
        if self.port(behavior, position).is_none() {
            return write!(f, "{value}");
        }
        write_port_value(
            f,
            value,
            |s| self.slots.get(usize::from(s)).map(|s| s.name.as_str()),
            |c| self.constants.get(usize::from(c)).map(Literal::as_constant),
        )
    }
}

impl Imported {
    /// The names the image carries for host tools: the main tree's ID, the models'
    /// behavior set with its ports, the blackboard keys, the scripting enums, the
    /// constants, the document's version and what it says of each node, titled by the
    /// tree's ID (a producer may give a better title). For a tree imported against
    /// its models; one read against a known set ([`Target::Known`](crate::xml::Target))
    /// takes that set's names.
    #[must_use]
    pub fn names(&self) -> Names {
        let mut names = Names::of(&format!("BehaviorTree.CPP tree `{}`", self.main), self, &[]);
        names.tree_id.clone_from(&self.main);
        names.slots = self.slots.iter().map(|s| s.name.clone()).collect();
        names.enums.clone_from(&self.enums);
        names.constants.clone_from(&self.constants);
        names.source_format = match self.version {
            Version::V3 => 3,
            Version::V4 => 4,
        };
        names.nodes.clone_from(&self.meta);
        names.subtrees.clone_from(&self.subtrees);
        names
    }

    /// The imported tree an image holds, rebuilt from its nodes, ports section and the
    /// names [`Imported::names`] wrote: what `export` and `btlog` need to write the tree
    /// as its document did (scripts, loops, SubTree nodes, node names) without the
    /// model files. `Ok(None)` for an image without such names (stripped, made before
    /// images carried them, or not imported from BehaviorTree.CPP).
    ///
    /// # Errors
    /// [`NamesError::Image`] for an image that does not decode, another
    /// [`NamesError`] for names that do not read or do not fit the image.
    pub fn from_image(bytes: &[u8]) -> Result<Option<Self>, NamesError> {
        let Some(names) = Names::of_image(bytes)? else {
            return Ok(None);
        };
        let header = bt_core::image::read_header(bytes)?;
        if names.nodes.is_empty() || names.fingerprint() != header.fingerprint {
            return Ok(None);
        }
        let mut behaviors = Vec::with_capacity(names.behaviors.len());
        for b in &names.behaviors {
            let mut ports = Vec::with_capacity(b.params.len());
            for p in &b.params {
                // A grounded argument: not a set read from models.
                let Some(d) = &p.port else { return Ok(None) };
                ports.push(PortModel {
                    name: p.name.clone(),
                    direction: d.direction,
                    type_name: (!d.type_name.is_empty()).then(|| d.type_name.clone()),
                    default: d.default.clone(),
                });
            }
            behaviors.push(Behavior { id: b.name.clone(), kind: b.kind, ports });
        }
        let mut nodes = vec![Node::EMPTY; usize::from(header.node_count)];
        let mut values = vec![0u16; bytes.len()];
        let decoded = bt_core::image::decode(bytes, &mut nodes, &mut values)?;
        nodes.truncate(decoded.nodes);
        values.truncate(decoded.values);
        if names.nodes.len() != nodes.len() {
            return Err(NamesError::Malformed(format!(
                "{} source nodes for a tree of {} nodes",
                names.nodes.len(),
                nodes.len()
            )));
        }
        let table = PortTable::of_image(bytes)?;
        let slots = (0..table.slot_count())
            .map(|i| {
                let info = table.slot(i).ok_or_else(|| NamesError::Malformed(format!("slot {i} does not read")))?;
                let name = names.slots.get(usize::from(i)).cloned().unwrap_or_else(|| format!("slot{i}"));
                Ok(Slot { name, info, type_name: None })
            })
            .collect::<Result<Vec<_>, NamesError>>()?;
        // Behaviors by ID, as an import numbers them: names in another order (or twice)
        // would name other behaviors than the image's.
        let catalog = XmlCatalog::new(behaviors);
        if catalog.fingerprint() != header.fingerprint {
            return Ok(None);
        }
        Ok(Some(Self {
            main: names.tree_id.clone(),
            fingerprint: header.fingerprint,
            catalog,
            nodes,
            values,
            slots,
            constants: names.constants.clone(),
            meta: names.nodes.clone(),
            subtrees: names.subtrees.clone(),
            enums: names.enums.clone(),
            version: if names.source_format == 3 { Version::V3 } else { Version::V4 },
        }))
    }

    /// The image a controller loads, without names.
    ///
    /// # Errors
    /// [`ImageError`] when the tree does not fit an image.
    pub fn image(&self) -> Result<Vec<u8>, ImageError> {
        self.encode(None)
    }

    /// The image with a names section (see [`Imported::names`]), which host tools read
    /// and the controller never does.
    ///
    /// # Errors
    /// As [`Imported::image`].
    pub fn named_image(&self, names: &Names) -> Result<Vec<u8>, ImageError> {
        self.encode(Some(names))
    }

    fn encode(&self, names: Option<&Names>) -> Result<Vec<u8>, ImageError> {
        let slots: Vec<bt_core::port::SlotInfo> = self.slots.iter().map(|s| s.info).collect();
        let image = Image::new(&self.nodes).values(&self.values).ports(&slots, &self.constants);
        match names {
            Some(n) => image.names(n).encode(self.fingerprint),
            None => image.encode(self.fingerprint),
        }
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
        let mut starting = Vec::new();
        for (slot, s) in renamed.slots.iter_mut().enumerate() {
            let name = crate::xml::lower::script_name(&s.name).into_owned();
            if let Some(constant) = s.info.initial {
                let value = self.constants.get(usize::from(constant)).map(|c| c.text()).unwrap_or_default();
                // Text a SubTree attribute reads as a key, or as no value.
                if value.is_empty() || value.starts_with('{') || value.starts_with("${") {
                    return Err(XmlError::StartValue { slot, key: s.name.clone(), value });
                }
                starting.push((name.clone(), value));
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
            version: self.version,
            starting: &starting,
        };
        to_xml_with(&renamed.nodes, &renamed, &options)
    }
}
