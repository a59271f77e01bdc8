//! Images with a ports section: loaded and checked leaf by leaf, every fault refused.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use bt_core::image::ImageParts;
use bt_core::port::{Constant, PortFault, SlotInfo, UNSET, encode_table};
use bt_core::*;

const MOVE: [PortInfo<'static>; 2] =
    [PortInfo::input("speed", PortType::Double, "double"), PortInfo::output("done", PortType::Bool, "bool")];
const SET: [Behavior<'static>; 1] = [Behavior::new(BehaviorInfo::action("Move", 2), &MOVE)];

fn image(values: [u16; 2], table: &[u8]) -> Vec<u8> {
    let nodes = [Node::new(NodeKind::Action(Leaf::with_args(0, &values).unwrap()), 1)];
    let parts = ImageParts::new(&nodes).ports(table);
    let mut out = vec![0u8; parts.max_len()];
    let n = encode_with(&parts, SET.fingerprint(), &mut out).unwrap();
    out.truncate(n);
    out
}

fn table() -> Vec<u8> {
    let mut t = vec![0u8; 64];
    let n = encode_table(
        &[SlotInfo { ty: PortType::Bool, initial: None }],
        &[Constant::Double(0.25), Constant::Str("x")],
        &mut t,
    )
    .unwrap();
    t.truncate(n);
    t
}

fn load_err(bytes: &[u8]) -> LoadError {
    let mut nodes = [Node::EMPTY; 2];
    load_with_ports::<_, 4>(bytes, &SET, &mut nodes, &mut []).map(|_| ()).unwrap_err()
}

#[test]
fn a_tree_whose_ports_check_loads_and_reads() {
    let bytes = image([0, 0x8000], &table());
    let mut nodes = [Node::EMPTY; 2];
    let (tree, ports): (Tree<'_, 4>, _) = load_with_ports(&bytes, &SET, &mut nodes, &mut []).unwrap();
    let (_, leaf) = tree.nodes()[0].kind().leaf().unwrap();
    assert_eq!(ports.port(tree.args(&leaf), 0).and_then(|p| p.double()), Some(0.25));
    assert_eq!(ports.port(tree.args(&leaf), 1).and_then(|p| p.slot()), Some(0));
    let unset = image([UNSET, UNSET], &table());
    let mut nodes = [Node::EMPTY; 2];
    assert!(load_with_ports::<_, 4>(&unset, &SET, &mut nodes, &mut []).is_ok());
}

#[test]
fn every_port_fault_is_refused_naming_the_leaf() {
    let bad = |values, fault| assert_eq!(load_err(&image(values, &table())), LoadError::BadPort { node: 0, fault });
    bad([2, 0x8000], PortFault::NoSuchConstant { position: 0, index: 2, count: 2 });
    bad([0, 0x8001], PortFault::NoSuchSlot { position: 1, index: 1, count: 1 });
    bad(
        [1, 0x8000],
        PortFault::ConstantType {
            position: 0,
            index: 1,
            expected: port::ConstantKind::Double,
            found: port::ConstantKind::Str,
        },
    );
    bad([0, 0], PortFault::OutputConstant { position: 1 });
    bad([0x8000, 0x8000], PortFault::SlotType { position: 0, index: 0, port: PortType::Double, slot: PortType::Bool });
    // No ports section: a constant names nothing.
    let nodes = [Node::new(NodeKind::Action(Leaf::with_args(0, &[0, UNSET]).unwrap()), 1)];
    let mut out = vec![0u8; 64];
    let n = encode(&nodes, SET.fingerprint(), &mut out).unwrap();
    assert_eq!(
        load_err(&out[..n]),
        LoadError::BadPort { node: 0, fault: PortFault::NoSuchConstant { position: 0, index: 0, count: 0 } }
    );
    // A ports section that does not decode.
    let mut broken = table();
    broken.truncate(broken.len() - 1);
    assert_eq!(load_err(&image([0, 0x8000], &broken)).code(), "malformed-section");
}
