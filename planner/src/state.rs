//! A set of true ground atoms as a bitset: the symbolic world state.

use crate::ground::AtomId;

/// The atoms that hold, one bit each.
#[derive(Debug, Default, PartialEq, Eq, Hash)]
pub struct State {
    words: Vec<u64>,
}

impl Clone for State {
    fn clone(&self) -> Self {
        Self { words: self.words.clone() }
    }

    /// Reuses the storage: an episode that resets its world allocates nothing.
    fn clone_from(&mut self, source: &Self) {
        self.words.clone_from(&source.words);
    }
}

impl State {
    /// All `atoms` false.
    #[must_use]
    pub fn new(atoms: usize) -> Self {
        Self { words: vec![0; atoms.div_ceil(64)] }
    }

    /// Whether `atom` holds (false for atoms out of range).
    #[inline]
    #[must_use]
    pub fn holds(&self, atom: AtomId) -> bool {
        let a = atom as usize;
        self.words.get(a / 64).is_some_and(|w| w & (1 << (a % 64)) != 0)
    }

    /// Makes `atom` true or false (ignored out of range).
    #[inline]
    pub fn set(&mut self, atom: AtomId, value: bool) {
        let a = atom as usize;
        if let Some(w) = self.words.get_mut(a / 64) {
            if value {
                *w |= 1 << (a % 64);
            } else {
                *w &= !(1 << (a % 64));
            }
        }
    }

    /// The atoms that hold, in increasing order.
    pub fn iter(&self) -> impl Iterator<Item = AtomId> + '_ {
        self.words.iter().enumerate().flat_map(|(i, &w)| bits(i, w))
    }

    /// The bits, 64 atoms a word (atom `a` is bit `a % 64` of word `a / 64`).
    #[must_use]
    pub(crate) fn words(&self) -> &[u64] {
        &self.words
    }

    /// The atoms set in both `words` and `mask`, in increasing order: the true atoms
    /// among those `mask` selects, without visiting the others.
    pub(crate) fn iter_masked<'a>(words: &'a [u64], mask: &'a [u64]) -> impl Iterator<Item = AtomId> + 'a {
        words.iter().zip(mask).enumerate().flat_map(|(i, (&w, &m))| bits(i, w & m))
    }

    /// Makes every atom false.
    pub fn clear(&mut self) {
        self.words.fill(0);
    }
}

/// The atoms of the set bits of `word`, word `i` of a state, in increasing order.
fn bits(i: usize, word: u64) -> impl Iterator<Item = AtomId> {
    let mut rest = word;
    std::iter::from_fn(move || {
        if rest == 0 {
            return None;
        }
        let b = rest.trailing_zeros();
        rest &= rest - 1;
        Some((i as u32) * 64 + b)
    })
}
