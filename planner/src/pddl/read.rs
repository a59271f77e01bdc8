//! Interpretation of the parenthesised structure as a domain or a problem.

use super::sexp::Sexp;
use super::{ErrorKind, Pos};
use crate::model::{Domain, DomainBuilder, ModelError, Problem, ProblemBuilder};

type R<T> = Result<T, (Pos, ErrorKind)>;

fn expected<T>(what: &str, found: &Sexp) -> R<T> {
    Err((found.pos(), ErrorKind::Expected { expected: what.to_string(), found: found.describe() }))
}

fn list<'a>(s: &'a Sexp, what: &str) -> R<&'a [Sexp]> {
    match s.list() {
        Some(l) => Ok(l),
        None => expected(what, s),
    }
}

fn symbol<'a>(s: &'a Sexp, what: &str) -> R<&'a str> {
    match s.symbol() {
        Some(l) => Ok(l),
        None => expected(what, s),
    }
}

/// `(define (KIND NAME) sections...)`: returns the name and the sections.
fn define<'a>(s: &'a Sexp, kind: &str) -> R<(&'a str, Pos, &'a [Sexp])> {
    let shape = format!("`(define ({kind} NAME) ...)`");
    let items = list(s, &shape)?;
    let Some((head, rest)) = items.split_first() else {
        return expected(&shape, s);
    };
    if head.symbol() != Some("define") {
        return expected("`define`", head);
    }
    let Some((decl, sections)) = rest.split_first() else {
        return Err((s.pos(), ErrorKind::Missing(format!("({kind} NAME)"))));
    };
    let d = list(decl, &format!("`({kind} NAME)`"))?;
    match d {
        [k, name] if k.symbol() == Some(kind) => Ok((symbol(name, "a name")?, name.pos(), sections)),
        [k, ..] if k.symbol() != Some(kind) => expected(&format!("`{kind}`"), k),
        _ => expected(&format!("`({kind} NAME)`"), decl),
    }
}

fn model<T>(pos: Pos, r: Result<T, ModelError>) -> R<T> {
    r.map_err(|e| (pos, ErrorKind::Model(e)))
}

/// Where in an atom `(p a b)` a model error points: the argument it names, else the
/// predicate name.
fn locate(err: &ModelError, atom: &[Sexp], fallback: Pos) -> Pos {
    let named = match err {
        ModelError::UnknownParameter { name, .. } => Some(format!("?{name}")),
        ModelError::UnknownObject { name } => Some(name.clone()),
        ModelError::TypeMismatch { argument, .. } => Some(argument.clone()),
        ModelError::UnknownPredicate { .. } => return atom.first().map_or(fallback, Sexp::pos),
        _ => None,
    };
    named
        .and_then(|n| atom.iter().skip(1).find(|s| s.symbol() == Some(n.as_str()) || s.symbol() == n.strip_prefix('?')))
        .map_or(fallback, Sexp::pos)
}

#[derive(Default)]
struct Requirements {
    typing: bool,
    negative: bool,
}

fn requirements(items: &[Sexp], req: &mut Requirements) -> R<()> {
    for r in items {
        match symbol(r, "a requirement such as `:strips`")? {
            ":strips" => {}
            ":typing" => req.typing = true,
            ":negative-preconditions" => req.negative = true,
            other => return Err((r.pos(), ErrorKind::UnsupportedRequirement(other.to_string()))),
        }
    }
    Ok(())
}

/// One entry of a typed list: name, its position, type name, its position.
struct Typed<'a> {
    name: &'a str,
    pos: Pos,
    ty: &'a str,
    ty_pos: Pos,
}

/// `a b - t c - u d` (names) or `?a ?b - t` (variables); untyped entries are `object`.
fn typed_list<'a>(items: &'a [Sexp], variables: bool, req: &Requirements) -> R<Vec<Typed<'a>>> {
    let what = if variables { "a parameter `?name`" } else { "a name" };
    let mut out = Vec::new();
    let mut pending = 0usize;
    let mut it = items.iter();
    while let Some(s) = it.next() {
        let text = symbol(s, what)?;
        if text == "-" {
            if !req.typing {
                return Err((s.pos(), ErrorKind::TypingNeedsRequirement));
            }
            let Some(ty) = it.next() else {
                return Err((
                    s.pos(),
                    ErrorKind::Expected { expected: "a type after `-`".into(), found: "`)`".into() },
                ));
            };
            if ty.list().is_some_and(|l| l.first().and_then(Sexp::symbol) == Some("either")) {
                return Err((ty.pos(), ErrorKind::Unsupported("either".into())));
            }
            let name = symbol(ty, "a type name")?;
            if pending == 0 {
                return expected(what, ty);
            }
            let len = out.len();
            for t in out.iter_mut().skip(len - pending) {
                let t: &mut Typed<'a> = t;
                t.ty = name;
                t.ty_pos = ty.pos();
            }
            pending = 0;
            continue;
        }
        if variables != text.starts_with('?') {
            return expected(what, s);
        }
        out.push(Typed { name: text, pos: s.pos(), ty: "object", ty_pos: s.pos() });
        pending += 1;
    }
    Ok(out)
}

/// Checks that each named type exists, pointing at the type's position.
fn check_types(domain: &Domain, list: &[Typed<'_>]) -> R<()> {
    for t in list {
        if domain.type_id(t.ty).is_none() {
            return Err((t.ty_pos, ErrorKind::Model(ModelError::UnknownType { name: t.ty.to_string() })));
        }
    }
    Ok(())
}

/// A literal of a formula: polarity and the atom list `(p args...)`.
struct Lit<'a> {
    positive: bool,
    atom: &'a [Sexp],
    pos: Pos,
}

/// Flattens `()`, `(and ...)`, `(not ATOM)` and atoms into literals.
fn literals<'a>(f: &'a Sexp, out: &mut Vec<Lit<'a>>, negative_ok: Option<bool>) -> R<()> {
    let items = list(f, "a condition such as `(p ?x)`, `(not (p ?x))` or `(and ...)`")?;
    let Some(head) = items.first() else {
        return Ok(());
    };
    let name = symbol(head, "a predicate name, `and` or `not`")?;
    match name {
        "and" => {
            for sub in &items[1..] {
                literals(sub, out, negative_ok)?;
            }
            Ok(())
        }
        "not" => {
            if negative_ok == Some(false) {
                return Err((head.pos(), ErrorKind::NegativeNeedsRequirement));
            }
            let [_, inner] = items else {
                return expected("`(not (p ...))` with exactly one atom", f);
            };
            let atom = list(inner, "an atom `(p ...)`")?;
            match atom.first().and_then(Sexp::symbol) {
                Some(h) if is_keyword(h) => Err((inner.pos(), ErrorKind::Unsupported(h.to_string()))),
                Some(_) => {
                    out.push(Lit { positive: false, atom, pos: inner.pos() });
                    Ok(())
                }
                None => expected("an atom `(p ...)`", inner),
            }
        }
        h if is_keyword(h) => Err((head.pos(), ErrorKind::Unsupported(h.to_string()))),
        _ => {
            out.push(Lit { positive: true, atom: items, pos: f.pos() });
            Ok(())
        }
    }
}

fn is_keyword(h: &str) -> bool {
    matches!(
        h,
        "and" | "or" | "not" | "imply" | "exists" | "forall" | "when" | "=" | "increase" | "decrease" | "assign"
    ) || h.starts_with(':')
}

/// The argument names of an atom, checked to be symbols.
fn atom_args(atom: &[Sexp], variables: bool) -> R<(&str, Vec<&str>)> {
    let Some((head, rest)) = atom.split_first() else {
        return Err((
            Pos { line: 0, column: 0 },
            ErrorKind::Expected { expected: "an atom".into(), found: "`()`".into() },
        ));
    };
    let name = symbol(head, "a predicate name")?;
    let what = if variables { "a parameter `?name` (this reader has no constants)" } else { "an object name" };
    let mut args = Vec::with_capacity(rest.len());
    for a in rest {
        let s = symbol(a, what)?;
        if variables != s.starts_with('?') {
            return expected(what, a);
        }
        args.push(s);
    }
    Ok((name, args))
}

fn sections<'a>(sections: &'a [Sexp], known: &[&str]) -> R<Vec<(&'a str, &'a Sexp, &'a [Sexp])>> {
    let mut out: Vec<(&str, &Sexp, &[Sexp])> = Vec::new();
    for s in sections {
        let items = list(s, "a section such as `(:predicates ...)`")?;
        let Some(head) = items.first() else {
            return expected("a section such as `(:predicates ...)`", s);
        };
        let name = symbol(head, "a section keyword")?;
        if known.contains(&name) {
            if name != ":action" && out.iter().any(|o| o.0 == name) {
                return Err((head.pos(), ErrorKind::Duplicate(name.to_string())));
            }
            out.push((name, s, &items[1..]));
        } else if name.starts_with(':') {
            return Err((head.pos(), ErrorKind::Unsupported(name.to_string())));
        } else {
            return expected(&format!("a section ({})", known.join(", ")), head);
        }
    }
    Ok(out)
}

/// Reads `(define (domain ...) ...)`.
pub fn domain(s: &Sexp) -> R<Domain> {
    let (name, name_pos, rest) = define(s, "domain")?;
    let secs = sections(rest, &[":requirements", ":types", ":predicates", ":action"])?;
    let mut req = Requirements::default();
    for (_, _, items) in secs.iter().filter(|s| s.0 == ":requirements") {
        requirements(items, &mut req)?;
    }
    let mut b = DomainBuilder::new(name);
    model(name_pos, crate::model::builder::check_name(name))?;
    for (_, sec, items) in secs.iter().filter(|s| s.0 == ":types") {
        if !req.typing {
            return Err((sec.pos(), ErrorKind::TypingNeedsRequirement));
        }
        let list = typed_list(items, false, &req)?;
        let mut ids = Vec::with_capacity(list.len());
        for t in &list {
            ids.push(model(t.pos, b.declare_type(t.name))?);
        }
        for (t, id) in list.iter().zip(ids) {
            let parent = model(t.ty_pos, b.declare_type(t.ty))?;
            if t.ty != "object" || t.name != "object" {
                model(t.pos, b.set_parent(id, parent))?;
            }
        }
    }
    for (_, _, items) in secs.iter().filter(|s| s.0 == ":predicates") {
        for p in *items {
            let l = list(p, "a predicate declaration `(name ?x - type ...)`")?;
            let Some((head, params)) = l.split_first() else {
                return expected("a predicate declaration `(name ?x - type ...)`", p);
            };
            let pname = symbol(head, "a predicate name")?;
            let typed = typed_list(params, true, &req)?;
            check_types(b.domain(), &typed)?;
            let pairs: Vec<(&str, &str)> = typed.iter().map(|t| (t.name, t.ty)).collect();
            model(head.pos(), b.predicate(pname, &pairs).map(|_| ()))?;
        }
    }
    for (_, sec, items) in secs.iter().filter(|s| s.0 == ":action") {
        action(&mut b, sec, items, &req)?;
    }
    model(name_pos, b.build())
}

fn action(b: &mut DomainBuilder, sec: &Sexp, items: &[Sexp], req: &Requirements) -> R<()> {
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
        Some(p) => typed_list(list(p, "a parameter list `(?x - type ...)`")?, true, req)?,
        None => Vec::new(),
    };
    check_types(b.domain(), &typed)?;
    let pairs: Vec<(&str, &str)> = typed.iter().map(|t| (t.name, t.ty)).collect();
    let id = {
        let before = b.domain().actions.len();
        model(name_s.pos(), b.action(name, &pairs).map(|_| ()))?;
        before as u16
    };
    let mut lits = Vec::new();
    if let Some(p) = pre {
        literals(p, &mut lits, Some(req.negative))?;
    }
    let npre = lits.len();
    if let Some(e) = eff {
        literals(e, &mut lits, None)?;
    }
    if lits.len() == npre {
        return Err((name_s.pos(), ErrorKind::Model(ModelError::NoEffects { action: name.to_string() })));
    }
    let mut ab = b.action_mut(id);
    for (i, l) in lits.iter().enumerate() {
        let (pred, args) = atom_args(l.atom, true)?;
        let r = match (i < npre, l.positive) {
            (true, true) => ab.pre(pred, &args).map(|_| ()),
            (true, false) => ab.pre_not(pred, &args).map(|_| ()),
            (false, true) => ab.effect(pred, &args).map(|_| ()),
            (false, false) => ab.effect_not(pred, &args).map(|_| ()),
        };
        if let Err(e) = r {
            return Err((locate(&e, l.atom, l.pos), ErrorKind::Model(e)));
        }
    }
    Ok(())
}

/// Reads `(define (problem ...) ...)` over `domain`.
pub fn problem(s: &Sexp, domain: &Domain) -> R<Problem> {
    let (name, name_pos, rest) = define(s, "problem")?;
    model(name_pos, crate::model::builder::check_name(name))?;
    let secs = sections(rest, &[":domain", ":requirements", ":objects", ":init", ":goal"])?;
    let mut req = Requirements { typing: true, negative: true };
    for (_, _, items) in secs.iter().filter(|s| s.0 == ":requirements") {
        requirements(items, &mut req)?;
    }
    let Some((_, dsec, ditems)) = secs.iter().find(|s| s.0 == ":domain") else {
        return Err((s.pos(), ErrorKind::Missing("(:domain NAME)".into())));
    };
    let [dname] = ditems else {
        return expected("`(:domain NAME)`", dsec);
    };
    let dn = symbol(dname, "the domain's name")?;
    if dn != domain.name {
        let e = ModelError::DomainMismatch { problem: dn.to_string(), domain: domain.name.clone() };
        return Err((dname.pos(), ErrorKind::Model(e)));
    }
    let mut b = ProblemBuilder::new(name, domain);
    for (_, _, items) in secs.iter().filter(|s| s.0 == ":objects") {
        for t in typed_list(items, false, &req)? {
            if domain.type_id(t.ty).is_none() {
                return Err((t.ty_pos, ErrorKind::Model(ModelError::UnknownType { name: t.ty.to_string() })));
            }
            model(t.pos, b.objects(&[t.name], t.ty).map(|_| ()))?;
        }
    }
    for (_, _, items) in secs.iter().filter(|s| s.0 == ":init") {
        for a in *items {
            let atom = list(a, "an atom `(p obj ...)`")?;
            match atom.first().and_then(Sexp::symbol) {
                Some("not") => return Err((a.pos(), ErrorKind::Model(ModelError::NegativeInit))),
                Some(h) if is_keyword(h) => return Err((a.pos(), ErrorKind::Unsupported(h.to_string()))),
                _ => {}
            }
            let (pred, args) =
                atom_args(atom, false).map_err(|(p, k)| if p.line == 0 { (a.pos(), k) } else { (p, k) })?;
            if let Err(e) = b.init(pred, &args) {
                return Err((locate(&e, atom, a.pos()), ErrorKind::Model(e)));
            }
        }
    }
    let Some((_, gsec, gitems)) = secs.iter().find(|s| s.0 == ":goal") else {
        return Err((s.pos(), ErrorKind::Missing("(:goal ...)".into())));
    };
    let [g] = gitems else {
        return expected("`(:goal CONDITION)` with one condition", gsec);
    };
    let mut lits = Vec::new();
    literals(g, &mut lits, None)?;
    for l in &lits {
        let (pred, args) = atom_args(l.atom, false).map_err(|(p, k)| if p.line == 0 { (l.pos, k) } else { (p, k) })?;
        let r = if l.positive { b.goal(pred, &args) } else { b.goal_not(pred, &args) };
        if let Err(e) = r {
            return Err((locate(&e, l.atom, l.pos), ErrorKind::Model(e)));
        }
    }
    model(gsec.pos(), b.build())
}
