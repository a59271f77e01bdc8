//! The builder: trees in code, into caller storage, with an error for each misuse.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use bt_core::{BuildError, Builder, LeafError, Node, NodeKind};

#[test]
fn writes_pre_order_with_subtree_sizes() {
    let mut storage = [Node::EMPTY; 8];
    let mut b = Builder::<4>::new(&mut storage);
    b.sequence().unwrap().condition(0, &[]).unwrap().inverter().unwrap().action(1, &[5]).unwrap().end().unwrap();
    b.parallel(1, 1).unwrap().action(1, &[]).unwrap().end().unwrap().end().unwrap();
    let nodes = b.finish().unwrap();
    let sizes: Vec<u16> = nodes.iter().map(Node::size).collect();
    assert_eq!(sizes, [6, 1, 2, 1, 2, 1]);
    assert_eq!(nodes[3].kind().leaf().unwrap().1.args(), [5]);
    assert_eq!(
        *nodes[4].kind(),
        NodeKind::Parallel { success_threshold: 1, failure_threshold: 1, count_skipped: false }
    );
}

#[test]
fn each_misuse_has_its_error() {
    let mut storage = [Node::EMPTY; 2];
    let mut b = Builder::<4>::new(&mut storage);
    b.sequence().unwrap().condition(0, &[]).unwrap();
    assert_eq!(b.condition(0, &[]).unwrap_err(), BuildError::Full { capacity: 2 });

    let mut storage = [Node::EMPTY; 8];
    let mut b = Builder::<2>::new(&mut storage);
    b.sequence().unwrap().sequence().unwrap();
    assert_eq!(b.sequence().unwrap_err(), BuildError::TooDeep { limit: 2 });

    let mut storage = [Node::EMPTY; 8];
    let mut b = Builder::<2>::new(&mut storage);
    assert_eq!(b.end().unwrap_err(), BuildError::NothingOpen);
    b.condition(0, &[]).unwrap();
    assert_eq!(b.condition(0, &[]).unwrap_err(), BuildError::NotOneRoot);

    let mut storage = [Node::EMPTY; 8];
    let mut b = Builder::<2>::new(&mut storage);
    b.fallback().unwrap();
    assert_eq!(b.finish().unwrap_err(), BuildError::Unclosed { open: 1 });

    let mut storage = [Node::EMPTY; 8];
    let b = Builder::<2>::new(&mut storage);
    assert_eq!(b.finish().unwrap_err(), BuildError::NotOneRoot);

    let mut storage = [Node::EMPTY; 8];
    let mut b = Builder::<2>::new(&mut storage);
    assert_eq!(b.open(NodeKind::Action(bt_core::Leaf::new(0))).unwrap_err(), BuildError::LeafOpened);
    assert_eq!(b.action(0, &[1, 2, 3, 4]).unwrap_err(), BuildError::Leaf(LeafError::TooManyArgs(4)));
    assert_eq!(b.action(0, &[u16::MAX]).unwrap_err(), BuildError::Leaf(LeafError::ReservedValue(0)));
}
