//! `(define (domain NAME) ...)`: requirements, types, constants, predicates, functions,
//! actions and the rules of derived predicates.

use super::super::sexp::{Sexp, clip};
use super::super::{ErrorKind, Pos};
use super::formula::{Ctx, Owner, Scope};
use super::{R, Requirements, Typed, expected, list, model, sections, symbol, typed_list};
use crate::model::builder::{check_declared, check_variable};
use crate::model::{Domain, DomainBuilder, ModelError, TypeId, Var};

/// The type of a typed-list entry, making an `either` union when it names several.
fn type_of(b: &mut DomainBuilder, t: &Typed<'_>) -> R<TypeId> {
    for name in &t.ty {
        if b.names().type_id(name).is_none() {
            return Err((t.ty_pos, ErrorKind::Model(ModelError::UnknownType { name: clip(name) })));
        }
    }
    model(t.ty_pos, b.either(&t.ty))
}

/// Reads `(define (domain ...) ...)`.
pub fn domain(s: &Sexp, w: &mut Vec<(Pos, String)>) -> R<Domain> {
    let (name, name_pos, rest) = super::define(s, "domain")?;
    let secs = sections(
        rest,
        &[":requirements", ":types", ":constants", ":predicates", ":functions", ":action", ":derived"],
        &[],
        w,
    )?;
    let mut req = Requirements::default();
    for (_, _, items) in secs.iter().filter(|s| s.0 == ":requirements") {
        req.add(items)?;
    }
    let name = model(name_pos, check_declared(name, "a domain"))?;
    let mut b = DomainBuilder::new(&name);
    for (_, _, items) in secs.iter().filter(|s| s.0 == ":requirements") {
        items.iter().filter_map(Sexp::symbol).for_each(|r| b.requirement(r));
    }
    for (_, sec, items) in secs.iter().filter(|s| s.0 == ":types") {
        let typing = req.typing;
        req.need(typing, ":typing", "`:types`", sec.pos(), w);
        types(&mut b, items, &mut req, w)?;
    }
    for (_, _, items) in secs.iter().filter(|s| s.0 == ":constants") {
        for t in typed_list(items, false, &mut req, w)? {
            let ty = type_of(&mut b, &t)?;
            if t.ty.len() > 1 {
                return Err((t.ty_pos, ErrorKind::Unsupported("`either` as the type of a constant".into())));
            }
            model(t.pos, b.constants_of_type(&[t.name], ty))?;
        }
    }
    for (_, _, items) in secs.iter().filter(|s| s.0 == ":predicates") {
        for p in *items {
            predicate(&mut b, p, &mut req, w)?;
        }
    }
    for (_, _, items) in secs.iter().filter(|s| s.0 == ":functions") {
        functions(&mut b, items, &mut req, w)?;
    }
    let mut action_pos = Vec::new();
    for (_, sec, items) in secs.iter().filter(|s| s.0 == ":action") {
        action_pos.push(action(&mut b, sec, items, &mut req, w)?);
    }
    let mut rule_pos = Vec::new();
    for (_, sec, items) in secs.iter().filter(|s| s.0 == ":derived") {
        let have = req.derived;
        req.need(have, ":derived-predicates", "`:derived`", sec.pos(), w);
        rule_pos.push(derived(&mut b, sec, items, &mut req, w)?);
    }
    // Name the rule or action at fault.
    if let Err(e) = b.domain().check_derived() {
        let d = b.domain();
        let pos = match &e {
            ModelError::DerivedChanged { action, .. } => {
                d.actions.iter().position(|a| a.name == *action).map(|i| action_pos[i])
            }
            ModelError::NotStratifiable { predicate, through } => {
                // The rule of `predicate` that names `through`, else its first.
                let through = d.predicate(through);
                let names = |a: &crate::model::ActionTemplate| {
                    let mut found = false;
                    a.pre.iter().for_each(|c| c.for_each_literal(&mut |l| found |= Some(l.atom.predicate) == through));
                    found
                };
                let rules = || d.axioms.iter().enumerate().filter(|(_, a)| a.name == *predicate);
                rules().find(|(_, a)| names(a)).or_else(|| rules().next()).map(|(i, _)| rule_pos[i])
            }
            _ => None,
        };
        return Err((pos.unwrap_or(name_pos), ErrorKind::Model(e)));
    }
    model(name_pos, b.build())
}

/// The variables of a parameter list (an action's, or a derived predicate's head), and
/// their `(name, type name)` pairs for the builder.
fn scope_of(b: &mut DomainBuilder, typed: &[Typed<'_>], owner: &str) -> R<(Scope, Vec<(String, String)>)> {
    let mut scope = Scope { names: Vec::new(), types: Vec::new(), action: owner.to_string() };
    let mut pairs = Vec::with_capacity(typed.len());
    for (i, t) in typed.iter().enumerate() {
        let ty = type_of(b, t)?;
        let vname = model(t.pos, check_variable(t.name))?;
        let index = u8::try_from(i)
            .map_err(|_| (t.pos, ErrorKind::Model(ModelError::TooManyVariables { action: clip(owner) })))?;
        scope.names.push((vname.clone(), Var { index, ty }));
        scope.types.push(ty);
        pairs.push((vname, b.domain().types[usize::from(ty)].name.clone()));
    }
    Ok((scope, pairs))
}

/// `(:derived (p ?x - t ...) BODY)`: a rule making `p` true where `BODY` holds; returns
/// the position of its head.
fn derived(
    b: &mut DomainBuilder,
    sec: &Sexp,
    items: &[Sexp],
    req: &mut Requirements,
    w: &mut Vec<(Pos, String)>,
) -> R<Pos> {
    let shape = "`(:derived (predicate ?x - type ...) CONDITION)`";
    let [head, body] = items else {
        return expected(shape, sec);
    };
    let l = list(head, "the derived atom `(predicate ?x - type ...)`")?;
    let Some((name_s, params)) = l.split_first() else {
        return expected("the derived atom `(predicate ?x - type ...)`", head);
    };
    let name = symbol(name_s, "a predicate name")?;
    let typed = typed_list(params, true, req, w)?;
    let (mut scope, pairs) = scope_of(b, &typed, name)?;
    let pairs: Vec<(&str, &str)> = pairs.iter().map(|(n, t)| (n.as_str(), t.as_str())).collect();
    model(name_s.pos(), b.derived(name, &pairs).map(|_| ()))?;
    let id = b.domain().axioms.len() - 1;
    let mut owner = Owner::Domain(b);
    let mut ctx = Ctx { owner: &mut owner, req, warnings: w };
    let condition = ctx.condition(&mut scope, body, true)?;
    let Owner::Domain(b) = owner else { return Ok(head.pos()) };
    let mut rule = b.derived_mut(id);
    rule.set_vars(scope.types);
    match condition {
        crate::model::Condition::And(parts) => parts.into_iter().for_each(|c| {
            rule.condition(c);
        }),
        c => {
            rule.condition(c);
        }
    }
    Ok(head.pos())
}

fn types(b: &mut DomainBuilder, items: &[Sexp], req: &mut Requirements, w: &mut Vec<(Pos, String)>) -> R<()> {
    let list = typed_list(items, false, req, w)?;
    let mut ids = Vec::with_capacity(list.len());
    for t in &list {
        ids.push(model(t.pos, b.declare_type(t.name))?);
    }
    for (t, id) in list.iter().zip(ids) {
        let [parent] = t.ty[..] else {
            return Err((t.ty_pos, ErrorKind::Unsupported("`either` as a parent type".into())));
        };
        let parent = model(t.ty_pos, b.declare_type(parent))?;
        if parent != id && (parent != crate::model::OBJECT || id != crate::model::OBJECT) {
            model(t.pos, b.set_parent(id, parent))?;
        }
    }
    Ok(())
}

fn predicate(b: &mut DomainBuilder, p: &Sexp, req: &mut Requirements, w: &mut Vec<(Pos, String)>) -> R<()> {
    let l = list(p, "a predicate declaration `(name ?x - type ...)`")?;
    let Some((head, params)) = l.split_first() else {
        return expected("a predicate declaration `(name ?x - type ...)`", p);
    };
    let pname = symbol(head, "a predicate name")?;
    let typed = typed_list(params, true, req, w)?;
    let mut names: Vec<String> = Vec::with_capacity(typed.len());
    let mut types = Vec::with_capacity(typed.len());
    for t in &typed {
        let mut n = model(t.pos, check_variable(t.name))?;
        if names.contains(&n) {
            // Other planners take a repeated name here: only the position matters.
            let mut k = 2;
            while names.contains(&format!("{n}-{k}")) {
                k += 1;
            }
            w.push((
                t.pos,
                format!("`?{n}` repeated in the declaration of `{}`; the second is read as `?{n}-{k}`", clip(pname)),
            ));
            n = format!("{n}-{k}");
        }
        names.push(n);
        types.push(type_of(b, t)?);
    }
    let type_names: Vec<String> = types.iter().map(|&t| b.domain().types[usize::from(t)].name.clone()).collect();
    let pairs: Vec<(&str, &str)> =
        names.iter().map(String::as_str).zip(type_names.iter().map(String::as_str)).collect();
    model(head.pos(), b.predicate(pname, &pairs).map(|_| ()))
}

/// `(:functions (total-cost) - number (f ?x - t) ...)`: every function is a number.
fn functions(b: &mut DomainBuilder, items: &[Sexp], req: &mut Requirements, w: &mut Vec<(Pos, String)>) -> R<()> {
    let mut it = items.iter().peekable();
    while let Some(f) = it.next() {
        let l = list(f, "a function declaration `(name ?x - type ...)`")?;
        let Some((head, params)) = l.split_first() else {
            return expected("a function declaration `(name ?x - type ...)`", f);
        };
        let fname = symbol(head, "a function name")?;
        let typed = typed_list(params, true, req, w)?;
        let mut pairs = Vec::with_capacity(typed.len());
        for t in &typed {
            let ty = type_of(b, t)?;
            pairs.push((t.name, b.domain().types[usize::from(ty)].name.clone()));
        }
        let pairs: Vec<(&str, &str)> = pairs.iter().map(|(n, t)| (*n, t.as_str())).collect();
        model(head.pos(), b.function(fname, &pairs).map(|_| ()))?;
        if it.peek().and_then(|s| s.symbol()) == Some("-") {
            it.next();
            match it.next() {
                Some(t) if t.symbol() == Some("number") => {}
                Some(t) => return Err((t.pos(), ErrorKind::Unsupported(format!("function type {}", t.describe())))),
                None => {
                    return Err((
                        f.pos(),
                        ErrorKind::Expected { expected: "`number` after `-`".into(), found: "`)`".into() },
                    ));
                }
            }
        }
    }
    Ok(())
}

fn action(
    b: &mut DomainBuilder,
    sec: &Sexp,
    items: &[Sexp],
    req: &mut Requirements,
    w: &mut Vec<(Pos, String)>,
) -> R<Pos> {
    let Some((name_s, rest)) = items.split_first() else {
        return Err((sec.pos(), ErrorKind::Missing("action name".into())));
    };
    let name = symbol(name_s, "an action name")?;
    let mut params: Option<&Sexp> = None;
    let mut pre: Option<&Sexp> = None;
    let mut eff: Option<&Sexp> = None;
    let mut it = rest.iter();
    while let Some(k) = it.next() {
        let key = symbol(k, "`:parameters`, `:precondition` or `:effect`")?;
        let slot = match key {
            ":parameters" => &mut params,
            ":precondition" => &mut pre,
            ":effect" => &mut eff,
            _ => return expected("`:parameters`, `:precondition` or `:effect`", k),
        };
        if slot.is_some() {
            return Err((k.pos(), ErrorKind::Duplicate(key.to_string())));
        }
        let Some(v) = it.next() else {
            return Err((
                k.pos(),
                ErrorKind::Expected { expected: format!("a value after `{key}`"), found: "`)`".into() },
            ));
        };
        *slot = Some(v);
    }
    let typed = match params {
        Some(p) => typed_list(list(p, "a parameter list `(?x - type ...)`")?, true, req, w)?,
        None => Vec::new(),
    };
    let (mut scope, pairs) = scope_of(b, &typed, name)?;
    let pairs: Vec<(&str, &str)> = pairs.iter().map(|(n, t)| (n.as_str(), t.as_str())).collect();
    let id = b.domain().actions.len() as u16;
    model(name_s.pos(), b.action(name, &pairs).map(|_| ()))?;
    let mut owner = Owner::Domain(b);
    let mut ctx = Ctx { owner: &mut owner, req, warnings: w };
    let condition = match pre {
        Some(p) => Some(ctx.condition(&mut scope, p, true)?),
        None => None,
    };
    let mut effects = Vec::new();
    let mut cost = Vec::new();
    if let Some(e) = eff {
        ctx.effect(&mut scope, e, &[], &[], &mut effects, &mut cost)?;
    }
    if effects.is_empty() {
        return Err((name_s.pos(), ErrorKind::Model(ModelError::NoEffects { action: clip(name) })));
    }
    let Owner::Domain(b) = owner else { return Ok(name_s.pos()) };
    let mut ab = b.action_mut(id);
    ab.set_vars(scope.types);
    match condition {
        // A top-level conjunction keeps its parts as the precondition list.
        Some(crate::model::Condition::And(parts)) => parts.into_iter().for_each(|c| {
            ab.condition(c);
        }),
        Some(c) => {
            ab.condition(c);
        }
        None => {}
    }
    for e in effects {
        ab.effect_item(e);
    }
    for c in cost {
        ab.cost(c);
    }
    Ok(name_s.pos())
}
