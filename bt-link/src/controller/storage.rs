//! The controller's memory: two image slots and the running tree's per-node state.

use bt_core::{Catalog, LoadError, Node, NodeState, Tree};

use crate::wire::{ImageInfo, MAX_CHUNK};

/// One image buffer and the nodes and value table it decodes into.
#[derive(Debug)]
pub struct Slot<const NODES: usize, const BYTES: usize, const VALUES: usize> {
    pub(super) bytes: [u8; BYTES],
    nodes: [Node; NODES],
    values: [u16; VALUES],
    /// Entries of `values` the loaded tree uses.
    value_count: usize,
    /// The image held, if one was loaded into `nodes`.
    pub(super) image: Option<ImageInfo>,
}

impl<const NODES: usize, const BYTES: usize, const VALUES: usize> Slot<NODES, BYTES, VALUES> {
    const fn new() -> Self {
        Self { bytes: [0; BYTES], nodes: [Node::EMPTY; NODES], values: [0; VALUES], value_count: 0, image: None }
    }

    /// Loads `len` bytes of the buffer into the nodes.
    pub(super) fn load<C: Catalog + ?Sized, const DEPTH: usize>(
        &mut self,
        len: usize,
        catalog: &C,
    ) -> Result<ImageInfo, LoadError> {
        self.image = None;
        let bytes = self.bytes.get(..len).ok_or(LoadError::TooManyNodes { count: len, capacity: BYTES })?;
        let tree: Tree<'_, DEPTH> = bt_core::image::load_with(bytes, catalog, &mut self.nodes, &mut self.values)?;
        let info = ImageInfo { crc: crate::image_crc(bytes), len: len as u32, nodes: tree.len() as u16 };
        self.value_count = tree.values().len();
        self.image = Some(info);
        Ok(info)
    }

    /// The tree loaded into this slot (validated again: cheap, and no borrow has to
    /// outlive the load).
    pub(super) fn tree<C: Catalog + ?Sized, const DEPTH: usize>(&self, catalog: &C) -> Option<Tree<'_, DEPTH>> {
        let nodes = self.nodes.get(..usize::from(self.image?.nodes))?;
        let values = self.values.get(..self.value_count)?;
        Tree::validate_with(nodes, values, catalog).ok()
    }

    /// The loaded tree's nodes (empty without one).
    pub(super) fn nodes(&self) -> &[Node] {
        let count = self.image.map_or(0, |i| usize::from(i.nodes));
        self.nodes.get(..count).unwrap_or(&[])
    }

    /// Image bytes at `offset`, at most [`MAX_CHUNK`].
    pub(super) fn chunk(&self, offset: u32) -> &[u8] {
        let len = self.image.map_or(0, |i| i.len as usize);
        let start = (offset as usize).min(len);
        self.bytes.get(start..len.min(start + MAX_CHUNK)).unwrap_or(&[])
    }
}

/// Everything a controller keeps of its trees: two slots and the running tree's
/// per-node state. `NODES` bounds a tree's node count, `BYTES` an image's length,
/// `VALUES` its value table (leaves with more than three values; 0 refuses such
/// images). A `static` or an RTIC `local` can hold it: [`Storage::new`] is `const`.
#[derive(Debug)]
pub struct Storage<const NODES: usize, const BYTES: usize, const VALUES: usize> {
    pub(super) slots: [Slot<NODES, BYTES, VALUES>; 2],
    pub(super) state: [NodeState; NODES],
}

impl<const NODES: usize, const BYTES: usize, const VALUES: usize> Default for Storage<NODES, BYTES, VALUES> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const NODES: usize, const BYTES: usize, const VALUES: usize> Storage<NODES, BYTES, VALUES> {
    /// Empty storage (`const`: can be a `static`).
    #[must_use]
    pub const fn new() -> Self {
        Self { slots: [Slot::new(), Slot::new()], state: [NodeState::IDLE; NODES] }
    }
}
