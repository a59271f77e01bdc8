//! Import errors: one line each, naming the construct and where it is
//! (`file:line:column`).

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A place in a source file: 1-based line and column (in characters).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Location {
    /// The file, as it was named (given on the command line or by `<include path>`).
    pub file: Arc<Path>,
    /// Line, from 1.
    pub line: u32,
    /// Column in characters, from 1.
    pub column: u32,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file.display(), self.line, self.column)
    }
}

/// A source file's text with its line starts, to turn byte offsets into locations.
#[derive(Debug)]
pub(crate) struct Source {
    pub path: Arc<Path>,
    /// The text as parsed: the file's, with every bare `&` written `&amp;`.
    pub text: String,
    /// The file's text, which locations count in.
    original: String,
    line_starts: Vec<usize>,
    /// Where in `text` each `&amp;` written for a bare `&` starts, in order.
    escapes: Vec<usize>,
}

/// Whether `rest` (the text after a `&`) starts an entity or character reference.
fn is_reference(rest: &str) -> bool {
    let b = rest.as_bytes();
    let end = match b.first() {
        Some(b'#') if matches!(b.get(1), Some(b'x')) => 2 + b[2..].iter().take_while(|c| c.is_ascii_hexdigit()).count(),
        Some(b'#') => 1 + b[1..].iter().take_while(|c| c.is_ascii_digit()).count(),
        Some(c) if c.is_ascii_alphabetic() || *c == b'_' || *c == b':' => {
            1 + b[1..]
                .iter()
                .take_while(|c| c.is_ascii_alphanumeric() || matches!(c, b'_' | b':' | b'.' | b'-'))
                .count()
        }
        _ => return false,
    };
    end > 1 && b.get(end) == Some(&b';')
}

impl Source {
    /// The source of `path`. BehaviorTree.CPP's XML parser takes a bare `&` (as in
    /// `code="a && b"`) for itself; so do we, reading it as `&amp;`.
    pub fn new(path: &Path, original: String) -> Self {
        let mut line_starts = vec![0];
        line_starts.extend(original.bytes().enumerate().filter(|&(_, b)| b == b'\n').map(|(i, _)| i + 1));
        let mut text = String::with_capacity(original.len());
        let mut escapes = Vec::new();
        let mut last = 0;
        for (i, _) in original.match_indices('&') {
            if !is_reference(&original[i + 1..]) {
                text.push_str(&original[last..i]);
                escapes.push(text.len());
                text.push_str("&amp;");
                last = i + 1;
            }
        }
        text.push_str(&original[last..]);
        Self { path: Arc::from(path), text, original, line_starts, escapes }
    }

    /// The location of byte `offset` of the parsed text.
    pub fn at(&self, offset: usize) -> Location {
        let offset = offset.min(self.text.len());
        // Back to the file's bytes: each escape before `offset` added 4.
        let before = self.escapes.partition_point(|&e| e < offset);
        let offset = match before.checked_sub(1).and_then(|k| self.escapes.get(k)) {
            // Inside an `&amp;` written for a `&`: at that `&`.
            Some(&e) if offset < e + 5 => e - 4 * (before - 1),
            _ => offset - 4 * before,
        };
        let offset = offset.min(self.original.len());
        let line = self.line_starts.partition_point(|&s| s <= offset).max(1);
        let start = self.line_starts[line - 1];
        let column = self.original.get(start..offset).map_or(1, |s| s.chars().count() + 1);
        Location { file: self.path.clone(), line: line as u32, column: column as u32 }
    }

    /// The location roxmltree gives (line and column of the parsed text), in the file.
    pub fn at_pos(&self, row: u32, col: u32) -> Location {
        let line_start =
            self.text.split_inclusive('\n').take(row.saturating_sub(1) as usize).map(str::len).sum::<usize>();
        let offset = self.text[line_start..]
            .char_indices()
            .nth(col.saturating_sub(1) as usize)
            .map_or(self.text.len(), |(i, _)| line_start + i);
        self.at(offset)
    }
}

/// Why a BehaviorTree.CPP document could not be imported. Nothing is produced when
/// there is one.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub struct ImportError {
    /// Where, when the fault is in a file's text.
    pub at: Option<Location>,
    /// What (boxed: results stay small).
    pub fault: Box<Fault>,
}

impl fmt::Display for ImportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.at {
            Some(at) => write!(f, "{at}: {}", self.fault),
            None => write!(f, "{}", self.fault),
        }
    }
}

impl ImportError {
    pub(crate) fn new(at: &Location, fault: Fault) -> Self {
        Self { at: Some(at.clone()), fault: Box::new(fault) }
    }

    pub(crate) fn nowhere(fault: Fault) -> Self {
        Self { at: None, fault: Box::new(fault) }
    }
}

/// What is wrong, naming the construct.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum Fault {
    /// A file could not be read.
    #[error("cannot read {}: {message}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The system's reason.
        message: String,
    },
    /// Not well-formed XML.
    #[error("not well-formed XML: {0}")]
    Xml(String),
    /// The document element is not `<root>`.
    #[error("the document element is <{0}>; BehaviorTree.CPP documents start with <root>")]
    NotRoot(String),
    /// A `BTCPP_format` this importer does not read.
    #[error("BTCPP_format=\"{0}\" is not supported (3 and 4 are)")]
    Format(String),
    /// A required attribute is missing.
    #[error("<{element}> needs the attribute `{attribute}`")]
    MissingAttribute {
        /// The element.
        element: String,
        /// The attribute.
        attribute: &'static str,
    },
    /// `<include>` of a file that includes itself, directly or not.
    #[error("<include> cycle: {0}")]
    IncludeCycle(String),
    /// `<include ros_pkg>`: needs a ROS installation to resolve.
    #[error("<include ros_pkg=\"{0}\"> needs ROS to find the package; give the path relative to this file instead")]
    RosPackage(String),
    /// Two `<BehaviorTree>` with the same ID.
    #[error("<BehaviorTree ID=\"{id}\"> is defined twice (first at {first})")]
    DuplicateTree {
        /// The ID.
        id: String,
        /// Where it was first defined.
        first: Location,
    },
    /// Two models of the same node type that truly differ (kind, a port's direction, a
    /// port one of them lacks), which BehaviorTree.CPP would not both accept.
    #[error("the models of `{id}` here and at {first} differ: {difference}{hint}")]
    ModelConflict {
        /// The node type.
        id: String,
        /// The other model.
        first: Location,
        /// What differs, with both values (this model's first).
        difference: String,
        /// Which one wins how, when one can.
        hint: String,
    },
    /// Node types used that are neither built-ins nor declared by any model: every one,
    /// with where it is first used (the error is placed at the first).
    #[error("{}", undeclared(nodes))]
    Undeclared {
        /// Each node type, and where it is first used.
        nodes: Vec<(String, Location)>,
    },
    /// No tree with the requested ID.
    #[error("no <BehaviorTree ID=\"{id}\"> (the documents define {})", list(available))]
    NoSuchTree {
        /// The ID asked for.
        id: String,
        /// The IDs defined.
        available: Vec<String>,
    },
    /// Several trees and no `main_tree_to_execute` or `--main`.
    #[error("{} trees ({}) and no main_tree_to_execute: say which one to import", available.len(), list(available))]
    NoMainTree {
        /// The IDs defined.
        available: Vec<String>,
    },
    /// No `<BehaviorTree>` at all.
    #[error("the document defines no <BehaviorTree>")]
    NoTree,
    /// `<SubTree>` recursion.
    #[error("SubTree recursion: {0}")]
    SubtreeCycle(String),
    /// A SubTree instance leaves a port without remapping that its model requires.
    #[error("<SubTree ID=\"{subtree}\"> does not remap the port `{port}`, which its model declares without a default")]
    MandatorySubtreePort {
        /// The subtree.
        subtree: String,
        /// The port.
        port: String,
    },
    /// A node with the wrong number of children.
    #[error("<{node}> {expected}, found {found}")]
    Children {
        /// The node's type.
        node: String,
        /// What it needs, in words.
        expected: &'static str,
        /// Children found.
        found: usize,
    },
    /// A node type that no model declares and that is not built in.
    #[error(
        "`{0}` is neither a BehaviorTree.CPP built-in node nor declared in any <TreeNodesModel> (give its model with --nodes)"
    )]
    UnknownNode(String),
    /// An unknown node type named like a loop (`LoopPose`).
    #[error(
        "`{0}` is neither a BehaviorTree.CPP built-in node nor declared in any <TreeNodesModel>; if the program registers it as a LoopNode<T> (registerNodeType<LoopNode<T>>(\"{0}\")), give --loop {0}"
    )]
    UnknownLoop(String),
    /// A construct this importer cannot put on a controller.
    #[error("{construct} is not supported: {reason}")]
    Unsupported {
        /// The construct, e.g. `<Script>` or `the attribute _skipIf`.
        construct: String,
        /// Why, and what to do instead.
        reason: String,
    },
    /// A script (`Script`, `ScriptCondition`) that does not parse or compile.
    #[error("<{node}> {attribute} \"{code}\": {message} (at byte {offset} of the script)")]
    Script {
        /// The node's type.
        node: String,
        /// The attribute holding the script (`code`, `if`, `_skipIf`, ...).
        attribute: String,
        /// The script, shortened.
        code: String,
        /// What is wrong.
        message: String,
        /// The byte offset in the script.
        offset: usize,
    },
    /// An attribute that names no port of the node's model.
    #[error("<{node}> has no port `{port}` (its model declares {})", if declared.is_empty() { "none".to_string() } else { list(declared) })]
    UnknownPort {
        /// The node's type.
        node: String,
        /// The attribute.
        port: String,
        /// The ports the model declares.
        declared: Vec<String>,
    },
    /// An output port given a literal.
    #[error(
        "<{node}> port `{port}` is an output port; it takes a blackboard key like {{{port}}}, not the literal \"{value}\""
    )]
    OutputLiteral {
        /// The node's type.
        node: String,
        /// The port.
        port: String,
        /// The literal.
        value: String,
    },
    /// A literal that does not convert to the port's type.
    #[error("<{node}> port `{port}`: \"{value}\" is not a valid {ty}")]
    BadLiteral {
        /// The node's type.
        node: String,
        /// The port.
        port: String,
        /// The literal.
        value: String,
        /// The port's declared type.
        ty: String,
    },
    /// A parameter of a built-in node that must be a literal.
    #[error("<{node}> `{port}` must be a literal number here, not the blackboard key {value}")]
    ParameterFromBlackboard {
        /// The node.
        node: String,
        /// The parameter.
        port: String,
        /// The value written.
        value: String,
    },
    /// Two ports sharing a blackboard key with incompatible types.
    #[error("blackboard key `{key}` is used as {second} here and as {first} at {at}")]
    KeyTypeConflict {
        /// The key.
        key: String,
        /// Its type where first used.
        first: String,
        /// The type here.
        second: String,
        /// Where it was first used.
        at: Location,
    },
    /// The tree does not fit an image (nodes, values, constants or slots).
    #[error("the tree is too large for an image: {0}")]
    TooLarge(String),
}

fn undeclared(nodes: &[(String, Location)]) -> String {
    let stub = "`sim-host catalog --stub TREE.xml --out models.xml` (ports from the attributes used; check the kinds it guesses)";
    match nodes {
        [(id, _)] => format!(
            "`{id}` is neither a BehaviorTree.CPP built-in node nor declared in any <TreeNodesModel>; give its model with --nodes, or write one with {stub}"
        ),
        _ => format!(
            "{} node types are neither BehaviorTree.CPP built-ins nor declared in any <TreeNodesModel>: {}; give their models with --nodes, or write them with {stub}",
            nodes.len(),
            nodes.iter().map(|(id, at)| format!("`{id}` ({at})")).collect::<Vec<_>>().join(", ")
        ),
    }
}

fn list(items: &[String]) -> String {
    items.iter().map(|s| format!("`{s}`")).collect::<Vec<_>>().join(", ")
}

/// Shorthand for results of this crate.
pub type Result<T, E = ImportError> = std::result::Result<T, E>;
