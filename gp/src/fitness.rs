//! Fitness: what the world side implements, and the cache that makes every tree an
//! episode at most once.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use bt_core::Node;

use crate::genome::{Genome, Token};

/// Scores a tree by running it: one call is one episode.
///
/// Implemented by the worlds (the symbolic and physics brick worlds of `sim-host`,
/// with the fitness of Eq. (1) and (2) of seed 003), and by any
/// `Fn(&[Node]) -> f64 + Sync` closure. Higher is better.
///
/// The GP calls it from several threads at once (rayon) and relies on it being a pure
/// function of the tree: the same tree must always score the same, which is what
/// makes the cache exact and a parallel run equal to a sequential one. A NaN score is
/// treated as the worst possible (`-inf`).
pub trait Fitness: Sync {
    /// The fitness of `tree` (a valid pre-order node array of reactive Sequence,
    /// Fallback and argument-less leaves).
    fn fitness(&self, tree: &[Node]) -> f64;
}

impl<F: Fn(&[Node]) -> f64 + Sync> Fitness for F {
    fn fitness(&self, tree: &[Node]) -> f64 {
        self(tree)
    }
}

/// FxHash-style multiply-rotate hasher: a genome hashes in a few nanoseconds. The map
/// is never iterated into an output, so the hash function cannot affect results.
#[derive(Clone, Copy, Default, Debug)]
pub struct TokenHasher(u64);

impl TokenHasher {
    const K: u64 = 0xf135_7aea_2e62_a9c5;

    #[inline(always)]
    fn add(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(26) ^ word).wrapping_mul(Self::K);
    }
}

impl Hasher for TokenHasher {
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.add(u64::from_le_bytes(word));
        }
    }

    #[inline(always)]
    fn write_u32(&mut self, i: u32) {
        self.add(u64::from(i));
    }

    #[inline(always)]
    fn write_u64(&mut self, i: u64) {
        self.add(i);
    }

    #[inline(always)]
    fn write_usize(&mut self, i: usize) {
        self.add(i as u64);
    }

    #[inline(always)]
    fn finish(&self) -> u64 {
        self.0.rotate_left(20)
    }
}

/// Every tree simulated so far with its fitness: the reference's hash table. Its size
/// is the number of episodes (unique simulations), the x-axis of the paper's curves.
#[derive(Clone, Debug, Default)]
pub struct FitnessCache {
    map: HashMap<Genome, f64, BuildHasherDefault<TokenHasher>>,
}

impl FitnessCache {
    /// An empty cache.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The fitness of a tree simulated before.
    #[inline]
    #[must_use]
    pub fn get(&self, tokens: &[Token]) -> Option<f64> {
        self.map.get(tokens).copied()
    }

    /// Whether the tree was simulated before.
    #[inline]
    #[must_use]
    pub fn contains(&self, tokens: &[Token]) -> bool {
        self.map.contains_key(tokens)
    }

    /// Records an episode's result (NaN stored as `-inf`). Returns false, changing
    /// nothing, if the tree was already there.
    pub fn insert(&mut self, genome: Genome, fitness: f64) -> bool {
        if self.map.contains_key(genome.tokens()) {
            return false;
        }
        self.map.insert(genome, sanitize(fitness));
        true
    }

    /// Episodes so far: the number of distinct trees simulated.
    #[must_use]
    pub fn episodes(&self) -> u64 {
        self.map.len() as u64
    }
}

/// NaN is the worst fitness.
#[inline]
pub(crate) fn sanitize(f: f64) -> f64 {
    if f.is_nan() { f64::NEG_INFINITY } else { f }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cache_counts_distinct_trees() {
        let mut cache = FitnessCache::new();
        let g = Genome::from(vec![Token::Sequence, Token::Action(1), Token::Close]);
        let h = Genome::from(vec![Token::Sequence, Token::Action(2), Token::Close]);
        assert!(cache.insert(g.clone(), -1.0));
        assert!(!cache.insert(g.clone(), -5.0));
        assert!(cache.insert(h.clone(), f64::NAN));
        assert_eq!(cache.episodes(), 2);
        assert_eq!(cache.get(g.tokens()), Some(-1.0));
        assert_eq!(cache.get(h.tokens()), Some(f64::NEG_INFINITY));
        assert!(!cache.contains(&[Token::Action(1)]));
    }
}
