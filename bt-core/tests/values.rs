//! Leaf values beyond three: extended leaves, the value table, and the image sections
//! that carry it (format version 2).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use bt_core::image::{CRC_LEN, HEADER_LEN, ImageParts, SECTION_NAMES, SECTION_VALUES, crc32, section};
use bt_core::{
    ArgumentFault, BehaviorInfo, BehaviorSet, Context, Executor, Leaf, LeafError, LoadError, Node, NodeId, NodeKind,
    NodeState, Status, Tree, encode_with, fingerprint, load, load_with,
};
use proptest::prelude::*;

const SET: [BehaviorInfo<'static>; 3] =
    [BehaviorInfo::condition("at", 4), BehaviorInfo::action("drive-truck", 5), BehaviorInfo::action("wait", 1)];

/// Sequence[ at(10, 11, 12, 13), drive-truck(1, 2, 3, 4, 5), wait(9) ]: the first two
/// leaves take their values from the table.
fn sample() -> (Vec<Node>, Vec<u16>) {
    let values = vec![10, 11, 12, 13, 1, 2, 3, 4, 5];
    let nodes = vec![
        Node::new(NodeKind::Sequence, 4),
        Node::new(NodeKind::Condition(Leaf::extended(0, 0, 4).unwrap()), 1),
        Node::new(NodeKind::Action(Leaf::extended(1, 4, 5).unwrap()), 1),
        Node::new(NodeKind::Action(Leaf::with_args(2, &[9]).unwrap()), 1),
    ];
    (nodes, values)
}

fn image(parts: &ImageParts<'_>) -> Vec<u8> {
    let mut out = vec![0u8; parts.max_len()];
    let n = encode_with(parts, fingerprint(&SET), &mut out).unwrap();
    out.truncate(n);
    out
}

fn reseal(mut bytes: Vec<u8>) -> Vec<u8> {
    let n = bytes.len() - CRC_LEN;
    let crc = crc32(&bytes[..n]);
    bytes[n..].copy_from_slice(&crc.to_le_bytes());
    bytes
}

fn try_load(bytes: &[u8]) -> Result<(Vec<Node>, Vec<u16>), LoadError> {
    let (mut storage, mut values) = ([Node::EMPTY; 16], [0u16; 16]);
    load_with::<_, 4>(bytes, &SET, &mut storage, &mut values).map(|t| (t.nodes().to_vec(), t.values().to_vec()))
}

/// Records the values each behavior sees.
#[derive(Default)]
struct Seen(Vec<(NodeId, Vec<u16>)>);

impl BehaviorSet for Seen {
    fn condition(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        self.0.push((ctx.node, ctx.args(leaf).to_vec()));
        Status::Success
    }
    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        self.0.push((ctx.node, ctx.args(leaf).to_vec()));
        Status::Success
    }
    fn halt(&mut self, _: &Leaf, _: NodeId) {}
}

#[test]
fn extended_leaves_round_trip_and_behaviors_read_all_their_values() {
    let (nodes, values) = sample();
    let bytes = image(&ImageParts::new(&nodes).values(&values));
    assert_eq!(try_load(&bytes), Ok((nodes.clone(), values.clone())));

    let (mut storage, mut table) = ([Node::EMPTY; 8], [0u16; 9]);
    let tree: Tree<'_, 4> = load_with(&bytes, &SET, &mut storage, &mut table).unwrap();
    let mut state = [NodeState::IDLE; 8];
    let mut exec = Executor::new(tree, &mut state).unwrap();
    let mut seen = Seen::default();
    assert_eq!(exec.tick(&mut seen, 0), Ok(Status::Success));
    assert_eq!(seen.0, [(1, vec![10, 11, 12, 13]), (2, vec![1, 2, 3, 4, 5]), (3, vec![9])]);
    assert_eq!(
        tree.display(&SET).to_string(),
        "{-} Sequence\n    --> at(10, 11, 12, 13)\n    --> drive-truck(1, 2, 3, 4, 5)\n    --> wait(9)\n"
    );
}

#[test]
fn a_leaf_keeps_its_12_bytes_and_reserves_two_inline_values() {
    assert_eq!(size_of::<Node>(), 12);
    assert_eq!(Leaf::with_args(0, &[0xfffe]), Err(LeafError::ReservedValue(0)));
    assert_eq!(Leaf::with_args(0, &[1, 0xffff]), Err(LeafError::ReservedValue(1)));
    assert_eq!(Leaf::extended(0, 0, 3), Err(LeafError::BadRange(3, 0)));
    assert_eq!(Leaf::extended(0, 0xfffe, 4), Err(LeafError::BadRange(4, 0xfffe)));
    let x = Leaf::extended(7, 2, 4).unwrap();
    assert_eq!((x.behavior(), x.argc(), x.range(), x.args()), (7, 4, Some((2, 4)), &[][..]));
    assert_eq!(x.args_in(&[0, 0, 5, 6, 7, 8]), [5, 6, 7, 8]);
    assert_eq!(x.args_in(&[0, 0, 5]), &[] as &[u16], "a range outside the table gives nothing");
    let inline = Leaf::with_values(7, &[1, 2], 0).unwrap();
    assert_eq!((inline.range(), inline.args()), (None, &[1, 2][..]));
    assert_eq!(Leaf::with_values(7, &[1, 2, 3, 4], 6).unwrap(), Leaf::extended(7, 6, 4).unwrap());
}

#[test]
fn validation_checks_ranges_and_arities_of_extended_leaves() {
    let (nodes, values) = sample();
    assert!(Tree::<4>::validate_with(&nodes, &values, &SET).is_ok());
    let out_of_range =
        LoadError::BadArgument { node: 2, fault: ArgumentFault::ValuesOutOfRange { start: 4, len: 5, table: 8 } };
    assert_eq!(Tree::<4>::validate_with(&nodes, &values[..8], &SET), Err(out_of_range));
    // Without a table every extended leaf is out of range.
    assert_eq!(
        Tree::<4>::validate(&nodes, &SET),
        Err(LoadError::BadArgument { node: 1, fault: ArgumentFault::ValuesOutOfRange { start: 0, len: 4, table: 0 } })
    );
    let mut wrong = nodes.clone();
    wrong[2] = Node::new(NodeKind::Action(Leaf::extended(1, 4, 4).unwrap()), 1);
    assert_eq!(
        Tree::<4>::validate_with(&wrong, &values, &SET),
        Err(LoadError::BadArgument { node: 2, fault: ArgumentFault::Count { behavior: 1, expected: 5, found: 4 } })
    );
}

#[test]
fn the_value_table_needs_storage() {
    let (nodes, values) = sample();
    let bytes = image(&ImageParts::new(&nodes).values(&values));
    let mut storage = [Node::EMPTY; 8];
    assert_eq!(load::<_, 4>(&bytes, &SET, &mut storage), Err(LoadError::TooManyValues { count: 9, capacity: 0 }));
    let (mut storage, mut table) = ([Node::EMPTY; 8], [0u16; 8]);
    assert_eq!(
        load_with::<_, 4>(&bytes, &SET, &mut storage, &mut table),
        Err(LoadError::TooManyValues { count: 9, capacity: 8 })
    );
}

#[test]
fn the_names_section_is_carried_and_never_read_by_the_loader() {
    let (nodes, values) = sample();
    let names = b"\xff anything the host wants \x00";
    let bytes = image(&ImageParts::new(&nodes).values(&values).names(names));
    assert_eq!(try_load(&bytes), Ok((nodes.clone(), values.clone())));
    assert_eq!(section(&bytes, SECTION_NAMES), Ok(Some(&names[..])));
    assert_eq!(section(&bytes, SECTION_VALUES).unwrap().map(<[u8]>::len), Some(10));
    let plain = image(&ImageParts::new(&nodes[3..]));
    assert_eq!(section(&plain, SECTION_NAMES), Ok(None));
}

/// The image of `sample` with its sections replaced by `sections`.
fn with_sections(sections: &[u8]) -> (Vec<u8>, usize) {
    let (nodes, values) = sample();
    let full = image(&ImageParts::new(&nodes).values(&values));
    let plain = image(&ImageParts::new(&nodes));
    let at = plain.len() - CRC_LEN;
    let mut b = full[..at].to_vec();
    b.extend_from_slice(sections);
    b.extend_from_slice(&[0; CRC_LEN]);
    (reseal(b), at)
}

#[test]
fn every_section_fault_is_named() {
    let values = [SECTION_VALUES, 10, 9, 10, 11, 12, 13, 1, 2, 3, 4, 5];
    let (b, _) = with_sections(&values);
    assert!(try_load(&b).is_ok());

    let names = [SECTION_NAMES, 1, b'x'];
    let (b, at) = with_sections(&[&names[..], &values[..]].concat());
    assert_eq!(try_load(&b), Err(LoadError::MalformedSection { tag: SECTION_VALUES, offset: at + 3 }), "out of order");
    let (b, at) = with_sections(&[&values[..], &names[..], &names[..]].concat());
    assert_eq!(try_load(&b), Err(LoadError::MalformedSection { tag: SECTION_NAMES, offset: at + 15 }), "repeated");
    let (b, at) = with_sections(&[SECTION_VALUES, 40, 9]);
    assert_eq!(try_load(&b), Err(LoadError::MalformedSection { tag: SECTION_VALUES, offset: at }), "runs past the end");
    let (b, at) = with_sections(&[SECTION_VALUES, 11, 9, 10, 11, 12, 13, 1, 2, 3, 4, 5, 6]);
    assert_eq!(try_load(&b), Err(LoadError::MalformedSection { tag: SECTION_VALUES, offset: at }), "bytes left in it");
    let (b, at) = with_sections(&[SECTION_VALUES, 3, 9, 10, 11]);
    assert_eq!(try_load(&b), Err(LoadError::MalformedSection { tag: SECTION_VALUES, offset: at }), "fewer than said");
    let (b, at) = with_sections(&[SECTION_VALUES, 4, 1, 0xff, 0xff, 0xff]);
    assert_eq!(try_load(&b), Err(LoadError::MalformedSection { tag: SECTION_VALUES, offset: at }), "not a u16");
    let (b, at) = with_sections(&[4, 0]);
    assert_eq!(try_load(&b), Err(LoadError::UnknownSection { tag: 4, offset: at }), "after the ports section");
    let (b, at) = with_sections(&[&values[..], &[200, 0]].concat());
    assert_eq!(try_load(&b), Err(LoadError::UnknownSection { tag: 200, offset: at + values.len() }));
}

#[test]
fn version_1_has_no_extended_leaves() {
    let (nodes, values) = sample();
    let mut b = image(&ImageParts::new(&nodes).values(&values));
    b[4..6].copy_from_slice(&1u16.to_le_bytes());
    // Node 1 is the first extended leaf: its tag (13) did not exist in version 1.
    assert_eq!(try_load(&reseal(b)), Err(LoadError::MalformedNode { node: 1, offset: HEADER_LEN + 2 }));
}

fn arb_tree() -> impl Strategy<Value = (Vec<Node>, Vec<u16>)> {
    // A Sequence of leaves with 0 to 8 values each, behaviors declared to match.
    prop::collection::vec(prop::collection::vec(0u16..0xfffe, 0..9), 1..12).prop_map(|leaves| {
        let mut values = Vec::new();
        let mut nodes = vec![Node::new(NodeKind::Sequence, leaves.len() as u16 + 1)];
        for v in &leaves {
            let leaf = Leaf::with_values(v.len() as u16, v, values.len() as u16).unwrap();
            if leaf.range().is_some() {
                values.extend_from_slice(v);
            }
            nodes.push(Node::new(NodeKind::Action(leaf), 1));
        }
        (nodes, values)
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    /// Trees with any mix of inline and extended leaves come back as they went in.
    #[test]
    fn any_mix_of_inline_and_extended_leaves_round_trips((nodes, values) in arb_tree()) {
        let names: Vec<String> = (0..9).map(|n| format!("a{n}")).collect();
        let set: Vec<BehaviorInfo<'_>> = names.iter().enumerate().map(|(n, s)| BehaviorInfo::action(s, n as u8)).collect();
        let parts = ImageParts::new(&nodes).values(&values);
        let mut out = vec![0u8; parts.max_len()];
        let n = encode_with(&parts, fingerprint(&set), &mut out).unwrap();
        let (mut storage, mut table) = (vec![Node::EMPTY; 16], vec![0u16; 128]);
        let tree: Tree<'_, 4> = load_with(&out[..n], set.as_slice(), &mut storage, &mut table).unwrap();
        prop_assert_eq!(tree.nodes(), &nodes[..]);
        prop_assert_eq!(tree.values(), &values[..]);
    }

    /// Sealed images with arbitrary sections never panic the loader.
    #[test]
    fn arbitrary_sections_never_panic(sections in prop::collection::vec(any::<u8>(), 0..64)) {
        let (b, _) = with_sections(&sections);
        let _ = try_load(&b);
        let _ = section(&b, SECTION_NAMES);
    }
}
