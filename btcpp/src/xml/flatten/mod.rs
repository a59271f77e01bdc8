//! SubTrees flattened per instance, blackboard keys resolved to the scope that owns
//! them, and BehaviorTree.CPP's node ids (`_uid`) and paths (`_fullpath`) assigned as
//! its factory assigns them.
//!
//! Each `<SubTree>` instance gets its own blackboard scope, as BehaviorTree.CPP gives it
//! its own blackboard: a port `{key}` inside it names
//! - the parent's key that the instance remaps `key` to (`key="{parent_key}"`, or
//!   `key="{=}"` for the same name), resolved in the parent at once;
//! - a local entry that starts with the literal the instance gives (`key="3"`);
//! - the parent's `key` itself when the instance has `_autoremap="true"` (keys starting
//!   with `_` stay private);
//! - otherwise a key local to the instance.
//!
//! `{@key}` names `key` of the root scope from anywhere.

use std::collections::BTreeMap;

use crate::error::{Fault, ImportError, Location, Result};
use crate::kinds::SCRIPT_ATTRIBUTES;
use crate::xml::document::{Document, Element, TreeDef};
use crate::xml::model::{ModelKind, NodeModel, convert};

/// Deepest nesting of elements (and SubTrees) read, as BehaviorTree.CPP limits it.
pub const MAX_NESTING: usize = 256;

/// A node of the flattened tree.
#[derive(Clone, Debug)]
pub struct Inst {
    /// The node type's registration ID (`Sequence`, `ComputePathToPose`), or the
    /// subtree's ID for a SubTree node.
    pub id: String,
    /// Whether it is a `<SubTree>` node (its one child is the subtree's root).
    pub is_subtree: bool,
    /// The `name` attribute.
    pub name: Option<String>,
    /// BehaviorTree.CPP's node id: creation order, from 1, SubTree nodes included.
    pub uid: u16,
    /// For a SubTree node, BehaviorTree.CPP's `_fullpath` of the node (its config path;
    /// the instance's own path is its scope's).
    pub path: String,
    /// The blackboard scope its ports are resolved in; for a SubTree node, the scope it
    /// opens.
    pub scope: usize,
    /// Port attributes, in document order, with their values resolved.
    pub ports: Vec<Bound>,
    /// Children in order.
    pub children: Vec<Inst>,
    /// Where the element is.
    pub at: Location,
    /// Its scripted attributes (`_skipIf`, `_onSuccess`, ...), in document order.
    pub hooks: Vec<Bound>,
    /// The scope its scripted attributes read keys in (a SubTree node's: its parent's).
    pub hook_scope: usize,
}

impl Inst {
    /// The instance name BehaviorTree.CPP gives the node: `name`, else its type ID.
    #[must_use]
    pub fn instance_name(&self) -> &str {
        self.name.as_deref().unwrap_or(&self.id)
    }
}

/// A port attribute and what it names.
#[derive(Clone, Debug)]
pub struct Bound {
    /// The port.
    pub port: String,
    /// The attribute's text, as written.
    pub raw: String,
    /// What it names.
    pub value: Value,
    /// Where the attribute is.
    pub at: Location,
}

/// A port attribute's meaning.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Value {
    /// A literal.
    Literal(String),
    /// A blackboard entry.
    Key(Key),
}

/// A blackboard entry: a key in a scope.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Key {
    /// The scope (0 is the root).
    pub scope: usize,
    /// The key's name in it.
    pub name: String,
}

/// A blackboard scope: the root, or one SubTree instance.
#[derive(Clone, Debug, Default)]
pub struct Scope {
    /// The instance's path (`""` for the root).
    pub path: String,
    /// Local entries that start with a literal, with where the literal is written.
    pub initial: BTreeMap<String, (String, Location)>,
    parent: Option<usize>,
    remap: BTreeMap<String, Key>,
    autoremap: bool,
}

/// The tree to import, flattened.
#[derive(Clone, Debug)]
pub struct Flat {
    /// The main tree's ID.
    pub main: String,
    /// The root node.
    pub root: Inst,
    /// Blackboard scopes; index 0 is the root's.
    pub scopes: Vec<Scope>,
}

/// The entry `key` names in `scope` (see the module docs).
#[must_use]
pub fn resolve(scopes: &[Scope], scope: usize, key: &str) -> Key {
    let mut scope = scope;
    loop {
        if let Some(k) = key.strip_prefix('@') {
            return Key { scope: 0, name: k.to_string() };
        }
        let Some(s) = scopes.get(scope) else {
            return Key { scope, name: key.to_string() };
        };
        if let Some(k) = s.remap.get(key) {
            return k.clone();
        }
        if s.initial.contains_key(key) {
            return Key { scope, name: key.to_string() };
        }
        match s.parent {
            Some(p) if s.autoremap && !key.starts_with('_') => scope = p,
            _ => return Key { scope, name: key.to_string() },
        }
    }
}

/// Whether an attribute value names a blackboard entry (BehaviorTree.CPP's rule:
/// `{key}`, spaces around the braces allowed), and which key.
#[must_use]
pub fn blackboard_key(value: &str) -> Option<&str> {
    let t = value.trim_matches(' ');
    if t.len() >= 3 && t.starts_with('{') && t.ends_with('}') { Some(&t[1..t.len() - 1]) } else { None }
}

/// Which tree is the main one: `main` if given, else the document's
/// `main_tree_to_execute`, else the tree file's only tree, else the only tree read.
///
/// # Errors
/// [`Fault::NoSuchTree`], [`Fault::NoMainTree`] or [`Fault::NoTree`].
pub fn main_tree<'d>(doc: &'d Document, main: Option<&str>) -> Result<&'d TreeDef> {
    let available = || doc.trees.keys().cloned().collect::<Vec<_>>();
    let (id, at) = match (main, &doc.main) {
        (Some(m), _) => (m.to_string(), None),
        (None, Some((m, at))) => (m.clone(), Some(at)),
        (None, None) => match (doc.own.as_slice(), doc.trees.len()) {
            // The tree file's only tree, as BehaviorTree.CPP picks it among the trees
            // other files registered before.
            ([only], _) => (only.clone(), None),
            (_, 0) => return Err(ImportError::nowhere(Fault::NoTree)),
            (_, 1) => return Ok(doc.trees.values().next().expect("one tree")),
            _ => return Err(ImportError::nowhere(Fault::NoMainTree { available: available() })),
        },
    };
    doc.trees.get(&id).ok_or_else(|| {
        let fault = Fault::NoSuchTree { id, available: available() };
        match at {
            Some(at) => ImportError::new(at, fault),
            None => ImportError::nowhere(fault),
        }
    })
}

/// Flattens tree `main` of `doc`; `subtree_models` are the `<SubTree>` entries of the
/// models (for their mandatory ports and defaults).
///
/// # Errors
/// The first [`ImportError`].
pub fn flatten(doc: &Document, main: &TreeDef, models: &[NodeModel]) -> Result<Flat> {
    let v3 = doc.format.as_deref() != Some("4");
    let mut f = Flattener { doc, models, v3, scopes: vec![Scope::default()], uid: 0, ancestors: vec![main.id.clone()] };
    let root = f.node(&main.root, 0, "", 1)?;
    Ok(Flat { main: main.id.clone(), root, scopes: f.scopes })
}

struct Flattener<'a> {
    doc: &'a Document,
    models: &'a [NodeModel],
    v3: bool,
    scopes: Vec<Scope>,
    uid: u16,
    ancestors: Vec<String>,
}

impl Flattener<'_> {
    fn resolve(&self, scope: usize, key: &str) -> Key {
        resolve(&self.scopes, scope, key)
    }

    fn next_uid(&mut self, at: &Location) -> Result<u16> {
        self.uid = self.uid.checked_add(1).ok_or_else(|| {
            ImportError::new(at, Fault::TooLarge("more than 65535 nodes after SubTrees are expanded".into()))
        })?;
        Ok(self.uid)
    }

    fn node(&mut self, e: &Element, scope: usize, prefix: &str, depth: usize) -> Result<Inst> {
        if depth > MAX_NESTING {
            return Err(ImportError::new(
                &e.at,
                Fault::TooLarge(format!("nesting deeper than {MAX_NESTING} levels (SubTrees included)")),
            ));
        }
        let hooks: Vec<Bound> = e
            .attrs
            .iter()
            .filter(|a| SCRIPT_ATTRIBUTES.contains(&a.name.as_str()))
            .map(|a| Bound {
                port: a.name.clone(),
                raw: a.value.clone(),
                value: Value::Literal(a.value.clone()),
                at: a.at.clone(),
            })
            .collect();
        let explicit = matches!(e.tag.as_str(), "Action" | "Condition" | "Control" | "Decorator");
        let subtree = matches!(e.tag.as_str(), "SubTree" | "SubTreePlus");
        let id = if explicit || subtree {
            e.attr("ID").ok_or_else(|| {
                ImportError::new(&e.at, Fault::MissingAttribute { element: e.tag.clone(), attribute: "ID" })
            })?
        } else {
            if let Some(a) = e.attr_at("ID") {
                return Err(ImportError::new(
                    &a.at,
                    Fault::Unsupported {
                        construct: format!("the attribute ID on <{}>", e.tag),
                        reason: "only <Action>, <Condition>, <Control>, <Decorator> and <SubTree> take an ID; write <Action ID=\"...\"> or the node type as the tag".into(),
                    },
                ));
            }
            e.tag.as_str()
        };
        let uid = self.next_uid(&e.at)?;
        let name = e.attr("name").map(str::to_string);
        if subtree {
            let mut inst = self.subtree(e, id, name, uid, scope, prefix, depth)?;
            inst.hooks = hooks;
            inst.hook_scope = scope;
            return Ok(inst);
        }
        let mut ports = Vec::new();
        for a in e.attrs.iter().filter(|a| is_port_name(&a.name)) {
            let value = match a.value.as_str() {
                "{=}" | "=" => Value::Key(self.resolve(scope, &a.name)),
                v => match blackboard_key(v) {
                    Some(k) => Value::Key(self.resolve(scope, k)),
                    None => Value::Literal(v.to_string()),
                },
            };
            ports.push(Bound { port: a.name.clone(), raw: a.value.clone(), value, at: a.at.clone() });
        }
        let mut children = Vec::with_capacity(e.children.len());
        for c in &e.children {
            children.push(self.node(c, scope, prefix, depth + 1)?);
        }
        Ok(Inst {
            id: id.to_string(),
            is_subtree: false,
            name,
            uid,
            path: String::new(),
            scope,
            ports,
            children,
            at: e.at.clone(),
            hooks,
            hook_scope: scope,
        })
    }

    #[allow(clippy::too_many_arguments)]
    fn subtree(
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
        let mut autoremap = false;
        if let Some(a) = e.attr_at("_autoremap") {
            autoremap = match convert(Some("bool"), &a.value) {
                Some(crate::xml::model::Literal::Bool(b)) => b,
                _ => {
                    return Err(ImportError::new(
                        &a.at,
                        Fault::BadLiteral {
                            node: format!("SubTree ID=\"{id}\""),
                            port: "_autoremap".into(),
                            value: a.value.clone(),
                            ty: "bool".into(),
                        },
                    ));
                }
            };
        }
        if self.v3 && e.attr("__shared_blackboard").is_some_and(|v| matches!(v, "true" | "1" | "True" | "TRUE")) {
            autoremap = true;
        }
        // The instance's path, as BehaviorTree.CPP builds it for _fullpath.
        let own = name.clone().unwrap_or_else(|| format!("{id}::{uid}"));
        let path = format!("{prefix}{own}");
        let scope = self.scopes.len();
        let mut s = Scope { path: path.clone(), parent: Some(parent), autoremap, ..Scope::default() };
        let mut ports = Vec::new();
        for a in e.attrs.iter().filter(|a| is_port_name(&a.name)) {
            let text = if a.value == "{=}" { format!("{{{}}}", a.name) } else { a.value.clone() };
            let value = match blackboard_key(&text) {
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
        if let Some(model) = self.models.iter().find(|m| m.kind == ModelKind::SubTree && m.id == id) {
            for p in &model.ports {
                if s.remap.contains_key(&p.name) || s.initial.contains_key(&p.name) || autoremap {
                    continue;
                }
                match p.default.as_deref() {
                    None => {
                        return Err(ImportError::new(
                            &e.at,
                            Fault::MandatorySubtreePort { subtree: id.to_string(), port: p.name.clone() },
                        ));
                    }
                    Some(d) => match blackboard_key(d) {
                        Some(k) => {
                            let key = self.resolve(parent, k);
                            s.remap.insert(p.name.clone(), key);
                        }
                        None => {
                            s.initial.insert(p.name.clone(), (d.to_string(), model.at.clone()));
                        }
                    },
                }
            }
        }
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
        })
    }
}

/// Whether an attribute name is one BehaviorTree.CPP takes as a port: it starts with a
/// letter and is not `name` or `ID` (attributes starting with `_` are metadata such as
/// `_uid`, `_fullpath`, `_description`, ignored as BehaviorTree.CPP ignores them, or
/// the scripted conditions of [`SCRIPT_ATTRIBUTES`]).
#[must_use]
pub fn is_port_name(name: &str) -> bool {
    name.starts_with(|c: char| c.is_alphabetic()) && name != "name" && name != "ID"
}
