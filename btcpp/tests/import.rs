//! Importing BehaviorTree.CPP documents: what is read, and every refusal with its
//! place and construct.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;

use bt_core::{Catalog, NodeKind, PortValue};
use btcpp::xml::model::Literal;
use btcpp::xml::{ImportOptions, Imported, import, import_text};

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

/// The image loads where the same models were compiled in, and a controller reads each
/// port through bt-core: constants typed, keys as slots, the rest unset.
#[test]
fn the_image_loads_and_its_ports_read_on_the_controller_side() {
    let i = ok(&doc(r#"
  <BehaviorTree ID="Main">
    <Sequence><MoveTo goal="{target}" speed="0.5" error="{err}"/><Say text="hello"/><Count n="7"/></Sequence>
  </BehaviorTree>"#));
    let image = i.image().unwrap();
    let mut nodes = [bt_core::Node::EMPTY; 8];
    let mut values = [0u16; 8];
    let (tree, ports): (bt_core::Tree<'_, 8>, _) =
        bt_core::load_with_ports(&image, &i.catalog, &mut nodes, &mut values).unwrap();
    assert_eq!((ports.slot_count(), ports.constant_count()), (2, 3));
    let leaf = |n: u16| tree.node(n).unwrap().kind().leaf().unwrap().1;
    let mv = leaf(1);
    let args = tree.args(&mv);
    assert_eq!(ports.port(args, 0), Some(bt_core::Port::Slot(0)));
    assert_eq!(ports.port(args, 1).and_then(|p| p.double()), Some(0.5));
    assert_eq!(ports.port(args, 2), Some(bt_core::Port::Slot(1)));
    assert_eq!(ports.port(tree.args(&leaf(2)), 0).and_then(|p| p.str()), Some("hello"));
    assert_eq!(ports.port(tree.args(&leaf(3)), 0).and_then(|p| p.int()), Some(7));
    // Another set of models: refused by fingerprint.
    let other = ok(&doc("<BehaviorTree ID=\"Main\"><BatteryOk/></BehaviorTree>").replace("default=\"0.3\"", ""));
    let mut nodes = [bt_core::Node::EMPTY; 8];
    let mut values = [0u16; 8];
    let e = bt_core::load_with_ports::<_, 8>(&image, &other.catalog, &mut nodes, &mut values).map(|_| ()).unwrap_err();
    assert_eq!(e.code(), "foreign-behavior-set");
}

/// A controller's behavior set: slots for the scripts, and one queue of three elements,
/// popped by index (a controller would keep a `heapless::Deque` per queue slot).
struct Controller<'p> {
    ports: bt_core::PortTable<'p>,
    slots: [Option<bt_core::script::Value>; 4],
    queue: [bt_core::script::Value; 3],
    popped: usize,
    /// What `Say` read from its `text` slot, each time it was ticked.
    said: Vec<Option<bt_core::script::Value>>,
    /// `ctx.starting` of each pop.
    starts: Vec<bool>,
}

impl bt_core::BehaviorSet for Controller<'_> {
    fn condition(&mut self, _: &bt_core::Leaf, _: bt_core::Context<'_>) -> bt_core::Status {
        bt_core::Status::Failure
    }
    fn action(&mut self, leaf: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> bt_core::Status {
        if let Some(bt_core::Port::Slot(s)) = self.ports.port(ctx.args(leaf), 0) {
            self.said.push(self.slots[usize::from(s)]);
        }
        bt_core::Status::Success
    }
    fn halt(&mut self, _: &bt_core::Leaf, _: bt_core::NodeId) {}
    fn script(
        &mut self,
        code: &[u16],
        _: bt_core::Context<'_>,
    ) -> Result<bt_core::script::Value, bt_core::script::ScriptFault> {
        bt_core::script::run(code, &self.ports, &mut self.slots)
    }
    fn pop(
        &mut self,
        _queue: u16,
        value: u16,
        ctx: bt_core::Context<'_>,
    ) -> Result<bool, bt_core::script::ScriptFault> {
        self.starts.push(ctx.starting);
        let Some(&v) = self.queue.get(self.popped) else { return Ok(false) };
        self.popped += 1;
        self.slots[usize::from(value)] = Some(v);
        Ok(true)
    }
}

/// Loops run on the controller with no heap: a literal queue's elements are assigned by
/// the programs the image carries, a `{key}` queue is popped by the behavior set; one
/// element per tick, then `if_empty`.
#[test]
fn loops_run_on_the_controller_side() {
    use bt_core::script::Value;
    use bt_core::{Executor, NodeState, Status};
    let run = |text: &str, loops: &[&str], ticks: usize| {
        let options =
            ImportOptions { loops: loops.iter().map(|l| l.to_string()).collect(), ..ImportOptions::default() };
        let i = import_text(Path::new("t.xml"), text, &options).unwrap_or_else(|e| panic!("{e}"));
        let image = i.image().unwrap();
        let mut nodes = [bt_core::Node::EMPTY; 8];
        let mut values = [0u16; 64];
        let (tree, ports): (bt_core::Tree<'_, 8>, _) =
            bt_core::load_with_ports(&image, &i.catalog, &mut nodes, &mut values).unwrap();
        let mut set = Controller {
            ports,
            slots: [None; 4],
            queue: [Value::Double(1.0), Value::Double(2.0), Value::Double(3.0)],
            popped: 0,
            said: vec![],
            starts: vec![],
        };
        let mut state = [NodeState::IDLE; 8];
        let mut exec = Executor::new(tree, &mut state).unwrap();
        let statuses: Vec<Status> = (0..ticks).map(|k| exec.tick(&mut set, k as u32).unwrap()).collect();
        (statuses, set.said, set.starts, set.slots)
    };
    use Status::{Failure, Running, Success};
    // A literal queue: 1, 2.5, then 4, for which the condition fails (and the loop).
    let (statuses, _, starts, slots) = run(
        &doc(r#"<BehaviorTree ID="Main"><Sequence>
             <LoopDouble queue="1;2.5;4" value="{x}"><ScriptCondition code="x &lt; 3"/></LoopDouble>
           </Sequence></BehaviorTree>"#),
        &[],
        3,
    );
    assert_eq!(statuses, [Running, Running, Failure]);
    assert!(starts.is_empty(), "a literal queue never asks the behavior set to pop");
    assert_eq!(slots[0], Some(Value::Double(4.0)));
    // A blackboard queue of a type the program registers a loop for: the set pops it.
    let (statuses, said, starts, _) = run(
        &doc(r#"<BehaviorTree ID="Main"><Sequence>
             <LoopPose queue="{waypoints}" value="{wp}"><Say text="{wp}"/></LoopPose>
           </Sequence></BehaviorTree>"#),
        &["LoopPose"],
        5,
    );
    assert_eq!(statuses, [Running, Running, Running, Success, Success]);
    assert_eq!(said, [1.0, 2.0, 3.0].map(|v| Some(Value::Double(v))));
    // Asked afresh on the first pop of each activation: ticks 0 and 4.
    assert_eq!(starts, [true, false, false, false, true]);
    // A set that keeps no queues refuses the pop, and the tick ends with that fault.
    struct NoQueues;
    impl bt_core::BehaviorSet for NoQueues {
        fn condition(&mut self, _: &bt_core::Leaf, _: bt_core::Context<'_>) -> Status {
            Failure
        }
        fn action(&mut self, _: &bt_core::Leaf, _: bt_core::Context<'_>) -> Status {
            Success
        }
        fn halt(&mut self, _: &bt_core::Leaf, _: bt_core::NodeId) {}
    }
    let text =
        doc(r#"<BehaviorTree ID="Main"><LoopPose queue="{q}" value="{v}"><Say text="{v}"/></LoopPose></BehaviorTree>"#);
    let options = ImportOptions { loops: vec!["LoopPose".into()], ..ImportOptions::default() };
    let i = import_text(Path::new("t.xml"), &text, &options).unwrap();
    let image = i.image().unwrap();
    let (mut nodes, mut values) = ([bt_core::Node::EMPTY; 4], [0u16; 16]);
    let (tree, _): (bt_core::Tree<'_, 4>, _) =
        bt_core::load_with_ports(&image, &i.catalog, &mut nodes, &mut values).unwrap();
    let mut state = [NodeState::IDLE; 4];
    let e = Executor::new(tree, &mut state).unwrap().tick(&mut NoQueues, 0).unwrap_err();
    assert_eq!(
        e.to_string(),
        "script node 0: this behavior set keeps no blackboard queues (BehaviorSet::pop), which a loop over a {key} needs"
    );
}

/// The operator of a controller: each time a `ManualSelector` asks, the next command
/// (a teleoperation input), and the `Say` actions ticked.
struct Operator {
    commands: std::collections::VecDeque<bt_core::Selection>,
    /// How many children each asking `ManualSelector` had.
    asked: Vec<u8>,
    said: Vec<bt_core::NodeId>,
}

impl bt_core::BehaviorSet for Operator {
    fn condition(&mut self, _: &bt_core::Leaf, _: bt_core::Context<'_>) -> bt_core::Status {
        bt_core::Status::Failure
    }
    fn action(&mut self, _: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> bt_core::Status {
        self.said.push(ctx.node);
        bt_core::Status::Success
    }
    fn halt(&mut self, _: &bt_core::Leaf, _: bt_core::NodeId) {}
    fn select(
        &mut self,
        children: u8,
        _: bt_core::Context<'_>,
    ) -> Result<bt_core::Selection, bt_core::script::ScriptFault> {
        self.asked.push(children);
        self.commands.pop_front().ok_or(bt_core::script::ScriptFault::NoSelections)
    }
}

/// BehaviorTree.CPP's ex03 tree on the controller: its `ManualSelector`s ask the
/// behavior set (the operator's commands), not a terminal; the one without children asks
/// for a status. Its XML gives the same image back.
#[test]
fn manual_selectors_take_the_operators_choice_from_the_behavior_set() {
    use bt_core::{Executor, NodeState, Selection, Status};
    let text = doc(r#"<BehaviorTree ID="Main"><Repeat num_cycles="3">
          <ManualSelector repeat_last_selection="0">
            <Say text="one"/><Say text="two"/><ManualSelector name="YouChoose"/>
          </ManualSelector>
        </Repeat></BehaviorTree>"#);
    let i = ok(&text);
    assert_eq!(i.nodes[1].kind(), &NodeKind::ManualSelector { repeat_last: false });
    assert_eq!(i.nodes[4], bt_core::Node::new(NodeKind::ManualSelector { repeat_last: false }, 1));
    let again = import_text(Path::new("t.xml"), &i.to_xml().unwrap(), &ImportOptions::default()).unwrap();
    assert_eq!(again.image().unwrap(), i.image().unwrap());
    // A Groot2 log of it names them as BehaviorTree.CPP does, with the port as written
    // (the default added where absent), and the model a program registering the node has.
    let xml = btcpp::btlog::LogTree::of_imported(&i).unwrap().xml();
    assert!(xml.contains(r#"<ManualSelector name="ManualSelector" _uid="2" repeat_last_selection="0">"#), "{xml}");
    assert!(xml.contains(r#"<ManualSelector name="YouChoose" _uid="5" repeat_last_selection="false"/>"#), "{xml}");
    assert!(xml.contains(r#"<Control ID="ManualSelector">"#), "{xml}");
    let image = i.image().unwrap();
    let mut nodes = [bt_core::Node::EMPTY; 8];
    let mut values = [0u16; 8];
    let (tree, _): (bt_core::Tree<'_, 8>, _) =
        bt_core::load_with_ports(&image, &i.catalog, &mut nodes, &mut values).unwrap();
    let mut state = [NodeState::IDLE; 8];
    let mut exec = Executor::new(tree, &mut state).unwrap();
    let commands = [Selection::Child(1), Selection::Child(0), Selection::Child(2), Selection::Failure];
    let mut operator = Operator { commands: commands.into(), asked: vec![], said: vec![] };
    // "two", then "one" (each a cycle of the Repeat, which asks to be ticked again),
    // then the selector without children, told to fail.
    let statuses: Vec<Status> = (0..3).map(|k| exec.tick(&mut operator, k).unwrap()).collect();
    assert_eq!(statuses, [Status::Running, Status::Running, Status::Failure]);
    assert_eq!(operator.said, [3, 2]);
    assert_eq!(operator.asked, [3, 3, 3, 0]);
    // A set that gives no selections refuses, and the tick ends with that fault.
    let e = exec.tick(&mut operator, 3).unwrap_err();
    assert_eq!(e, bt_core::TickError::Script { node: 1, fault: bt_core::script::ScriptFault::NoSelections });
    // The set chooses by a u8: 256 children are refused at import, with the place.
    let many = doc(&format!(
        "<BehaviorTree ID=\"Main\"><ManualSelector>{}</ManualSelector></BehaviorTree>",
        "<BatteryOk/>".repeat(256)
    ));
    assert_eq!(
        err(&many),
        "t.xml:2:25: <ManualSelector> with 256 children is not supported: the behavior set chooses a child by a \
         number from 0 to 254: at most 255 children"
    );
}

/// The XML of a flattened tree writes scripts with the keys as it names them: a key a
/// SubTree remaps becomes its parent's, a SubTree's own key a name made of its path; a
/// key the SubTree starts at a literal is given by a SubTree around the tree.
#[test]
fn scripts_in_subtrees_are_written_with_the_flattened_keys() {
    let imported = |doc: &str| import_text(Path::new("t.xml"), doc, &ImportOptions::default()).unwrap();
    let refusal = |doc: &str| imported(doc).to_xml().unwrap_err().to_string();
    let round_trip = |doc: &str| {
        let i = imported(doc);
        let xml = i.to_xml().unwrap();
        let again = import_text(Path::new("t.xml"), &xml, &ImportOptions::default()).unwrap();
        assert_eq!(again.image().unwrap(), i.image().unwrap(), "{xml}");
        xml
    };
    let remapped = r#"<root BTCPP_format="4" main_tree_to_execute="M">
  <BehaviorTree ID="M"><Sequence><SubTree ID="S" out="{result}"/><Script code="done := result"/></Sequence></BehaviorTree>
  <BehaviorTree ID="S"><Script code="out := 'ok'"/></BehaviorTree>
</root>"#;
    let xml = round_trip(remapped);
    assert!(xml.contains(r#"code="result := &apos;ok&apos;""#), "{xml}");

    // Two instances' own `x` stay two keys.
    let local = r#"<root BTCPP_format="4" main_tree_to_execute="M">
  <BehaviorTree ID="M"><Sequence><SubTree ID="S"/><SubTree ID="S"/></Sequence></BehaviorTree>
  <BehaviorTree ID="S"><Script code="x := x + 1"/></BehaviorTree>
</root>"#;
    let xml = round_trip(local);
    assert!(xml.contains(r#"code="S_2_x := S_2_x + 1""#) && xml.contains(r#"code="S_4_x := S_4_x + 1""#), "{xml}");

    let started = r#"<root BTCPP_format="4" main_tree_to_execute="M">
  <BehaviorTree ID="M"><SubTree ID="S" x="3"/></BehaviorTree>
  <BehaviorTree ID="S"><Script code="x := x + 1"/></BehaviorTree>
</root>"#;
    // Written as a SubTree giving it, every other key shared.
    let xml = round_trip(started);
    assert!(
        xml.contains(r#"<SubTree ID="M.body" _autoremap="true" S_1_x="3"/>"#)
            && xml.contains(r#"<BehaviorTree ID="M.body">"#),
        "{xml}"
    );

    let clash = r#"<root BTCPP_format="4" main_tree_to_execute="M">
  <BehaviorTree ID="M"><Sequence><Script code="S_3_x := 1"/><SubTree ID="S"/></Sequence></BehaviorTree>
  <BehaviorTree ID="S"><Script code="x := 2"/></BehaviorTree>
</root>"#;
    assert_eq!(refusal(clash), "blackboard keys `S_3_x` and `S::3/x` (slot 1) would both be written as `S_3_x`");
}

/// Polymorphic casts as BehaviorTree.CPP's registry allows them: an input port reads a
/// key of a type that reaches the port's through casts upwards, or of its direct base;
/// output ports and types without a cast stay conflicts.
#[test]
fn input_ports_read_through_registered_polymorphic_casts() {
    let doc = |body: &str| {
        format!(
            r#"<root BTCPP_format="4">
  <BehaviorTree ID="M"><Sequence>{body}</Sequence></BehaviorTree>
  <TreeNodesModel>
    <Action ID="MakeSphynx"><output_port name="p" type="Sphynx::Ptr"/></Action>
    <Action ID="MakeAnimal"><output_port name="p" type="Animal::Ptr"/></Action>
    <Action ID="MakeCat"><output_port name="p" type="Cat::Ptr"/></Action>
    <Action ID="UseAnimal"><input_port name="p" type="Animal::Ptr"/></Action>
    <Action ID="UseCat"><input_port name="p" type="Cat::Ptr"/></Action>
    <Action ID="UseSphynx"><input_port name="p" type="Sphynx::Ptr"/></Action>
  </TreeNodesModel>
</root>"#
        )
    };
    let casts = |list: &[(&str, &str)]| ImportOptions {
        casts: list.iter().map(|(d, b)| (d.to_string(), b.to_string())).collect(),
        ..ImportOptions::default()
    };
    let both = casts(&[("Cat::Ptr", "Animal::Ptr"), ("Sphynx::Ptr", "Cat::Ptr")]);
    let import = |body: &str, options: &ImportOptions<'_>| {
        import_text(Path::new("t.xml"), &doc(body), options).map(|i| i.slots.len()).map_err(|e| e.to_string())
    };
    // Upwards, through two casts.
    let up = r#"<MakeSphynx p="{a}"/><UseAnimal p="{a}"/>"#;
    assert_eq!(import(up, &both), Ok(1));
    let e = import(up, &casts(&[("Cat::Ptr", "Animal::Ptr")])).unwrap_err();
    assert!(e.contains("blackboard key `a` is used as Animal::Ptr here and as Sphynx::Ptr"), "{e}");
    assert!(import(up, &ImportOptions::default()).is_err());
    // Down one cast, not two.
    assert_eq!(import(r#"<MakeAnimal p="{a}"/><UseCat p="{a}"/>"#, &both), Ok(1));
    assert!(import(r#"<MakeAnimal p="{a}"/><UseSphynx p="{a}"/>"#, &both).is_err());
    // An output port of another type is a conflict, cast or not.
    let e = import(r#"<MakeCat p="{a}"/><MakeSphynx p="{a}"/>"#, &both).unwrap_err();
    assert!(e.contains("is used as Sphynx::Ptr here and as Cat::Ptr"), "{e}");
}
