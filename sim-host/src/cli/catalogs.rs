//! The behavior sets this binary knows, found by an image's fingerprint.

use bt_core::{Catalog, LeafKind, Node};
use bt_formats::{Names, NamesError};
use planner::duplo::Task;
use planner::{PddlCatalog, domains, pddl};

/// A behavior set the binary knows by name.
pub struct Known {
    /// What it is, for people.
    pub name: String,
    /// Its short name (`tower`, `cube-sphere`) for `--behaviors`; empty for sets read
    /// from an image.
    pub short: &'static str,
    /// The set: its names, ports and values, how they print and read back.
    pub catalog: Box<dyn Catalog>,
    /// The tree's ID in BehaviorTree.CPP XML, when the image's names give one.
    pub tree_id: String,
    /// Something the reader should know about these names (printed by `inspect`).
    pub note: Option<String>,
}

/// The built-in PDDL domains, each with the objects of its shipped problem (blocks:
/// `b0`..`b63`, the names `domains::blocks_world` gives).
fn pddl_catalogs() -> Vec<Known> {
    let blocks = domains::blocks_world_pddl(64);
    let sets = [
        (
            "cube-sphere",
            "PDDL domain `cube-sphere` (Colledanchise et al. 2019)",
            domains::CUBE_SPHERE_DOMAIN,
            domains::CUBE_SPHERE_PROBLEM,
        ),
        (
            "cellphone",
            "PDDL domain `cellphone` (Colledanchise et al. 2019)",
            domains::CELLPHONE_DOMAIN,
            domains::CELLPHONE_PROBLEM,
        ),
        ("blocks", "PDDL domain `blocks`", domains::BLOCKS_DOMAIN, blocks.as_str()),
    ];
    sets.into_iter()
        .filter_map(|(short, name, d, p)| {
            let d = pddl::parse_domain("built-in", d).ok()?;
            let p = pddl::parse_problem("built-in", p, &d).ok()?;
            let catalog = Box::new(PddlCatalog::new(&p));
            Some(Known { name: name.to_string(), short, catalog, tree_id: String::new(), note: None })
        })
        .collect()
}

/// Every behavior set built into the binary.
pub fn all() -> Vec<Known> {
    Task::ALL
        .into_iter()
        .map(|t| Known {
            name: format!("brick task `{}`", t.name()),
            short: t.name(),
            catalog: Box::new(t.spec()),
            tree_id: String::new(),
            note: None,
        })
        .chain(pddl_catalogs())
        .collect()
}

/// The built-in behavior set with this short name (`tower`, `cube-sphere`).
pub fn by_name(name: &str) -> Option<Known> {
    all().into_iter().find(|k| k.short == name)
}

/// The short names of the built-in behavior sets.
pub fn names() -> Vec<&'static str> {
    all().into_iter().map(|k| k.short).collect()
}

/// The built-in behavior set with this fingerprint.
pub fn by_fingerprint(fingerprint: u64) -> Option<Known> {
    all().into_iter().find(|k| k.catalog.fingerprint() == fingerprint)
}

/// Loads `bytes`, the image named `name`, as a controller would (envelope, CRC,
/// fingerprint, nodes, validation) against the names [`for_image_with`] finds for it
/// (`models` first), and hands the names, the envelope and the tree to `f`.
///
/// # Errors
/// As [`for_image_with`]; an image that does not load (naming it); what `f` returns.
pub fn load_image<R>(
    name: &std::path::Path,
    bytes: &[u8],
    models: &[std::path::PathBuf],
    f: impl FnOnce(Known, bt_core::image::Header, bt_core::Tree<'_, { bt_formats::DEPTH }>) -> anyhow::Result<R>,
) -> anyhow::Result<R> {
    let (known, header) = for_image_with(name, bytes, models)?;
    let mut storage = vec![Node::EMPTY; usize::from(header.node_count)];
    // The value table (extended leaves' values) has fewer entries than the image bytes.
    let mut values = vec![0u16; bytes.len()];
    let tree = bt_core::load_with(bytes, known.catalog.as_ref(), &mut storage, &mut values)
        .map_err(|e| anyhow::anyhow!("{}: {e}", name.display()))?;
    f(known, header, tree)
}

/// Reads an image's envelope and finds the names to show it with: the image's own
/// names section when it matches the image's behavior set (the truth, whatever the
/// problem), else the built-in set with that fingerprint, else ids only (`#3(#0, #1)`),
/// with a note saying so.
///
/// # Errors
/// A bad envelope, node or section (as its `LoadError`), naming the file.
pub fn for_image(path: &std::path::Path, bytes: &[u8]) -> anyhow::Result<(Known, bt_core::image::Header)> {
    for_image_with(path, bytes, &[])
}

/// [`for_image`], first trying the behavior set of BehaviorTree.CPP models read from
/// `models` (the files given to `import`), for an image whose names were stripped or
/// that was imported before images carried them. Models of another behavior set are an
/// error, naming both fingerprints.
///
/// # Errors
/// As [`for_image`]; a model file that does not read; models of another set.
pub fn for_image_with(
    path: &std::path::Path,
    bytes: &[u8],
    models: &[std::path::PathBuf],
) -> anyhow::Result<(Known, bt_core::image::Header)> {
    let fail = |e: bt_core::LoadError| anyhow::anyhow!("{}: {e}", path.display());
    let header = bt_core::image::read_header(bytes).map_err(fail)?;
    if !models.is_empty() {
        let doc = btcpp::xml::document::read_models(models)?;
        let catalog = btcpp::xml::Models::new(&doc.models)?.catalog();
        let files: Vec<String> = models.iter().map(|f| f.display().to_string()).collect();
        if catalog.fingerprint() != header.fingerprint {
            anyhow::bail!(
                "{}: made for behavior set {:#018x}, but the models of --nodes {} give {:#018x}; give the files \
                 `import` read (its tree file and its --nodes)",
                path.display(),
                header.fingerprint,
                files.join(", "),
                catalog.fingerprint()
            );
        }
        let known = Known {
            name: format!("BehaviorTree.CPP models of {}", files.join(", ")),
            short: "",
            catalog: Box::new(catalog),
            tree_id: String::new(),
            note: None,
        };
        return Ok((known, header));
    }
    let mut note = None;
    match Names::of_image(bytes) {
        Ok(Some(names)) if names.fingerprint() == header.fingerprint => {
            let name = format!("{} (names from the image)", names.title);
            let tree_id = names.tree_id.clone();
            return Ok((Known { name, short: "", catalog: Box::new(names), tree_id, note: None }, header));
        }
        Ok(Some(_)) => {
            note = Some("the image's names section does not match its behavior set; names ignored".to_string())
        }
        Ok(None) => {}
        Err(NamesError::Image(e)) => return Err(fail(e)),
        Err(e) => note = Some(format!("{e}; names ignored")),
    }
    if let Some(mut known) = by_fingerprint(header.fingerprint) {
        known.note = note;
        return Ok((known, header));
    }
    let ids = IdCatalog::of_image(bytes, header.fingerprint).map_err(fail)?;
    let why = note.map_or(String::new(), |n| format!("{n}; "));
    let known = Known {
        name: "unknown to this binary".to_string(),
        short: "",
        catalog: Box::new(ids),
        tree_id: String::new(),
        note: Some(format!(
            "{why}behavior set {:#018x} is not built in and the image carries no names: \
             behaviors and values are shown as ids",
            header.fingerprint
        )),
    };
    Ok((known, header))
}

/// Names for an image whose behavior set is unknown: each behavior is `#id`, with the
/// kind and arity its leaves (and plugin decorators' gates, which are actions) use, and
/// the image's own fingerprint, so the tree can still be loaded, validated and shown.
struct IdCatalog {
    behaviors: Vec<Option<(String, LeafKind, u8)>>,
    fingerprint: u64,
}

impl IdCatalog {
    fn of_image(bytes: &[u8], fingerprint: u64) -> Result<Self, bt_core::LoadError> {
        let header = bt_core::image::read_header(bytes)?;
        let mut nodes = vec![Node::EMPTY; usize::from(header.node_count)];
        let mut values = vec![0u16; usize::from(u16::MAX)];
        let d = bt_core::image::decode(bytes, &mut nodes, &mut values)?;
        let mut behaviors: Vec<Option<(String, LeafKind, u8)>> = Vec::new();
        for node in &nodes[..d.nodes] {
            let used = match *node.kind() {
                bt_core::NodeKind::Gate(leaf) => Some((LeafKind::Action, leaf)),
                ref other => other.leaf(),
            };
            if let Some((kind, leaf)) = used {
                let id = usize::from(leaf.behavior());
                if behaviors.len() <= id {
                    behaviors.resize(id + 1, None);
                }
                // The first use decides; validation reports any leaf that disagrees.
                let arity = u8::try_from(leaf.argc()).unwrap_or(u8::MAX);
                behaviors[id].get_or_insert_with(|| (format!("#{id}"), kind, arity));
            }
        }
        Ok(Self { behaviors, fingerprint })
    }
}

impl Catalog for IdCatalog {
    fn len(&self) -> usize {
        self.behaviors.len()
    }

    fn info(&self, id: bt_core::BehaviorId) -> Option<bt_core::BehaviorInfo<'_>> {
        let (name, kind, arity) = self.behaviors.get(usize::from(id))?.as_ref()?;
        Some(bt_core::BehaviorInfo { name, kind: *kind, arity: *arity })
    }

    fn fingerprint(&self) -> u64 {
        self.fingerprint
    }
}
