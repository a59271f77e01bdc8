//! Fitness: what the world side implements, and the cache that makes every tree an
//! episode at most once.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use bt_core::Node;

use crate::genome::Genome;

/// Scores a tree by running it: one call is one episode.
///
/// Implemented by the worlds (the symbolic and physics brick worlds of `sim-host`,
/// with the fitness of Eq. (1) and (2) of Styrud et al.), and by any
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

    /// The size of `tree` as the controller it is learned for holds it: what a
    /// [`Bound`](crate::Bound) limits. By default the image of the tree itself, without
    /// a names section, as `bt-formats` encodes it; a world that ships the tree in
    /// another form (the PDDL leaf contract adds an Inverter per negative condition)
    /// measures that form. `None` when it makes no image at all.
    fn size(&self, tree: &[Node]) -> Option<Size> {
        image_size(tree)
    }
}

impl<F: Fn(&[Node]) -> f64 + Sync> Fitness for F {
    fn fitness(&self, tree: &[Node]) -> f64 {
        self(tree)
    }
}

pub use bt_formats::image::Size;

/// The size of the image of `nodes` (no values, no names) as a controller holds it;
/// `None` past what an image holds.
#[must_use]
pub fn image_size(nodes: &[Node]) -> Option<Size> {
    bt_formats::image::Image::new(nodes).size().ok()
}

/// Hands the hash a [`Genome`] carries straight to the map: a genome is hashed once,
/// when it is made. (The map is never iterated into an output, so hashing cannot affect
/// results.)
#[derive(Clone, Copy, Default, Debug)]
pub struct GenomeHasher(u64);

impl Hasher for GenomeHasher {
    fn write(&mut self, bytes: &[u8]) {
        // Only reached by keys other than genomes; FNV-1a keeps it correct.
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    #[inline(always)]
    fn write_u64(&mut self, i: u64) {
        self.0 ^= i;
    }

    #[inline(always)]
    fn finish(&self) -> u64 {
        self.0
    }
}

/// Every tree simulated so far with its fitness: the reference's hash table. Its size
/// is the number of episodes (unique simulations), the x-axis of the paper's curves.
#[derive(Clone, Debug, Default)]
pub struct FitnessCache {
    map: HashMap<Genome, f64, BuildHasherDefault<GenomeHasher>>,
}

impl FitnessCache {
    /// An empty cache.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty cache with room for `episodes` trees.
    #[must_use]
    pub fn with_capacity(episodes: usize) -> Self {
        Self { map: HashMap::with_capacity_and_hasher(episodes, BuildHasherDefault::default()) }
    }

    /// The fitness of a tree simulated before.
    #[inline]
    #[must_use]
    pub fn get(&self, genome: &Genome) -> Option<f64> {
        self.map.get(genome).copied()
    }

    /// Whether the tree was simulated before.
    #[inline]
    #[must_use]
    pub fn contains(&self, genome: &Genome) -> bool {
        self.map.contains_key(genome)
    }

    /// Records an episode's result (NaN stored as `-inf`). Returns false, changing
    /// nothing, if the tree was already there.
    pub fn insert(&mut self, genome: Genome, fitness: f64) -> bool {
        match self.map.entry(genome) {
            std::collections::hash_map::Entry::Occupied(_) => false,
            std::collections::hash_map::Entry::Vacant(v) => {
                v.insert(sanitize(fitness));
                true
            }
        }
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
        use crate::genome::Token;
        let mut cache = FitnessCache::new();
        let g = Genome::from(vec![Token::Sequence, Token::Action(1), Token::Close]);
        let h = Genome::from(vec![Token::Sequence, Token::Action(2), Token::Close]);
        assert!(cache.insert(g.clone(), -1.0));
        assert!(!cache.insert(g.clone(), -5.0));
        assert!(cache.insert(h.clone(), f64::NAN));
        assert_eq!(cache.episodes(), 2);
        assert_eq!(cache.get(&g), Some(-1.0));
        assert_eq!(cache.get(&h), Some(f64::NEG_INFINITY));
        assert!(!cache.contains(&Genome::from(vec![Token::Action(1)])));
    }
}
