//! BehaviorTree.CPP v4 XML, read and written.
//!
//! Reading goes through a model of the document first ([`document`]: files,
//! includes, trees, models, with locations), then flattens the main tree
//! ([`flatten`]: SubTrees per instance, blackboard scopes, BehaviorTree.CPP's node
//! ids), then lowers it to bt-core ([`lower`]: kinds, leaf values, constants, slots)
//! against the behavior set of its models ([`catalog`]). Writing ([`to_xml`]) is the
//! way back, for trees made here and for imported ones; both take the behavior set as
//! a [`bt_core::Catalog`]. An imported tree becomes an image with its names
//! ([`Imported::names`], [`Imported::named_image`]) through `bt-formats`.

pub mod catalog;
pub mod document;
pub mod flatten;
pub mod lower;
pub mod merge;
pub mod model;
pub mod script;
pub mod stub;
mod view;
pub(crate) mod write;

use std::path::{Path, PathBuf};

pub use catalog::{Models, XmlCatalog};
pub use lower::{Imported, Target};
pub use write::{XmlError, XmlOptions, to_xml, to_xml_with};

use crate::error::Result;

/// What to import besides the tree file.
#[derive(Clone, Default)]
pub struct ImportOptions<'k> {
    /// Files whose `<TreeNodesModel>` declare the node types (Nav2's
    /// `nav2_tree_nodes.xml`, a Groot2 project); read before the tree file. Their
    /// `<BehaviorTree>`s are registered too, as a C++ program registers several files
    /// (`registerBehaviorTreeFromFile`) before it creates the tree.
    pub models: Vec<PathBuf>,
    /// The tree to import, instead of `main_tree_to_execute`.
    pub main: Option<String>,
    /// A known behavior set to resolve leaves against instead of the models' (to read
    /// back XML written for a PDDL domain or a brick task): see [`Target::Known`].
    pub known: Option<&'k dyn bt_core::Catalog>,
    /// Scripting enums (BT.CPP's `registerScriptingEnum`): names scripts read as numbers.
    pub enums: Vec<(String, i64)>,
    /// Polymorphic casts (BT.CPP's `registerPolymorphicCast<Derived, Base>()`), as
    /// `(derived, base)` port type names written as the models write them: an input
    /// port may then read a key of another type when the key's type reaches the port's
    /// through these casts upwards (`Sphynx::Ptr` to `Cat::Ptr` to `Animal::Ptr`) or is
    /// the port's direct base, as BT.CPP allows.
    pub casts: Vec<(String, String)>,
    /// Node types the C++ program registers as BT.CPP's `LoopNode<T>` for a type of its
    /// own (`registerNodeType<LoopNode<Pose2D>>("LoopPose")`): read as loops over a
    /// blackboard queue, with the ports of `LoopInt` and the others.
    pub loops: Vec<String>,
    /// A model of `models` wins outright over the tree file's model of the same node
    /// type, however they differ (see [`merge`]).
    pub nodes_override: bool,
}

impl std::fmt::Debug for ImportOptions<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ImportOptions")
            .field("models", &self.models)
            .field("main", &self.main)
            .field("known", &self.known.map(|k| format!("behavior set {:#018x}", k.fingerprint())))
            .field("enums", &self.enums)
            .field("casts", &self.casts)
            .field("loops", &self.loops)
            .field("nodes_override", &self.nodes_override)
            .finish()
    }
}

/// Imports the main tree of a BehaviorTree.CPP XML file.
///
/// # Errors
/// The first [`ImportError`](crate::ImportError), with its file, line and column.
pub fn import(path: &Path, options: &ImportOptions<'_>) -> Result<Imported> {
    let doc = document::read(path, &options.models)?;
    import_document(&doc, options)
}

/// Imports XML text; `path` names it in errors and anchors its `<include>`s.
///
/// # Errors
/// As [`import`].
pub fn import_text(path: &Path, text: &str, options: &ImportOptions<'_>) -> Result<Imported> {
    let doc = document::read_text(path, text, &options.models)?;
    import_document(&doc, options)
}

/// Imports the main tree of a document already read.
///
/// # Errors
/// As [`import`].
pub fn import_document(doc: &document::Document, options: &ImportOptions<'_>) -> Result<Imported> {
    let models = Models::read(&doc.models, options.nodes_override)?;
    let main = flatten::main_tree(doc, options.main.as_deref())?;
    let flat = flatten::flatten(doc, main, &models)?;
    let target = options.known.map_or(Target::Models, Target::Known);
    lower::lower(&flat, &models, target, &options.enums, &options.casts, &options.loops)
}
