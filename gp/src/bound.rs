//! The size bound of a run ([`Bound`]): a validity rule on how much a tree may take on
//! the controller, and the random trees of the first generation that keep to it.

use std::fmt;

use rand_chacha::ChaCha8Rng;

use crate::alphabet::Alphabet;
use crate::fitness::{Fitness, Size};
use crate::genome::{Genome, Token, length, write_nodes};
use crate::operators::{MAX_ATTEMPTS, random_tree};
use crate::params::Params;
use crate::run::GpError;

/// The most bytes and nodes a tree may take on the controller, as
/// [`Fitness::size`](crate::Fitness::size) measures it. `None`: no limit.
///
/// It is a validity rule, as the paper's are: a random tree or an offspring over the
/// bound is refused and drawn again, never simulated, so it costs no episode and no
/// tree over the bound is ever in the population (a penalty in the fitness would spend
/// episodes on trees that can never be the answer, and would still let one win).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Bound {
    /// Most image bytes (without the names section).
    pub bytes: Option<usize>,
    /// Most bt-core nodes.
    pub nodes: Option<usize>,
}

impl Bound {
    /// No limit.
    pub const NONE: Self = Self { bytes: None, nodes: None };

    /// Whether there is a limit at all.
    #[must_use]
    pub const fn is_none(&self) -> bool {
        self.bytes.is_none() && self.nodes.is_none()
    }

    /// Whether a tree of `size` is within the bound.
    #[must_use]
    pub fn admits(&self, size: Size) -> bool {
        self.bytes.is_none_or(|b| size.bytes <= b) && self.nodes.is_none_or(|n| size.nodes <= n)
    }
}

impl fmt::Display for Bound {
    /// `at most 300 bytes and 20 nodes`, `at most 300 bytes`, `no bound`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use crate::genome::count;
        match (self.bytes, self.nodes) {
            (None, None) => f.write_str("no bound"),
            (Some(b), None) => write!(f, "at most {}", count(b, "byte")),
            (None, Some(n)) => write!(f, "at most {}", count(n, "node")),
            (Some(b), Some(n)) => write!(f, "at most {} and {}", count(b, "byte"), count(n, "node")),
        }
    }
}

/// Whether a valid tree is within `bound` (always, without one). Measured only when
/// bounded: an unbounded run does exactly what it did before bounds existed.
pub(crate) fn fits<F: Fitness + ?Sized>(tokens: &[Token], bound: Bound, fitness: &F) -> bool {
    if bound.is_none() {
        return true;
    }
    // Nodes never shrink in the shipped form, so the count alone can refuse at once.
    if bound.nodes.is_some_and(|n| length(tokens) > n) {
        return false;
    }
    let mut nodes = Vec::with_capacity(tokens.len());
    write_nodes(tokens, &mut nodes).is_ok() && fitness.size(&nodes).is_some_and(|size| bound.admits(size))
}

/// The initial population's random trees within the bound: of `initial_length` nodes
/// (at most the bound's nodes); where [`MAX_ATTEMPTS`] draws in a row are over the
/// bound, one node fewer, down to `min_length`. Unbounded, exactly the draws of
/// [`random_tree`].
pub(crate) struct RandomTrees {
    length: usize,
    min_length: usize,
    bound: Bound,
    misses: usize,
}

impl RandomTrees {
    pub(crate) fn new(params: &Params) -> Self {
        let length = params.initial_length.min(params.bound.nodes.unwrap_or(usize::MAX));
        Self { length, min_length: params.min_length, bound: params.bound, misses: 0 }
    }

    pub(crate) fn next<F: Fitness + ?Sized>(
        &mut self,
        alphabet: &Alphabet,
        fitness: &F,
        rng: &mut ChaCha8Rng,
    ) -> Result<Genome, GpError> {
        let too_small = GpError::BoundTooSmall { bound: self.bound, min_length: self.min_length };
        loop {
            if self.length < self.min_length.max(1) {
                return Err(too_small);
            }
            let tree = random_tree(self.length, alphabet, rng).ok_or(GpError::NoRandomTree(self.length))?;
            if fits(tree.tokens(), self.bound, fitness) {
                return Ok(tree);
            }
            self.misses += 1;
            if self.misses == MAX_ATTEMPTS {
                self.misses = 0;
                self.length -= 1;
            }
        }
    }
}
