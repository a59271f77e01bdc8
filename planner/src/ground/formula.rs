//! Conditions under a binding of their variables: relaxed truth (for reachability) and
//! the disjunctive normal form over ground literals (to compile ADL away).
//!
//! Recursion follows the formula's nesting, which the PDDL reader bounds.

use crate::model::{Condition, Literal, ObjectId, Term, Var};

use super::action::Lit;
use super::tables::{Atoms, Objects, UNBOUND, key_into};

/// A formula in disjunctive normal form: alternatives, each a conjunction of literals.
/// No alternatives is false; one empty alternative is true.
pub(super) type Dnf = Vec<Vec<Lit>>;

/// More alternatives than the limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct TooManyAlternatives;

/// What a literal's atom is worth under the tables.
enum Truth {
    Const(bool),
    Lit(Lit),
}

/// Reads formulas against the objects, the atoms met so far and the static predicates.
pub(super) struct Eval<'a> {
    pub(super) objects: &'a Objects,
    pub(super) atoms: &'a Atoms,
    pub(super) statics: &'a [bool],
    pub(super) key: Vec<u16>,
    /// With `Some`: collects the keys of atoms met in a literal but never registered
    /// (for goals, whose atoms get ids even when unreachable).
    pub(super) missing: Option<Vec<Box<[u16]>>>,
}

pub(super) fn term(t: Term, binding: &[ObjectId]) -> ObjectId {
    match t {
        Term::Object(o) => o,
        Term::Var(v) => binding.get(usize::from(v)).copied().unwrap_or(UNBOUND),
    }
}

impl Eval<'_> {
    fn literal(&mut self, l: &Literal<Term>, binding: &[ObjectId]) -> Truth {
        key_into(&mut self.key, l.atom.predicate, l.atom.args.iter().map(|&t| term(t, binding)));
        let is_static = self.statics.get(usize::from(l.atom.predicate)).copied().unwrap_or(false);
        match self.atoms.get(&self.key) {
            Some(a) if is_static => Truth::Const(self.atoms.in_init(a) == l.positive),
            Some(a) => Truth::Lit(Lit { atom: a, positive: l.positive }),
            None => {
                if let Some(m) = self.missing.as_mut() {
                    m.push(self.key.as_slice().into());
                }
                Truth::Const(!l.positive)
            }
        }
    }

    /// Relaxed truth: a positive literal holds when its atom was reached, a negative
    /// one unless its atom is static and true. Monotone in the atoms reached.
    pub(super) fn relaxed(&mut self, c: &Condition, binding: &mut Vec<ObjectId>) -> bool {
        match c {
            Condition::Literal(l) => match self.literal(l, binding) {
                Truth::Const(b) => b,
                Truth::Lit(_) => true,
            },
            Condition::Equal { positive, left, right } => (term(*left, binding) == term(*right, binding)) == *positive,
            Condition::And(parts) => parts.iter().all(|p| self.relaxed(p, binding)),
            Condition::Or(parts) => parts.iter().any(|p| self.relaxed(p, binding)),
            Condition::Forall(vars, body) => {
                let mut all = true;
                self.bindings(vars, binding, &mut |e, b| {
                    all = e.relaxed(body, b);
                    all
                });
                all
            }
            Condition::Exists(vars, body) => {
                let mut any = false;
                self.bindings(vars, binding, &mut |e, b| {
                    any = e.relaxed(body, b);
                    !any
                });
                any
            }
        }
    }

    /// Calls `f` with each binding of `vars` over their types' objects, while it
    /// returns true; restores the binding afterwards.
    pub(super) fn bindings(
        &mut self,
        vars: &[Var],
        binding: &mut Vec<ObjectId>,
        f: &mut dyn FnMut(&mut Self, &mut Vec<ObjectId>) -> bool,
    ) {
        for v in vars {
            if binding.len() <= usize::from(v.index) {
                binding.resize(usize::from(v.index) + 1, UNBOUND);
            }
        }
        let saved: Vec<ObjectId> = vars.iter().map(|v| binding[usize::from(v.index)]).collect();
        let lists: Vec<&[ObjectId]> = vars.iter().map(|v| self.objects.of(v.ty)).collect();
        if lists.iter().all(|l| !l.is_empty()) {
            let mut at = vec![0usize; vars.len()];
            'outer: loop {
                for (i, v) in vars.iter().enumerate() {
                    binding[usize::from(v.index)] = lists[i][at[i]];
                }
                if !f(self, binding) {
                    break;
                }
                let mut i = vars.len();
                loop {
                    if i == 0 {
                        break 'outer;
                    }
                    i -= 1;
                    at[i] += 1;
                    if at[i] < lists[i].len() {
                        break;
                    }
                    at[i] = 0;
                }
            }
        }
        for (v, s) in vars.iter().zip(saved) {
            binding[usize::from(v.index)] = s;
        }
    }

    /// The formula under `binding` in disjunctive normal form over ground literals:
    /// static atoms are replaced by their truth, atoms never reached by false.
    pub(super) fn dnf(
        &mut self,
        c: &Condition,
        binding: &mut Vec<ObjectId>,
        limit: usize,
    ) -> Result<Dnf, TooManyAlternatives> {
        match c {
            Condition::Literal(l) => Ok(match self.literal(l, binding) {
                Truth::Const(true) => vec![Vec::new()],
                Truth::Const(false) => Vec::new(),
                Truth::Lit(lit) => vec![vec![lit]],
            }),
            Condition::Equal { positive, left, right } => {
                let holds = (term(*left, binding) == term(*right, binding)) == *positive;
                Ok(if holds { vec![Vec::new()] } else { Vec::new() })
            }
            Condition::And(parts) => {
                let mut acc: Dnf = vec![Vec::new()];
                for p in parts {
                    let d = self.dnf(p, binding, limit)?;
                    acc = and(&acc, &d, limit)?;
                    if acc.is_empty() {
                        break;
                    }
                }
                Ok(acc)
            }
            Condition::Or(parts) => {
                let mut acc: Dnf = Vec::new();
                for p in parts {
                    let d = self.dnf(p, binding, limit)?;
                    or(&mut acc, d, limit)?;
                    if acc.iter().any(Vec::is_empty) {
                        return Ok(vec![Vec::new()]);
                    }
                }
                Ok(acc)
            }
            Condition::Forall(vars, body) => {
                let mut acc: Result<Dnf, TooManyAlternatives> = Ok(vec![Vec::new()]);
                self.bindings(vars, binding, &mut |e, b| {
                    let next = match &acc {
                        Ok(a) => e.dnf(body, b, limit).and_then(|d| and(a, &d, limit)),
                        Err(x) => Err(*x),
                    };
                    let go = next.as_ref().is_ok_and(|a| !a.is_empty());
                    acc = next;
                    go
                });
                acc
            }
            Condition::Exists(vars, body) => {
                let mut acc: Result<Dnf, TooManyAlternatives> = Ok(Vec::new());
                self.bindings(vars, binding, &mut |e, b| {
                    let next = match std::mem::replace(&mut acc, Ok(Vec::new())) {
                        Ok(mut a) => e.dnf(body, b, limit).and_then(|d| or(&mut a, d, limit).map(|()| a)),
                        Err(x) => Err(x),
                    };
                    let go = next.as_ref().is_ok_and(|a| !a.iter().any(Vec::is_empty));
                    acc = next;
                    go
                });
                acc.map(|a| if a.iter().any(Vec::is_empty) { vec![Vec::new()] } else { a })
            }
        }
    }
}

/// The conjunction of two formulas in DNF, dropping contradictory alternatives.
fn and(a: &Dnf, b: &Dnf, limit: usize) -> Result<Dnf, TooManyAlternatives> {
    let mut out: Dnf = Vec::new();
    for x in a {
        'next: for y in b {
            let mut c = x.clone();
            for &l in y {
                if c.contains(&l.negated()) {
                    continue 'next;
                }
                if !c.contains(&l) {
                    c.push(l);
                }
            }
            if !out.contains(&c) {
                if out.len() >= limit {
                    return Err(TooManyAlternatives);
                }
                out.push(c);
            }
        }
    }
    Ok(out)
}

/// Adds the alternatives of `b` to `a`.
fn or(a: &mut Dnf, b: Dnf, limit: usize) -> Result<(), TooManyAlternatives> {
    for c in b {
        if !a.contains(&c) {
            if a.len() >= limit {
                return Err(TooManyAlternatives);
            }
            a.push(c);
        }
    }
    Ok(())
}
