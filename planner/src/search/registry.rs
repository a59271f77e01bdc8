//! Search states stored once: each as the sorted list of its true atoms in one arena,
//! found again through a hash table of their hashes. Static atoms (of predicates no
//! action changes, such as a grid's `connected`) are the same in every state of a
//! search: they are kept once, not per state.

use std::collections::HashMap;
use std::hash::{Hash, Hasher};

use crate::ground::Grounding;
use crate::state::State;

/// Every state met, by id.
#[derive(Debug)]
pub(super) struct Registry {
    arena: Vec<u32>,
    start: Vec<u64>,
    /// Hash of a state's atoms → the first state with that hash; further ones chain
    /// through `next`.
    by_hash: HashMap<u64, u32>,
    next: Vec<u32>,
    scratch: Vec<u32>,
    /// Whether each atom is static.
    fixed: Vec<bool>,
    /// The static atoms true in every state of the search.
    always: Vec<u32>,
}

const END: u32 = u32::MAX;

fn hash(atoms: &[u32]) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    atoms.hash(&mut h);
    h.finish()
}

impl Registry {
    /// A registry for states of `g` reached from `start` (whose static atoms every one
    /// of them shares).
    pub(super) fn new(g: &Grounding, start: &State) -> Self {
        let fixed: Vec<bool> = (0..g.atom_count()).map(|a| u32::try_from(a).is_ok_and(|a| g.is_static(a))).collect();
        let always = start.iter().filter(|&a| fixed.get(a as usize).copied().unwrap_or(false)).collect();
        Self {
            arena: Vec::new(),
            start: vec![0],
            by_hash: HashMap::new(),
            next: Vec::new(),
            scratch: Vec::new(),
            fixed,
            always,
        }
    }

    /// How many states.
    pub(super) fn len(&self) -> usize {
        self.next.len()
    }

    /// Bytes used by the stored states.
    pub(super) fn bytes(&self) -> usize {
        self.arena.len() * 4 + self.start.len() * 8 + self.next.len() * 4 + self.by_hash.len() * 24
    }

    fn get(&self, id: u32) -> &[u32] {
        let s = self.start[id as usize] as usize;
        let e = self.start[id as usize + 1] as usize;
        &self.arena[s..e]
    }

    /// The id of `state`, storing it if it is new; and whether it was.
    pub(super) fn insert(&mut self, state: &State) -> (u32, bool) {
        let mut atoms = std::mem::take(&mut self.scratch);
        atoms.clear();
        atoms.extend(state.iter().filter(|&a| !self.fixed.get(a as usize).copied().unwrap_or(false)));
        let h = hash(&atoms);
        let mut at = self.by_hash.get(&h).copied().unwrap_or(END);
        let mut last = END;
        while at != END {
            if self.get(at) == atoms.as_slice() {
                self.scratch = atoms;
                return (at, false);
            }
            last = at;
            at = self.next[at as usize];
        }
        let id = self.next.len() as u32;
        self.arena.extend_from_slice(&atoms);
        self.start.push(self.arena.len() as u64);
        self.next.push(END);
        if last == END {
            self.by_hash.insert(h, id);
        } else {
            self.next[last as usize] = id;
        }
        self.scratch = atoms;
        (id, true)
    }

    /// Writes state `id` into `out`.
    pub(super) fn load(&self, id: u32, out: &mut State) {
        out.clear();
        for &a in self.get(id).iter().chain(&self.always) {
            out.set(a, true);
        }
    }
}
