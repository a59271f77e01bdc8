//! The table is consistent: what an entry reads, it writes back, under its own ID and
//! shape, reading only the ports it declares.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::cell::RefCell;
use std::path::Path;

use bt_core::{Code, NodeKind};

use super::*;
use crate::error::Location;

/// A node with the given attributes and children; scripts compile to nothing.
struct Stub {
    entry: &'static Entry,
    attrs: Vec<(&'static str, String)>,
    children: usize,
    at: Location,
    /// Ports asked for that the entry does not declare.
    undeclared: RefCell<Vec<String>>,
}

impl Stub {
    fn new(entry: &'static Entry, attrs: Vec<(&'static str, String)>, children: usize) -> Self {
        let at = Location { file: Path::new("t.xml").into(), line: 1, column: 1 };
        Self { entry, attrs, children, at, undeclared: RefCell::new(Vec::new()) }
    }

    fn check(&self, port: &str) {
        if self.entry.port(port).is_none() {
            self.undeclared.borrow_mut().push(port.to_string());
        }
    }
}

impl Params for Stub {
    fn id(&self) -> &str {
        self.entry.id
    }

    fn at(&self) -> &Location {
        &self.at
    }

    fn children(&self) -> usize {
        self.children
    }

    fn attr(&self, port: &str) -> Option<(&str, &Location)> {
        self.check(port);
        self.attrs.iter().find(|(p, _)| *p == port).map(|(_, v)| (v.as_str(), &self.at))
    }

    fn text(&self, port: &str) -> Result<Option<(String, Location)>> {
        self.check(port);
        let given = self.attrs.iter().find(|(p, _)| *p == port).map(|(_, v)| v.clone());
        let default = self.entry.port(port).and_then(|p| p.default).map(str::to_string);
        Ok(given.or(default).map(|v| (v, self.at.clone())))
    }

    fn set_blackboard(&mut self) -> Result<Code> {
        self.check("value");
        self.check("output_key");
        Ok(Code { start: 0, len: 1 })
    }

    fn script(&mut self, port: &'static str) -> Result<Code> {
        self.check(port);
        Ok(Code { start: 0, len: 1 })
    }

    fn count_slot(&mut self, port: &'static str) -> Result<Option<u16>> {
        self.check(port);
        Ok(None)
    }

    fn comparison(&mut self, _: Compared) -> Result<Code> {
        self.check("value_A");
        self.check("value_B");
        Ok(Code { start: 0, len: 1 })
    }
}

/// A value for each port without a default, as a document would give it.
fn required(entry: &Entry) -> Vec<(&'static str, String)> {
    entry
        .ports
        .iter()
        .filter(|p| p.default.is_none() && p.name != "wrap_around")
        .map(|p| {
            let v = match p.name {
                "if" | "code" => "x := 1",
                name if name.ends_with("threshold") => "1",
                _ => "5",
            };
            (p.name, v.to_string())
        })
        .collect()
}

fn children(entry: &Entry) -> usize {
    match entry.shape {
        Shape::Leaf => 0,
        Shape::Decorator => 1,
        Shape::Two => 2,
        Shape::TwoOrThree | Shape::Control | Shape::AnyNumber => 3,
    }
}

#[test]
fn every_kind_read_is_written_back_by_its_entry() {
    let mut read = 0;
    for entry in TABLE.iter().chain(TABLE_V3) {
        let n = children(entry);
        let kind = match entry.map {
            Map::Refused(_) | Map::Loop(_) => continue,
            Map::Plain(kind, _) => kind,
            Map::Params { read, .. } => {
                let mut stub = Stub::new(entry, required(entry), n);
                let kind = read(&mut stub).unwrap_or_else(|e| panic!("{}: {e}", entry.id));
                assert_eq!(stub.undeclared.borrow().as_slice(), [] as [String; 0], "{}", entry.id);
                kind
            }
        };
        read += 1;
        assert_eq!(Shape::of(&kind), entry.shape, "{}", entry.id);
        let (back, written) =
            written_as(&kind, n, Some(entry.id)).unwrap_or_else(|| panic!("{}: {kind:?} is not written", entry.id));
        assert_eq!(back.id, entry.id);
        // Its parameters, read again, give the same kind.
        if let Map::Params { read, .. } = entry.map {
            let mut stub = Stub::new(entry, written.params.clone(), n);
            if entry.takes_scripts() {
                stub.attrs.extend(required(entry).into_iter().filter(|(p, _)| *p == "if" || *p == "code"));
            }
            assert_eq!(read(&mut stub).unwrap(), kind, "{}", entry.id);
        }
    }
    assert_eq!(read, 40);
}

#[test]
fn loops_are_found_by_element_and_id() {
    for entry in TABLE {
        if let Map::Loop(element) = entry.map {
            assert_eq!(loop_entry(element).unwrap().id, entry.id);
            assert_eq!(loop_element(entry.id), Some(element));
            assert_eq!(entry.shape, Shape::Decorator);
        }
    }
    assert!(loop_entry(Element::Registered).is_none());
}

#[test]
fn ids_are_distinct_per_version_and_each_version_reads_its_own() {
    for table in [TABLE, TABLE_V3] {
        let mut ids: Vec<&str> =
            table.iter().flat_map(|e| std::iter::once(e.id).chain(e.aliases.iter().copied())).collect();
        let all = ids.len();
        ids.sort_unstable();
        ids.dedup();
        assert_eq!(ids.len(), all);
    }
    use crate::xml::document::Version::{V3, V4};
    // BehaviorTree.CPP 4 reads `SequenceStar` as its SequenceWithMemory; 3.8 has its own.
    assert!(matches!(by_id_in("SequenceStar", V3).unwrap().map, Map::Plain(NodeKind::SequenceStarV3, _)));
    assert!(matches!(by_id_in("SequenceStar", V4).unwrap().map, Map::Plain(NodeKind::SequenceStar, _)));
    // The misspelt Retry of 3.5 and 3.6 is read in version 3 documents only.
    assert_eq!(by_id_in("RetryUntilSuccesful", V3).unwrap().id, "RetryUntilSuccessful");
    assert!(by_id("RetryUntilSuccesful").is_none());
    // Version 4's nodes are not read in version 3 documents, nor 3's in 4's.
    assert!(by_id_in("Script", V3).is_none() && by_id_in("BlackboardCheckInt", V4).is_none());
    assert_eq!(by_id_in("Parallel", V3).unwrap().ports[0].name, "success_threshold");
    assert_eq!(nav2_controls(), "PipelineSequence, RecoveryNode and RoundRobin");
}

#[test]
fn tick_counting_kinds_and_gates_have_no_node_type() {
    for kind in [NodeKind::Repeat(2), NodeKind::Retry(2), NodeKind::Timeout(2), NodeKind::Gate(bt_core::Leaf::new(0))] {
        assert!(written(&kind, 1).is_none(), "{kind:?}");
    }
}
