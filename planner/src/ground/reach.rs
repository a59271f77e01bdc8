//! Grounding by reachability: the atoms and action instances of the delete relaxation,
//! found by joining each action's preconditions against the atoms reached so far
//! until nothing new is reached (the relaxed planning graph, without its layers).
//!
//! An action template becomes a *schema*: its top-level precondition literals (used
//! for the join), its equalities, and the rest of its precondition (the ADL parts,
//! checked under the relaxed semantics once the variables are bound). `exists` at the
//! top level adds its variables to the ones the join binds. Variables no positive
//! literal binds range over their type's objects; their count is checked first.

use std::collections::HashSet;

use foldhash::fast::FixedState;
use std::time::Instant;

use crate::PlanError;
use crate::model::{ActionTemplate, Condition, Literal, ObjectId, Problem, TemplateId, Term};

use super::Limits;
use super::formula::Eval;
use super::tables::{Atoms, Objects, UNBOUND, key_into};

/// The instances of a schema found so far, by the values of its bound variables.
type Seen = HashSet<Box<[ObjectId]>, FixedState>;

/// An action template prepared for the join.
#[derive(Clone, Debug)]
pub(super) struct Schema {
    pub(super) template: TemplateId,
    /// Variables whose values make an instance: the parameters, then `exists` ones
    /// lifted from the top level.
    pub(super) bound: Vec<u8>,
    /// Top-level literals, in the order written.
    pub(super) simple: Vec<Literal<Term>>,
    /// Top-level equalities.
    pub(super) eq: Vec<(bool, Term, Term)>,
    /// The rest of the precondition.
    pub(super) residue: Vec<Condition>,
    /// Predicates whose facts the join and the residue read, with the fact count seen
    /// at the last join.
    reads: Vec<(u16, usize)>,
    joined: bool,
}

impl Schema {
    pub(super) fn new(template: TemplateId, t: &ActionTemplate) -> Self {
        let mut s = Self {
            template,
            bound: (0..t.params.len() as u8).collect(),
            simple: Vec::new(),
            eq: Vec::new(),
            residue: Vec::new(),
            reads: Vec::new(),
            joined: false,
        };
        let mut stack: Vec<&Condition> = t.pre.iter().rev().collect();
        while let Some(c) = stack.pop() {
            match c {
                Condition::Literal(l) => s.simple.push(l.clone()),
                Condition::Equal { positive, left, right } => s.eq.push((*positive, *left, *right)),
                Condition::And(parts) => stack.extend(parts.iter().rev()),
                Condition::Exists(vars, body) => {
                    s.bound.extend(vars.iter().map(|v| v.index));
                    stack.push(body);
                }
                other => s.residue.push(other.clone()),
            }
        }
        let mut preds: Vec<u16> = s.simple.iter().filter(|l| l.positive).map(|l| l.atom.predicate).collect();
        for r in &s.residue {
            r.for_each_literal(&mut |l| preds.push(l.atom.predicate));
        }
        preds.sort_unstable();
        preds.dedup();
        s.reads = preds.into_iter().map(|p| (p, 0)).collect();
        s
    }
}

/// One reachable instance of a schema: the values of its bound variables, in a
/// binding over all the template's variables.
#[derive(Clone, Debug)]
pub(super) struct Instance {
    pub(super) schema: u32,
    pub(super) binding: Box<[ObjectId]>,
}

/// The result of the reachability analysis.
pub(super) struct Reached {
    pub(super) atoms: Atoms,
    pub(super) schemas: Vec<Schema>,
    pub(super) instances: Vec<Instance>,
}

struct Search<'a> {
    problem: &'a Problem,
    objects: &'a Objects,
    statics: &'a [bool],
    limits: &'a Limits,
}

fn too_large(what: &'static str, count: usize, limit: usize) -> PlanError {
    PlanError::TooLarge { what, count: count as u64, limit: limit as u64 }
}

/// Runs the analysis.
pub(super) fn reach(
    problem: &Problem,
    objects: &Objects,
    statics: &[bool],
    limits: &Limits,
) -> Result<Reached, PlanError> {
    let d = &problem.domain;
    let mut atoms = Atoms::new(d.predicates.len());
    let mut key = Vec::new();
    for a in &problem.init {
        key_into(&mut key, a.predicate, a.args.iter().copied());
        atoms.insert(&key, true);
    }
    let mut schemas: Vec<Schema> = d.actions.iter().enumerate().map(|(i, t)| Schema::new(i as TemplateId, t)).collect();
    let search = Search { problem, objects, statics, limits };
    let mut instances: Vec<Instance> = Vec::new();
    let mut seen: Vec<Seen> = vec![Seen::default(); schemas.len()];
    // Instances whose quantified or conditional effects have not all fired yet.
    let mut pending: Vec<(u32, u32)> = Vec::new();
    loop {
        let before = (atoms.len(), instances.len());
        for si in 0..schemas.len() {
            let stale = !schemas[si].joined || schemas[si].reads.iter().any(|&(p, v)| atoms.version(p) != v);
            if !stale {
                continue;
            }
            for r in &mut schemas[si].reads {
                r.1 = atoms.version(r.0);
            }
            schemas[si].joined = true;
            let found = search.join(&schemas[si], &atoms, &seen[si])?;
            let t = &d.actions[usize::from(schemas[si].template)];
            for binding in found {
                let key_vals: Box<[ObjectId]> = schemas[si].bound.iter().map(|&v| binding[usize::from(v)]).collect();
                if !seen[si].insert(key_vals) {
                    continue;
                }
                if instances.len() >= limits.actions {
                    return Err(too_large("ground actions", instances.len() + 1, limits.actions));
                }
                let id = instances.len() as u32;
                for (ei, e) in t.effects.iter().enumerate() {
                    if e.forall.is_empty() && e.when.is_empty() {
                        if e.literal.positive {
                            add_atom(&mut atoms, &mut key, &e.literal, &binding, limits)?;
                        }
                    } else if e.literal.positive {
                        pending.push((id, ei as u32));
                    }
                }
                instances.push(Instance { schema: si as u32, binding });
            }
            search.check_time()?;
        }
        // Quantified and conditional effects whose condition is now reachable.
        let mut still = Vec::with_capacity(pending.len());
        for (id, ei) in std::mem::take(&mut pending) {
            let inst = &instances[id as usize];
            let t = &d.actions[usize::from(schemas[inst.schema as usize].template)];
            let e = &t.effects[ei as usize];
            let mut binding = inst.binding.to_vec();
            let mut fired = Vec::new();
            let mut all = true;
            {
                let mut ev = Eval { objects, atoms: &atoms, statics, key: Vec::new(), missing: None };
                ev.bindings(&e.forall, &mut binding, &mut |ev, b| {
                    if e.when.iter().all(|c| ev.relaxed(c, b)) {
                        fired.push(b.clone());
                    } else {
                        all = false;
                    }
                    true
                });
            }
            for b in &fired {
                add_atom(&mut atoms, &mut key, &e.literal, b, limits)?;
            }
            if !all {
                still.push((id, ei));
            }
        }
        pending = still;
        search.check_time()?;
        if (atoms.len(), instances.len()) == before {
            return Ok(Reached { atoms, schemas, instances });
        }
    }
}

fn add_atom(
    atoms: &mut Atoms,
    key: &mut Vec<u16>,
    l: &Literal<Term>,
    binding: &[ObjectId],
    limits: &Limits,
) -> Result<(), PlanError> {
    key_into(
        key,
        l.atom.predicate,
        l.atom.args.iter().map(|t| match *t {
            Term::Object(o) => o,
            Term::Var(v) => binding.get(usize::from(v)).copied().unwrap_or(UNBOUND),
        }),
    );
    if key.iter().skip(1).any(|&o| o == UNBOUND) {
        return Ok(());
    }
    let (_, new) = atoms.insert(key, false);
    if new && atoms.len() > limits.atoms {
        return Err(too_large("ground atoms", atoms.len(), limits.atoms));
    }
    Ok(())
}

/// One step of the join: which literal, and the candidate facts left to try.
struct Frame {
    literal: usize,
    candidates: Vec<u32>,
    next: usize,
    /// Variables this frame bound, to unbind when it moves on.
    bound_here: Vec<u8>,
}

impl Search<'_> {
    fn check_time(&self) -> Result<(), PlanError> {
        match self.limits.deadline {
            Some(d) if Instant::now() >= d => Err(PlanError::Timeout { stage: "grounding" }),
            _ => Ok(()),
        }
    }

    /// The bindings of the schema's variables that satisfy its positive literals over
    /// `atoms`, its equalities, static negative literals and, relaxed, its residue.
    fn join(&self, s: &Schema, atoms: &Atoms, seen: &Seen) -> Result<Vec<Box<[ObjectId]>>, PlanError> {
        let t = &self.problem.domain.actions[usize::from(s.template)];
        let nvars = t.vars.len();
        let positive: Vec<usize> = (0..s.simple.len()).filter(|&i| s.simple[i].positive).collect();
        let mut binding = vec![UNBOUND; nvars];
        let mut out = Vec::new();
        let mut stack: Vec<Frame> = Vec::new();
        let mut used = vec![false; s.simple.len()];
        let mut steps: u64 = 0;
        // Depth-first over the positive literals, most constrained first.
        loop {
            let depth = stack.len();
            if depth < positive.len() {
                let Some(lit) = self.pick(s, &positive, &used, &binding, atoms) else { break };
                used[lit] = true;
                let candidates = self.candidates(&s.simple[lit], &binding, atoms);
                stack.push(Frame { literal: lit, candidates, next: 0, bound_here: Vec::new() });
            } else {
                self.complete(s, t, &mut binding, atoms, seen, &mut out)?;
                if out.len() > self.limits.actions {
                    return Err(too_large("ground actions", out.len(), self.limits.actions));
                }
            }
            // Advance the top frame to its next consistent candidate, popping
            // exhausted frames.
            loop {
                let Some(f) = stack.last_mut() else { return Ok(out) };
                for &v in &f.bound_here {
                    binding[usize::from(v)] = UNBOUND;
                }
                f.bound_here.clear();
                let mut found = false;
                while f.next < f.candidates.len() {
                    for &v in &f.bound_here {
                        binding[usize::from(v)] = UNBOUND;
                    }
                    f.bound_here.clear();
                    let atom = f.candidates[f.next];
                    f.next += 1;
                    steps += 1;
                    if steps & 0xFFFF == 0 {
                        self.check_time()?;
                    }
                    if bind(&s.simple[f.literal], atoms.key(atom), &mut binding, &mut f.bound_here, t, self.objects) {
                        found = true;
                        break;
                    }
                }
                if found {
                    break;
                }
                for &v in &f.bound_here {
                    binding[usize::from(v)] = UNBOUND;
                }
                used[f.literal] = false;
                stack.pop();
            }
        }
        Ok(out)
    }

    /// The next literal to join: the unused one with the most bound arguments,
    /// static ones first on ties, then the one with fewer facts.
    fn pick(
        &self,
        s: &Schema,
        positive: &[usize],
        used: &[bool],
        binding: &[ObjectId],
        atoms: &Atoms,
    ) -> Option<usize> {
        positive.iter().copied().filter(|&i| !used[i]).max_by_key(|&i| {
            let l = &s.simple[i];
            let bound = l
                .atom
                .args
                .iter()
                .filter(|t| match t {
                    Term::Object(_) => true,
                    Term::Var(v) => binding[usize::from(*v)] != UNBOUND,
                })
                .count();
            let is_static = self.statics.get(usize::from(l.atom.predicate)).copied().unwrap_or(false);
            let size = atoms.relations.get(usize::from(l.atom.predicate)).map_or(0, |r| r.facts.len());
            (bound, is_static, std::cmp::Reverse(size), std::cmp::Reverse(i))
        })
    }

    /// The facts that may match a literal: through the index of its most selective
    /// bound argument, or all facts of its predicate.
    fn candidates(&self, l: &Literal<Term>, binding: &[ObjectId], atoms: &Atoms) -> Vec<u32> {
        let Some(r) = atoms.relations.get(usize::from(l.atom.predicate)) else { return Vec::new() };
        let mut best: Option<&[u32]> = None;
        for (i, t) in l.atom.args.iter().enumerate() {
            let o = match *t {
                Term::Object(o) => o,
                Term::Var(v) => binding[usize::from(v)],
            };
            if o == UNBOUND {
                continue;
            }
            let list = r.with_arg(i, o);
            if best.is_none_or(|b| list.len() < b.len()) {
                best = Some(list);
            }
        }
        best.unwrap_or(&r.facts).to_vec()
    }

    /// With every positive literal matched: binds the remaining variables over their
    /// types and keeps the bindings that pass the other checks.
    fn complete(
        &self,
        s: &Schema,
        t: &ActionTemplate,
        binding: &mut Vec<ObjectId>,
        atoms: &Atoms,
        seen: &Seen,
        out: &mut Vec<Box<[ObjectId]>>,
    ) -> Result<(), PlanError> {
        let free: Vec<crate::model::Var> = s
            .bound
            .iter()
            .filter(|&&v| binding[usize::from(v)] == UNBOUND)
            .map(|&v| crate::model::Var { index: v, ty: t.vars[usize::from(v)] })
            .collect();
        let count = free.iter().map(|v| self.objects.of(v.ty).len()).fold(1usize, usize::saturating_mul);
        if count > self.limits.actions {
            let names: Vec<String> = free
                .iter()
                .map(|v| t.params.get(usize::from(v.index)).map_or_else(|| "?".into(), |p| format!("?{}", p.name)))
                .collect();
            return Err(PlanError::Unbounded { action: t.name.clone(), params: names.join(" "), count: count as u64 });
        }
        let mut ev = Eval { objects: self.objects, atoms, statics: self.statics, key: Vec::new(), missing: None };
        let mut err = None;
        let mut key: Vec<ObjectId> = Vec::with_capacity(s.bound.len());
        ev.bindings(&free, binding, &mut |ev, b| {
            let eq_ok = s.eq.iter().all(|&(positive, l, r)| {
                let v = |x: Term| match x {
                    Term::Object(o) => o,
                    Term::Var(i) => b[usize::from(i)],
                };
                (v(l) == v(r)) == positive
            });
            let neg_ok = s.simple.iter().filter(|l| !l.positive).all(|l| {
                let c = Condition::Literal(l.clone());
                ev.relaxed(&c, b)
            });
            // An instance found in an earlier round needs no second look at its residue.
            let mut new = || {
                key.clear();
                key.extend(s.bound.iter().map(|&v| b[usize::from(v)]));
                !seen.contains(key.as_slice())
            };
            if eq_ok && neg_ok && new() && s.residue.iter().all(|c| ev.relaxed(c, b)) {
                out.push(b.clone().into_boxed_slice());
                if out.len() > self.limits.actions {
                    err = Some(too_large("ground actions", out.len(), self.limits.actions));
                    return false;
                }
            }
            true
        });
        err.map_or(Ok(()), Err)
    }
}

/// Binds the literal's variables to the atom's arguments, if consistent (objects
/// equal, variables unbound or equal, types fit). Records what it bound.
fn bind(
    l: &Literal<Term>,
    key: &[u16],
    binding: &mut [ObjectId],
    bound_here: &mut Vec<u8>,
    t: &ActionTemplate,
    objects: &Objects,
) -> bool {
    let args = key.get(1..).unwrap_or(&[]);
    if args.len() != l.atom.args.len() {
        return false;
    }
    for (term, &o) in l.atom.args.iter().zip(args) {
        match *term {
            Term::Object(x) => {
                if x != o {
                    return false;
                }
            }
            Term::Var(v) => {
                let slot = &mut binding[usize::from(v)];
                if *slot == UNBOUND {
                    if !objects.is(o, t.vars[usize::from(v)]) {
                        return false;
                    }
                    *slot = o;
                    bound_here.push(v);
                } else if *slot != o {
                    return false;
                }
            }
        }
    }
    true
}
