//! What a catalog says about a leaf's values: names for display apart from declared
//! ports (which alone the fingerprint covers), values read back, ports written
//! `name=value` with unset ones left out.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use bt_core::port::{SLOT_BASE, UNSET};
use bt_core::*;

const SET: [BehaviorInfo<'static>; 2] = [BehaviorInfo::condition("at", 2), BehaviorInfo::action("MoveTo", 1)];

/// The same set, its parameters named for display.
struct Named;

impl Catalog for Named {
    fn len(&self) -> usize {
        SET.len()
    }

    fn info(&self, id: BehaviorId) -> Option<BehaviorInfo<'_>> {
        SET.get(usize::from(id)).copied()
    }

    fn port_name(&self, id: BehaviorId, position: usize) -> Option<&str> {
        [["x", "place"], ["goal", ""]].get(usize::from(id))?.get(position).copied()
    }
}

/// A leaf of `behavior` with `values`, as `catalog` writes it.
fn shown<C: Catalog + ?Sized>(catalog: &C, behavior: BehaviorId, values: &[u16]) -> String {
    render::display_leaf(catalog, &Leaf::with_args(behavior, values).unwrap(), values).to_string()
}

#[test]
fn names_for_display_change_neither_the_fingerprint_nor_the_leaves() {
    assert_eq!(Named.fingerprint(), fingerprint(&SET));
    assert_eq!(Named.port_name(0, 1), Some("place"));
    assert_eq!(SET[..].port_name(0, 1), None);
    assert_eq!(shown(&Named, 0, &[3, 4]), "at(3, 4)");
    assert_eq!(Named.parse_arg(0, 0, "3"), Some(3));
    assert_eq!(Named.parse_arg(0, 0, "cube"), None);
}

#[test]
fn declared_ports_are_named_and_unset_ones_left_out() {
    const PORTS: [PortInfo<'static>; 3] = [
        PortInfo::input("goal", PortType::Other, "Pose"),
        PortInfo::input("speed", PortType::Double, "double"),
        PortInfo::output("path", PortType::Other, "Path"),
    ];
    let set = [Behavior::new(BehaviorInfo::action("Plan", 3), &PORTS)];
    assert_eq!(set[..].port_name(0, 2), Some("path"));
    assert_eq!(set[..].fingerprint(), fingerprint_with_ports(&set));
    let values = [SLOT_BASE, UNSET, SLOT_BASE + 1];
    assert_eq!(shown(&set[..], 0, &values), "Plan(goal=32768, path=32769)");
    assert_eq!(shown(&set[..], 0, &[UNSET; 3]), "Plan");
}
