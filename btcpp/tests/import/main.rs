//! Importing BehaviorTree.CPP documents: what is read, and every refusal with its
//! place and construct.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;

use bt_core::{Catalog, NodeKind, PortValue};
use btcpp::xml::model::Literal;
use btcpp::xml::{ImportOptions, Imported, import, import_text};

mod on_controller;

const MODELS: &str = r#"
  <TreeNodesModel>
    <Condition ID="BatteryOk"/>
    <Condition ID="AtGoal"><input_port name="goal" type="Pose"/></Condition>
    <Action ID="MoveTo">
      <input_port name="goal" type="Pose"/>
      <input_port name="speed" type="double" default="0.3"/>
      <output_port name="error" type="int"/>
    </Action>
    <Action ID="Say"><input_port name="text" type="std::string"/></Action>
    <Action ID="Count"><input_port name="n" type="unsigned int"/></Action>
    <Action ID="Flag"><input_port name="on" type="bool"/></Action>
    <Action ID="Read"><output_port name="value" type="double"/></Action>
  </TreeNodesModel>"#;

fn doc(body: &str) -> String {
    format!("<root BTCPP_format=\"4\" main_tree_to_execute=\"Main\">\n{body}\n{MODELS}\n</root>\n")
}

fn ok(text: &str) -> Imported {
    import_text(Path::new("t.xml"), text, &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn err(text: &str) -> String {
    match import_text(Path::new("t.xml"), text, &ImportOptions::default()) {
        Ok(i) => panic!("imported {} nodes, expected an error", i.nodes.len()),
        Err(e) => e.to_string(),
    }
}

fn ascii(i: &Imported) -> String {
    planner_free_ascii(i)
}

/// The tree as bt-core renders it with the imported names.
fn planner_free_ascii(i: &Imported) -> String {
    let tree: bt_core::Tree<'_, 64> = bt_core::Tree::validate(&i.nodes, i).unwrap();
    tree.display(i).to_string()
}

#[test]
fn compact_and_explicit_leaves_names_and_comments() {
    let i = ok(&doc(r#"
  <!-- a comment -->
  <BehaviorTree ID="Main">
    <ReactiveSequence name="guard">
      <BatteryOk/>
      <Condition ID="BatteryOk" name="again"/>
      <!-- another -->
      <Action ID="MoveTo" goal="{target}" speed="0.5"/>
      <Fallback><AtGoal goal="{target}"/><MoveTo goal="{target}"/></Fallback>
    </ReactiveSequence>
  </BehaviorTree>"#));
    assert_eq!(i.nodes.len(), 7);
    assert!(matches!(i.nodes[0].kind(), NodeKind::Sequence));
    assert!(matches!(i.nodes[4].kind(), NodeKind::FallbackWithMemory));
    assert_eq!(i.meta[0].name.as_deref(), Some("guard"));
    assert_eq!(i.meta[2].name.as_deref(), Some("again"));
    assert_eq!(i.slots.len(), 1);
    assert_eq!(i.slots[0].name, "target");
    assert_eq!(i.constants, vec![Literal::Double(0.5)]);
    let text = ascii(&i);
    assert!(text.contains("MoveTo(goal={target}, speed=0.5)"), "{text}");
    // The second MoveTo leaves speed unset (its default) and error unset.
    assert!(text.contains("--> MoveTo(goal={target})"), "{text}");
    assert_eq!(i.meta.iter().map(|m| m.uid).collect::<Vec<_>>(), [1, 2, 3, 4, 5, 6, 7]);
}

#[test]
fn literals_are_typed_by_their_port_and_interned_once() {
    let i = ok(&doc(r#"
  <BehaviorTree ID="Main">
    <Sequence>
      <Count n="3"/><Count n="3"/><Flag on="true"/><Say text="3"/><MoveTo goal="{g}" speed="3"/>
    </Sequence>
  </BehaviorTree>"#));
    assert_eq!(i.constants, vec![Literal::Int(3), Literal::Bool(true), Literal::Str("3".into()), Literal::Double(3.0)]);
    let leaf = |n: usize| match i.nodes[n].kind() {
        NodeKind::Action(l) => *l,
        k => panic!("{k:?}"),
    };
    assert_eq!(i.leaf_values(&leaf(1)), i.leaf_values(&leaf(2)));
    let mv = i.leaf_values(&leaf(5)).to_vec();
    assert_eq!(
        mv.iter().map(|&v| PortValue::from_u16(v)).collect::<Vec<_>>(),
        [PortValue::Slot(0), PortValue::Constant(3), PortValue::Unset]
    );
}

#[test]
fn several_trees_main_tree_to_execute_and_main_override() {
    let two = r#"<root BTCPP_format="4" main_tree_to_execute="B">
  <BehaviorTree ID="A"><AlwaysSuccess/></BehaviorTree>
  <BehaviorTree ID="B"><Say text="b"/></BehaviorTree>
  <TreeNodesModel><Action ID="Say"><input_port name="text"/></Action></TreeNodesModel>
</root>"#;
    let b = ok(two);
    assert_eq!(b.main, "B");
    let e = import_text(Path::new("t.xml"), two, &ImportOptions { main: Some("C".into()), ..ImportOptions::default() })
        .unwrap_err()
        .to_string();
    assert_eq!(e, "no <BehaviorTree ID=\"C\"> (the documents define `A`, `B`)");
    let none = two.replace(" main_tree_to_execute=\"B\"", "");
    assert_eq!(err(&none), "2 trees (`A`, `B`) and no main_tree_to_execute: say which one to import");
    let wrong = two.replace("main_tree_to_execute=\"B\"", "main_tree_to_execute=\"X\"");
    assert_eq!(err(&wrong), "t.xml:1:24: no <BehaviorTree ID=\"X\"> (the documents define `A`, `B`)");
}

#[test]
fn v3_documents_without_the_format_attribute() {
    let i = ok(r#"<root main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <ReactiveSequence><Say text="x"/><SubTree ID="Sub" __shared_blackboard="true"/></ReactiveSequence>
  </BehaviorTree>
  <BehaviorTree ID="Sub"><Say text="{msg}"/></BehaviorTree>
  <TreeNodesModel><Action ID="Say"><input_port name="text"/></Action></TreeNodesModel>
</root>"#);
    assert!(matches!(i.nodes[0].kind(), NodeKind::Sequence));
    // __shared_blackboard: the subtree's key is the parent's.
    assert_eq!(i.slots[0].name, "msg");
}

#[test]
fn subtrees_are_flattened_per_instance_with_remapping() {
    let i = ok(&doc(r#"
  <BehaviorTree ID="Main">
    <Sequence>
      <SubTree ID="Go" target="{home}" fast="1.5"/>
      <SubTree ID="Go" name="second" target="{=}" fast="{speed}"/>
      <SubTree ID="Go" _autoremap="true" fast="2"/>
      <SubTree ID="Go" fast="3"/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Go">
    <Sequence>
      <MoveTo goal="{target}" speed="{fast}" error="{err}"/>
      <MoveTo goal="{@home}"/>
    </Sequence>
  </BehaviorTree>"#));
    // 1 + 4 x (Sequence + 2 leaves): SubTree nodes are not bt-core nodes.
    assert_eq!(i.nodes.len(), 13);
    let names: Vec<&str> = i.slots.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["home", "Go::2/err", "target", "speed", "second/err", "err", "Go::14/target", "Go::14/err"]);
    // Literal remappings read only are constants of the port's type.
    assert_eq!(i.constants, vec![Literal::Double(1.5), Literal::Double(2.0), Literal::Double(3.0)]);
    // BehaviorTree.CPP's uids count the SubTree nodes; paths as it writes _fullpath.
    let subs: Vec<(u16, &str, &str)> =
        i.subtrees.iter().map(|s| (s.uid, s.path.as_str(), s.instance.as_str())).collect();
    assert_eq!(
        subs,
        [(2, "Go::2", "Go::2"), (6, "second", "second"), (10, "Go::10", "Go::10"), (14, "Go::14", "Go::14")]
    );
    assert_eq!(i.meta[1].uid, 3);
}

#[test]
fn a_subtree_model_requires_its_ports_or_gives_defaults() {
    let body = r#"
  <BehaviorTree ID="Main"><SubTree ID="Go"/></BehaviorTree>
  <BehaviorTree ID="Go"><MoveTo goal="{target}" speed="{fast}"/></BehaviorTree>"#;
    let with = |ports: &str| {
        doc(body).replace("<TreeNodesModel>", &format!("<TreeNodesModel><SubTree ID=\"Go\">{ports}</SubTree>"))
    };
    let e = err(&with(r#"<input_port name="target"/>"#));
    assert_eq!(
        e,
        "t.xml:3:27: <SubTree ID=\"Go\"> does not remap the port `target`, which its model declares without a default"
    );
    let i = ok(&with(r#"<input_port name="target" default="{home}"/><input_port name="fast" default="0.25"/>"#));
    assert_eq!(i.slots[0].name, "home");
    assert_eq!(i.constants, vec![Literal::Double(0.25)]);
}

#[test]
fn subtree_recursion_names_the_cycle() {
    let e = err(&doc(r#"
  <BehaviorTree ID="Main"><SubTree ID="A"/></BehaviorTree>
  <BehaviorTree ID="A"><Sequence><BatteryOk/><SubTree ID="B"/></Sequence></BehaviorTree>
  <BehaviorTree ID="B"><SubTree ID="A"/></BehaviorTree>"#));
    assert_eq!(e, "t.xml:5:24: SubTree recursion: A -> B -> A");
}

#[test]
fn includes_are_relative_to_the_including_file() {
    let dir = tempfile_dir();
    std::fs::create_dir_all(dir.join("sub/deeper")).unwrap();
    std::fs::write(
        dir.join("main.xml"),
        r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <include path="sub/lib.xml"/>
  <BehaviorTree ID="Main"><SubTree ID="Lib"/></BehaviorTree>
</root>"#,
    )
    .unwrap();
    std::fs::write(
        dir.join("sub/lib.xml"),
        r#"<root BTCPP_format="4"><include path="deeper/models.xml"/>
  <BehaviorTree ID="Lib"><Say text="hi"/></BehaviorTree></root>"#,
    )
    .unwrap();
    std::fs::write(
        dir.join("sub/deeper/models.xml"),
        r#"<root BTCPP_format="4"><TreeNodesModel><Action ID="Say"><input_port name="text"/></Action></TreeNodesModel></root>"#,
    )
    .unwrap();
    let i = import(&dir.join("main.xml"), &ImportOptions::default()).unwrap();
    assert_eq!(i.nodes.len(), 1);
    // A missing include is reported at the <include>.
    std::fs::remove_file(dir.join("sub/deeper/models.xml")).unwrap();
    let e = import(&dir.join("main.xml"), &ImportOptions::default()).unwrap_err().to_string();
    assert!(e.contains("sub/lib.xml:1:24: cannot read") && e.contains("models.xml"), "{e}");
    // A cycle of includes.
    std::fs::write(dir.join("sub/deeper/models.xml"), r#"<root><include path="../lib.xml"/></root>"#).unwrap();
    let e = import(&dir.join("main.xml"), &ImportOptions::default()).unwrap_err().to_string();
    assert!(e.starts_with("<include> cycle: ") && e.ends_with("lib.xml"), "{e}");
}

fn tempfile_dir() -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("btcpp-import-{}-{:?}", std::process::id(), std::thread::current().id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Every construct a controller cannot run: the message names it and where it is.
#[test]
fn what_cannot_run_is_refused_with_its_place() {
    let cases: &[(&str, &str)] = &[
        (
            r#"<Script code="x:= 1 +"/>"#,
            "t.xml:2:35: <Script> code \"x:= 1 +\": an operand is missing at the end (at byte 7 of the script)",
        ),
        (
            r#"<ScriptCondition code="x > 'open"/>"#,
            "t.xml:2:44: <ScriptCondition> code \"x > 'open\": a string without its closing quote (at byte 4 of the script)",
        ),
        (
            r#"<Script code="1 := x"/>"#,
            "t.xml:2:35: <Script> code \"1 := x\": the left side of an assignment must be a blackboard key (at byte 2",
        ),
        (r#"<Script/>"#, "t.xml:2:27: <Script> needs the attribute `code`"),
        // A bare `&` is read as BehaviorTree.CPP reads it; columns after it stay the file's.
        (
            r#"<Sequence><ScriptCondition code="a && b"/><Nope/></Sequence>"#,
            "t.xml:2:69: `Nope` is neither a BehaviorTree.CPP built-in node",
        ),
        // A scripted attribute whose script does not parse, placed at the attribute.
        (
            r#"<BatteryOk _skipIf="x =="/>"#,
            "t.xml:2:38: <BatteryOk> _skipIf \"x ==\": an operand is missing at the end",
        ),
        (
            r#"<Precondition if="x" else="IDLE"><BatteryOk/></Precondition>"#,
            "t.xml:2:48: <Precondition> port `else`: \"IDLE\" is not a valid status (SUCCESS, FAILURE, RUNNING or SKIPPED)",
        ),
        (r#"<Precondition><BatteryOk/></Precondition>"#, "t.xml:2:27: <Precondition> needs the attribute `if`"),
        (
            r#"<Switch2 variable="{v}" case_1="a" case_2="b"><BatteryOk/><BatteryOk/><BatteryOk/></Switch2>"#,
            "t.xml:2:27: <Switch2> is not supported: it compares blackboard strings",
        ),
        (
            r#"<LoopInt queue="1;x" value="{v}"><BatteryOk/></LoopInt>"#,
            "t.xml:2:36: <LoopInt> port `queue`: \"x\" is not a valid int",
        ),
        (r#"<LoopInt value="{v}"><BatteryOk/></LoopInt>"#, "t.xml:2:27: <LoopInt> needs the attribute `queue`"),
        (
            r#"<LoopDouble queue="1" value="2"><BatteryOk/></LoopDouble>"#,
            "t.xml:2:49: <LoopDouble> port `value` is an output port; it takes a blackboard key",
        ),
        (
            r#"<LoopString queue="a" if_empty="IDLE"><BatteryOk/></LoopString>"#,
            "t.xml:2:49: <LoopString> port `if_empty`: \"IDLE\" is not a valid status",
        ),
        (
            r#"<LoopPose queue="{q}" value="{v}"><BatteryOk/></LoopPose>"#,
            "t.xml:2:27: `LoopPose` is neither a BehaviorTree.CPP built-in node nor declared in any <TreeNodesModel>; if the program registers it as a LoopNode<T> (registerNodeType<LoopNode<T>>(\"LoopPose\")), give --loop LoopPose",
        ),
        (r#"<UnsetBlackboard key="k"/>"#, "t.xml:2:27: <UnsetBlackboard> is not supported"),
        (
            r#"<SetBlackboard value="1" output_key="{k}"/>"#,
            "t.xml:2:52: <SetBlackboard output_key=\"{k}\"> is not supported: a {key} here names the entry whose name",
        ),
        (r#"<SetBlackboard value="1"/>"#, "t.xml:2:27: <SetBlackboard> needs the attribute `output_key`"),
        (
            r#"<Teleport/>"#,
            "t.xml:2:27: `Teleport` is neither a BehaviorTree.CPP built-in node nor declared in any <TreeNodesModel>",
        ),
        (r#"<Action ID="Teleport"/>"#, "t.xml:2:27: `Teleport` is neither"),
        (
            r#"<MoveTo goal="{g}" sped="1"/>"#,
            "t.xml:2:46: <MoveTo> has no port `sped` (its model declares `goal`, `speed`, `error`)",
        ),
        (
            r#"<MoveTo goal="{g}" error="3"/>"#,
            "t.xml:2:46: <MoveTo> port `error` is an output port; it takes a blackboard key like {error}, not the literal \"3\"",
        ),
        (r#"<MoveTo goal="{g}" speed="fast"/>"#, "t.xml:2:46: <MoveTo> port `speed`: \"fast\" is not a valid double"),
        (r#"<Count n="-1"/>"#, "t.xml:2:34: <Count> port `n`: \"-1\" is not a valid unsigned int"),
        (
            r#"<Sequence><Read value="{v}"/><Flag on="{v}"/></Sequence>"#,
            "t.xml:2:62: blackboard key `v` is used as bool here and as double at t.xml:2:43",
        ),
        (
            r#"<Sequence><Read value="{n}"/><Repeat num_cycles="{n}"><BatteryOk/></Repeat></Sequence>"#,
            "t.xml:2:64: blackboard key `n` is used as int here and as double at t.xml:2:43",
        ),
        (r#"<Inverter><BatteryOk/><BatteryOk/></Inverter>"#, "t.xml:2:27: <Inverter> takes exactly one child, found 2"),
        (r#"<BatteryOk><BatteryOk/></BatteryOk>"#, "t.xml:2:27: <BatteryOk> takes no children, found 1"),
        (r#"<Sequence/>"#, "t.xml:2:27: <Sequence> takes one or more children, found 0"),
        (r#"<BatteryOk ID="x"/>"#, "t.xml:2:38: the attribute ID on <BatteryOk> is not supported"),
        (r#"<Action name="x"/>"#, "t.xml:2:27: <Action> needs the attribute `ID`"),
        (
            r#"<Parallel success_count="3"><BatteryOk/><BatteryOk/></Parallel>"#,
            "t.xml:2:27: <Parallel success_count> of 3 with 2 children is not supported",
        ),
        (
            r#"<ManualSelector repeat_last_selection="{again}"><BatteryOk/></ManualSelector>"#,
            "t.xml:2:43: <ManualSelector> `repeat_last_selection` must be a literal",
        ),
        (
            r#"<ManualSelector repeat_last_selection="often"/>"#,
            "t.xml:2:43: <ManualSelector> port `repeat_last_selection`: \"often\" is not a valid bool",
        ),
    ];
    for (body, expected) in cases {
        let text = doc(&format!("  <BehaviorTree ID=\"Main\">{body}</BehaviorTree>"));
        let e = err(&text);
        assert!(e.starts_with(expected), "for {body}:\n  got      {e}\n  expected {expected}");
    }
}

#[test]
fn bad_documents() {
    assert_eq!(
        err("<root><BehaviorTree ID=\"M\"><A></BehaviorTree></root>"),
        "t.xml:1:31: not well-formed XML: expected 'A' tag, not 'BehaviorTree'"
    );
    assert_eq!(
        err("<tree/>"),
        "t.xml:1:1: the document element is <tree>; BehaviorTree.CPP documents start with <root>"
    );
    assert_eq!(err("<root BTCPP_format=\"5\"/>"), "t.xml:1:7: BTCPP_format=\"5\" is not supported (3 and 4 are)");
    assert_eq!(err("<root/>"), "the document defines no <BehaviorTree>");
    assert_eq!(
        err("<root><BehaviorTree ID=\"M\"><AlwaysSuccess/><AlwaysSuccess/></BehaviorTree></root>"),
        "t.xml:1:7: <BehaviorTree ID=\"M\"> must have exactly one child, found 2"
    );
    assert_eq!(
        err(
            "<root><BehaviorTree ID=\"M\"><AlwaysSuccess/></BehaviorTree><BehaviorTree ID=\"M\"><AlwaysSuccess/></BehaviorTree></root>"
        ),
        "t.xml:1:59: <BehaviorTree ID=\"M\"> is defined twice (first at t.xml:1:7)"
    );
    let conflict = "<root><BehaviorTree><A/></BehaviorTree><TreeNodesModel><Action ID=\"A\"/><Condition ID=\"A\"/></TreeNodesModel></root>";
    assert_eq!(
        err(conflict),
        "t.xml:1:72: the models of `A` here and at t.xml:1:56 differ: its kind, Condition here and Action there; BehaviorTree.CPP ignores the models in tree files: give the node's model with --nodes and --nodes-override"
    );
}

#[test]
fn the_catalog_is_sorted_and_its_fingerprint_covers_ports() {
    let a = ok(&doc("<BehaviorTree ID=\"Main\"><BatteryOk/></BehaviorTree>"));
    let ids: Vec<&str> = a.catalog.behaviors().iter().map(|b| b.id.as_str()).collect();
    assert_eq!(ids, ["AtGoal", "BatteryOk", "Count", "Flag", "MoveTo", "Read", "Say"]);
    let changed =
        doc("<BehaviorTree ID=\"Main\"><BatteryOk/></BehaviorTree>").replace("default=\"0.3\"", "default=\"0.4\"");
    assert_ne!(ok(&changed).fingerprint, a.fingerprint);
    let retyped = doc("<BehaviorTree ID=\"Main\"><BatteryOk/></BehaviorTree>").replace("type=\"int\"", "type=\"long\"");
    assert_ne!(ok(&retyped).fingerprint, a.fingerprint);
    assert_eq!(a.fingerprint, a.catalog.fingerprint());
}
