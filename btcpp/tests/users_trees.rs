//! Constructs of users' own trees that bt-core reads in its own way: Nav2's "plan once"
//! `RateController` rates, counts from a `{key}`, `BlackboardCheck*`'s
//! `return_on_mismatch`, a key a SubTree starts at a literal that a later port types,
//! and two models of one node type.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;

use bt_core::{NodeKind, Span, Status};
use btcpp::xml::document::read_text;
use btcpp::xml::{ImportOptions, Imported, Models, import_text};

fn import(text: &str) -> Result<Imported, String> {
    import_text(Path::new("t.xml"), text, &ImportOptions::default()).map_err(|e| e.to_string())
}

fn v4(body: &str) -> String {
    format!(
        r#"<root BTCPP_format="4" main_tree_to_execute="Main">
<BehaviorTree ID="Main">{body}</BehaviorTree>
<TreeNodesModel><Action ID="A"/><Action ID="Count"><input_port name="n" type="int"/></Action></TreeNodesModel>
</root>"#
    )
}

fn v3(body: &str) -> String {
    v4(body).replace(r#" BTCPP_format="4""#, "")
}

/// The image a controller loads.
fn loads(i: &Imported) {
    let image = i.image().unwrap();
    let mut nodes = vec![bt_core::Node::EMPTY; i.nodes.len()];
    let mut values = vec![0u16; image.len()];
    bt_core::load_with_ports::<_, 64>(&image, i, &mut nodes, &mut values).unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn rate_controllers_that_never_expire_and_those_a_controller_cannot_time() {
    let rate = |hz: &str| import(&v4(&format!(r#"<RateController hz="{hz}"><A/></RateController>"#)));
    // Nav2's "plan once": a period past 2^32 ms, which `now` never reaches.
    let once = rate("0.0000001").unwrap();
    assert_eq!(*once.nodes[0].kind(), NodeKind::RateController(Span::NEVER));
    loads(&once);
    assert!(once.to_xml().unwrap().contains(r#"<RateController _uid="1" hz="0.0000001">"#));
    assert_eq!(*rate("0.0001").unwrap().nodes[0].kind(), NodeKind::RateController(Span::new(10_000_000).unwrap()));
    // Between 2^24 ms (a start time's 24 bits) and 2^32 ms: refused, with the place.
    let e = rate("0.00001").unwrap_err();
    assert!(
        e.starts_with(r#"t.xml:2:41: <RateController hz="0.00001"> is not supported: its period is longer"#),
        "{e}"
    );
    assert!(rate("0").unwrap_err().contains("the rate must be above 0"));
}

#[test]
fn counts_from_a_key_are_read_on_every_tick() {
    let repeat = import(&v4(r#"<Sequence><Count n="{k}"/><Repeat num_cycles="{k}"><A/></Repeat></Sequence>"#)).unwrap();
    assert!(matches!(repeat.nodes[2].kind(), NodeKind::Cycles { from_slot: true, retry: false, v3: false, count: 0 }));
    loads(&repeat);
    let retry = import(&v3(r#"<RetryUntilSuccessful num_attempts="{k}"><A/></RetryUntilSuccessful>"#)).unwrap();
    assert!(matches!(retry.nodes[0].kind(), NodeKind::Cycles { from_slot: true, retry: true, v3: true, .. }));
    loads(&retry);
}

#[test]
fn blackboard_checks_return_what_3_8_reads_on_a_mismatch() {
    let check = |on: &str| {
        let body = format!(
            r#"<BlackboardCheckInt value_A="{{a}}" value_B="3" return_on_mismatch="{on}"><A/></BlackboardCheckInt>"#
        );
        import(&v3(&body)).map(|i| match i.nodes[0].kind() {
            NodeKind::Check { otherwise, .. } => *otherwise,
            other => panic!("{other:?}"),
        })
    };
    assert_eq!(check("RUNNING"), Ok(Status::Running));
    assert_eq!(check("SUCCESS"), Ok(Status::Success));
    // 3.8 leaves FAILURE when the text is no status.
    assert_eq!(check("running"), Ok(Status::Failure));
    let e = check("IDLE").unwrap_err();
    assert!(e.contains(r#"<BlackboardCheckInt return_on_mismatch="IDLE"> is not supported"#), "{e}");
}

#[test]
fn a_key_a_subtree_starts_at_a_literal_keeps_the_type_of_the_port_that_reads_it() {
    // A script names `x` before the int port does: the slot and its starting constant
    // are both int, so the image loads.
    let text = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
<BehaviorTree ID="Main"><SubTree ID="S" x="5"/></BehaviorTree>
<BehaviorTree ID="S"><Sequence><Script code="y := x"/><Count n="{x}"/><Script code="x := 6"/></Sequence></BehaviorTree>
<TreeNodesModel><Action ID="Count"><input_port name="n" type="int"/></Action></TreeNodesModel>
</root>"#;
    let i = import(text).unwrap();
    loads(&i);
    let again = import(&i.to_xml().unwrap()).unwrap();
    assert_eq!(again.image(), i.image());
}

#[test]
fn two_models_of_one_node_type() {
    let models = |second: &str| {
        let text = format!(
            r#"<root BTCPP_format="4">
<TreeNodesModel><Action ID="Dock"><input_port name="side" type="int" default="1"/></Action></TreeNodesModel>
<TreeNodesModel><Action ID="Dock">{second}</Action></TreeNodesModel>
</root>"#
        );
        let doc = read_text(Path::new("t.xml"), &text, &[]).unwrap();
        Models::new(&doc.models).map_err(|e| e.to_string())
    };
    // Another type or default: one model, the first read.
    let merged = models(r#"<input_port name="side" type="std::string"/>"#).unwrap();
    assert_eq!(merged.get("Dock").unwrap().ports[0].type_name.as_deref(), Some("int"));
    // Another direction: both named, with both places.
    let e = models(r#"<output_port name="side"/>"#).unwrap_err();
    assert!(e.starts_with("t.xml:3:17: the models of `Dock` here and at t.xml:2:17 differ: port `side`, an output port here and an input port there"), "{e}");
}
