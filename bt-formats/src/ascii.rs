//! The indented view people know from py_trees: bt-core's renderer
//! ([`bt_core::render`]) over a tree checked first, with the catalog's names.

use bt_core::{Catalog, LoadError, Node, Tree};

use crate::DEPTH;

/// The tree as indented lines, one per node, leaves named by `catalog`.
///
/// # Errors
/// The [`LoadError`] of validating `nodes` against `catalog`.
pub fn to_ascii<C: Catalog + ?Sized>(nodes: &[Node], catalog: &C) -> Result<String, LoadError> {
    to_ascii_with(nodes, &[], catalog)
}

/// [`to_ascii`] for a tree with a value table (leaves with more than
/// [`bt_core::MAX_ARGS`] values).
///
/// # Errors
/// As [`to_ascii`].
pub fn to_ascii_with<C: Catalog + ?Sized>(nodes: &[Node], values: &[u16], catalog: &C) -> Result<String, LoadError> {
    let tree: Tree<'_, DEPTH> = Tree::validate_with(nodes, values, catalog)?;
    Ok(tree.display(catalog).to_string())
}

/// A leaf as the catalog renders it, e.g. `holding(cube)`.
pub(crate) fn leaf_text<C: Catalog + ?Sized>(catalog: &C, leaf: &bt_core::Leaf, values: &[u16]) -> String {
    bt_core::render::display_leaf(catalog, leaf, values).to_string()
}
