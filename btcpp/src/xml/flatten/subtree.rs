//! A `<SubTree>` instance: its scope, opened by the rules of the document's version,
//! and its subtree flattened in it.

use super::scope::{Autoremap, Scope, key_in};
use super::{Bound, Flattener, Inst, Value, is_port_in};
use crate::error::{Fault, ImportError, Result};
use crate::xml::document::{Attr, Element, Version};
use crate::xml::model::{Literal, ModelKind, convert};

impl Flattener<'_> {
    #[allow(clippy::too_many_arguments)]
    pub(super) fn subtree(
        &mut self,
        e: &Element,
        id: &str,
        name: Option<String>,
        uid: u16,
        parent: usize,
        prefix: &str,
        depth: usize,
    ) -> Result<Inst> {
        if !e.children.is_empty() {
            return Err(ImportError::new(
                &e.at,
                Fault::Children {
                    node: format!("SubTree ID=\"{id}\""),
                    expected: "takes no children",
                    found: e.children.len(),
                },
            ));
        }
        let Some(def) = self.doc.trees.get(id) else {
            return Err(ImportError::new(
                &e.at,
                Fault::NoSuchTree { id: id.to_string(), available: self.doc.trees.keys().cloned().collect() },
            ));
        };
        if let Some(i) = self.ancestors.iter().position(|a| a == id) {
            let mut cycle = self.ancestors[i..].to_vec();
            cycle.push(id.to_string());
            return Err(ImportError::new(&e.at, Fault::SubtreeCycle(cycle.join(" -> "))));
        }
        self.check_version(def, Some(&e.at))?;
        // The instance's path, as BehaviorTree.CPP builds it for _fullpath.
        let own = name.clone().unwrap_or_else(|| format!("{id}::{uid}"));
        let path = format!("{prefix}{own}");
        let scope = self.scopes.len();
        let mut s = Scope { path: path.clone(), parent: Some(parent), ..Scope::default() };
        let ports = match (self.version, e.tag.as_str()) {
            (Version::V4, _) => self.remap_v4(e, id, parent, &mut s)?,
            (Version::V3, "SubTreePlus") => self.remap_plus(e, id, parent, &mut s)?,
            (Version::V3, _) => self.remap_by_name(e, id, parent, &mut s)?,
        };
        self.scopes.push(s);
        self.ancestors.push(id.to_string());
        let child = self.node(&def.root, scope, &format!("{path}/"), depth + 1)?;
        self.ancestors.pop();
        let instance = name.clone().unwrap_or_else(|| id.to_string());
        let node_path =
            if instance == id { format!("{prefix}{instance}::{uid}") } else { format!("{prefix}{instance}") };
        Ok(Inst {
            id: id.to_string(),
            is_subtree: true,
            name,
            uid,
            path: node_path,
            scope,
            ports,
            children: vec![child],
            at: e.at.clone(),
            hooks: Vec::new(),
            hook_scope: parent,
            tag: None,
        })
    }

    /// A boolean attribute of a `<SubTree>` (`_autoremap`, `__shared_blackboard`).
    fn flag(id: &str, a: &Attr) -> Result<bool> {
        match convert(Some("bool"), &a.value) {
            Some(Literal::Bool(b)) => Ok(b),
            _ => Err(ImportError::new(
                &a.at,
                Fault::BadLiteral {
                    node: format!("SubTree ID=\"{id}\""),
                    port: a.name.clone(),
                    value: a.value.clone(),
                    ty: "bool".into(),
                },
            )),
        }
    }

    /// BehaviorTree.CPP 4: `{key}` and `{=}` remap, other text starts a local entry,
    /// `_autoremap` shares the public keys; a SubTree model's defaults fill the ports
    /// the instance leaves out, and its ports without a default must be given.
    fn remap_v4(&mut self, e: &Element, id: &str, parent: usize, s: &mut Scope) -> Result<Vec<Bound>> {
        if let Some(a) = e.attr_at("_autoremap")
            && Self::flag(id, a)?
        {
            s.autoremap = Autoremap::Public;
        }
        let mut ports = Vec::new();
        for a in e.attrs.iter().filter(|a| is_port_in(Version::V4, &a.name)) {
            let text = if a.value == "{=}" { format!("{{{}}}", a.name) } else { a.value.clone() };
            let value = match key_in(Version::V4, &text) {
                Some(k) => {
                    let key = self.resolve(parent, k);
                    s.remap.insert(a.name.clone(), key.clone());
                    Value::Key(key)
                }
                None => {
                    s.initial.insert(a.name.clone(), (text.clone(), a.at.clone()));
                    Value::Literal(text.clone())
                }
            };
            ports.push(Bound { port: a.name.clone(), raw: a.value.clone(), value, at: a.at.clone() });
        }
        let model = self.models.get(id).filter(|m| m.kind == ModelKind::SubTree);
        for p in model.iter().flat_map(|m| &m.ports) {
            if s.remap.contains_key(&p.name) || s.initial.contains_key(&p.name) || s.autoremap != Autoremap::Off {
                continue;
            }
            match p.default.as_deref() {
                None => {
                    return Err(ImportError::new(
                        &e.at,
                        Fault::MandatorySubtreePort { subtree: id.to_string(), port: p.name.clone() },
                    ));
                }
                Some(d) => match key_in(Version::V4, d) {
                    Some(k) => {
                        let key = self.resolve(parent, k);
                        s.remap.insert(p.name.clone(), key);
                    }
                    None => {
                        let at = model.map_or_else(|| e.at.clone(), |m| m.at.clone());
                        s.initial.insert(p.name.clone(), (d.to_string(), at));
                    }
                },
            }
        }
        Ok(ports)
    }

    /// BehaviorTree.CPP 3's `<SubTree>`: every attribute remaps the subtree's key of its
    /// name to the parent's key its text names, verbatim; with `__shared_blackboard`
    /// true, the parent's blackboard is the subtree's and the other attributes mean
    /// nothing.
    fn remap_by_name(&mut self, e: &Element, id: &str, parent: usize, s: &mut Scope) -> Result<Vec<Bound>> {
        // 3.8 reads the first `__shared_blackboard` and nothing else when it is true.
        if let Some(a) = e.attr_at("__shared_blackboard")
            && Self::flag(id, a)?
        {
            s.autoremap = Autoremap::All;
            let ports = e.attrs.iter().filter(|a| is_port_in(Version::V3, &a.name));
            return Ok(ports
                .map(|a| Bound {
                    port: a.name.clone(),
                    raw: a.value.clone(),
                    value: Value::Literal(a.value.clone()),
                    at: a.at.clone(),
                })
                .collect());
        }
        let mut ports = Vec::new();
        for a in e.attrs.iter().filter(|a| is_port_in(Version::V3, &a.name)) {
            let key = self.resolve(parent, &a.value);
            s.remap.insert(a.name.clone(), key.clone());
            ports.push(Bound { port: a.name.clone(), raw: a.value.clone(), value: Value::Key(key), at: a.at.clone() });
        }
        Ok(ports)
    }

    /// BehaviorTree.CPP 3's `<SubTreePlus>`: `{key}` and `${key}` remap, other text
    /// starts a local entry (a string), `__autoremap` shares every other key.
    fn remap_plus(&mut self, e: &Element, id: &str, parent: usize, s: &mut Scope) -> Result<Vec<Bound>> {
        let mut ports = Vec::new();
        for a in e.attrs.iter().filter(|a| is_port_in(Version::V3, &a.name)) {
            if a.name == "__autoremap" {
                if Self::flag(id, a)? {
                    s.autoremap = Autoremap::All;
                }
                continue;
            }
            let value = match key_in(Version::V3, &a.value) {
                Some(k) => {
                    let key = self.resolve(parent, k);
                    s.remap.insert(a.name.clone(), key.clone());
                    Value::Key(key)
                }
                None => {
                    s.initial.insert(a.name.clone(), (a.value.clone(), a.at.clone()));
                    Value::Literal(a.value.clone())
                }
            };
            ports.push(Bound { port: a.name.clone(), raw: a.value.clone(), value, at: a.at.clone() });
        }
        Ok(ports)
    }
}
