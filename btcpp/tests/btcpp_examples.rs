//! BehaviorTree.CPP's own example and test trees: each imports, or is refused for the
//! reason listed.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;

use btcpp::xml::{ImportOptions, import, import_text};

/// (file, main tree when the program names it, expected: `Ok(nodes)` or the refusal).
const EXPECTED: &[(&str, Option<&str>, Result<usize, &str>)] = &[
    ("ex01_wrap_legacy.xml", None, Ok(1)),
    ("ex02_runtime_ports.xml", None, Ok(3)),
    // Its operator's choices come from the behavior set (BehaviorSet::select).
    ("ex03_ncurses_manual_selector.xml", None, Ok(7)),
    ("ex03_sqlite_log.xml", Some("MainTree"), Ok(13)),
    ("t01_build_your_first_tree.xml", None, Ok(5)),
    ("t02_basic_ports.xml", None, Ok(5)),
    ("t03_generic_ports.xml", None, Ok(5)),
    ("t04_reactive_sequence.xml", None, Ok(5)),
    ("t04_reactive_sequence_1.xml", None, Ok(6)),
    ("t05_crossdoor.xml", Some("MainTree"), Ok(10)),
    ("t06_subtree_port_remapping.xml", Some("MainTree"), Ok(9)),
    // With the two documents its program registers first (see below).
    ("t07_load_multiple_xml.xml", None, Ok(4)),
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
    // With t14_subtree_model.xml, where its program loads MySub from.
    ("t14_subtree_model_1.xml", None, Ok(6)),
    ("t15_nodes_mocking.xml", Some("MainTree"), Ok(11)),
    ("t15_nodes_mocking_strict_failure.xml", Some("MainTree"), Ok(12)),
    // With its program's own PrintNumber (port `val`; the others' has `value`).
    ("t16_global_blackboard.xml", Some("MainTree"), Ok(5)),
    ("t17_blackboard_backup.xml", Some("MainTree"), Ok(10)),
    // With the LoopNode<Pose2D> its program registers (see below).
    ("t18_waypoints.xml", None, Ok(6)),
    // With the polymorphic casts its program registers (see below).
    ("t19_polymorphic_ports.xml", None, Ok(5)),
    // No BTCPP_format: read as BehaviorTree.CPP 3, which has no SequenceWithMemory.
    (
        "test_files/Check.xml",
        None,
        Err(
            "it is a node type of BehaviorTree.CPP 4, and the document is read as BehaviorTree.CPP 3 (it has no BTCPP_format=\"4\"",
        ),
    ),
    ("test_files/log_test.xml", Some("Main"), Ok(7)),
    ("test_files/subtree_test.xml", Some("BehaviorTree"), Ok(5)),
    ("trees/parent_no_include.xml", None, Ok(1)),
    ("trees/parent_include_child.xml", None, Ok(3)),
    ("trees/parent_include_child_include_child.xml", None, Ok(5)),
    ("trees/parent_include_child_include_parent.xml", None, Ok(5)),
    ("trees/parent_include_child_include_sibling.xml", None, Ok(5)),
];

/// Trees that import but whose flattened XML cannot be written, and why.
/// What the example's C++ program registers before it creates the tree: the models
/// (and other documents), scripting enums and polymorphic casts.
fn program(dir: &Path, file: &str) -> ImportOptions<'static> {
    let models = |files: &[&str]| files.iter().map(|f| dir.join(f)).collect();
    let mut options = ImportOptions { models: models(&["example_nodes.xml"]), ..ImportOptions::default() };
    match file {
        // Color { RED = 1, BLUE = 2, GREEN = 3 } and THE_ANSWER = 42.
        "t09_scripting.xml" => {
            options.enums =
                [("RED", 1), ("BLUE", 2), ("GREEN", 3), ("THE_ANSWER", 42)].map(|(n, v)| (n.to_string(), v)).to_vec();
        }
        // SubA and SubB, from its second and third document.
        "t07_load_multiple_xml.xml" => {
            options.models =
                models(&["example_nodes.xml", "t07_load_multiple_xml_1.xml", "t07_load_multiple_xml_2.xml"]);
        }
        "t14_subtree_model_1.xml" => options.models = models(&["example_nodes.xml", "t14_subtree_model.xml"]),
        "t16_global_blackboard.xml" => options.models = models(&["t16_nodes.xml"]),
        // registerNodeType<LoopNode<Pose2D>>("LoopPose").
        "t18_waypoints.xml" => options.loops = vec!["LoopPose".to_string()],
        // registerPolymorphicCast<Cat, Animal>() and <Sphynx, Cat>().
        "t19_polymorphic_ports.xml" => {
            options.casts = [("Cat::Ptr", "Animal::Ptr"), ("Sphynx::Ptr", "Cat::Ptr")]
                .map(|(d, b)| (d.to_string(), b.to_string()))
                .to_vec();
        }
        _ => {}
    }
    options
}

#[test]
fn behaviortree_cpp_examples_import_or_are_refused_for_their_reason() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/btcpp-examples");
    // 35 of BehaviorTree.CPP 4.10's 36 example and test trees import; the other has no
    // BTCPP_format, so is read as BehaviorTree.CPP 3's, and uses a node type of 4.
    assert_eq!(EXPECTED.len(), 36);
    let imported = EXPECTED.iter().filter(|(file, main, _)| {
        let options = ImportOptions { main: main.map(str::to_string), ..program(&dir, file) };
        import(&dir.join(file), &options).is_ok()
    });
    assert_eq!(imported.count(), 35);
    for &(file, main, expected) in EXPECTED {
        let options = ImportOptions { main: main.map(str::to_string), ..program(&dir, file) };
        match (import(&dir.join(file), &options), expected) {
            (Ok(i), Ok(nodes)) => {
                assert_eq!(i.nodes.len(), nodes, "{file}");
                // Its XML (scripts written as the document wrote them) imports as the same image.
                // (t14's MySub starts `sub_in_value` at 42: written as a SubTree giving it.)
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
