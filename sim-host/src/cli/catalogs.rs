//! The behavior sets this binary knows, found by an image's fingerprint.

use bt_core::Catalog;
use planner::duplo::Task;
use planner::{PddlCatalog, Ports, domains, pddl};

/// A behavior set the binary knows by name.
pub struct Known {
    /// What it is, for people.
    pub name: String,
    /// The set.
    pub catalog: Box<dyn Catalog>,
    /// Port names of its leaves' arguments, for BehaviorTree.CPP XML (PDDL domains).
    pub ports: Option<Box<dyn Ports>>,
}

/// The built-in PDDL domains, each with the objects of its shipped problem (blocks:
/// `b0`..`b63`, the names `domains::blocks_world` gives).
fn pddl_catalogs() -> Vec<Known> {
    let blocks = domains::blocks_world_pddl(64);
    let sets = [
        ("PDDL domain `cube-sphere` (seed 000)", domains::CUBE_SPHERE_DOMAIN, domains::CUBE_SPHERE_PROBLEM),
        ("PDDL domain `cellphone` (seed 000)", domains::CELLPHONE_DOMAIN, domains::CELLPHONE_PROBLEM),
        ("PDDL domain `blocks`", domains::BLOCKS_DOMAIN, blocks.as_str()),
    ];
    sets.into_iter()
        .filter_map(|(name, d, p)| {
            let d = pddl::parse_domain("built-in", d).ok()?;
            let p = pddl::parse_problem("built-in", p, &d).ok()?;
            let c = PddlCatalog::new(&p);
            Some(Known { name: name.to_string(), catalog: Box::new(c.clone()), ports: Some(Box::new(c)) })
        })
        .collect()
}

/// Every behavior set built into the binary.
pub fn all() -> Vec<Known> {
    Task::ALL
        .into_iter()
        .map(|t| Known {
            name: format!("brick task `{}` (seed 003)", t.name()),
            catalog: Box::new(t.spec()) as Box<dyn Catalog>,
            ports: None,
        })
        .chain(pddl_catalogs())
        .collect()
}

/// The built-in behavior set with this fingerprint.
pub fn by_fingerprint(fingerprint: u64) -> Option<Known> {
    all().into_iter().find(|k| k.catalog.fingerprint() == fingerprint)
}

/// Reads an image's envelope and finds its behavior set among the built-in ones.
///
/// # Errors
/// A bad envelope (as its `LoadError`) or an unknown fingerprint, naming the file.
pub fn for_image(path: &std::path::Path, bytes: &[u8]) -> anyhow::Result<(Known, bt_core::image::Header)> {
    let header = bt_core::image::read_header(bytes).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let known = by_fingerprint(header.fingerprint).ok_or_else(|| {
        anyhow::anyhow!(
            "{}: built for behavior set {:#018x}, which this binary does not know",
            path.display(),
            header.fingerprint
        )
    })?;
    Ok((known, header))
}
