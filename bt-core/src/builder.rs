//! Building trees in code, into the caller's storage.

use crate::error::BuildError;
use crate::node::{Arity, BehaviorId, Leaf, Node, NodeKind};

/// Writes a tree in pre-order into caller storage: open a control node or decorator,
/// add its children, close it with [`Builder::end`]. At most `DEPTH` nodes open at once.
///
/// ```
/// use bt_core::{Builder, Node};
/// let mut storage = [Node::EMPTY; 8];
/// let mut b = Builder::<4>::new(&mut storage);
/// b.fallback()?
///     .condition(0, &[])?          // cube on goal?
///     .sequence()?
///         .action(1, &[7])?        // MoveTo(7)
///         .action(2, &[])?         // Place
///     .end()?
/// .end()?;
/// let nodes = b.finish()?;
/// assert_eq!(nodes.len(), 5);
/// assert_eq!(nodes[2].size(), 3);
/// # Ok::<(), bt_core::BuildError>(())
/// ```
#[derive(Debug)]
pub struct Builder<'a, const DEPTH: usize> {
    nodes: &'a mut [Node],
    len: usize,
    open: heapless::Vec<u16, DEPTH>,
}

impl<'a, const DEPTH: usize> Builder<'a, DEPTH> {
    /// A builder writing into `storage` (its length is the node capacity).
    pub fn new(storage: &'a mut [Node]) -> Self {
        Self { nodes: storage, len: 0, open: heapless::Vec::new() }
    }

    /// Nodes written so far.
    #[must_use]
    pub fn len(&self) -> usize {
        self.len
    }

    /// True before the first node.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    fn push(&mut self, kind: NodeKind) -> Result<&mut Self, BuildError> {
        if self.open.is_empty() && self.len > 0 {
            return Err(BuildError::NotOneRoot);
        }
        let capacity = self.nodes.len().min(usize::from(u16::MAX));
        if self.len >= capacity {
            return Err(BuildError::Full { capacity });
        }
        let id = self.len as u16;
        if kind.arity() != Arity::Leaf && self.open.push(id).is_err() {
            return Err(BuildError::TooDeep { limit: DEPTH });
        }
        if let Some(slot) = self.nodes.get_mut(self.len) {
            *slot = Node::new(kind, 1);
        }
        self.len += 1;
        Ok(self)
    }

    /// Opens a control node or decorator of any kind; close it with [`Builder::end`].
    ///
    /// # Errors
    /// [`BuildError::LeafOpened`] for a leaf kind, or as [`Builder::end`]'s siblings.
    pub fn open(&mut self, kind: NodeKind) -> Result<&mut Self, BuildError> {
        if kind.arity() == Arity::Leaf {
            return Err(BuildError::LeafOpened);
        }
        self.push(kind)
    }

    /// Closes the innermost open node.
    ///
    /// # Errors
    /// [`BuildError::NothingOpen`] when no node is open.
    pub fn end(&mut self) -> Result<&mut Self, BuildError> {
        let id = self.open.pop().ok_or(BuildError::NothingOpen)?;
        let size = (self.len - usize::from(id)) as u16;
        if let Some(node) = self.nodes.get_mut(usize::from(id)) {
            node.set_size(size);
        }
        Ok(self)
    }

    /// Adds a condition leaf.
    ///
    /// # Errors
    /// [`BuildError::Full`], [`BuildError::NotOneRoot`], or bad arguments.
    pub fn condition(&mut self, behavior: BehaviorId, args: &[u16]) -> Result<&mut Self, BuildError> {
        let leaf = Leaf::with_args(behavior, args)?;
        self.push(NodeKind::Condition(leaf))
    }

    /// Adds an action leaf.
    ///
    /// # Errors
    /// As [`Builder::condition`].
    pub fn action(&mut self, behavior: BehaviorId, args: &[u16]) -> Result<&mut Self, BuildError> {
        let leaf = Leaf::with_args(behavior, args)?;
        self.push(NodeKind::Action(leaf))
    }

    /// Adds a leaf of any leaf kind ([`NodeKind::AlwaysSuccess`], ...).
    ///
    /// # Errors
    /// [`BuildError::NotALeaf`] for other kinds, or as [`Builder::condition`].
    pub fn leaf(&mut self, kind: NodeKind) -> Result<&mut Self, BuildError> {
        if kind.arity() != Arity::Leaf {
            return Err(BuildError::NotALeaf);
        }
        self.push(kind)
    }

    /// Opens a [`NodeKind::Gate`] asking `behavior` (an action of the set).
    ///
    /// # Errors
    /// As [`Builder::condition`] and [`Builder::sequence`].
    pub fn gate(&mut self, behavior: BehaviorId, args: &[u16]) -> Result<&mut Self, BuildError> {
        let leaf = Leaf::with_args(behavior, args)?;
        self.push(NodeKind::Gate(leaf))
    }

    /// Opens a reactive [`NodeKind::Sequence`].
    ///
    /// # Errors
    /// [`BuildError::Full`], [`BuildError::TooDeep`] or [`BuildError::NotOneRoot`].
    pub fn sequence(&mut self) -> Result<&mut Self, BuildError> {
        self.push(NodeKind::Sequence)
    }

    /// Opens a reactive [`NodeKind::Fallback`].
    ///
    /// # Errors
    /// As [`Builder::sequence`].
    pub fn fallback(&mut self) -> Result<&mut Self, BuildError> {
        self.push(NodeKind::Fallback)
    }

    /// Opens a [`NodeKind::SequenceWithMemory`].
    ///
    /// # Errors
    /// As [`Builder::sequence`].
    pub fn sequence_with_memory(&mut self) -> Result<&mut Self, BuildError> {
        self.push(NodeKind::SequenceWithMemory)
    }

    /// Opens a [`NodeKind::FallbackWithMemory`].
    ///
    /// # Errors
    /// As [`Builder::sequence`].
    pub fn fallback_with_memory(&mut self) -> Result<&mut Self, BuildError> {
        self.push(NodeKind::FallbackWithMemory)
    }

    /// Opens a [`NodeKind::Parallel`].
    ///
    /// # Errors
    /// As [`Builder::sequence`].
    pub fn parallel(&mut self, success_threshold: u16, failure_threshold: u16) -> Result<&mut Self, BuildError> {
        self.push(NodeKind::Parallel { success_threshold, failure_threshold, count_skipped: false })
    }

    /// Opens an [`NodeKind::Inverter`].
    ///
    /// # Errors
    /// As [`Builder::sequence`].
    pub fn inverter(&mut self) -> Result<&mut Self, BuildError> {
        self.push(NodeKind::Inverter)
    }

    /// Opens a [`NodeKind::ForceSuccess`].
    ///
    /// # Errors
    /// As [`Builder::sequence`].
    pub fn force_success(&mut self) -> Result<&mut Self, BuildError> {
        self.push(NodeKind::ForceSuccess)
    }

    /// Opens a [`NodeKind::ForceFailure`].
    ///
    /// # Errors
    /// As [`Builder::sequence`].
    pub fn force_failure(&mut self) -> Result<&mut Self, BuildError> {
        self.push(NodeKind::ForceFailure)
    }

    /// Opens a [`NodeKind::Repeat`].
    ///
    /// # Errors
    /// As [`Builder::sequence`].
    pub fn repeat(&mut self, n: u16) -> Result<&mut Self, BuildError> {
        self.push(NodeKind::Repeat(n))
    }

    /// Opens a [`NodeKind::Retry`].
    ///
    /// # Errors
    /// As [`Builder::sequence`].
    pub fn retry(&mut self, n: u16) -> Result<&mut Self, BuildError> {
        self.push(NodeKind::Retry(n))
    }

    /// Opens a [`NodeKind::Timeout`].
    ///
    /// # Errors
    /// As [`Builder::sequence`].
    pub fn timeout(&mut self, ticks: u16) -> Result<&mut Self, BuildError> {
        self.push(NodeKind::Timeout(ticks))
    }

    /// The finished node array: validate it with [`Tree::validate`](crate::Tree::validate).
    ///
    /// # Errors
    /// [`BuildError::Unclosed`] while nodes are open, [`BuildError::NotOneRoot`] if empty.
    pub fn finish(self) -> Result<&'a [Node], BuildError> {
        if !self.open.is_empty() {
            return Err(BuildError::Unclosed { open: self.open.len() });
        }
        if self.len == 0 {
            return Err(BuildError::NotOneRoot);
        }
        let nodes: &'a [Node] = self.nodes;
        Ok(nodes.get(..self.len).unwrap_or(&[]))
    }
}
