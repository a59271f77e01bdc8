//! The behavior sets this binary knows, found by an image's fingerprint.

use bt_core::Catalog;
use planner::duplo::Task;

/// A behavior set the binary knows by name.
pub struct Known {
    /// What it is, for people.
    pub name: String,
    /// The set.
    pub catalog: Box<dyn Catalog>,
}

/// Every behavior set built into the binary.
pub fn all() -> Vec<Known> {
    Task::ALL
        .into_iter()
        .map(|t| Known {
            name: format!("brick task `{}` (seed 003)", t.name()),
            catalog: Box::new(t.spec()) as Box<dyn Catalog>,
        })
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
