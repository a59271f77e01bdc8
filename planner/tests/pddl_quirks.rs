//! Files as other tools write them (a byte-order mark, old Mac line ends), goals that
//! cannot hold, constructs used without their requirement, and errors that must name
//! the right file.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use planner::PlanError;
use planner::ground::Grounding;
use planner::pddl::{parse_domain, parse_problem, read_domain, read_problem};

const DOMAIN: &str = "(define (domain hand)
  (:requirements :strips)
  (:predicates (hand-empty) (holding ?x))
  (:action pick :parameters (?x) :precondition (hand-empty)
    :effect (and (holding ?x) (not (hand-empty))))
  (:action drop :parameters (?x) :precondition (holding ?x)
    :effect (and (hand-empty) (not (holding ?x)))))";

const PROBLEM: &str = "(define (problem p) (:domain hand) (:objects ball) (:init (hand-empty))
  (:goal (holding ball)))";

#[test]
fn a_utf8_byte_order_mark_is_skipped() {
    let d = parse_domain("d.pddl", &format!("\u{feff}{DOMAIN}")).unwrap();
    parse_problem("p.pddl", &format!("\u{feff}{PROBLEM}"), &d).unwrap();
    // Positions after it count from the first real character.
    let bad = "(define (domain d) (:predicates (p ?x)) (:bogus))";
    let e = parse_domain("d.pddl", &format!("\u{feff}{bad}")).unwrap_err();
    assert!(e.to_string().starts_with("d.pddl:1:42:"), "{e}");
    assert_eq!(e, parse_domain("d.pddl", bad).unwrap_err());
}

#[test]
fn carriage_returns_alone_end_lines() {
    let text = DOMAIN.replace('\n', "\r");
    // A comment on the first line ends at its `\r`, not at the end of the file.
    let d = parse_domain("d.pddl", &format!("; old Mac file\r{text}")).unwrap();
    assert_eq!(d.actions.len(), 2);
    let e = parse_domain("d.pddl", "(define (domain d)\r  (:predicates (p ?x))\r  (:bogus))").unwrap_err();
    assert!(e.to_string().starts_with("d.pddl:3:4:"), "{e}");
    let e = parse_domain("d.pddl", "(define (domain d)\r\n  (:predicates (p ?x))\r\n  (:bogus))").unwrap_err();
    assert!(e.to_string().starts_with("d.pddl:3:4:"), "{e}");
}

#[test]
fn a_contradictory_goal_is_reported_not_planned() {
    let d = parse_domain("d.pddl", &DOMAIN.replace(":strips", ":strips :negative-preconditions")).unwrap();
    let p = parse_problem(
        "p.pddl",
        "(define (problem p) (:domain hand) (:objects ball) (:init (hand-empty))
           (:goal (and (hand-empty) (not (hand-empty)))))",
        &d,
    )
    .unwrap();
    assert_eq!(Grounding::new(&p).unwrap_err(), PlanError::ContradictoryGoal { atom: "hand-empty".into() });
}

#[test]
fn a_negative_goal_without_its_requirement_is_read_with_a_warning_on_the_problem() {
    let problem = "(define (problem p) (:domain hand) (:objects ball) (:init (hand-empty))
  (:goal (and (hand-empty) (not (holding ball)))))";
    let (d, dw) = read_domain("d.pddl", DOMAIN).unwrap();
    assert!(dw.is_empty(), "{dw:?}");
    let (_, w) = read_problem("p.pddl", problem, &d).unwrap();
    assert_eq!(w.len(), 1, "{w:?}");
    let text = w[0].to_string();
    assert!(text.starts_with("p.pddl:2:33: warning:"), "{text}");
    assert!(text.contains(":negative-preconditions"), "{text}");
    // Declared by the domain: no warning.
    let (d, _) = read_domain("d.pddl", &DOMAIN.replace(":strips", ":strips :negative-preconditions")).unwrap();
    let (_, w) = read_problem("p.pddl", problem, &d).unwrap();
    assert!(w.is_empty(), "{w:?}");
}

#[test]
fn predicates_with_many_parameters_are_read_and_the_limit_is_reported_on_the_domain() {
    // Four parameters: read, grounded and planned (an extended leaf).
    let d = parse_domain(
        "d.pddl",
        "(define (domain d) (:predicates (p ?a ?b ?c ?d)) (:action a :parameters (?a ?b ?c ?d) :effect (p ?a ?b ?c ?d)))",
    )
    .unwrap();
    let p = parse_problem("p.pddl", "(define (problem q) (:domain d) (:objects o) (:goal (p o o o o)))", &d).unwrap();
    Grounding::new(&p).unwrap();
    // Beyond what a behavior declares (255): refused in the domain file, at the predicate.
    let params: Vec<String> = (0..300).map(|i| format!("?a{i}")).collect();
    let text = format!("(define (domain d)\n (:predicates\n  (p {})))", params.join(" "));
    let e = parse_domain("d.pddl", &text).unwrap_err();
    assert!(e.to_string().starts_with("d.pddl:3:4:"), "{e}");
}

#[test]
fn too_many_predicates_are_refused_while_reading_at_the_first_one_too_many() {
    let mut text = String::from("(define (domain d)\n(:predicates\n");
    for i in 0..70_000 {
        text.push_str(&format!("(p{i})\n"));
    }
    text.push_str(") (:action a :parameters () :effect (p1)))");
    let e = parse_domain("d.pddl", &text).unwrap_err();
    // Line 3 holds the first predicate: the 65,536th is on line 65,538.
    assert!(e.to_string().starts_with("d.pddl:65538:1: more than 65535 predicates and actions"), "{e}");
}

#[test]
fn a_problem_with_65000_objects_is_refused_with_the_true_grounding_count() {
    let d = parse_domain(
        "d.pddl",
        "(define (domain d) (:predicates (q ?a ?b)) (:action a :parameters (?a ?b) :effect (q ?a ?b)))",
    )
    .unwrap();
    let objects: Vec<String> = (0..65_000).map(|i| format!("o{i}")).collect();
    let text = format!("(define (problem q) (:domain d) (:objects {}) (:goal (q o1 o2)))", objects.join(" "));
    let p = parse_problem("p.pddl", &text, &d).unwrap();
    match Grounding::new(&p).unwrap_err() {
        PlanError::Unbounded { action, count, .. } => {
            assert_eq!(action, "a");
            assert_eq!(count, 65_000 * 65_000);
        }
        e => panic!("{e}"),
    }
}

#[test]
fn an_action_named_with_a_question_mark_or_a_reserved_word_is_refused_where_it_is() {
    let e = parse_domain("d.pddl", &DOMAIN.replace("(:action pick", "(:action ?pick")).unwrap_err();
    assert!(e.to_string().starts_with("d.pddl:4:12: `?pick` is not a valid name"), "{e}");
    let e = parse_domain("d.pddl", &DOMAIN.replace("(:action pick", "(:action and")).unwrap_err();
    assert!(e.to_string().starts_with("d.pddl:4:12: `and` is a reserved word of PDDL"), "{e}");
}
