//! Imported trees on the controller side: their images load, their ports, loops,
//! manual selectors and scripts read and run as bt-core runs them.

use std::path::Path;

use bt_core::NodeKind;
use btcpp::xml::{ImportOptions, import_text};

use super::{doc, err, ok};

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
