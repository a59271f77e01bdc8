//! The node types of BehaviorTree.CPP 4.10 (with the v3 names it still reads) and Nav2's
//! control nodes, in one table ([`TABLE`]), and those of BehaviorTree.CPP 3.8 that
//! differ from them ([`TABLE_V3`]): for each, its registration ID, shape and ports, the
//! bt-core kind it becomes and how its parameters map to that kind's fields, both ways,
//! and what a Groot2 log writes for it. A document is read with the node types of its
//! version ([`by_id_in`]): version 4's [`TABLE`]; version 3's [`TABLE_V3`] and the
//! entries of [`TABLE`] that 3.8 has with the same ports and semantics
//! ([`Entry::v3`]).
//!
//! Everything that names a built-in node reads the table: lowering
//! ([`crate::xml::lower`]: XML ID to [`NodeKind`], the import's refusals and port
//! checks), writing ([`crate::xml::to_xml_with`]: [`NodeKind`] to XML ID and
//! attributes), the Groot2 log tree ([`crate::btlog::LogTree`]: its elements,
//! attributes and replay kinds) and the log's models ([`Entry::log_model`]).
//!
//! A BehaviorTree.CPP node type with a new bt-core kind is one entry here (its
//! [`Map::Params`] reads and writes the kind), plus what BehaviorTree.CPP's node does in
//! the log's replay (a [`Kind`] and its rule in [`crate::btlog::replay`]); the kind
//! itself, its tick rules and its image encoding live in `bt-core`.
//!
//! ```
//! use btcpp::kinds;
//!
//! let repeat = kinds::by_id("Repeat").unwrap();
//! assert_eq!(repeat.ports[0].name, "num_cycles");
//! let (entry, written) = kinds::written(&bt_core::NodeKind::RepeatCycles(3), 1).unwrap();
//! assert_eq!((entry.id, written.params), ("Repeat", vec![("num_cycles", "3".to_string())]));
//! // The v3 name reads as the v4 one.
//! assert_eq!(kinds::by_id("SequenceStar").unwrap().id, "SequenceWithMemory");
//! ```

mod params;
mod table;
mod v3;

use bt_core::script::Element;
use bt_core::{NodeKind, PortType};

pub use params::{
    Compared, Count, Params, boolean, count, count_of, cycles, int, period, rate, refuse, span, status, status_code,
    status_name,
};
pub use table::TABLE;
pub use v3::TABLE_V3;

use crate::btlog::tree::Kind;
use crate::error::Result;
use crate::xml::document::Version;

/// How many children a node type takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// No children.
    Leaf,
    /// Exactly one.
    Decorator,
    /// One or more.
    Control,
    /// Exactly two (Nav2's `RecoveryNode`).
    Two,
    /// Two or three (`IfThenElse`, `WhileDoElse`).
    TwoOrThree,
    /// Any number, none included (`ManualSelector`).
    AnyNumber,
}

impl Shape {
    /// The rule in words, for errors.
    #[must_use]
    pub const fn rule(self) -> &'static str {
        match self {
            Self::Leaf => "takes no children",
            Self::Decorator => "takes exactly one child",
            Self::Control => "takes one or more children",
            Self::Two => "takes exactly two children",
            Self::TwoOrThree => "takes two or three children",
            Self::AnyNumber => "takes any number of children",
        }
    }

    /// Whether `n` children fit.
    #[must_use]
    pub const fn fits(self, n: usize) -> bool {
        match self {
            Self::Leaf => n == 0,
            Self::Decorator => n == 1,
            Self::Control => n >= 1,
            Self::Two => n == 2,
            Self::TwoOrThree => n == 2 || n == 3,
            Self::AnyNumber => true,
        }
    }

    /// The shape of a bt-core kind.
    #[must_use]
    pub const fn of(kind: &NodeKind) -> Self {
        match kind.arity() {
            bt_core::Arity::Leaf => Self::Leaf,
            bt_core::Arity::One => Self::Decorator,
            bt_core::Arity::AtLeastOne => Self::Control,
            bt_core::Arity::Two => Self::Two,
            bt_core::Arity::TwoOrThree => Self::TwoOrThree,
            bt_core::Arity::Any => Self::AnyNumber,
        }
    }
}

/// A port of a built-in node type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Port {
    /// Its name.
    pub name: &'static str,
    /// Its type.
    pub ty: PortType,
    /// Its default, as BehaviorTree.CPP's model writes it; lowering reads an absent
    /// parameter as this.
    pub default: Option<&'static str>,
}

/// Who provides a node type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    /// BehaviorTree.CPP itself: its models in a document are skipped, as BehaviorTree.CPP
    /// writes them into logs and Groot2 files.
    BehaviorTreeCpp,
    /// Nav2 (plugins: `nav2_tree_nodes.xml` declares them, but they are read whether or
    /// not a model is given).
    Nav2,
}

/// Where the XML writer takes a node's attributes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Attrs {
    /// From the kind, always.
    Kind,
    /// As the document wrote them (an imported tree), else from the kind.
    Document,
    /// As the document wrote them only: the image keeps a program, not the script's
    /// text, so a tree made otherwise cannot be written.
    Script,
}

/// A node type's parameters as BehaviorTree.CPP writes them, and its kind in the log's
/// replay.
#[derive(Clone, Debug, PartialEq)]
pub struct Written {
    /// Attribute names and values, in port order.
    pub params: Vec<(&'static str, String)>,
    /// What the replay runs for it.
    pub log: Kind,
}

/// Reads a node's parameters into its kind ([`Params`] gives the node's attributes).
pub type Read = fn(&mut dyn Params) -> Result<NodeKind>;

/// The parameters and log kind of a kind this entry reads, given the node's number of
/// children; `None` for any other kind.
pub type Write = fn(&NodeKind, usize) -> Option<Written>;

/// How a node type becomes a bt-core kind, and back.
#[derive(Clone, Copy, Debug)]
pub enum Map {
    /// Not imported; the reason and what to do instead.
    Refused(&'static str),
    /// Always this kind, without parameters; and what the log's replay runs for it.
    Plain(NodeKind, Kind),
    /// A kind with parameters (or checks).
    Params {
        /// From the node's attributes to the kind.
        read: Read,
        /// From the kind to attributes.
        write: Write,
        /// Where the XML writer takes the attributes from.
        attrs: Attrs,
    },
    /// A loop ([`NodeKind::Loop`]) over elements of this type: its queue is compiled
    /// into the image (see `crate::xml::lower`).
    Loop(Element),
}

/// One node type.
#[derive(Clone, Copy, Debug)]
pub struct Entry {
    /// Its registration ID in BehaviorTree.CPP 4 (or Nav2).
    pub id: &'static str,
    /// Older names read as it (BehaviorTree.CPP 3's `SequenceStar`).
    pub aliases: &'static [&'static str],
    /// Who provides it.
    pub origin: Origin,
    /// Children it takes.
    pub shape: Shape,
    /// Its ports, in the order its model declares them.
    pub ports: &'static [Port],
    /// Its bt-core kind.
    pub map: Map,
    /// The defaults BehaviorTree.CPP adds to a node's attributes in a log when they are
    /// absent, as it prints them, in its model's port order.
    pub log_defaults: &'static [(&'static str, &'static str)],
    /// Its model as BehaviorTree.CPP 4.10 writes it into a log whose tree has one, when
    /// it is not among the factory's built-ins (`btlog/builtin-models.xml`).
    pub log_model: Option<&'static str>,
    /// For an entry of [`TABLE`]: whether BehaviorTree.CPP 3.8 (and Nav2 humble) has the
    /// node type with the same ports and semantics, so that version 3 documents read
    /// it too. Always true in [`TABLE_V3`].
    pub v3: bool,
}

impl Entry {
    /// The reason it is not imported, if it is not.
    #[must_use]
    pub const fn refused(&self) -> Option<&'static str> {
        match self.map {
            Map::Refused(why) => Some(why),
            _ => None,
        }
    }

    /// Whether its parameters are scripts (`Script`, `ScriptCondition`, `Precondition`).
    #[must_use]
    pub const fn takes_scripts(&self) -> bool {
        matches!(self.map, Map::Params { attrs: Attrs::Script, .. })
    }

    /// The port `name`.
    #[must_use]
    pub fn port(&self, name: &str) -> Option<&'static Port> {
        self.ports.iter().find(|p| p.name == name)
    }

    /// The port names, for errors.
    #[must_use]
    pub fn port_names(&self) -> Vec<String> {
        self.ports.iter().map(|p| p.name.to_string()).collect()
    }
}

/// The node type with this ID in a BehaviorTree.CPP 4 document (`SequenceStar` read as
/// its successor `SequenceWithMemory`, as BehaviorTree.CPP 4 reads it).
#[must_use]
pub fn by_id(id: &str) -> Option<&'static Entry> {
    by_id_in(id, Version::V4)
}

/// The node type with this ID in a document of `version`: [`TABLE`] for version 4;
/// [`TABLE_V3`], then the entries of [`TABLE`] 3.8 shares, for version 3.
#[must_use]
pub fn by_id_in(id: &str, version: Version) -> Option<&'static Entry> {
    let named = |e: &&Entry| e.id == id || e.aliases.contains(&id);
    match version {
        Version::V4 => TABLE.iter().find(named),
        Version::V3 => TABLE_V3.iter().find(named).or_else(|| TABLE.iter().filter(|e| e.v3).find(named)),
    }
}

/// Whether `id` is a built-in node type of either version (its models in a document
/// are skipped: BehaviorTree.CPP's own, as it writes them into logs and Groot files).
#[must_use]
pub fn is_builtin(id: &str) -> bool {
    [Version::V4, Version::V3].into_iter().any(|v| by_id_in(id, v).is_some_and(|e| e.origin == Origin::BehaviorTreeCpp))
}

/// The node type a kind is written as, with its parameters and log kind (`children`:
/// the node's number of children); `None` for kinds without a BehaviorTree.CPP node
/// type (bt-core's tick-counting `Repeat`, `Retry` and `Timeout`, a plugin's gate) and
/// for the kinds the writers handle themselves (leaves, guards, loops).
#[must_use]
pub fn written(kind: &NodeKind, children: usize) -> Option<(&'static Entry, Written)> {
    TABLE.iter().chain(TABLE_V3).find_map(|e| match e.map {
        Map::Plain(k, log) if k == *kind => Some((e, Written { params: Vec::new(), log })),
        Map::Params { write, .. } => write(kind, children).map(|w| (e, w)),
        _ => None,
    })
}

/// [`written`], under the node type `id` names when it is one that writes `kind` (an
/// imported `SetBlackboard`, which is a `Script`; a version 3 node type), else as
/// [`written`] names it.
#[must_use]
pub fn written_as(kind: &NodeKind, children: usize, id: Option<&str>) -> Option<(&'static Entry, Written)> {
    let named = id
        .into_iter()
        .flat_map(|id| TABLE.iter().chain(TABLE_V3).filter(move |e| e.id == id || e.aliases.contains(&id)));
    named
        .filter_map(|e| match e.map {
            Map::Plain(k, log) if k == *kind => Some((e, Written { params: Vec::new(), log })),
            Map::Params { write, .. } => write(kind, children).map(|w| (e, w)),
            _ => None,
        })
        .next()
        .or_else(|| written(kind, children))
}

/// The element type of a built-in loop (`LoopInt`, ...).
#[must_use]
pub fn loop_element(id: &str) -> Option<Element> {
    match by_id(id)?.map {
        Map::Loop(element) => Some(element),
        _ => None,
    }
}

/// The built-in loop over `element` (none for [`Element::Registered`], whose ID the
/// program gives).
#[must_use]
pub fn loop_entry(element: Element) -> Option<&'static Entry> {
    TABLE.iter().find(|e| matches!(e.map, Map::Loop(el) if el == element))
}

/// A loop's ports; the type of `value` is its element's. A loop the program registers
/// (`LoopNode<T>`) has them too.
pub const LOOP_PORTS: [Port; 3] = [
    Port { name: "queue", ty: PortType::Any, default: None },
    Port { name: "if_empty", ty: PortType::Any, default: Some("SUCCESS") },
    Port { name: "value", ty: PortType::Any, default: None },
];

/// A loop's [`Entry::log_defaults`].
pub const LOOP_LOG_DEFAULTS: &[(&str, &str)] = &[("if_empty", "SUCCESS")];

/// The attributes BehaviorTree.CPP reserves for scripted pre- and post-conditions, in
/// the order of [`bt_core::script::Hook`] (a [`NodeKind::Guard`]'s table).
pub const SCRIPT_ATTRIBUTES: [&str; 8] =
    ["_failureIf", "_successIf", "_skipIf", "_while", "_onHalted", "_onFailure", "_onSuccess", "_post"];

/// Nav2's control nodes that bt-core runs, in words: `A, B and C`.
#[must_use]
pub fn nav2_controls() -> String {
    let ids: Vec<&str> = TABLE
        .iter()
        .filter(|e| e.origin == Origin::Nav2 && !matches!(e.shape, Shape::Leaf | Shape::Decorator))
        .map(|e| e.id)
        .collect();
    match ids.split_last() {
        Some((last, [])) => (*last).to_string(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests;
