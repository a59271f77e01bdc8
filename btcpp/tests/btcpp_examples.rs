//! BehaviorTree.CPP's own example and test trees: each imports, or is refused for the
//! reason listed.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;

use btcpp::xml::{ImportOptions, import, import_text};

/// (file, main tree when the program names it, expected: `Ok(nodes)` or the refusal).
const EXPECTED: &[(&str, Option<&str>, Result<usize, &str>)] = &[
    ("ex01_wrap_legacy.xml", None, Ok(1)),
    ("ex02_runtime_ports.xml", None, Ok(3)),
    ("ex03_ncurses_manual_selector.xml", None, Err("`ManualSelector` is neither")),
    ("ex03_sqlite_log.xml", Some("MainTree"), Ok(13)),
    ("t01_build_your_first_tree.xml", None, Ok(5)),
    ("t02_basic_ports.xml", None, Ok(5)),
    ("t03_generic_ports.xml", None, Ok(5)),
    ("t04_reactive_sequence.xml", None, Ok(5)),
    ("t04_reactive_sequence_1.xml", None, Ok(6)),
    ("t05_crossdoor.xml", Some("MainTree"), Ok(10)),
    ("t06_subtree_port_remapping.xml", Some("MainTree"), Ok(9)),
    // The program registers SubA and SubB from other strings.
    ("t07_load_multiple_xml.xml", None, Err("no <BehaviorTree ID=\"SubA\">")),
    ("t07_load_multiple_xml_1.xml", None, Ok(1)),
    ("t07_load_multiple_xml_2.xml", None, Ok(1)),
    ("t08_additional_node_args.xml", None, Ok(3)),
    // With the enums its program registers (see below).
    ("t09_scripting.xml", None, Ok(9)),
    ("t10_observer.xml", Some("MainTree"), Ok(8)),
    ("t11_groot_howto.xml", Some("MainTree"), Ok(13)),
    ("t12_default_ports.xml", None, Ok(1)),
    ("t13_access_by_ref.xml", None, Ok(4)),
    ("t14_subtree_model.xml", None, Ok(3)),
    // The program loads MySub from t14_subtree_model.xml.
    ("t14_subtree_model_1.xml", None, Err("no <BehaviorTree ID=\"MySub\">")),
    ("t15_nodes_mocking.xml", Some("MainTree"), Ok(11)),
    ("t15_nodes_mocking_strict_failure.xml", Some("MainTree"), Ok(12)),
    // This example's PrintNumber has a port `val`; t02's and others' `value`.
    ("t16_global_blackboard.xml", Some("MainTree"), Err("<PrintNumber> has no port `val`")),
    ("t17_blackboard_backup.xml", Some("MainTree"), Ok(10)),
    ("t18_waypoints.xml", None, Err("<LoopDouble> is not supported")),
    // A polymorphic cast (Cat to Animal) registered in C++.
    ("t19_polymorphic_ports.xml", None, Err("blackboard key `pet` is used as Animal::Ptr here and as Cat::Ptr")),
    ("test_files/Check.xml", None, Ok(3)),
    ("test_files/log_test.xml", Some("Main"), Ok(7)),
    ("test_files/subtree_test.xml", Some("BehaviorTree"), Ok(5)),
    ("trees/parent_no_include.xml", None, Ok(1)),
    ("trees/parent_include_child.xml", None, Ok(3)),
    ("trees/parent_include_child_include_child.xml", None, Ok(5)),
    ("trees/parent_include_child_include_parent.xml", None, Ok(5)),
    ("trees/parent_include_child_include_sibling.xml", None, Ok(5)),
];

#[test]
fn behaviortree_cpp_examples_import_or_are_refused_for_their_reason() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/btcpp-examples");
    for &(file, main, expected) in EXPECTED {
        // t09's program registers Color { RED = 1, BLUE = 2, GREEN = 3 } and THE_ANSWER = 42.
        let enums = if file == "t09_scripting.xml" {
            [("RED", 1), ("BLUE", 2), ("GREEN", 3), ("THE_ANSWER", 42)].map(|(n, v)| (n.to_string(), v)).to_vec()
        } else {
            vec![]
        };
        let options = ImportOptions {
            models: vec![dir.join("example_nodes.xml")],
            main: main.map(str::to_string),
            enums,
            known: None,
        };
        match (import(&dir.join(file), &options), expected) {
            (Ok(i), Ok(nodes)) => {
                assert_eq!(i.nodes.len(), nodes, "{file}");
                // Its XML (scripts written as the document wrote them) imports as the same image.
                let xml = i.to_xml().unwrap_or_else(|e| panic!("{file}: {e}"));
                let again = import_text(&dir.join(file), &xml, &ImportOptions { models: vec![], ..options.clone() })
                    .unwrap_or_else(|e| panic!("{file}: its XML: {e}\n{xml}"));
                assert_eq!(again.image().unwrap(), i.image().unwrap(), "{file}: its XML gives another image");
            }
            (Err(e), Err(why)) => assert!(e.to_string().contains(why), "{file}: {e}"),
            (Ok(i), Err(why)) => panic!("{file}: imported {} nodes, expected the refusal {why}", i.nodes.len()),
            (Err(e), Ok(_)) => panic!("{file}: {e}"),
        }
    }
}
