//! `(define (problem NAME) ...)`: objects, initial state, goal and metric.

use super::super::sexp::{Sexp, clip};
use super::super::{ErrorKind, Pos};
use super::formula::{Ctx, Owner, Scope, is_keyword, number};
use super::{R, Requirements, expected, list, model, sections, symbol, typed_list};
use crate::model::builder::check_declared;
use crate::model::{Atom, Condition, Domain, ModelError, Problem, ProblemBuilder};

/// Reads `(define (problem ...) ...)` over `domain`.
pub fn problem(s: &Sexp, domain: &Domain, w: &mut Vec<(Pos, String)>) -> R<Problem> {
    let (name, name_pos, rest) = super::define(s, "problem")?;
    let name = model(name_pos, check_declared(name, "a problem"))?;
    let secs = sections(rest, &[":domain", ":requirements", ":objects", ":init", ":goal", ":metric"], &[":length"], w)?;
    // A problem reads its conditions with the domain's requirements and its own: a
    // construct that neither declares (a negative goal without
    // `:negative-preconditions`) is read with a warning, as in a domain.
    let mut req = Requirements::default();
    for r in &domain.requirements {
        req.add_one(r, name_pos)?;
    }
    for (_, _, items) in secs.iter().filter(|s| s.0 == ":requirements") {
        req.add(items)?;
    }
    let Some((_, dsec, ditems)) = secs.iter().find(|s| s.0 == ":domain") else {
        return Err((s.pos(), ErrorKind::Missing("(:domain NAME)".into())));
    };
    let [dname] = ditems else {
        return expected("`(:domain NAME)`", dsec);
    };
    let dn = symbol(dname, "the domain's name")?;
    if dn != domain.name {
        let e = ModelError::DomainMismatch { problem: clip(dn), domain: domain.name.clone() };
        return Err((dname.pos(), ErrorKind::Model(e)));
    }
    let mut b = ProblemBuilder::new(&name, domain);
    for (_, _, items) in secs.iter().filter(|s| s.0 == ":objects") {
        for t in typed_list(items, false, &mut req, w)? {
            let [ty] = t.ty[..] else {
                return Err((t.ty_pos, ErrorKind::Unsupported("`either` as the type of an object".into())));
            };
            let Some(ty) = b.names().type_id(ty) else {
                return Err((t.ty_pos, ErrorKind::Model(ModelError::UnknownType { name: clip(ty) })));
            };
            model(t.pos, b.object_of_type(t.name, ty).map(|_| ()))?;
        }
    }
    for (_, _, items) in secs.iter().filter(|s| s.0 == ":init") {
        for a in *items {
            init(&mut b, a)?;
        }
    }
    if let Some((_, msec, mitems)) = secs.iter().find(|s| s.0 == ":metric") {
        match mitems {
            [dir, what] if dir.symbol() == Some("minimize") && what.head() == Some("total-cost") => {
                b.minimize_total_cost();
            }
            _ => {
                return Err((msec.pos(), ErrorKind::Unsupported("a metric other than `minimize (total-cost)`".into())));
            }
        }
    }
    let Some((_, gsec, gitems)) = secs.iter().find(|s| s.0 == ":goal") else {
        return Err((s.pos(), ErrorKind::Missing("(:goal ...)".into())));
    };
    let [g] = gitems else {
        return expected("`(:goal CONDITION)` with one condition", gsec);
    };
    let mut scope = Scope { names: Vec::new(), types: Vec::new(), action: "the goal".into() };
    let goal = {
        let mut owner = Owner::Problem(&b);
        let mut ctx = Ctx { owner: &mut owner, req: &mut req, warnings: w };
        ctx.condition(&mut scope, g, true)?
    };
    match goal {
        Condition::And(parts) if !parts.is_empty() => parts.into_iter().for_each(|c| {
            b.goal_condition(c);
        }),
        c => {
            b.goal_condition(c);
        }
    }
    model(gsec.pos(), b.build())
}

/// One entry of `:init`: an atom, or `(= (f objects...) N)`.
fn init(b: &mut ProblemBuilder, a: &Sexp) -> R<()> {
    let items = list(a, "an atom `(p obj ...)`")?;
    match items.first().and_then(Sexp::symbol) {
        Some("not") => return Err((a.pos(), ErrorKind::Model(ModelError::NegativeInit))),
        Some("=") => return function_value(b, a, &items[1..]),
        Some("at") if items.get(1).is_some_and(|x| x.symbol().is_some_and(|n| n.parse::<f64>().is_ok())) => {
            return Err((a.pos(), ErrorKind::Unsupported("timed initial literal `(at N ...)`".into())));
        }
        Some(h) if is_keyword(h) => return Err((a.pos(), ErrorKind::Unsupported(format!("`{}` in :init", clip(h))))),
        _ => {}
    }
    let scope = Scope { names: Vec::new(), types: Vec::new(), action: "the initial state".into() };
    let atom = {
        let mut req = Requirements::default();
        let mut w = Vec::new();
        let mut owner = Owner::Problem(b);
        let ctx = Ctx { owner: &mut owner, req: &mut req, warnings: &mut w };
        ctx.atom(&scope, a)?
    };
    let args = atom
        .args
        .iter()
        .map(|t| match t {
            crate::model::Term::Object(o) => *o,
            crate::model::Term::Var(_) => 0,
        })
        .collect();
    b.init_atom(Atom { predicate: atom.predicate, args });
    Ok(())
}

/// `(= (f objects...) N)` in `:init`.
fn function_value(b: &mut ProblemBuilder, a: &Sexp, rest: &[Sexp]) -> R<()> {
    let [term, value] = rest else {
        return expected("`(= (function objects...) NUMBER)`", a);
    };
    let items = list(term, "a function term `(f objects...)`")?;
    let Some((head, args)) = items.split_first() else {
        return expected("a function term `(f objects...)`", term);
    };
    let fname = symbol(head, "a function name")?;
    let Some(function) = b.names().function(fname) else {
        return Err((head.pos(), ErrorKind::Model(ModelError::UnknownFunction { name: clip(fname) })));
    };
    let value_text = symbol(value, "a number")?;
    let v = number(value_text, value.pos())?;
    if fname == "total-cost" {
        return Ok(());
    }
    let mut objs = Vec::with_capacity(args.len());
    for x in args {
        let n = symbol(x, "an object name")?;
        let o = b.object(n).ok_or((x.pos(), ErrorKind::Model(ModelError::UnknownObject { name: clip(n) })))?;
        objs.push(o);
    }
    let arity = b.problem().domain.functions[usize::from(function)].params.len();
    if arity != objs.len() {
        let e = ModelError::WrongArity { predicate: clip(fname), expected: arity, found: objs.len() };
        return Err((term.pos(), ErrorKind::Model(e)));
    }
    model(a.pos(), b.function_value(function, objs, v))
}
