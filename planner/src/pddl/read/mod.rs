//! Interpretation of the parenthesised structure as a domain or a problem.
//!
//! [`domain`] and [`problem`] read the sections; `formula` reads conditions, effects
//! and costs with the variables in scope.

mod domain;
mod formula;
mod problem;

pub use domain::domain;
pub use problem::problem;

use super::sexp::{Sexp, clip};
use super::{ErrorKind, Pos};
use crate::model::ModelError;

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

fn model<T>(pos: Pos, r: Result<T, ModelError>) -> R<T> {
    r.map_err(|e| (pos, ErrorKind::Model(e)))
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

/// The requirements a file declares, and the warnings already given for constructs
/// used without theirs.
#[derive(Default, Clone, Debug)]
pub(crate) struct Requirements {
    typing: bool,
    negative: bool,
    equality: bool,
    disjunctive: bool,
    existential: bool,
    universal: bool,
    conditional: bool,
    costs: bool,
    derived: bool,
    warned: Vec<&'static str>,
}

/// Requirements refused outright: what they bring is not in the model.
const REFUSED: &[&str] = &[
    ":fluents",
    ":numeric-fluents",
    ":object-fluents",
    ":durative-actions",
    ":duration-inequalities",
    ":continuous-effects",
    ":timed-initial-literals",
    ":timed-initial-fluents",
    ":preferences",
    ":constraints",
];

impl Requirements {
    fn add(&mut self, items: &[Sexp]) -> R<()> {
        for r in items {
            self.add_one(symbol(r, "a requirement such as `:strips`")?, r.pos())?;
        }
        Ok(())
    }

    /// Adds one requirement, `pos` naming it in errors.
    pub(crate) fn add_one(&mut self, name: &str, pos: Pos) -> R<()> {
        {
            match name {
                ":strips" => {}
                ":typing" => self.typing = true,
                ":negative-preconditions" => self.negative = true,
                ":disjunctive-preconditions" => self.disjunctive = true,
                ":equality" => self.equality = true,
                ":existential-preconditions" => self.existential = true,
                ":universal-preconditions" => self.universal = true,
                ":quantified-preconditions" => {
                    self.existential = true;
                    self.universal = true;
                }
                ":conditional-effects" => self.conditional = true,
                ":action-costs" => self.costs = true,
                ":derived-predicates" => self.derived = true,
                ":adl" => {
                    self.typing = true;
                    self.negative = true;
                    self.disjunctive = true;
                    self.equality = true;
                    self.existential = true;
                    self.universal = true;
                    self.conditional = true;
                }
                other if REFUSED.contains(&other) => {
                    return Err((pos, ErrorKind::UnsupportedRequirement(other.to_string())));
                }
                other => return Err((pos, ErrorKind::UnsupportedRequirement(clip(other)))),
            }
        }
        Ok(())
    }

    /// Records a warning at `pos` when `have` is false, once per requirement.
    fn need(&mut self, have: bool, requirement: &'static str, what: &str, pos: Pos, w: &mut Vec<(Pos, String)>) {
        if !have && !self.warned.contains(&requirement) {
            self.warned.push(requirement);
            w.push((pos, format!("{what} without `{requirement}` in :requirements (read as if it were there)")));
        }
    }
}

/// One entry of a typed list: name, its position, type (a name, or the members of an
/// `either`), and the type's position.
struct Typed<'a> {
    name: &'a str,
    pos: Pos,
    ty: Vec<&'a str>,
    ty_pos: Pos,
}

/// `a b - t c - u d` (names) or `?a ?b - t` (variables); untyped entries are `object`.
/// A type may be `(either t u ...)`.
fn typed_list<'a>(
    items: &'a [Sexp],
    variables: bool,
    req: &mut Requirements,
    w: &mut Vec<(Pos, String)>,
) -> R<Vec<Typed<'a>>> {
    let what = if variables { "a variable `?name`" } else { "a name" };
    let mut out: Vec<Typed<'a>> = Vec::new();
    let mut pending = 0usize;
    let mut it = items.iter();
    while let Some(s) = it.next() {
        let text = symbol(s, what)?;
        if text == "-" {
            let typing = req.typing;
            req.need(typing, ":typing", "a typed list", s.pos(), w);
            let Some(ty) = it.next() else {
                return Err((
                    s.pos(),
                    ErrorKind::Expected { expected: "a type after `-`".into(), found: "`)`".into() },
                ));
            };
            let names: Vec<&str> = match ty {
                Sexp::Symbol(name, _) => vec![name.as_str()],
                Sexp::List(l, _) if l.first().and_then(Sexp::symbol) == Some("either") && l.len() > 1 => {
                    l[1..].iter().map(|m| symbol(m, "a type name")).collect::<R<Vec<_>>>()?
                }
                _ => return expected("a type name or `(either ...)`", ty),
            };
            if pending == 0 {
                return expected(what, ty);
            }
            let len = out.len();
            for t in out.iter_mut().skip(len - pending) {
                t.ty.clone_from(&names);
                t.ty_pos = ty.pos();
            }
            pending = 0;
            continue;
        }
        if variables != text.starts_with('?') {
            return expected(what, s);
        }
        out.push(Typed { name: text, pos: s.pos(), ty: vec!["object"], ty_pos: s.pos() });
        pending += 1;
    }
    Ok(out)
}

/// Splits `sections` by their keyword, refusing unknown and repeated ones (`:action`
/// and `:derived` may repeat). `ignored` sections are skipped with a warning.
fn sections<'a>(
    sections: &'a [Sexp],
    known: &[&str],
    ignored: &[&str],
    w: &mut Vec<(Pos, String)>,
) -> R<Vec<(&'a str, &'a Sexp, &'a [Sexp])>> {
    let mut out: Vec<(&str, &Sexp, &[Sexp])> = Vec::new();
    for s in sections {
        let items = list(s, "a section such as `(:predicates ...)`")?;
        let Some(head) = items.first() else {
            return expected("a section such as `(:predicates ...)`", s);
        };
        let name = symbol(head, "a section keyword")?;
        if known.contains(&name) {
            if name != ":action" && name != ":derived" && out.iter().any(|o| o.0 == name) {
                return Err((head.pos(), ErrorKind::Duplicate(name.to_string())));
            }
            out.push((name, s, &items[1..]));
        } else if ignored.contains(&name) {
            w.push((head.pos(), format!("`{name}` section ignored")));
        } else if name.starts_with(':') {
            let what = match name {
                ":durative-action" => ":durative-action (temporal planning)".to_string(),
                other => clip(other),
            };
            return Err((head.pos(), ErrorKind::Unsupported(what)));
        } else {
            return expected(&format!("a section ({})", known.join(", ")), head);
        }
    }
    Ok(out)
}
