//! SubTrees flattened per instance, blackboard keys resolved to the scope that owns
//! them, and BehaviorTree.CPP's node ids (`_uid`) and paths (`_fullpath`) assigned as
//! its factory assigns them.
//!
//! The document is read by the rules of its version ([`Version`]; how each writes a
//! key is in the `scope` module). Each `<SubTree>` instance gets its own blackboard scope, as
//! BehaviorTree.CPP gives it its own blackboard. In a BehaviorTree.CPP 4 document a
//! port `{key}` inside it names
//! - the parent's key that the instance remaps `key` to (`key="{parent_key}"`, or
//!   `key="{=}"` for the same name), resolved in the parent at once;
//! - a local entry that starts with the literal the instance gives (`key="3"`);
//! - the parent's `key` itself when the instance has `_autoremap="true"` (keys starting
//!   with `_` stay private);
//! - otherwise a key local to the instance.
//!
//! `{@key}` names `key` of the root scope from anywhere.
//!
//! In a BehaviorTree.CPP 3 document (3.8's `XMLParser`) a `<SubTree>` remaps by name:
//! `key="parent_key"` remaps `key` to the parent's entry named `parent_key`, whatever
//! its text (a literal cannot be passed); `__shared_blackboard="true"` gives the
//! subtree its parent's blackboard instead, every key shared and every other attribute
//! ignored. `<SubTreePlus>` remaps `{parent_key}` and `${parent_key}`, starts a local
//! entry at any other text, and with `__autoremap="true"` shares every other key
//! (`_private` ones too). A literal on an output port names the key it writes.
//! Attributes other than `ID`, `name` and `_description` are ports: version 4's
//! scripted attributes are not scripts there.

use crate::error::{Fault, ImportError, Location, Result};
use crate::kinds::SCRIPT_ATTRIBUTES;
use crate::xml::catalog::Models;
use crate::xml::document::{Document, Element, TreeDef, Version};
use crate::xml::model::ModelKind;

mod scope;
mod subtree;

pub use scope::{Autoremap, Key, Scope, blackboard_key, key_in, port_key, resolve};

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
    /// The kind its element names, for `<Action ID>`, `<Condition ID>`, `<Control ID>`
    /// and `<Decorator ID>`.
    pub tag: Option<ModelKind>,
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

/// The tree to import, flattened.
#[derive(Clone, Debug)]
pub struct Flat {
    /// The main tree's ID.
    pub main: String,
    /// The root node.
    pub root: Inst,
    /// Blackboard scopes; index 0 is the root's.
    pub scopes: Vec<Scope>,
    /// The rules the document was read by.
    pub version: Version,
}

impl Flat {
    /// The entry `key` names in `scope` ([`resolve`] by the document's rules).
    #[must_use]
    pub fn resolve(&self, scope: usize, key: &str) -> Key {
        resolve(&self.scopes, self.version, scope, key)
    }

    /// The key a port attribute (or a model's default) names, by the document's rules.
    #[must_use]
    pub fn port_key<'a>(&self, port: &'a str, value: &'a str) -> Option<&'a str> {
        port_key(self.version, port, value)
    }
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

/// Flattens tree `main` of `doc` against `models` (a SubTree model's mandatory ports
/// and defaults; in a version 3 document, which ports are outputs).
///
/// # Errors
/// The first [`ImportError`].
pub fn flatten(doc: &Document, main: &TreeDef, models: &Models) -> Result<Flat> {
    let version = doc.version();
    let mut f =
        Flattener { doc, models, version, scopes: vec![Scope::default()], uid: 0, ancestors: vec![main.id.clone()] };
    f.check_version(main, None)?;
    let root = f.node(&main.root, 0, "", 1)?;
    Ok(Flat { main: main.id.clone(), root, scopes: f.scopes, version })
}

struct Flattener<'a> {
    doc: &'a Document,
    models: &'a Models,
    version: Version,
    scopes: Vec<Scope>,
    uid: u16,
    ancestors: Vec<String>,
}

impl Flattener<'_> {
    fn resolve(&self, scope: usize, key: &str) -> Key {
        resolve(&self.scopes, self.version, scope, key)
    }

    /// Refuses a tree whose file declares the other version than the document's: one
    /// BehaviorTree.CPP reads every file by its own rules.
    fn check_version(&self, def: &TreeDef, used: Option<&Location>) -> Result<()> {
        let Some((format, at)) = &def.format else { return Ok(()) };
        if Version::of(Some(format)) == self.version {
            return Ok(());
        }
        Err(ImportError::new(
            used.unwrap_or(at),
            Fault::Unsupported {
                construct: format!("<BehaviorTree ID=\"{}\"> of a BTCPP_format=\"{format}\" file (at {at})", def.id),
                reason: format!(
                    "the document is read by {}'s rules (its first file {}), and one library reads every file by its own; give each document's files the same BTCPP_format",
                    self.version.library(),
                    if self.version == Version::V4 { "has BTCPP_format=\"4\"" } else { "has no BTCPP_format=\"4\"" }
                ),
            },
        ))
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
        let v4 = self.version == Version::V4;
        let hooks: Vec<Bound> = e
            .attrs
            .iter()
            .filter(|a| v4 && SCRIPT_ATTRIBUTES.contains(&a.name.as_str()))
            .map(|a| Bound {
                port: a.name.clone(),
                raw: a.value.clone(),
                value: Value::Literal(a.value.clone()),
                at: a.at.clone(),
            })
            .collect();
        let explicit = matches!(e.tag.as_str(), "Action" | "Condition" | "Control" | "Decorator");
        let subtree = e.tag == "SubTree" || (e.tag == "SubTreePlus" && !v4);
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
        for a in e.attrs.iter().filter(|a| is_port_in(self.version, &a.name)) {
            let value = match port_key(self.version, &a.name, &a.value) {
                Some(k) => Value::Key(self.resolve(scope, k)),
                None => self.literal(id, a, scope)?,
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
            tag: ModelKind::from_tag(&e.tag).filter(|_| explicit),
        })
    }

    /// A port attribute that names no key: a literal, except on an output port of a
    /// version 3 document, where BehaviorTree.CPP 3 writes the key the text names.
    fn literal(&self, id: &str, a: &crate::xml::document::Attr, scope: usize) -> Result<Value> {
        let direction = match self.version {
            Version::V3 => self
                .models
                .get(id)
                .filter(|m| matches!(m.kind, ModelKind::Action | ModelKind::Condition | ModelKind::Decorator))
                .and_then(|m| m.port(&a.name))
                .map(|p| p.direction),
            Version::V4 => None,
        };
        match direction {
            Some(bt_core::PortDirection::Output) => Ok(Value::Key(self.resolve(scope, &a.value))),
            Some(bt_core::PortDirection::InOut) => Err(ImportError::new(
                &a.at,
                Fault::Unsupported {
                    construct: format!("<{id} {}=\"{}\">", a.name, a.value),
                    reason: format!(
                        "`{}` is an in/out port: {} reads the text as a literal and writes the key `{}`; a bt-core port is one or the other: write {{{}}} to read and write that key",
                        a.name,
                        Version::V3.library(),
                        a.value,
                        a.value
                    ),
                },
            )),
            _ => Ok(Value::Literal(a.value.clone())),
        }
    }
}

/// Whether an attribute name is one BehaviorTree.CPP takes as a port: it starts with a
/// letter and is not `name` or `ID` (attributes starting with `_` are metadata such as
/// `_uid`, `_fullpath`, `_description`, ignored as BehaviorTree.CPP ignores them, or
/// the scripted conditions of [`SCRIPT_ATTRIBUTES`]).
#[must_use]
pub fn is_port_name(name: &str) -> bool {
    is_port_in(Version::V4, name)
}

/// [`is_port_name`] by `version`'s rules: BehaviorTree.CPP 3 reserves only `ID`, `name`
/// and `_description`.
#[must_use]
pub fn is_port_in(version: Version, name: &str) -> bool {
    match version {
        Version::V4 => name.starts_with(|c: char| c.is_alphabetic()) && name != "name" && name != "ID",
        Version::V3 => !matches!(name, "ID" | "name" | "_description"),
    }
}
