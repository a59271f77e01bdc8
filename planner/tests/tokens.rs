//! The token notation of Styrud et al. over the brick tasks' behaviors: every name
//! reads back, controls nest, and errors name their line and column.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use bt_core::{Leaf, Node, NodeKind};
use bt_formats::tokens::{Location, TokenError, parse, to_string};
use planner::duplo::Task;

#[test]
fn round_trips_every_brick_behavior() {
    for task in Task::ALL {
        let spec = task.spec();
        let leaves: Vec<&str> = spec.names.iter().map(String::as_str).collect();
        let text = format!("f( s( {} ) )", leaves.join(" "));
        let nodes = parse(&text, &spec).unwrap();
        assert_eq!(nodes.len(), leaves.len() + 2);
        assert_eq!(to_string(&nodes, &spec).unwrap(), text);
    }
}

#[test]
fn nested_controls_and_sizes() {
    let spec = Task::Tower.spec();
    let nodes = parse("s( f( 0 on 1? s( pick 0! place on 1! ) ) apply force 0! )", &spec).unwrap();
    let sizes: Vec<u16> = nodes.iter().map(Node::size).collect();
    assert_eq!(sizes, [7, 5, 1, 3, 1, 1, 1]);
    assert_eq!(nodes[2].kind(), &NodeKind::Condition(Leaf::new(spec.id_by_name("0 on 1?").unwrap())));
}

fn at(line: usize, column: usize) -> Location {
    Location { line, column }
}

#[test]
fn errors_name_the_line_and_column() {
    let spec = Task::Tower.spec();
    assert_eq!(parse("s( pick 9! )", &spec), Err(TokenError::UnknownLeaf { at: at(1, 4), name: "pick 9!".into() }));
    assert_eq!(parse("s( pick 0! ) )", &spec), Err(TokenError::SecondTree { at: at(1, 14) }));
    assert_eq!(parse("pick 0! )", &spec), Err(TokenError::SecondTree { at: at(1, 9) }));
    assert_eq!(parse(")", &spec), Err(TokenError::UnbalancedClose { at: at(1, 1) }));
    assert_eq!(parse("s( f( )", &spec), Err(TokenError::EmptyControl { at: at(1, 7) }));
    assert_eq!(parse("s( pick 0!", &spec), Err(TokenError::Unclosed { at: at(1, 11), open: 1 }));
    assert_eq!(parse("s( hello )", &spec), Err(TokenError::BadToken { at: at(1, 4), text: "hello".into() }));
    assert_eq!(parse("   ", &spec), Err(TokenError::Empty));
    // A condition name written as an action is unknown.
    assert!(matches!(
        parse("picked 0!", &spec),
        Err(TokenError::UnknownLeaf { at: Location { line: 1, column: 1 }, .. })
    ));
    // Lines and columns, in characters, after line breaks and non-ASCII text.
    let text = "s(\n  f( picked 0? pick 0! )\n  pick 9!\n)";
    assert_eq!(parse(text, &spec), Err(TokenError::UnknownLeaf { at: at(3, 3), name: "pick 9!".into() }));
    assert_eq!(parse("s( é\n  bad )", &spec), Err(TokenError::BadToken { at: at(1, 4), text: "é".into() }));
    assert_eq!(parse("s(\n\n      x", &spec), Err(TokenError::BadToken { at: at(3, 7), text: "x".into() }));
    assert_eq!(
        parse("s( pick 0!\n", &spec).map_err(|e| e.to_string()),
        Err("2:1: the text ends with 1 control node not closed".into())
    );
}

#[test]
fn long_names_are_cut_in_messages() {
    let spec = Task::Tower.spec();
    let long = format!("s( {}! )", "x".repeat(1_000_000));
    let e = parse(&long, &spec).unwrap_err().to_string();
    assert!(e.len() < 200, "{e}");
    assert!(e.starts_with("1:4: unknown behavior `xxxx") && e.ends_with("... (1000001 characters)`"), "{e}");
}

#[test]
fn the_largest_tree_a_u16_count_allows_is_read() {
    let spec = Task::Tower.spec();
    let most = usize::from(u16::MAX);
    let text = format!("s( {})", "pick 0! ".repeat(most - 1));
    let nodes = parse(&text, &spec).unwrap();
    assert_eq!(nodes.len(), most);
    assert_eq!(nodes[0].size(), u16::MAX);
    let over = format!("s( {})", "pick 0! ".repeat(most));
    assert_eq!(parse(&over, &spec), Err(TokenError::TooLong { at: at(1, 4 + 8 * (most - 1)) }));
}

#[test]
fn other_kinds_are_refused() {
    let spec = Task::Tower.spec();
    let nodes = [Node::new(NodeKind::Inverter, 2), Node::new(NodeKind::Condition(Leaf::new(0)), 1)];
    assert_eq!(to_string(&nodes, &spec), Err(TokenError::NotExpressible { node: 0, kind: "Inverter" }));
    assert_eq!(
        to_string(&nodes, &spec).unwrap_err().to_string(),
        "the token notation cannot express this tree: node 0 is an Inverter; it has only s( f( ) and leaves"
    );
    let bad = [Node::new(NodeKind::Sequence, 3), Node::new(NodeKind::Condition(Leaf::new(0)), 1)];
    assert_eq!(to_string(&bad, &spec), Err(TokenError::Malformed { node: 0, size: 3 }));
}
