//! The tables grounding builds on: objects by type, and the registry of ground atoms
//! with one relation per predicate, indexed by argument for joins.

use std::collections::HashMap;

use foldhash::fast::FixedState;

use crate::model::{ObjectId, PredicateId, Problem, TypeId};

use super::action::AtomId;

/// Marks a variable without a value in a binding.
pub(super) const UNBOUND: ObjectId = ObjectId::MAX;

/// The objects of each type (declared, or a union), in object order, and a membership
/// bitset per type.
#[derive(Clone, Debug)]
pub(super) struct Objects {
    of_type: Vec<Vec<ObjectId>>,
    member: Vec<Vec<u64>>,
}

impl Objects {
    pub(super) fn new(problem: &Problem) -> Self {
        let d = &problem.domain;
        let n = problem.objects.len();
        let mut of_type = vec![Vec::new(); d.types.len()];
        let mut member = vec![vec![0u64; n.div_ceil(64)]; d.types.len()];
        for (o, obj) in problem.objects.iter().enumerate() {
            for (t, list) in of_type.iter_mut().enumerate() {
                if d.object_is(obj.ty, t as TypeId) {
                    list.push(o as ObjectId);
                    member[t][o / 64] |= 1 << (o % 64);
                }
            }
        }
        Self { of_type, member }
    }

    /// The objects of type `ty`.
    pub(super) fn of(&self, ty: TypeId) -> &[ObjectId] {
        self.of_type.get(usize::from(ty)).map_or(&[], Vec::as_slice)
    }

    /// Whether object `o` is of type `ty`.
    pub(super) fn is(&self, o: ObjectId, ty: TypeId) -> bool {
        let o = usize::from(o);
        self.member.get(usize::from(ty)).and_then(|m| m.get(o / 64)).is_some_and(|w| w & (1 << (o % 64)) != 0)
    }
}

/// The ground atoms of one predicate, with an index per argument position.
#[derive(Clone, Debug, Default)]
pub(super) struct Relation {
    pub(super) facts: Vec<AtomId>,
    index: Vec<HashMap<ObjectId, Vec<AtomId>, FixedState>>,
}

impl Relation {
    /// The facts whose argument `position` is `o`.
    pub(super) fn with_arg(&self, position: usize, o: ObjectId) -> &[AtomId] {
        self.index.get(position).and_then(|m| m.get(&o)).map_or(&[], Vec::as_slice)
    }
}

/// Every ground atom met so far: the initial state's and those reached, by key
/// `[predicate, args...]`.
#[derive(Clone, Debug, Default)]
pub(super) struct Atoms {
    index: HashMap<Box<[u16]>, AtomId, FixedState>,
    keys: Vec<Box<[u16]>>,
    pub(super) relations: Vec<Relation>,
    in_init: Vec<bool>,
}

impl Atoms {
    pub(super) fn new(predicates: usize) -> Self {
        Self { relations: vec![Relation::default(); predicates], ..Self::default() }
    }

    pub(super) fn len(&self) -> usize {
        self.keys.len()
    }

    /// The id of an atom by key, if it was met.
    pub(super) fn get(&self, key: &[u16]) -> Option<AtomId> {
        self.index.get(key).copied()
    }

    /// The key `[predicate, args...]` of an atom.
    pub(super) fn key(&self, atom: AtomId) -> &[u16] {
        self.keys.get(atom as usize).map_or(&[], |k| &k[..])
    }

    /// Whether the atom is in the initial state.
    pub(super) fn in_init(&self, atom: AtomId) -> bool {
        self.in_init.get(atom as usize).copied().unwrap_or(false)
    }

    /// Registers an atom (once); returns its id and whether it is new.
    pub(super) fn insert(&mut self, key: &[u16], init: bool) -> (AtomId, bool) {
        if let Some(&id) = self.index.get(key) {
            if init && let Some(f) = self.in_init.get_mut(id as usize) {
                *f = true;
            }
            return (id, false);
        }
        let id = self.keys.len() as AtomId;
        let boxed: Box<[u16]> = key.into();
        self.index.insert(boxed.clone(), id);
        self.keys.push(boxed);
        self.in_init.push(init);
        if let Some((&p, args)) = key.split_first()
            && let Some(r) = self.relations.get_mut(usize::from(p))
        {
            r.facts.push(id);
            if r.index.len() < args.len() {
                r.index.resize_with(args.len(), HashMap::default);
            }
            for (i, &o) in args.iter().enumerate() {
                r.index[i].entry(o).or_default().push(id);
            }
        }
        (id, true)
    }

    /// The number of facts of a predicate (grows as atoms are reached).
    pub(super) fn version(&self, p: PredicateId) -> usize {
        self.relations.get(usize::from(p)).map_or(0, |r| r.facts.len())
    }
}

/// `f` of the key `[head, args...]`, built on the stack where it is short (a lookup
/// per condition a tree ticks: no allocation).
pub(super) fn with_key<R>(head: u16, args: &[ObjectId], f: impl FnOnce(&[u16]) -> R) -> R {
    const SHORT: usize = 8;
    if args.len() < SHORT {
        let mut buf = [0u16; SHORT];
        buf[0] = head;
        buf[1..=args.len()].copy_from_slice(args);
        f(&buf[..=args.len()])
    } else {
        let mut buf = Vec::with_capacity(args.len() + 1);
        key_into(&mut buf, head, args.iter().copied());
        f(&buf)
    }
}

/// A key `[head, args...]` in a reusable buffer.
pub(super) fn key_into(buf: &mut Vec<u16>, head: u16, args: impl IntoIterator<Item = ObjectId>) {
    buf.clear();
    buf.push(head);
    buf.extend(args);
}
