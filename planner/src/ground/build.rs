//! Building a [`Grounding`]: reachability from the initial state, the ground actions,
//! the atoms' keys and indexes, and the goal.

use std::collections::HashMap;

use foldhash::fast::FixedState;

use super::derive::{Rule, Rules};
use super::formula::{Dnf, Eval, term};
use super::reach;
use super::tables::{self, Objects, UNBOUND, key_into};
use super::{ActionId, AtomId, CondEffect, GroundAction, Grounding, Leaves, Limits, Lit};
use crate::PlanError;
use crate::model::{ActionTemplate, Atom, Condition, CostTerm, ObjectId, Problem, Term};
use crate::state::State;

pub(super) fn build(original: &Problem, limits: &Limits) -> Result<Grounding, PlanError> {
    // Rules of derived predicates ground as actions after the real ones (so reachability
    // reaches derived atoms through them), and are split off at the end.
    let real_actions = original.domain.actions.len();
    let with_rules;
    let problem = if original.domain.axioms.is_empty() {
        original
    } else {
        let mut p = original.clone();
        let rules: Vec<ActionTemplate> = p.domain.axioms.iter().flat_map(split_rule).collect();
        p.domain.actions.extend(rules);
        with_rules = p;
        &with_rules
    };
    let d = &problem.domain;
    let statics = d.static_predicates();
    let objects = Objects::new(problem);
    let reach::Reached { mut atoms, schemas, instances } = reach::reach(problem, &objects, &statics, limits)?;
    // The goal's atoms exist even when no action reaches them.
    let goal_dnf = {
        let mut ev =
            Eval { objects: &objects, atoms: &atoms, statics: &statics, key: Vec::new(), missing: Some(Vec::new()) };
        let mut b = Vec::new();
        for c in &problem.goal {
            let _ = ev.dnf(c, &mut b, limits.alternatives);
        }
        ev.missing.take().unwrap_or_default()
    };
    let mut unreached = Vec::new();
    for key in goal_dnf {
        let (_, new) = atoms.insert(&key, false);
        if new {
            unreached.push(key);
        }
    }
    let ev_goal = |atoms: &tables::Atoms| -> Result<Dnf, PlanError> {
        let mut ev = Eval { objects: &objects, atoms, statics: &statics, key: Vec::new(), missing: None };
        ev.dnf(&Condition::And(problem.goal.clone()), &mut Vec::new(), limits.alternatives).map_err(|_| {
            PlanError::TooComplex { action: "the goal".into(), what: "condition", limit: limits.alternatives }
        })
    };
    let goal_alternatives = ev_goal(&atoms)?;

    // Canonical atom ids: sorted by key.
    let n = atoms.len();
    let mut order: Vec<u32> = (0..n as u32).collect();
    order.sort_unstable_by(|&a, &b| atoms.key(a).cmp(atoms.key(b)));
    let mut new_id = vec![0u32; n];
    for (i, &old) in order.iter().enumerate() {
        new_id[old as usize] = i as u32;
    }
    let remap = |l: Lit| Lit { atom: new_id[l.atom as usize], positive: l.positive };

    let unit_cost = !(d.has_costs() && problem.metric);
    let costs: HashMap<(u16, &[ObjectId]), u32> =
        problem.functions.iter().map(|f| ((f.function, f.args.as_slice()), f.value)).collect();

    // Ground actions, in template then argument order.
    let mut sorted: Vec<(Vec<u16>, usize)> = instances
        .iter()
        .enumerate()
        .map(|(i, inst)| {
            let s = &schemas[inst.schema as usize];
            let mut k = vec![s.template];
            k.extend(s.bound.iter().map(|&v| inst.binding[usize::from(v)]));
            (k, i)
        })
        .collect();
    sorted.sort_unstable();
    let mut actions: Vec<GroundAction> = Vec::new();
    let mut ev = Eval { objects: &objects, atoms: &atoms, statics: &statics, key: Vec::new(), missing: None };
    for (_, i) in sorted {
        let inst = &instances[i];
        let s = &schemas[inst.schema as usize];
        let t = &d.actions[usize::from(s.template)];
        let mut binding = inst.binding.to_vec();
        let name = || {
            let args: Vec<ObjectId> = binding_args(&inst.binding, t.params.len());
            problem.call_name(&t.name, &args)
        };
        // Preconditions: the top-level literals, then each alternative of the rest.
        let mut simple: Vec<Lit> = Vec::new();
        let mut dead = false;
        for l in &s.simple {
            match ev.dnf(&Condition::Literal(l.clone()), &mut binding, limits.alternatives) {
                Ok(d) if d.is_empty() => dead = true,
                Ok(d) => {
                    for &x in d.first().map_or(&[][..], Vec::as_slice) {
                        if !simple.contains(&x) {
                            simple.push(x);
                        }
                    }
                }
                Err(_) => dead = true,
            }
        }
        if dead {
            continue;
        }
        let residue = ev
            .dnf(&Condition::And(s.residue.clone()), &mut binding, limits.alternatives)
            .map_err(|_| PlanError::TooComplex { action: name(), what: "precondition", limit: limits.alternatives })?;
        if residue.is_empty() {
            continue;
        }
        // Effects.
        let mut add = Vec::new();
        let mut del = Vec::new();
        let mut cond: Vec<CondEffect> = Vec::new();
        for e in &t.effects {
            let mut err = None;
            ev.bindings(&e.forall, &mut binding, &mut |ev, b| {
                let when = match ev.dnf(&Condition::And(e.when.clone()), b, limits.alternatives) {
                    Ok(w) => w,
                    Err(_) => {
                        err = Some(PlanError::TooComplex {
                            action: name(),
                            what: "effect condition",
                            limit: limits.alternatives,
                        });
                        return false;
                    }
                };
                if when.is_empty() {
                    return true;
                }
                let mut k = Vec::new();
                key_into(&mut k, e.literal.atom.predicate, e.literal.atom.args.iter().map(|&x| term(x, b)));
                let Some(atom) = ev.atoms.get(&k) else { return true };
                for w in when {
                    let (a, dl) = if w.is_empty() {
                        (&mut add, &mut del)
                    } else {
                        let mut w = w;
                        w.sort_unstable();
                        let at = match cond.iter().position(|c| c.when == w) {
                            Some(at) => at,
                            None => {
                                cond.push(CondEffect { when: w, add: Vec::new(), del: Vec::new() });
                                cond.len() - 1
                            }
                        };
                        let c = &mut cond[at];
                        (&mut c.add, &mut c.del)
                    };
                    let list = if e.literal.positive { a } else { dl };
                    if !list.contains(&atom) {
                        list.push(atom);
                    }
                }
                true
            });
            if let Some(e) = err {
                return Err(e);
            }
        }
        del.retain(|x| !add.contains(x));
        let cost = if unit_cost { 1 } else { cost_of(&t.cost, &binding, &costs, problem)? };
        let args = binding_args(&inst.binding, t.params.len());
        for alt in &residue {
            let mut pre = simple.clone();
            let mut contradictory = false;
            for &l in alt {
                if pre.contains(&l.negated()) {
                    contradictory = true;
                }
                if !pre.contains(&l) {
                    pre.push(l);
                }
            }
            if contradictory {
                continue;
            }
            if actions.len() >= limits.actions {
                return Err(PlanError::TooLarge {
                    what: "ground actions",
                    count: actions.len() as u64 + 1,
                    limit: limits.actions as u64,
                });
            }
            let candidate = GroundAction {
                template: s.template,
                args: args.clone(),
                pre,
                add: add.clone(),
                del: del.clone(),
                cond: cond.clone(),
                cost,
            };
            // Two alternatives that ground the same are one action.
            let same = actions
                .iter()
                .rev()
                .take_while(|a| a.template == s.template && a.args == args)
                .any(|a| *a == candidate);
            if !same {
                actions.push(candidate);
            }
        }
        let _ = UNBOUND;
    }
    drop(ev);

    // Renumber atoms everywhere.
    for a in &mut actions {
        for l in &mut a.pre {
            *l = remap(*l);
        }
        for x in a.add.iter_mut().chain(a.del.iter_mut()) {
            *x = new_id[*x as usize];
        }
        for c in &mut a.cond {
            for l in &mut c.when {
                *l = remap(*l);
            }
            for x in c.add.iter_mut().chain(c.del.iter_mut()) {
                *x = new_id[*x as usize];
            }
        }
    }
    let keys: Vec<Box<[u16]>> = order.iter().map(|&o| atoms.key(o).into()).collect();
    let first_rule = actions.partition_point(|a| usize::from(a.template) < real_actions);
    let rules = rules(original, actions.split_off(first_rule), &keys)?;
    let mut init = State::new(n);
    for old in 0..n as u32 {
        if atoms.in_init(old) {
            init.set(new_id[old as usize], true);
        }
    }
    let goal: Vec<Lit> =
        choose_goal(problem, &atoms, &statics, &goal_alternatives, &unreached)?.into_iter().map(remap).collect();
    let atom_index = keys.iter().enumerate().map(|(i, k)| (k.clone(), i as AtomId)).collect();
    let mut action_index: HashMap<Box<[u16]>, Vec<ActionId>, FixedState> = HashMap::default();
    for (i, a) in actions.iter().enumerate() {
        let mut k = vec![a.template];
        k.extend_from_slice(&a.args);
        action_index.entry(k.into_boxed_slice()).or_default().push(i as ActionId);
    }
    let mut g = Grounding {
        problem: original.clone(),
        statics,
        keys,
        atom_index,
        init,
        actions,
        action_index,
        achievers: Vec::new(),
        goal,
        leaves: Leaves::Pddl,
        unit_cost,
        rules,
    };
    g.index();
    let mut init = std::mem::take(&mut g.init);
    g.close(&mut init);
    g.init = init;
    Ok(g)
}

/// Most rules one `:derived` rule is split into by [`split_rule`].
const SPLIT: usize = 32;

/// A rule split into one rule per alternative of its body's disjunctions, `exists`
/// kept around each (so its variables become ones the join binds, as a Datalog
/// translation does): `(or (and (con ?z ?y) (up ?x ?z)) ...)` under an `exists` is
/// joined through `con` and `up` instead of trying every object for `?z` and `?y`.
/// The rule is kept whole when that would make more than [`SPLIT`] rules.
fn split_rule(rule: &ActionTemplate) -> Vec<ActionTemplate> {
    let Some(alternatives) = alternatives(&Condition::And(rule.pre.clone())) else {
        return vec![rule.clone()];
    };
    alternatives.into_iter().map(|pre| ActionTemplate { pre, ..rule.clone() }).collect()
}

/// The alternatives of a condition as conjunctions (`None` past [`SPLIT`]).
fn alternatives(c: &Condition) -> Option<Vec<Vec<Condition>>> {
    let out = match c {
        Condition::Or(parts) => {
            let mut out = Vec::new();
            for p in parts {
                out.extend(alternatives(p)?);
            }
            out
        }
        Condition::And(parts) => {
            let mut out: Vec<Vec<Condition>> = vec![Vec::new()];
            for p in parts {
                let alts = alternatives(p)?;
                if out.len() * alts.len() > SPLIT {
                    return None;
                }
                out = out.iter().flat_map(|a| alts.iter().map(move |b| [a.clone(), b.clone()].concat())).collect();
            }
            out
        }
        Condition::Exists(vars, body) => alternatives(body)?
            .into_iter()
            .map(|alt| vec![Condition::Exists(vars.clone(), Box::new(Condition::And(alt)))])
            .collect(),
        other => vec![vec![other.clone()]],
    };
    (out.len() <= SPLIT).then_some(out)
}

/// The ground rules, from the rules grounded as actions (one per alternative of a
/// body), with their strata.
fn rules(problem: &Problem, ground: Vec<GroundAction>, keys: &[Box<[u16]>]) -> Result<Rules, PlanError> {
    if problem.domain.axioms.is_empty() {
        return Ok(Rules::default());
    }
    let strata = problem.domain.strata()?;
    let derived = problem.domain.derived_predicates();
    let of = |atom: AtomId| keys.get(atom as usize).map_or(0, |k| k[0]);
    let rules = ground
        .into_iter()
        .filter_map(|a| {
            let head = *a.add.first()?;
            Some((strata.get(usize::from(of(head))).copied().unwrap_or(0), Rule { head, body: a.pre }))
        })
        .collect();
    Ok(Rules::new(rules, keys.len(), |atom| derived.get(usize::from(of(atom))).copied().unwrap_or(false)))
}

fn binding_args(binding: &[ObjectId], params: usize) -> Vec<ObjectId> {
    binding.iter().take(params).copied().collect()
}

fn cost_of(
    terms: &[CostTerm],
    binding: &[ObjectId],
    values: &HashMap<(u16, &[ObjectId]), u32>,
    problem: &Problem,
) -> Result<u32, PlanError> {
    let mut sum: u32 = 0;
    for t in terms {
        let v = match t {
            CostTerm::Constant(c) => *c,
            CostTerm::Function { function, args } => {
                let objs: Vec<ObjectId> = args.iter().map(|&x| term(x, binding)).collect();
                match values.get(&(*function, objs.as_slice())) {
                    Some(v) => *v,
                    None => {
                        let name =
                            problem.domain.functions.get(usize::from(*function)).map_or("?", |f| f.name.as_str());
                        return Err(PlanError::MissingCost { term: problem.call_name(name, &objs) });
                    }
                }
            }
        };
        sum = sum.saturating_add(v);
    }
    Ok(sum)
}

/// The goal as one conjunction of literals, or the reason there is none. A goal that
/// is a conjunction of literals is kept as written (static literals included, so the
/// tree checks them); an ADL goal becomes its first alternative that is not false.
fn choose_goal(
    problem: &Problem,
    atoms: &tables::Atoms,
    statics: &[bool],
    alternatives: &Dnf,
    unreached: &[Box<[u16]>],
) -> Result<Vec<Lit>, PlanError> {
    let name = |k: &[u16]| problem.atom_name(&Atom { predicate: k[0], args: k[1..].to_vec() });
    let mut plain: Vec<&crate::model::Literal<Term>> = Vec::new();
    for c in &problem.goal {
        match c {
            Condition::Literal(l) => plain.push(l),
            Condition::And(v) if v.is_empty() => {}
            _ => {
                plain.clear();
                break;
            }
        }
    }
    for (i, l) in plain.iter().enumerate() {
        if plain[i + 1..].iter().any(|m| m.positive != l.positive && m.atom == l.atom) {
            let args: Vec<ObjectId> = l.atom.args.iter().map(|&t| term(t, &[])).collect();
            return Err(PlanError::ContradictoryGoal {
                atom: problem.atom_name(&Atom { predicate: l.atom.predicate, args }),
            });
        }
    }
    if !plain.is_empty() {
        let mut goal: Vec<Lit> = Vec::with_capacity(plain.len());
        let mut key = Vec::new();
        for l in plain {
            key_into(&mut key, l.atom.predicate, l.atom.args.iter().map(|&t| term(t, &[])));
            let Some(atom) = atoms.get(&key) else { continue };
            let is_static = statics.get(usize::from(l.atom.predicate)).copied().unwrap_or(false);
            if l.positive && unreached.iter().any(|k| k[..] == key[..]) {
                return Err(PlanError::Unsolvable(format!("no reachable action makes `{}` true", name(&key))));
            }
            if is_static && atoms.in_init(atom) != l.positive {
                let what = if l.positive { "false" } else { "true" };
                return Err(PlanError::Unsolvable(format!("`{}` is {what} and no action changes it", name(&key))));
            }
            let lit = Lit { atom, positive: l.positive };
            if !goal.contains(&lit) {
                goal.push(lit);
            }
        }
        return Ok(goal);
    }
    let Some(first) = alternatives.first() else {
        if let Some(k) = unreached.first() {
            return Err(PlanError::Unsolvable(format!("no reachable action makes `{}` true", name(k))));
        }
        return Err(PlanError::Unsolvable("the goal is false in every state reachable from the initial one".into()));
    };
    if first.is_empty() {
        return Err(PlanError::Unsolvable("the goal holds in every state: there is nothing to plan".into()));
    }
    Ok(first.clone())
}
