//! A tree and its name table in the notations people and tools read: the deployable
//! image, ASCII (bt-core's renderer), Graphviz DOT, BehaviorTree.CPP v4 XML, and the
//! token notation of seed 003 ([`crate::tokens`]).

mod dot;

pub use btcpp::xml::{XmlError, XmlOptions, to_xml, to_xml_with};
pub use dot::{to_dot, to_dot_with};

use bt_core::image::ImageParts;
use bt_core::{Catalog, Node, Tree};

use crate::names::NameTable;

use crate::PlanError;
use crate::tree::DEPTH;

/// The image bytes of `nodes` for `catalog` (`bt_core::encode` with its fingerprint).
///
/// # Errors
/// [`PlanError::TooManyNodes`] when the tree has more nodes than an image holds.
pub fn to_image<C: Catalog + ?Sized>(nodes: &[Node], catalog: &C) -> Result<Vec<u8>, PlanError> {
    to_image_with(&ImageParts::new(nodes), catalog)
}

/// The image bytes of a tree with its value table (empty: none) and, when given, a
/// names section (see [`crate::names`]).
///
/// # Errors
/// As [`to_image`]; [`PlanError::TooManyValues`] for a value table beyond what an
/// image holds.
pub fn to_image_parts<C: Catalog + ?Sized>(
    nodes: &[Node],
    values: &[u16],
    catalog: &C,
    names: Option<&NameTable>,
) -> Result<Vec<u8>, PlanError> {
    if values.len() > usize::from(u16::MAX) {
        return Err(PlanError::TooManyValues { limit: usize::from(u16::MAX) });
    }
    let names = names.map(NameTable::to_bytes);
    let mut parts = ImageParts::new(nodes);
    parts.values = values;
    if let Some(n) = &names {
        parts = parts.names(n);
    }
    to_image_with(&parts, catalog)
}

/// The image bytes of `nodes`, with a names section that lets host tools print the
/// tree as it is even without knowing its domain (see [`crate::names`]).
///
/// # Errors
/// As [`to_image`].
pub fn to_image_named<C: Catalog + ?Sized>(
    nodes: &[Node],
    catalog: &C,
    names: &NameTable,
) -> Result<Vec<u8>, PlanError> {
    let names = names.to_bytes();
    to_image_with(&ImageParts::new(nodes).names(&names), catalog)
}

fn to_image_with<C: Catalog + ?Sized>(parts: &ImageParts<'_>, catalog: &C) -> Result<Vec<u8>, PlanError> {
    let mut buf = vec![0u8; parts.max_len()];
    let len = bt_core::encode_with(parts, catalog.fingerprint(), &mut buf)
        .map_err(|_| PlanError::TooManyNodes { nodes: parts.nodes.len(), limit: usize::from(u16::MAX) })?;
    buf.truncate(len);
    Ok(buf)
}

/// The indented ASCII view (bt-core's renderer) with the catalog's names.
///
/// # Errors
/// [`PlanError::InvalidTree`] when `nodes` do not validate against `catalog`.
pub fn to_ascii<C: Catalog + ?Sized>(nodes: &[Node], catalog: &C) -> Result<String, PlanError> {
    to_ascii_with(nodes, &[], catalog)
}

/// [`to_ascii`] for a tree with a value table (leaves with more than
/// [`bt_core::MAX_ARGS`] arguments).
///
/// # Errors
/// As [`to_ascii`].
pub fn to_ascii_with<C: Catalog + ?Sized>(nodes: &[Node], values: &[u16], catalog: &C) -> Result<String, PlanError> {
    let tree: Tree<'_, DEPTH> =
        Tree::validate_with(nodes, values, catalog).map_err(|e| PlanError::InvalidTree(e.to_string()))?;
    Ok(tree.display(catalog).to_string())
}

/// A leaf as the catalog renders it, e.g. `holding(cube)`.
pub(crate) fn leaf_text<C: Catalog + ?Sized>(catalog: &C, leaf: &bt_core::Leaf, values: &[u16]) -> String {
    bt_core::render::display_leaf(catalog, leaf, values).to_string()
}

#[cfg(test)]
mod tests {
    #[test]
    fn brick_trees_use_compact_leaves_with_their_names() {
        let plan = crate::duplo::plan(crate::duplo::Task::Tower).unwrap();
        let spec = crate::duplo::Task::Tower.spec();
        let xml = super::to_xml(&plan.nodes, &spec, &crate::catalog::NoPorts).unwrap();
        // Numbered as BehaviorTree.CPP numbers the document (and our replay logs do).
        assert!(xml.contains("<pick_0 name=\"pick 0!\" _uid=\""), "{xml}");
        assert!(xml.contains(&format!(" _uid=\"{}\"", plan.nodes.len())) && xml.contains(" _uid=\"1\""), "{xml}");
        assert!(xml.contains("<Action ID=\"pick_0\"/>"), "{xml}");
        assert!(!xml[..xml.find("<TreeNodesModel>").unwrap()].contains("ID=\"pick"), "{xml}");
    }
}
