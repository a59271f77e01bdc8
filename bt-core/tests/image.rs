//! The image format: every `LoadError` variant from a corrupted or crafted image, and
//! `load` never panicking on arbitrary bytes.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;

use bt_core::image::{CRC_LEN, HEADER_LEN, MAGIC, VERSION, crc32, max_image_len, read_header};
use bt_core::{
    ArgumentFault, Arity, BehaviorInfo, Builder, Catalog, Executor, Leaf, LeafKind, LoadError, Node, NodeKind,
    NodeState, Status, Tree, encode, fingerprint, load,
};
use proptest::prelude::*;

const SET: [BehaviorInfo<'static>; 4] = [
    BehaviorInfo::condition("at goal?", 0),
    BehaviorInfo::condition("near", 1),
    BehaviorInfo::action("MoveTo", 2),
    BehaviorInfo::action("Place", 0),
];

/// Fallback[ at goal?, Seq[ near(1), MoveTo(1, 2) ], Place ] — 6 nodes.
fn sample(storage: &mut [Node]) -> &[Node] {
    let mut b = Builder::<8>::new(storage);
    b.fallback().unwrap().condition(0, &[]).unwrap();
    b.sequence().unwrap().condition(1, &[1]).unwrap().action(2, &[1, 2]).unwrap().end().unwrap();
    b.action(3, &[]).unwrap().end().unwrap();
    b.finish().unwrap()
}

fn image_of(nodes: &[Node]) -> Vec<u8> {
    let mut out = vec![0u8; max_image_len(nodes.len())];
    let n = encode(nodes, fingerprint(&SET), &mut out).unwrap();
    out.truncate(n);
    out
}

fn good() -> Vec<u8> {
    let mut storage = [Node::EMPTY; 8];
    image_of(sample(&mut storage))
}

/// Recomputes the CRC after crafting, so that the check under test is reached.
fn reseal(mut bytes: Vec<u8>) -> Vec<u8> {
    let n = bytes.len() - CRC_LEN;
    let crc = crc32(&bytes[..n]);
    bytes[n..].copy_from_slice(&crc.to_le_bytes());
    bytes
}

fn try_load(bytes: &[u8]) -> Result<Vec<Node>, LoadError> {
    let mut storage = [Node::EMPTY; 16];
    load::<_, 4>(bytes, &SET, &mut storage).map(|t| t.nodes().to_vec())
}

#[test]
fn a_good_image_round_trips_and_says_what_it_is() {
    let mut storage = [Node::EMPTY; 8];
    let nodes = sample(&mut storage).to_vec();
    let bytes = image_of(&nodes);
    assert_eq!(&bytes[..4], b"BTIM");
    assert_eq!(try_load(&bytes).unwrap(), nodes);
    let h = read_header(&bytes).unwrap();
    // A tree without scripts is written as version 2, which controllers built before
    // scripts load.
    assert_eq!(VERSION, 4);
    assert_eq!((h.version, h.fingerprint, h.node_count, h.len), (2, fingerprint(&SET), 6, bytes.len()));
    // 16 header + 6 nodes + 4 CRC: a handful of bytes per node.
    assert!(bytes.len() <= HEADER_LEN + 6 * 5 + CRC_LEN, "{} bytes", bytes.len());
}

#[test]
fn truncated_envelope() {
    assert_eq!(try_load(&good()[..10]), Err(LoadError::Truncated { len: 10, inside_node: None }));
    assert_eq!(try_load(&[]), Err(LoadError::Truncated { len: 0, inside_node: None }));
}

#[test]
fn truncated_inside_a_node() {
    let mut b = good();
    b.truncate(b.len() - CRC_LEN - 2); // cut the last node short
    b.extend_from_slice(&[0; CRC_LEN]);
    let len = b.len();
    assert_eq!(try_load(&reseal(b)), Err(LoadError::Truncated { len, inside_node: Some(5) }));
}

#[test]
fn bad_magic() {
    let mut b = good();
    b[0] = b'X';
    assert_eq!(try_load(&b), Err(LoadError::BadMagic { found: *b"XTIM" }));
    assert_ne!(MAGIC, *b"XTIM");
}

#[test]
fn unsupported_version() {
    for version in [0u16, 5, 0xffff] {
        let mut b = good();
        b[4..6].copy_from_slice(&version.to_le_bytes());
        assert_eq!(try_load(&b), Err(LoadError::UnsupportedVersion { found: version, supported: 4 }));
    }
    // Versions 3 and 4 only add kinds: a version-2 tree reads the same under them.
    for version in [3u16, 4] {
        let mut b = good();
        b[4..6].copy_from_slice(&version.to_le_bytes());
        assert!(try_load(&reseal(b)).is_ok());
    }
    // Version 1 (no extended leaves, no sections) still loads, as the same tree.
    let mut b = good();
    b[4..6].copy_from_slice(&1u16.to_le_bytes());
    assert_eq!(try_load(&reseal(b)), try_load(&good()));
}

#[test]
fn crc_mismatch_on_any_flipped_bit() {
    let b = good();
    for i in 6..b.len() {
        for bit in 0..8 {
            let mut c = b.clone();
            c[i] ^= 1 << bit;
            assert!(matches!(try_load(&c), Err(LoadError::CrcMismatch { .. })), "byte {i} bit {bit}");
        }
    }
}

#[test]
fn foreign_behavior_set() {
    let other =
        [BehaviorInfo::condition("at goal?", 0), BehaviorInfo::condition("near", 1), BehaviorInfo::action("MoveTo", 1)];
    let mut storage = [Node::EMPTY; 16];
    let err = load::<_, 4>(&good(), other.as_slice(), &mut storage).unwrap_err();
    assert_eq!(err, LoadError::ForeignBehaviorSet { image: fingerprint(&SET), expected: fingerprint(&other) });
}

#[test]
fn too_many_nodes_for_the_storage() {
    let mut storage = [Node::EMPTY; 5];
    assert_eq!(
        load::<_, 4>(&good(), &SET, &mut storage).unwrap_err(),
        LoadError::TooManyNodes { count: 6, capacity: 5 }
    );
}

#[test]
fn malformed_node() {
    let mut b = good();
    b[HEADER_LEN + 1] = 100; // first node's kind tag: there is no kind 100
    assert_eq!(try_load(&reseal(b)), Err(LoadError::MalformedNode { node: 0, offset: HEADER_LEN }));
    // A leaf with four arguments.
    let mut b = good();
    let body: Vec<u8> = vec![1, 11, 0, 4, 1, 2, 3, 4];
    b[14..16].copy_from_slice(&1u16.to_le_bytes());
    b.splice(HEADER_LEN..b.len() - CRC_LEN, body);
    assert_eq!(try_load(&reseal(b)), Err(LoadError::MalformedNode { node: 0, offset: HEADER_LEN }));
}

#[test]
fn trailing_bytes() {
    // Version 1 has no sections: any byte after the last node is one too many.
    let mut b = good();
    b[4..6].copy_from_slice(&1u16.to_le_bytes());
    let at = b.len() - CRC_LEN;
    b.splice(at..at, [1, 0, 0]);
    assert_eq!(try_load(&reseal(b)), Err(LoadError::TrailingBytes { count: 3 }));
    // In version 2 they are read as a section, here one with tag 0, which does not exist.
    let mut b = good();
    let at = b.len() - CRC_LEN;
    b.splice(at..at, [0, 0, 0]);
    assert_eq!(try_load(&reseal(b)), Err(LoadError::UnknownSection { tag: 0, offset: at }));
}

#[test]
fn empty_tree() {
    let mut b = good();
    b[14..16].copy_from_slice(&0u16.to_le_bytes());
    let end = b.len() - CRC_LEN;
    b.drain(HEADER_LEN..end);
    assert_eq!(try_load(&reseal(b)), Err(LoadError::EmptyTree));
}

fn crafted(nodes: &[Node]) -> Result<Vec<Node>, LoadError> {
    try_load(&image_of(nodes))
}

fn leaf(kind: LeafKind, behavior: u16, args: &[u16]) -> Node {
    let l = Leaf::with_args(behavior, args).unwrap();
    Node::new(if kind == LeafKind::Condition { NodeKind::Condition(l) } else { NodeKind::Action(l) }, 1)
}

fn at_goal() -> Node {
    leaf(LeafKind::Condition, 0, &[])
}

#[test]
fn subtree_sizes_inconsistent() {
    // Root claims 3 nodes, array has 2.
    let nodes = [Node::new(NodeKind::Sequence, 3), at_goal()];
    assert_eq!(crafted(&nodes), Err(LoadError::SubtreeSizeInconsistent { node: 0, size: 3 }));
    // A child sticking out of its parent.
    let nodes = [
        Node::new(NodeKind::Sequence, 4),
        Node::new(NodeKind::Inverter, 2),
        Node::new(NodeKind::Sequence, 2),
        at_goal(),
    ];
    assert_eq!(crafted(&nodes), Err(LoadError::SubtreeSizeInconsistent { node: 2, size: 2 }));
    // Size zero.
    let nodes = [Node::new(NodeKind::Sequence, 2), Node::new(NodeKind::Condition(Leaf::new(0)), 0)];
    assert_eq!(crafted(&nodes), Err(LoadError::SubtreeSizeInconsistent { node: 1, size: 0 }));
}

#[test]
fn wrong_arity_for_a_kind() {
    let two = [Node::new(NodeKind::Inverter, 3), at_goal(), at_goal()];
    assert_eq!(
        crafted(&two),
        Err(LoadError::WrongArity { node: 0, kind: "Inverter", children: 2, expected: Arity::One })
    );
    let none = [Node::new(NodeKind::Sequence, 2), Node::new(NodeKind::Fallback, 1)];
    assert_eq!(
        crafted(&none),
        Err(LoadError::WrongArity { node: 1, kind: "Fallback", children: 0, expected: Arity::AtLeastOne })
    );
    let parent_leaf = [Node::new(NodeKind::Condition(Leaf::new(0)), 2), at_goal()];
    assert_eq!(
        crafted(&parent_leaf),
        Err(LoadError::WrongArity { node: 0, kind: "Condition", children: 1, expected: Arity::Leaf })
    );
}

#[test]
fn depth_over_limit() {
    // Inverter^4 over a leaf: 5 levels, the loader allows 4.
    let mut nodes: Vec<Node> = (0..4).map(|i| Node::new(NodeKind::Inverter, 5 - i)).collect();
    nodes.push(at_goal());
    assert_eq!(crafted(&nodes), Err(LoadError::DepthOverLimit { node: 4, limit: 4 }));
    nodes.remove(0);
    assert!(crafted(&nodes).is_ok());
}

#[test]
fn unknown_behavior_id() {
    let nodes = [leaf(LeafKind::Action, 9, &[])];
    assert_eq!(crafted(&nodes), Err(LoadError::UnknownBehavior { node: 0, behavior: 9 }));
}

#[test]
fn wrong_leaf_kind() {
    let nodes = [leaf(LeafKind::Action, 0, &[])];
    assert_eq!(crafted(&nodes), Err(LoadError::WrongLeafKind { node: 0, behavior: 0, declared: LeafKind::Condition }));
}

#[test]
fn bad_arguments() {
    let nodes = [leaf(LeafKind::Action, 2, &[1])];
    assert_eq!(
        crafted(&nodes),
        Err(LoadError::BadArgument { node: 0, fault: ArgumentFault::Count { behavior: 2, expected: 2, found: 1 } })
    );
    let nodes = [Node::new(NodeKind::Repeat(0), 2), at_goal()];
    assert_eq!(
        crafted(&nodes),
        Err(LoadError::BadArgument { node: 0, fault: ArgumentFault::ZeroCount { kind: "Repeat" } })
    );
    let nodes = [
        Node::new(NodeKind::Parallel { success_threshold: 3, failure_threshold: 1, count_skipped: false }, 3),
        at_goal(),
        at_goal(),
    ];
    assert_eq!(
        crafted(&nodes),
        Err(LoadError::BadArgument {
            node: 0,
            fault: ArgumentFault::Threshold { which: "success", threshold: 3, children: 2 }
        })
    );
    // An argument of 65535 (reserved) can only come from crafted bytes.
    let mut b = good();
    let body: Vec<u8> = vec![1, 11, 1, 1, 0xff, 0xff, 0x03];
    b[14..16].copy_from_slice(&1u16.to_le_bytes());
    b.splice(HEADER_LEN..b.len() - CRC_LEN, body);
    assert_eq!(
        try_load(&reseal(b)),
        Err(LoadError::BadArgument { node: 0, fault: ArgumentFault::Reserved { position: 0 } })
    );
}

#[test]
fn every_error_reads_as_a_sentence() {
    let errors = [
        LoadError::Truncated { len: 3, inside_node: None },
        LoadError::Truncated { len: 30, inside_node: Some(2) },
        LoadError::BadMagic { found: *b"GIF8" },
        LoadError::UnsupportedVersion { found: 9, supported: 2 },
        LoadError::CrcMismatch { stored: 1, computed: 2 },
        LoadError::ForeignBehaviorSet { image: 1, expected: 2 },
        LoadError::TooManyNodes { count: 70, capacity: 64 },
        LoadError::MalformedNode { node: 3, offset: 40 },
        LoadError::TrailingBytes { count: 2 },
        LoadError::UnknownSection { tag: 9, offset: 60 },
        LoadError::MalformedSection { tag: 1, offset: 60 },
        LoadError::TooManyValues { count: 9, capacity: 4 },
        LoadError::EmptyTree,
        LoadError::SubtreeSizeInconsistent { node: 1, size: 9 },
        LoadError::WrongArity { node: 1, kind: "Inverter", children: 2, expected: Arity::One },
        LoadError::DepthOverLimit { node: 7, limit: 4 },
        LoadError::UnknownBehavior { node: 1, behavior: 99 },
        LoadError::WrongLeafKind { node: 1, behavior: 0, declared: LeafKind::Condition },
        LoadError::BadArgument { node: 1, fault: ArgumentFault::ZeroCount { kind: "Retry" } },
        LoadError::BadArgument { node: 1, fault: ArgumentFault::ValuesOutOfRange { start: 4, len: 5, table: 6 } },
    ];
    let text: Vec<String> = errors.iter().map(ToString::to_string).collect();
    insta_like(&text);

    // The short codes: one per variant, kebab-case, and the node where there is one.
    let codes: Vec<&str> = errors.iter().map(LoadError::code).collect();
    let mut distinct = codes.clone();
    distinct.dedup(); // the two `Truncated` are adjacent
    distinct.sort_unstable();
    distinct.dedup();
    assert_eq!(distinct.len(), errors.len() - 2, "{codes:?}"); // two Truncated, two BadArgument
    assert!(codes.iter().all(|c| c.bytes().all(|b| b.is_ascii_lowercase() || b == b'-')), "{codes:?}");
    assert_eq!(codes[4], "crc-mismatch");
    let nodes: Vec<Option<u16>> = errors.iter().map(LoadError::node).collect();
    assert_eq!(
        nodes,
        [
            None,
            Some(2),
            None,
            None,
            None,
            None,
            None,
            Some(3),
            None,
            None,
            None,
            None,
            None,
            Some(1),
            Some(1),
            Some(7),
            Some(1),
            Some(1),
            Some(1),
            Some(1)
        ]
    );
}

fn insta_like(lines: &[String]) {
    let expected = [
        "image truncated: 3 bytes, shorter than the 20 bytes of header and CRC",
        "image truncated: 30 bytes, the payload ends inside node 2",
        "not a behavior-tree image: starts with [47, 49, 46, 38], expected [42, 54, 49, 4d] (\"BTIM\")",
        "image format version 9 is not supported (this build reads versions 1 to 2)",
        "image corrupted: stored CRC-32 0x00000001, computed 0x00000002",
        "image built for behavior set 0x0000000000000001, this controller has 0x0000000000000002",
        "tree has 70 nodes, capacity is 64",
        "node 3 is malformed (bytes from offset 40 do not decode as a node)",
        "2 unexpected bytes after the last node",
        "unknown section 9 at offset 60",
        "section 1 at offset 60 is malformed",
        "value table has 9 entries, capacity is 4",
        "the tree has no nodes",
        "node 1 claims a subtree of 9 nodes, which does not fit inside its parent",
        "node 1 (Inverter) has 2 children; a decorator has exactly one",
        "node 7 is deeper than the limit of 4 levels",
        "node 1 uses behavior 99, which the behavior set does not have",
        "node 1 uses behavior 0 as an action, but it is declared as a condition",
        "node 1: `Retry(0)`: a Retry must allow at least 1 attempt",
        "node 1: the leaf's values 4..+5 lie outside the value table of 6 entries",
    ];
    assert_eq!(lines, expected);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(5_000))]

    /// Arbitrary bytes never panic the loader.
    #[test]
    fn load_never_panics_on_arbitrary_bytes(bytes in prop::collection::vec(any::<u8>(), 0..300)) {
        let _ = try_load(&bytes);
    }

    /// Valid envelopes (good magic, version and CRC) around arbitrary payloads reach the
    /// decoder and validator, which must not panic either; whatever loads can be ticked.
    #[test]
    fn sealed_garbage_never_panics_and_what_loads_runs(count in 0u16..20, payload in prop::collection::vec(any::<u8>(), 0..200)) {
        let mut b = Vec::new();
        b.extend_from_slice(&MAGIC);
        b.extend_from_slice(&VERSION.to_le_bytes());
        b.extend_from_slice(&fingerprint(&SET).to_le_bytes());
        b.extend_from_slice(&count.to_le_bytes());
        b.extend_from_slice(&payload);
        b.extend_from_slice(&[0; CRC_LEN]);
        let b = reseal(b);
        let mut storage = [Node::EMPTY; 32];
        if let Ok(tree) = load::<_, 8>(&b, &SET, &mut storage) {
            let mut state = [NodeState::IDLE; 32];
            let mut exec = Executor::new(tree, &mut state).unwrap();
            let mut w = Always(Status::Running);
            for t in 0..3 { exec.tick(&mut w, t).unwrap(); }
            exec.halt_all(&mut w);
        }
    }

    /// Flipping any byte or cutting the image anywhere gives an error, never a panic.
    #[test]
    fn mutated_images_are_refused(at in 0usize..60, xor in 1u8..=255, cut in 0usize..60) {
        let g = good();
        let mut flipped = g.clone();
        let i = at % g.len();
        flipped[i] ^= xor;
        prop_assert!(try_load(&flipped).is_err());
        let c = cut % g.len();
        prop_assert!(try_load(&g[..c]).is_err());
    }
}

struct Always(Status);
impl bt_core::BehaviorSet for Always {
    fn condition(&mut self, _: &Leaf, _: bt_core::Context<'_>) -> Status {
        Status::Failure
    }
    fn action(&mut self, _: &Leaf, _: bt_core::Context<'_>) -> Status {
        self.0
    }
    fn halt(&mut self, _: &Leaf, _: bt_core::NodeId) {}
}

#[test]
fn fingerprint_is_stable_and_sensitive() {
    // Pinned: host and controller compute it independently; changing it breaks images.
    assert_eq!(fingerprint(&SET), SET.as_slice().fingerprint());
    assert_eq!(format!("{:#018x}", fingerprint(&SET)), PINNED);
    let mut renamed = SET;
    renamed[1].name = "close";
    let mut arity = SET;
    arity[1].arity = 2;
    let mut kind = SET;
    kind[3].kind = LeafKind::Condition;
    let mut swapped = SET;
    swapped.swap(0, 1);
    for other in [renamed, arity, kind, swapped] {
        assert_ne!(fingerprint(&other), fingerprint(&SET));
    }
    assert_ne!(fingerprint(&SET[..3]), fingerprint(&SET));
}

// Computed independently of this crate, by FNV-1a in a few lines of Python over the
// byte layout that `fingerprint` documents.
const PINNED: &str = "0xb4a2c5a96767098b";

#[test]
fn validate_accepts_what_the_builder_makes() {
    let mut storage = [Node::EMPTY; 8];
    let nodes = sample(&mut storage);
    let tree = Tree::<4>::validate(nodes, &SET).unwrap();
    assert_eq!((tree.len(), tree.depth()), (6, 3));
    assert_eq!(tree.children(0).collect::<Vec<_>>(), [1, 2, 5]);
    assert_eq!(tree.parent(4), Some(2));
    assert_eq!(tree.parent(0), None);
    assert_eq!(Tree::<2>::validate(nodes, &SET), Err(LoadError::DepthOverLimit { node: 3, limit: 2 }));
    assert_eq!(Tree::<4>::validate(&[], &SET), Err(LoadError::EmptyTree));
}

#[test]
fn counts_of_one_are_singular() {
    use bt_core::{ArgumentFault, LoadError};
    assert_eq!(LoadError::TrailingBytes { count: 1 }.to_string(), "1 unexpected byte after the last node");
    assert_eq!(
        LoadError::Truncated { len: 1, inside_node: None }.to_string(),
        "image truncated: 1 byte, shorter than the 20 bytes of header and CRC"
    );
    assert_eq!(
        LoadError::SubtreeSizeInconsistent { node: 0, size: 1 }.to_string(),
        "node 0 claims a subtree of 1 node, which does not fit inside its parent"
    );
    let zero = |kind| LoadError::BadArgument { node: 2, fault: ArgumentFault::ZeroCount { kind } }.to_string();
    assert_eq!(zero("Timeout"), "node 2: `Timeout(0)`: a timeout must allow at least 1 tick");
    assert_eq!(zero("Repeat"), "node 2: `Repeat(0)`: a Repeat must run its child at least once");
    assert_eq!(
        ArgumentFault::Count { behavior: 3, expected: 1, found: 0 }.to_string(),
        "behavior 3 takes 1 argument, the leaf has 0"
    );
    assert_eq!(
        bt_core::StateTooSmall { needed: 1, given: 0 }.to_string(),
        "state array holds 0 entries, the tree has 1 node"
    );
}

/// A `ManualSelector` is tag 40 with one byte, `repeat_last_selection`, in version 3;
/// with no children too. A version-2 image cannot hold it.
#[test]
fn a_manual_selector_is_tag_40_of_version_3() {
    for (repeat_last, byte) in [(false, 0u8), (true, 1)] {
        let mut storage = [Node::EMPTY; 4];
        let mut b = Builder::<4>::new(&mut storage);
        b.open(NodeKind::ManualSelector { repeat_last }).unwrap().condition(0, &[]).unwrap().end().unwrap();
        let nodes = b.finish().unwrap().to_vec();
        let bytes = image_of(&nodes);
        assert_eq!(read_header(&bytes).unwrap().version, 3);
        // Size 2, tag 40, the flag; then the condition.
        assert_eq!(bytes[HEADER_LEN..HEADER_LEN + 3], [2, 40, byte]);
        assert_eq!(try_load(&bytes).unwrap(), nodes);
        let mut v2 = bytes.clone();
        v2[4..6].copy_from_slice(&2u16.to_le_bytes());
        assert_eq!(try_load(&reseal(v2)), Err(LoadError::MalformedNode { node: 0, offset: HEADER_LEN }));
        // A flag byte other than 0 or 1 is no ManualSelector.
        let mut bad = bytes.clone();
        bad[HEADER_LEN + 2] = 2;
        assert_eq!(try_load(&reseal(bad)), Err(LoadError::MalformedNode { node: 0, offset: HEADER_LEN }));
    }
    let lone = [Node::new(NodeKind::ManualSelector { repeat_last: false }, 1)];
    assert_eq!(try_load(&image_of(&lone)).unwrap(), lone);
}

/// The kinds of BehaviorTree.CPP 3 are tags 41 to 44 of version 4, and a span that never
/// expires makes an image version 4 too: a version-3 image holds neither, so a loader
/// of version 3 refuses such an image by its version.
#[test]
fn the_kinds_of_behaviortree_cpp_3_are_tags_41_to_44_of_version_4() {
    let code = bt_core::Code { start: 0, len: 1 };
    let cases: [(NodeKind, &[u8]); 5] = [
        (NodeKind::SequenceStarV3, &[2, 41]),
        (NodeKind::ParallelV3 { success_threshold: 1, failure_threshold: 1 }, &[2, 42, 1, 1]),
        (NodeKind::Cycles { count: 3, from_slot: false, retry: true, v3: true }, &[2, 43, 3, 6]),
        (NodeKind::Check { code, otherwise: Status::Running }, &[2, 44, 0, 1, 2]),
        (NodeKind::RateController(bt_core::Span::NEVER), &[2, 28, 0xff, 0xff, 3, 0xff, 0xff, 3]),
    ];
    for (kind, wire) in cases {
        let nodes = [Node::new(kind, 2), Node::new(NodeKind::Condition(Leaf::new(0)), 1)];
        let parts = bt_core::image::ImageParts::new(&nodes).values(&[bt_core::script::op::INT]);
        let mut buf = [0u8; 128];
        let len = bt_core::image::encode_with(&parts, fingerprint(&SET), &mut buf).unwrap();
        let bytes = buf[..len].to_vec();
        assert_eq!(read_header(&bytes).unwrap().version, 4, "{kind:?}");
        assert_eq!(&bytes[HEADER_LEN..HEADER_LEN + wire.len()], wire, "{kind:?}");
        let mut v3 = bytes.clone();
        v3[4..6].copy_from_slice(&3u16.to_le_bytes());
        assert!(matches!(try_load(&reseal(v3)), Err(LoadError::MalformedNode { node: 0, .. })), "{kind:?}");
    }
    // Flags beyond the three a Cycles has are no Cycles.
    let nodes = [
        Node::new(NodeKind::Cycles { count: 3, from_slot: false, retry: false, v3: false }, 2),
        Node::new(NodeKind::Condition(Leaf::new(0)), 1),
    ];
    let mut bytes = image_of(&nodes);
    assert_eq!(try_load(&bytes).unwrap(), nodes);
    bytes[HEADER_LEN + 3] = 8;
    assert_eq!(try_load(&reseal(bytes)), Err(LoadError::MalformedNode { node: 0, offset: HEADER_LEN }));
}
