//! Conditions (goal descriptions), effects and action costs, read into the model's
//! negation normal form with the variables in scope.

use super::super::sexp::{Sexp, clip};
use super::{ErrorKind, Pos, R, Requirements, expected, list, model, symbol};
use crate::model::builder::{NamesRef, atom_of, check_variable};
use crate::model::{
    Atom, Condition, CostTerm, Domain, DomainBuilder, Effect, Literal, ModelError, ObjectId, ProblemBuilder, Term,
    TypeId, Var,
};

/// Where the formula is: conditions there may use objects (goals) or constants only
/// (actions), and new `either` types can be made only while the domain is read.
pub(super) enum Owner<'a> {
    Domain(&'a mut DomainBuilder),
    Problem(&'a ProblemBuilder),
}

impl Owner<'_> {
    fn domain(&self) -> &Domain {
        match self {
            Self::Domain(b) => b.domain(),
            Self::Problem(b) => &b.problem().domain,
        }
    }

    fn names(&self) -> NamesRef<'_> {
        match self {
            Self::Domain(b) => b.names(),
            Self::Problem(b) => b.names(),
        }
    }

    fn object(&self, name: &str) -> Option<(ObjectId, TypeId)> {
        match self {
            Self::Domain(b) => {
                let c = b.names().constant(name)?;
                Some((c, b.domain().constants.get(usize::from(c))?.ty))
            }
            Self::Problem(b) => {
                let o = b.object(name)?;
                Some((o, b.problem().objects.get(usize::from(o))?.ty))
            }
        }
    }

    fn type_of(&mut self, names: &[&str], pos: Pos) -> R<TypeId> {
        match self {
            Self::Domain(b) => model(pos, b.either(names)),
            Self::Problem(b) => match names {
                [one] => b
                    .names()
                    .type_id(one)
                    .ok_or((pos, ErrorKind::Model(ModelError::UnknownType { name: (*one).to_string() }))),
                _ => Err((pos, ErrorKind::Unsupported("`either` in a problem's quantifier".into()))),
            },
        }
    }
}

/// The variables in scope: an action's parameters and the quantifiers around the
/// formula being read; `types[i]` is the type of variable `i`.
pub(super) struct Scope {
    pub(super) names: Vec<(String, Var)>,
    pub(super) types: Vec<TypeId>,
    pub(super) action: String,
}

impl Scope {
    fn lookup(&self, name: &str) -> Option<Var> {
        self.names.iter().rev().find(|(n, _)| n == name).map(|(_, v)| *v)
    }
}

/// The reading context of one formula.
pub(super) struct Ctx<'a, 'o> {
    pub(super) owner: &'a mut Owner<'o>,
    pub(super) req: &'a mut Requirements,
    pub(super) warnings: &'a mut Vec<(Pos, String)>,
}

const COMPARISONS: &[&str] = &["<", ">", "<=", ">="];

impl Ctx<'_, '_> {
    fn need(&mut self, have: fn(&Requirements) -> bool, requirement: &'static str, what: &str, pos: Pos) {
        let h = have(self.req);
        self.req.need(h, requirement, what, pos, self.warnings);
    }

    /// `(?a ?b - t ...)` of a quantifier: new variables, pushed onto the scope.
    fn quantified(&mut self, scope: &mut Scope, s: &Sexp) -> R<Vec<Var>> {
        let items = list(s, "a variable list `(?x - type ...)`")?;
        let typed = super::typed_list(items, true, self.req, self.warnings)?;
        let mut out = Vec::with_capacity(typed.len());
        for t in typed {
            let name = model(t.pos, check_variable(t.name))?;
            let ty = self.owner.type_of(&t.ty, t.ty_pos)?;
            let index = u8::try_from(scope.types.len()).map_err(|_| {
                (t.pos, ErrorKind::Model(ModelError::TooManyVariables { action: scope.action.clone() }))
            })?;
            scope.types.push(ty);
            let v = Var { index, ty };
            scope.names.push((name, v));
            out.push(v);
        }
        Ok(out)
    }

    /// A term: `?x` in scope, or an object (a constant in a domain).
    fn term(&self, scope: &Scope, s: &Sexp) -> R<(Term, TypeId, String)> {
        let text = symbol(s, "a variable `?x` or an object name")?;
        if text.starts_with('?') {
            let name = model(s.pos(), check_variable(text))?;
            return match scope.lookup(&name) {
                Some(v) => Ok((Term::Var(v.index), v.ty, text.to_string())),
                None => Err((
                    s.pos(),
                    ErrorKind::Model(ModelError::UnknownParameter { name: clip(&name), action: scope.action.clone() }),
                )),
            };
        }
        match self.owner.object(text) {
            Some((o, ty)) => Ok((Term::Object(o), ty, text.to_string())),
            None => Err((s.pos(), ErrorKind::Model(ModelError::UnknownObject { name: clip(text) }))),
        }
    }

    /// An atom `(p t...)`, checked against the predicate's declaration.
    pub(super) fn atom(&self, scope: &Scope, s: &Sexp) -> R<Atom<Term>> {
        let items = list(s, "an atom `(p ...)`")?;
        let Some((head, rest)) = items.split_first() else {
            return expected("an atom `(p ...)`", s);
        };
        let name = symbol(head, "a predicate name")?;
        if is_keyword(name) {
            return Err((head.pos(), ErrorKind::Unsupported(format!("`{}` here", clip(name)))));
        }
        if self.owner.names().function(name).is_some() {
            return Err((head.pos(), ErrorKind::Unsupported(format!("numeric fluent `{}`", clip(name)))));
        }
        let mut args = Vec::with_capacity(rest.len());
        for a in rest {
            args.push(self.term(scope, a)?);
        }
        atom_of(self.owner.domain(), &self.owner.names(), name, &args).map_err(|e| {
            let pos = match &e {
                ModelError::UnknownPredicate { .. } => head.pos(),
                ModelError::TypeMismatch { position, .. } => {
                    rest.get(position.saturating_sub(1)).map_or(s.pos(), Sexp::pos)
                }
                _ => s.pos(),
            };
            (pos, ErrorKind::Model(e))
        })
    }

    /// A goal description, in negation normal form; `positive` is false under an odd
    /// number of `not`s.
    pub(super) fn condition(&mut self, scope: &mut Scope, s: &Sexp, positive: bool) -> R<Condition> {
        let items = list(s, "a condition such as `(p ?x)`, `(not ...)`, `(and ...)` or `(or ...)`")?;
        let Some(head) = items.first() else {
            // `()` is the empty conjunction: true.
            return Ok(if positive { Condition::And(Vec::new()) } else { Condition::Or(Vec::new()) });
        };
        let name = symbol(head, "a predicate name or a connective such as `and`")?;
        let rest = &items[1..];
        match name {
            "and" | "or" => {
                if name == "or" {
                    self.need(|r| r.disjunctive, ":disjunctive-preconditions", "`or`", head.pos());
                }
                let parts = rest.iter().map(|x| self.condition(scope, x, positive)).collect::<R<Vec<_>>>()?;
                Ok(if (name == "and") == positive { Condition::And(parts) } else { Condition::Or(parts) })
            }
            "not" => {
                let [inner] = rest else {
                    return expected("`(not CONDITION)` with exactly one condition", s);
                };
                self.condition(scope, inner, !positive)
            }
            "imply" => {
                self.need(|r| r.disjunctive, ":disjunctive-preconditions", "`imply`", head.pos());
                let [a, b] = rest else {
                    return expected("`(imply CONDITION CONDITION)`", s);
                };
                // a → b is ¬a ∨ b; its negation a ∧ ¬b.
                let a = self.condition(scope, a, !positive)?;
                let b = self.condition(scope, b, positive)?;
                Ok(if positive { Condition::Or(vec![a, b]) } else { Condition::And(vec![a, b]) })
            }
            "forall" | "exists" => {
                if name == "forall" {
                    self.need(|r| r.universal, ":universal-preconditions", "`forall`", head.pos());
                } else {
                    self.need(|r| r.existential, ":existential-preconditions", "`exists`", head.pos());
                }
                let [vars, body] = rest else {
                    return expected(&format!("`({name} (?x - type ...) CONDITION)`"), s);
                };
                let depth = scope.names.len();
                let vars = self.quantified(scope, vars)?;
                let body = self.condition(scope, body, positive);
                scope.names.truncate(depth);
                let body = Box::new(body?);
                Ok(if (name == "forall") == positive {
                    Condition::Forall(vars, body)
                } else {
                    Condition::Exists(vars, body)
                })
            }
            "=" => {
                self.need(|r| r.equality, ":equality", "`=`", head.pos());
                let [a, b] = rest else {
                    return expected("`(= TERM TERM)`", s);
                };
                if a.list().is_some() || b.list().is_some() {
                    return Err((s.pos(), ErrorKind::Unsupported("numeric condition `=`".into())));
                }
                let (left, _, _) = self.term(scope, a)?;
                let (right, _, _) = self.term(scope, b)?;
                Ok(Condition::Equal { positive, left, right })
            }
            n if COMPARISONS.contains(&n) => {
                Err((head.pos(), ErrorKind::Unsupported(format!("numeric condition `{n}`"))))
            }
            n if is_keyword(n) => Err((head.pos(), ErrorKind::Unsupported(format!("`{}` in a condition", clip(n))))),
            _ => {
                let atom = self.atom(scope, s)?;
                if !positive {
                    self.need(|r| r.negative, ":negative-preconditions", "a negative condition", s.pos());
                }
                Ok(Condition::Literal(Literal { positive, atom }))
            }
        }
    }

    /// An effect: literals, possibly under `forall` and `when`, and cost increases.
    pub(super) fn effect(
        &mut self,
        scope: &mut Scope,
        s: &Sexp,
        forall: &[Var],
        when: &[Condition],
        out: &mut Vec<Effect>,
        cost: &mut Vec<CostTerm>,
    ) -> R<()> {
        let items = list(s, "an effect such as `(p ?x)`, `(not (p ?x))` or `(and ...)`")?;
        let Some(head) = items.first() else {
            return Ok(());
        };
        let name = symbol(head, "a predicate name or `and`, `not`, `forall`, `when`")?;
        let rest = &items[1..];
        match name {
            "and" => {
                for e in rest {
                    self.effect(scope, e, forall, when, out, cost)?;
                }
                Ok(())
            }
            "not" => {
                let [inner] = rest else {
                    return expected("`(not (p ...))` with exactly one atom", s);
                };
                if inner.head().is_some_and(is_keyword) {
                    return expected("an atom `(p ...)` after `not`", inner);
                }
                let atom = self.atom(scope, inner)?;
                out.push(Effect {
                    forall: forall.to_vec(),
                    when: when.to_vec(),
                    literal: Literal { positive: false, atom },
                });
                Ok(())
            }
            "forall" => {
                self.need(|r| r.conditional, ":conditional-effects", "`forall` in an effect", head.pos());
                let [vars, body] = rest else {
                    return expected("`(forall (?x - type ...) EFFECT)`", s);
                };
                let depth = scope.names.len();
                let vars = self.quantified(scope, vars)?;
                let all: Vec<Var> = forall.iter().chain(&vars).copied().collect();
                let r = self.effect(scope, body, &all, when, out, &mut Vec::new());
                scope.names.truncate(depth);
                r
            }
            "when" => {
                self.need(|r| r.conditional, ":conditional-effects", "`when`", head.pos());
                let [c, body] = rest else {
                    return expected("`(when CONDITION EFFECT)`", s);
                };
                let c = self.condition(scope, c, true)?;
                let mut all = when.to_vec();
                all.push(c);
                let mut none = Vec::new();
                self.effect(scope, body, forall, &all, out, &mut none)?;
                if !none.is_empty() {
                    return Err((head.pos(), ErrorKind::Unsupported("a cost inside `when` or `forall`".into())));
                }
                Ok(())
            }
            "increase" => {
                self.need(|r| r.costs, ":action-costs", "`increase`", head.pos());
                let [target, amount] = rest else {
                    return expected("`(increase (total-cost) AMOUNT)`", s);
                };
                if target.head() != Some("total-cost") || target.list().is_some_and(|l| l.len() != 1) {
                    return Err((
                        target.pos(),
                        ErrorKind::Unsupported(format!("numeric effect on {}", target.describe())),
                    ));
                }
                if !forall.is_empty() || !when.is_empty() {
                    return Err((head.pos(), ErrorKind::Unsupported("a cost inside `when` or `forall`".into())));
                }
                cost.push(self.cost(scope, amount)?);
                Ok(())
            }
            n @ ("decrease" | "assign" | "scale-up" | "scale-down") => {
                Err((head.pos(), ErrorKind::Unsupported(format!("numeric effect `{n}`"))))
            }
            n if is_keyword(n) => Err((head.pos(), ErrorKind::Unsupported(format!("`{}` in an effect", clip(n))))),
            _ => {
                let atom = self.atom(scope, s)?;
                out.push(Effect {
                    forall: forall.to_vec(),
                    when: when.to_vec(),
                    literal: Literal { positive: true, atom },
                });
                Ok(())
            }
        }
    }

    /// The amount of `increase (total-cost)`: a number, or `(f args...)`.
    fn cost(&self, scope: &Scope, s: &Sexp) -> R<CostTerm> {
        match s {
            Sexp::Symbol(text, pos) => Ok(CostTerm::Constant(number(text, *pos)?)),
            Sexp::List(items, _) => {
                let Some((head, rest)) = items.split_first() else {
                    return expected("a number or a function `(f ...)`", s);
                };
                let name = symbol(head, "a function name")?;
                let Some(function) = self.owner.names().function(name) else {
                    return Err((head.pos(), ErrorKind::Model(ModelError::UnknownFunction { name: clip(name) })));
                };
                let f = &self.owner.domain().functions[usize::from(function)];
                if f.params.len() != rest.len() {
                    let e = ModelError::WrongArity {
                        predicate: f.name.clone(),
                        expected: f.params.len(),
                        found: rest.len(),
                    };
                    return Err((s.pos(), ErrorKind::Model(e)));
                }
                let mut args = Vec::with_capacity(rest.len());
                for a in rest {
                    args.push(self.term(scope, a)?.0);
                }
                Ok(CostTerm::Function { function, args })
            }
        }
    }
}

/// A non-negative whole number (`5`, `5.0`).
pub(super) fn number(text: &str, pos: Pos) -> R<u32> {
    let bad = || (pos, ErrorKind::BadNumber(clip(text)));
    if let Ok(n) = text.parse::<u32>() {
        return Ok(n);
    }
    let f: f64 = text.parse().map_err(|_| bad())?;
    if f.is_finite() && f >= 0.0 && f.fract() == 0.0 && f <= f64::from(u32::MAX) {
        return Ok(f as u32);
    }
    Err(bad())
}

/// Words that are connectives or keywords, never predicates.
pub(super) fn is_keyword(h: &str) -> bool {
    matches!(
        h,
        "and"
            | "or"
            | "not"
            | "imply"
            | "exists"
            | "forall"
            | "when"
            | "="
            | "<"
            | ">"
            | "<="
            | ">="
            | "increase"
            | "decrease"
            | "assign"
            | "scale-up"
            | "scale-down"
            | "either"
    ) || h.starts_with(':')
}
