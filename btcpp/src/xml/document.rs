//! The document model: what a set of BehaviorTree.CPP XML files says, before any
//! meaning is given to it. Elements keep their attributes in document order and their
//! locations; comments and text are dropped.
//!
//! Reading follows BehaviorTree.CPP's loader: `<include path>` is resolved against the
//! directory of the including file and read before the including file's own trees,
//! `main_tree_to_execute` is taken from the first file, a `<BehaviorTree>` without `ID`
//! is allowed when it is its file's only one, and `<TreeNodesModel>` entries are
//! collected from every file.
//!
//! The first file's `BTCPP_format` says which BehaviorTree.CPP reads the document, and
//! so by which version's rules ([`Version`]): `4` by BehaviorTree.CPP 4's, `3` or none
//! by BehaviorTree.CPP 3's (as Nav2 humble and older ship their trees). A library reads
//! the files it is given by its own rules; a tree defined in a file that declares the
//! other version is refused when the main tree uses it (see `flatten`).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::error::{Fault, ImportError, Location, Result, Source};
use crate::xml::model::{self, NodeModel, Origin};

/// An XML element: a node of a tree, or a model.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Element {
    /// The tag, e.g. `Sequence`, `Action`, `ComputePathToPose`.
    pub tag: String,
    /// Attributes in document order.
    pub attrs: Vec<Attr>,
    /// Child elements in order.
    pub children: Vec<Element>,
    /// Where the element starts.
    pub at: Location,
}

/// An attribute and where its value is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Attr {
    /// Its name.
    pub name: String,
    /// Its value, with XML entities resolved.
    pub value: String,
    /// Where the attribute starts.
    pub at: Location,
}

impl Element {
    /// The value of attribute `name`.
    #[must_use]
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs.iter().find(|a| a.name == name).map(|a| a.value.as_str())
    }

    /// Attribute `name` with its location.
    #[must_use]
    pub fn attr_at(&self, name: &str) -> Option<&Attr> {
        self.attrs.iter().find(|a| a.name == name)
    }
}

/// The BehaviorTree.CPP version whose rules a document is read by.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Version {
    /// BehaviorTree.CPP 3 (3.8): `<root>` without `BTCPP_format`, or with `BTCPP_format="3"`.
    V3,
    /// BehaviorTree.CPP 4: `<root BTCPP_format="4">`.
    #[default]
    V4,
}

impl Version {
    /// The version a `BTCPP_format` attribute (or its absence) names.
    #[must_use]
    pub fn of(format: Option<&str>) -> Self {
        if format == Some("4") { Self::V4 } else { Self::V3 }
    }

    /// As people name it: `BehaviorTree.CPP 3` or `BehaviorTree.CPP 4`.
    #[must_use]
    pub const fn library(self) -> &'static str {
        match self {
            Self::V3 => "BehaviorTree.CPP 3",
            Self::V4 => "BehaviorTree.CPP 4",
        }
    }
}

/// One `<BehaviorTree>`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TreeDef {
    /// Its ID (`BehaviorTree_0`, ... for an unnamed one, as BehaviorTree.CPP names it).
    pub id: String,
    /// Its one child.
    pub root: Element,
    /// Where the `<BehaviorTree>` element is.
    pub at: Location,
    /// The `BTCPP_format` its file declares (`None` when the file has none), with where.
    pub format: Option<(String, Location)>,
}

/// Everything read from a tree file, its includes and the model files.
#[derive(Debug, Default)]
pub struct Document {
    /// Trees by ID.
    pub trees: BTreeMap<String, TreeDef>,
    /// `main_tree_to_execute` of the first file, with where it is.
    pub main: Option<(String, Location)>,
    /// Every `<TreeNodesModel>` entry, in reading order.
    pub models: Vec<NodeModel>,
    /// The IDs of the trees the first file itself defines (not its includes).
    pub own: Vec<String>,
    /// `BTCPP_format` of the first file (`None` for v3-style files without it).
    pub format: Option<String>,
    /// Files read so far (canonical paths): a file included twice is read once.
    seen: Vec<PathBuf>,
}

impl Document {
    /// The version the document is read by: its first file's ([`Version::of`]).
    #[must_use]
    pub fn version(&self) -> Version {
        Version::of(self.format.as_deref())
    }
}

/// Reads a tree file, the files it includes, and model files.
///
/// # Errors
/// The first [`ImportError`]: unreadable files, malformed XML, include cycles, bad or
/// duplicate definitions.
pub fn read(tree_file: &Path, model_files: &[PathBuf]) -> Result<Document> {
    let mut doc = Document::default();
    for m in model_files {
        let mut stack = Vec::new();
        read_file(m, &mut doc, &mut stack, false, Origin::Given)?;
    }
    let mut stack = Vec::new();
    read_file(tree_file, &mut doc, &mut stack, true, Origin::InFile)?;
    Ok(doc)
}

/// Reads the models (and trees) of several files, none of them the main one.
///
/// # Errors
/// As [`read`].
pub fn read_models(files: &[PathBuf]) -> Result<Document> {
    let mut doc = Document::default();
    for m in files {
        let mut stack = Vec::new();
        read_file(m, &mut doc, &mut stack, false, Origin::Given)?;
    }
    Ok(doc)
}

/// Reads a document from text (its includes, if any, relative to `path`'s directory).
///
/// # Errors
/// As [`read`].
pub fn read_text(path: &Path, text: &str, model_files: &[PathBuf]) -> Result<Document> {
    let mut doc = Document::default();
    for m in model_files {
        let mut stack = Vec::new();
        read_file(m, &mut doc, &mut stack, false, Origin::Given)?;
    }
    let mut stack = vec![path.to_path_buf()];
    read_source(&Source::new(path, text.to_string()), &mut doc, &mut stack, true, Origin::InFile)?;
    Ok(doc)
}

fn read_file(path: &Path, doc: &mut Document, stack: &mut Vec<PathBuf>, first: bool, origin: Origin) -> Result<()> {
    let key = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
    if let Some(i) = stack.iter().position(|p| *p == key) {
        let cycle: Vec<String> =
            stack[i..].iter().chain(std::iter::once(&key)).map(|p| p.display().to_string()).collect();
        return Err(ImportError::nowhere(Fault::IncludeCycle(cycle.join(" includes "))));
    }
    if doc.seen.contains(&key) {
        return Ok(());
    }
    doc.seen.push(key.clone());
    let text = read_bounded(path)?;
    stack.push(key);
    let r = read_source(&Source::new(path, text), doc, stack, first, origin);
    stack.pop();
    r
}

/// Most bytes an XML file may have: 64 MiB, far beyond any real tree or model file (Nav2's
/// largest is tens of kilobytes), and small enough to refuse `/dev/zero` at once.
pub const MAX_FILE_LEN: u64 = 64 << 20;

/// Reads `path` as text of at most [`MAX_FILE_LEN`] bytes.
fn read_bounded(path: &Path) -> Result<String> {
    use std::io::Read as _;
    let fault = |message: String| ImportError::nowhere(Fault::Read { path: path.to_path_buf(), message });
    let file = std::fs::File::open(path).map_err(|e| fault(e.to_string()))?;
    let mut bytes = Vec::new();
    file.take(MAX_FILE_LEN + 1).read_to_end(&mut bytes).map_err(|e| fault(e.to_string()))?;
    if bytes.len() as u64 > MAX_FILE_LEN {
        return Err(fault(format!(
            "larger than {} MiB, the most an XML file may be (read no further)",
            MAX_FILE_LEN >> 20
        )));
    }
    String::from_utf8(bytes).map_err(|e| {
        let offset = e.utf8_error().valid_up_to();
        let good = e.as_bytes().get(..offset).unwrap_or_default();
        let line = 1 + good.iter().filter(|&&b| b == b'\n').count();
        fault(format!("not UTF-8 at line {line} (byte offset {offset})"))
    })
}

/// Deepest element nesting read (BehaviorTree.CPP refuses more than 256 levels too).
const MAX_DEPTH: usize = crate::xml::flatten::MAX_NESTING + 8;

fn element(src: &Source, node: roxmltree::Node<'_, '_>, depth: usize) -> Result<Element> {
    let at = src.at(node.range().start);
    if depth > MAX_DEPTH {
        return Err(ImportError::new(&at, Fault::TooLarge(format!("elements nested deeper than {MAX_DEPTH} levels"))));
    }
    let attrs = node
        .attributes()
        .map(|a| Attr { name: a.name().to_string(), value: a.value().to_string(), at: src.at(a.range().start) })
        .collect();
    let children = node
        .children()
        .filter(roxmltree::Node::is_element)
        .map(|c| element(src, c, depth + 1))
        .collect::<Result<Vec<_>>>()?;
    Ok(Element { tag: node.tag_name().name().to_string(), attrs, children, at })
}

fn read_source(src: &Source, doc: &mut Document, stack: &mut Vec<PathBuf>, first: bool, origin: Origin) -> Result<()> {
    let opts = roxmltree::ParsingOptions { allow_dtd: false, ..roxmltree::ParsingOptions::default() };
    let xml = roxmltree::Document::parse_with_options(&src.text, opts).map_err(|e| {
        let pos = e.pos();
        let at = src.at_pos(pos.row, pos.col);
        ImportError::new(&at, Fault::Xml(strip_position(&e.to_string())))
    })?;
    let root = element(src, xml.root_element(), 0)?;
    if root.tag != "root" {
        return Err(ImportError::new(&root.at, Fault::NotRoot(root.tag.clone())));
    }
    let format = root.attr("BTCPP_format").map(str::to_string);
    let declared = root.attr_at("BTCPP_format").map(|a| (a.value.clone(), a.at.clone()));
    if let Some(f) = &format
        && f != "3"
        && f != "4"
    {
        let at = &root.attr_at("BTCPP_format").map_or(&root.at, |a| &a.at);
        return Err(ImportError::new(at, Fault::Format(f.clone())));
    }
    if first {
        doc.format = format;
        doc.main = root.attr_at("main_tree_to_execute").map(|a| (a.value.clone(), a.at.clone()));
    }
    for child in root.children.iter().filter(|c| c.tag == "include") {
        if let Some(pkg) = child.attr("ros_pkg") {
            return Err(ImportError::new(&child.at, Fault::RosPackage(pkg.to_string())));
        }
        let Some(rel) = child.attr("path") else {
            return Err(ImportError::new(
                &child.at,
                Fault::MissingAttribute { element: "include".into(), attribute: "path" },
            ));
        };
        let base = src.path.parent().unwrap_or_else(|| Path::new(""));
        let target = base.join(rel);
        read_file(&target, doc, stack, false, origin).map_err(|e| match e.at {
            // A file that cannot be read is reported at the <include> naming it.
            None if matches!(*e.fault, Fault::Read { .. }) => ImportError::new(&child.at, *e.fault),
            _ => e,
        })?;
    }
    let trees: Vec<&Element> = root.children.iter().filter(|c| c.tag == "BehaviorTree").collect();
    let mut unnamed = 0;
    for bt in &trees {
        let id = match bt.attr("ID") {
            Some(id) => id.to_string(),
            None if trees.len() == 1 => {
                let id = format!("BehaviorTree_{unnamed}");
                unnamed += 1;
                id
            }
            None => {
                return Err(ImportError::new(
                    &bt.at,
                    Fault::MissingAttribute { element: "BehaviorTree".into(), attribute: "ID" },
                ));
            }
        };
        let [child] = bt.children.as_slice() else {
            return Err(ImportError::new(
                &bt.at,
                Fault::Children {
                    node: format!("BehaviorTree ID=\"{id}\""),
                    expected: "must have exactly one child",
                    found: bt.children.len(),
                },
            ));
        };
        if let Some(first) = doc.trees.get(&id) {
            return Err(ImportError::new(&bt.at, Fault::DuplicateTree { id, first: first.at.clone() }));
        }
        if first {
            doc.own.push(id.clone());
        }
        doc.trees.insert(id.clone(), TreeDef { id, root: child.clone(), at: bt.at.clone(), format: declared.clone() });
    }
    for models in root.children.iter().filter(|c| c.tag == "TreeNodesModel") {
        doc.models.extend(model::read_models(models, origin)?);
    }
    Ok(())
}

/// roxmltree's messages end in ` at LINE:COL`; the location is printed in front instead.
fn strip_position(message: &str) -> String {
    match message.rfind(" at ") {
        Some(i) if message[i + 4..].chars().all(|c| c.is_ascii_digit() || c == ':') => message[..i].to_string(),
        _ => message.to_string(),
    }
}
