//! Search states stored once: each as the sorted list of its true atoms in one arena,
//! found again through a hash table of their hashes. Static atoms (of predicates no
//! action changes, such as a grid's `connected`) are the same in every state of a
//! search: they are kept once, not per state. Where the other atoms (fluents) are few
//! and many of them true, as in maintenance, a state is a bitset over the fluents
//! instead, whichever is smaller for the start state.

use std::collections::HashMap;
use std::hash::BuildHasher as _;

use foldhash::fast::FixedState;

use crate::ground::Grounding;
use crate::state::State;

/// Every state met, by id.
#[derive(Debug)]
pub(super) struct Registry {
    arena: Vec<u32>,
    start: Vec<u64>,
    /// Hash of a state's atoms → the first state with that hash; further ones chain
    /// through `next`.
    by_hash: HashMap<u64, u32, FixedState>,
    next: Vec<u32>,
    scratch: Vec<u32>,
    /// The fluents (atoms not static), one bit each as [`State`] has them: a state's
    /// fluents are its words masked by these.
    fluent_words: Vec<u64>,
    /// The static atoms true in every state of the search.
    always: Vec<u32>,
    /// How a state's fluents are written.
    encoding: Encoding,
}

/// A state's fluents as stored.
#[derive(Debug)]
enum Encoding {
    /// The true ones, in increasing order.
    List,
    /// One bit per fluent (`fluents`, in increasing order; `index` gives each atom's
    /// position among them, [`END`] for static atoms).
    Bits { fluents: Vec<u32>, index: Vec<u32> },
}

const END: u32 = u32::MAX;

/// A state's hash: foldhash with a fixed seed (fast, and the same in every run; the
/// ids do not depend on it anyway).
fn hash(atoms: &[u32]) -> u64 {
    FixedState::with_seed(0).hash_one(atoms)
}

impl Registry {
    /// A registry for states of `g` reached from `start` (whose static atoms every one
    /// of them shares).
    pub(super) fn new(g: &Grounding, start: &State) -> Self {
        Self::with_encoding(g, start, None)
    }

    /// [`Registry::new`], with the encoding chosen (`Some(true)`: bits) or not.
    fn with_encoding(g: &Grounding, start: &State, bits: Option<bool>) -> Self {
        let fixed: Vec<bool> = (0..g.atom_count()).map(|a| u32::try_from(a).is_ok_and(|a| g.is_static(a))).collect();
        let always: Vec<u32> = start.iter().filter(|&a| fixed.get(a as usize).copied().unwrap_or(false)).collect();
        let fluents: Vec<u32> = (0..g.atom_count())
            .filter(|&a| !fixed.get(a).copied().unwrap_or(true))
            .filter_map(|a| u32::try_from(a).ok())
            .collect();
        let mut fluent_words = vec![0u64; g.atom_count().div_ceil(64)];
        for &a in &fluents {
            if let Some(w) = fluent_words.get_mut(a as usize / 64) {
                *w |= 1 << (a % 64);
            }
        }
        let true_fluents = start.iter().count() - always.len();
        let encoding = if bits.unwrap_or(fluents.len().div_ceil(32) < true_fluents) {
            let mut index = vec![END; g.atom_count()];
            for (k, &a) in fluents.iter().enumerate() {
                if let Some(slot) = index.get_mut(a as usize) {
                    *slot = k as u32;
                }
            }
            Encoding::Bits { fluents, index }
        } else {
            Encoding::List
        };
        Self {
            arena: Vec::new(),
            start: vec![0],
            by_hash: HashMap::with_hasher(FixedState::with_seed(0)),
            next: Vec::new(),
            scratch: Vec::new(),
            fluent_words,
            always,
            encoding,
        }
    }

    /// Writes the fluents of `state` as stored into `out`.
    fn encode(&self, state: &State, out: &mut Vec<u32>) {
        out.clear();
        match &self.encoding {
            Encoding::List => out.extend(State::iter_masked(state.words(), &self.fluent_words)),
            Encoding::Bits { fluents, index } => {
                out.resize(fluents.len().div_ceil(32), 0);
                for a in State::iter_masked(state.words(), &self.fluent_words) {
                    let k = index.get(a as usize).copied().unwrap_or(END);
                    if let Some(w) = out.get_mut(k as usize / 32)
                        && k != END
                    {
                        *w |= 1 << (k % 32);
                    }
                }
            }
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
        self.encode(state, &mut atoms);
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
        for &a in &self.always {
            out.set(a, true);
        }
        match &self.encoding {
            Encoding::List => {
                for &a in self.get(id) {
                    out.set(a, true);
                }
            }
            Encoding::Bits { fluents, .. } => {
                for (i, &w) in self.get(id).iter().enumerate() {
                    let mut rest = w;
                    while rest != 0 {
                        let k = i * 32 + rest.trailing_zeros() as usize;
                        rest &= rest - 1;
                        if let Some(&a) = fluents.get(k) {
                            out.set(a, true);
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::indexing_slicing)]
    use super::*;

    /// Both encodings give every state back as it was stored, and the same ids.
    #[test]
    fn states_come_back_as_stored_in_either_encoding() {
        let g = crate::domains::blocks_world(5).unwrap();
        let mut regs = [false, true].map(|bits| Registry::with_encoding(&g, g.init(), Some(bits)));
        assert!(matches!(regs[1].encoding, Encoding::Bits { .. }) && matches!(regs[0].encoding, Encoding::List));
        // A walk through the state space: every applicable action of each state in turn.
        let mut frontier = vec![g.init().clone()];
        let mut out = State::new(g.atom_count());
        for _ in 0..200 {
            let Some(s) = frontier.pop() else { break };
            let ids = regs.each_mut().map(|r| r.insert(&s));
            assert_eq!(ids[0], ids[1]);
            for r in &regs {
                r.load(ids[0].0, &mut out);
                assert_eq!(out, s);
            }
            if ids[0].1 {
                for a in 0..g.actions().len() as u32 {
                    if let Some(x) = g.action(a).filter(|x| x.applicable(&s)) {
                        let mut n = s.clone();
                        g.apply(x, &mut n);
                        frontier.insert(0, n);
                    }
                }
            }
        }
        assert!(regs[0].len() > 20, "{}", regs[0].len());
    }
}
