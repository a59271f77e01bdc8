//! Malformed PDDL: each fault its own clear error with file, line and column; no input
//! makes the reader panic.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use planner::domains;
use planner::model::ModelError;
use planner::pddl::{ErrorKind, parse_domain, parse_problem};
use proptest::prelude::*;

type Check = fn(&ErrorKind) -> bool;

const DOMAIN: &str = "(define (domain d)
  (:requirements :strips :typing)
  (:types box place)
  (:predicates (at ?b - box ?p - place) (free ?p - place))
  (:action move
    :parameters (?b - box ?from ?to - place)
    :precondition (and (at ?b ?from) (free ?to))
    :effect (and (at ?b ?to) (not (at ?b ?from)))))";

fn domain_err(text: &str) -> (String, ErrorKind) {
    let e = parse_domain("d.pddl", text).unwrap_err();
    (e.to_string(), *e.kind)
}

fn problem_err(text: &str) -> (String, ErrorKind) {
    let d = parse_domain("d.pddl", DOMAIN).unwrap();
    let e = parse_problem("p.pddl", text, &d).unwrap_err();
    (e.to_string(), *e.kind)
}

#[test]
fn the_good_ones_parse() {
    let d = parse_domain("d.pddl", DOMAIN).unwrap();
    assert_eq!(d.actions[0].pre.len(), 2);
    let p = parse_problem(
        "p.pddl",
        "(define (problem p) (:domain d) (:objects b - box x y - place) (:init (at b x) (free y)) (:goal (at b y)))",
        &d,
    )
    .unwrap();
    assert_eq!(p.objects.len(), 3);
    assert!(domains::cube_sphere().is_ok() && domains::cellphone().is_ok());
}

#[test]
fn unknown_predicate() {
    let (msg, kind) = domain_err(&DOMAIN.replace("(free ?to))", "(fre ?to))"));
    assert!(matches!(kind, ErrorKind::Model(ModelError::UnknownPredicate { ref name, .. }) if name == "fre"));
    assert_eq!(msg, "d.pddl:7:39: unknown predicate `fre` (declared: at, free)");
}

#[test]
fn wrong_arity() {
    let (msg, kind) = domain_err(&DOMAIN.replace("(free ?to))", "(free ?to ?b))"));
    assert_eq!(kind, ErrorKind::Model(ModelError::WrongArity { predicate: "free".into(), expected: 1, found: 2 }));
    assert!(msg.starts_with("d.pddl:7:38: `free` takes 1 argument, given 2"), "{msg}");
}

#[test]
fn unbalanced_parentheses() {
    let (msg, kind) = domain_err(&DOMAIN[..DOMAIN.len() - 1]);
    assert_eq!(kind, ErrorKind::Unclosed);
    assert!(msg.starts_with("d.pddl:1:1: unbalanced parentheses"), "{msg}");
    let (msg, kind) = domain_err(&format!("{DOMAIN})"));
    assert_eq!(kind, ErrorKind::UnexpectedClose);
    assert!(msg.starts_with("d.pddl:8:52:"), "{msg}");
}

#[test]
fn undefined_type() {
    let (msg, kind) = domain_err(&DOMAIN.replace("?from ?to - place", "?from ?to - plaice"));
    assert_eq!(kind, ErrorKind::Model(ModelError::UnknownType { name: "plaice".into() }));
    assert_eq!(msg, "d.pddl:6:39: undefined type `plaice`");
}

#[test]
fn goal_on_an_undeclared_object() {
    let (msg, kind) =
        problem_err("(define (problem p) (:domain d)\n  (:objects b - box x - place)\n  (:goal (at b y)))");
    assert_eq!(kind, ErrorKind::Model(ModelError::UnknownObject { name: "y".into() }));
    assert_eq!(msg, "p.pddl:3:16: undeclared object `y`");
}

#[test]
fn action_with_no_effects() {
    let text = "(define (domain d) (:predicates (p)) (:action idle :parameters () :precondition (p)))";
    let (msg, kind) = domain_err(text);
    assert_eq!(kind, ErrorKind::Model(ModelError::NoEffects { action: "idle".into() }));
    assert_eq!(msg, "d.pddl:1:47: action `idle` has no effects");
}

#[test]
fn more_faults_each_with_its_own_error() {
    let cases: Vec<(String, Check)> = vec![
        (
            DOMAIN.replace(":typing", ":fluents"),
            |k| matches!(k, ErrorKind::UnsupportedRequirement(r) if r == ":fluents"),
        ),
        (
            DOMAIN.replace("(free ?to))", "(free ?x))"),
            |k| matches!(k, ErrorKind::Model(ModelError::UnknownParameter { name, .. }) if name == "x"),
        ),
        (DOMAIN.replace("(free ?to))", "(free ?b))"), |k| {
            matches!(k, ErrorKind::Model(ModelError::TypeMismatch { .. }))
        }),
        (
            DOMAIN.replace("(free ?to))", "(< (free ?to) 1))"),
            |k| matches!(k, ErrorKind::Unsupported(s) if s == "numeric condition `<`"),
        ),
        (
            DOMAIN.replace("(:types box place)", "(:types box place) (:durative-action go)"),
            |k| matches!(k, ErrorKind::Unsupported(s) if s.starts_with(":durative-action")),
        ),
        (format!("{DOMAIN} (extra)"), |k| *k == ErrorKind::Trailing),
        ("(define (problem x))".into(), |k| matches!(k, ErrorKind::Expected { .. })),
        (DOMAIN.replace("(free ?p - place))", "(free ?p - place) (free ?q - place))"), |k| {
            matches!(k, ErrorKind::Model(ModelError::DuplicatePredicate { .. }))
        }),
        ("(".repeat(100), |k| matches!(k, ErrorKind::TooDeep { .. })),
        ("".into(), |k| matches!(k, ErrorKind::Expected { .. })),
    ];
    for (text, want) in cases {
        let e = parse_domain("d.pddl", &text).unwrap_err();
        assert!(want(&e.kind), "{text}\n-> {e}");
        assert!(e.pos.line >= 1 && e.pos.column >= 1, "{e}");
    }
    let problems: Vec<(&str, Check)> = vec![
        ("(define (problem p) (:domain other) (:goal (free x)))", |k| {
            matches!(k, ErrorKind::Model(ModelError::DomainMismatch { .. }))
        }),
        ("(define (problem p) (:domain d) (:objects x - place) (:init (not (free x))) (:goal (free x)))", |k| {
            *k == ErrorKind::Model(ModelError::NegativeInit)
        }),
        ("(define (problem p) (:domain d) (:objects x - place))", |k| matches!(k, ErrorKind::Missing(_))),
        ("(define (problem p) (:domain d) (:objects x x - place) (:goal (free x)))", |k| {
            matches!(k, ErrorKind::Model(ModelError::DuplicateObject { .. }))
        }),
        ("(define (problem p) (:domain d) (:objects x - place) (:goal (and)))", |k| {
            *k == ErrorKind::Model(ModelError::EmptyGoal)
        }),
        ("(define (problem p) (:domain d) (:objects b - box) (:goal (free b)))", |k| {
            matches!(k, ErrorKind::Model(ModelError::TypeMismatch { .. }))
        }),
    ];
    for (text, want) in problems {
        let (msg, kind) = problem_err(text);
        assert!(want(&kind), "{text}\n-> {msg}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,300}") {
        let _ = parse_domain("d.pddl", &text);
        let d = parse_domain("d.pddl", DOMAIN).unwrap();
        let _ = parse_problem("p.pddl", &text, &d);
    }

    #[test]
    fn damaged_domains_never_panic(cut in 0usize..2000, len in 0usize..40, insert in "[()?a-z :-]{0,6}") {
        let src = domains::CELLPHONE_DOMAIN;
        let mut chars: Vec<char> = src.chars().collect();
        let at = cut % chars.len();
        let end = (at + len).min(chars.len());
        chars.splice(at..end, insert.chars());
        let text: String = chars.into_iter().collect();
        if let Ok(d) = parse_domain("d.pddl", &text)
            && let Ok(p) = parse_problem("p.pddl", domains::CELLPHONE_PROBLEM, &d) {
                let _ = planner::ground::Grounding::new(&p);
            }
    }
}

#[test]
fn a_byte_order_mark_is_skipped_and_every_line_ending_counts() {
    // A UTF-8 BOM was read as part of the first symbol (an invisible character in
    // backquotes); CR-only line endings made a comment swallow the rest of the file.
    let d = parse_domain("d.pddl", &format!("\u{feff}{DOMAIN}")).unwrap();
    assert_eq!(d.actions.len(), 1);
    let cr = format!("; a comment\r{}", DOMAIN.replace('\n', "\r"));
    assert_eq!(parse_domain("d.pddl", &cr).unwrap().actions.len(), 1);
    let crlf = format!("; a comment\r\n{}", DOMAIN.replace('\n', "\r\n"));
    assert_eq!(parse_domain("d.pddl", &crlf).unwrap().actions.len(), 1);
    // Places count lines the same way with every ending: `(frees ?to)` on line 8.
    for nl in ["\n", "\r", "\r\n"] {
        let text = format!("; c{nl}{}", DOMAIN.replace("(free ?to)", "(frees ?to)").replace('\n', nl));
        let (msg, _) = domain_err(&text);
        assert!(msg.starts_with("d.pddl:8:"), "{nl:?}: {msg}");
    }
}
