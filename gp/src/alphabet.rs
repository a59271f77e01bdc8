//! The leaves GP may use: a task's conditions and actions, drawn from any
//! [`bt_core::Catalog`].

use bt_core::{BehaviorId, Catalog, LeafKind};
use rand::{Rng, RngExt};

use crate::genome::Token;

/// Why a catalog cannot be a GP alphabet.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum AlphabetError {
    /// GP draws argument-less leaves only; this behavior takes arguments.
    #[error("behavior {id} `{name}` takes {}; GP leaves take none (ground it first)", crate::genome::count(*.arity, "argument"))]
    TakesArguments {
        /// Its id.
        id: BehaviorId,
        /// Its name.
        name: String,
        /// Its arity.
        arity: u8,
    },
    /// The catalog reports fewer behaviors than it claims to have.
    #[error("the catalog claims {} but has no behavior {id}", crate::genome::count(*.len, "behavior"))]
    Missing {
        /// The id it has nothing for.
        id: usize,
        /// The length it claims.
        len: usize,
    },
    /// Random trees and mutations need at least one action.
    #[error("the catalog has no action; GP needs at least one")]
    NoActions,
    /// More behaviors than a behavior id can name.
    #[error("{0} behaviors; behavior ids are 16-bit")]
    TooMany(usize),
}

/// The leaves of one task: its conditions and its actions, each in behavior-id order.
///
/// A leaf's behavior id is its index in the catalog (for the brick tasks, in
/// `planner::duplo::Task::behaviors`). Random leaves are drawn uniformly from all
/// conditions followed by all actions.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Alphabet {
    kinds: Vec<LeafKind>,
    conditions: Vec<BehaviorId>,
    actions: Vec<BehaviorId>,
}

impl Alphabet {
    /// The alphabet of a catalog whose behaviors all take no arguments.
    ///
    /// # Errors
    /// [`AlphabetError`] if a behavior takes arguments, the catalog has no action, or
    /// it has more behaviors than 16-bit ids can name.
    pub fn from_catalog<C: Catalog + ?Sized>(catalog: &C) -> Result<Self, AlphabetError> {
        let len = catalog.len();
        if len > usize::from(BehaviorId::MAX) {
            return Err(AlphabetError::TooMany(len));
        }
        let mut kinds = Vec::with_capacity(len);
        let (mut conditions, mut actions) = (Vec::new(), Vec::new());
        for id in 0..len {
            // len <= BehaviorId::MAX, checked above.
            let bid = id as BehaviorId;
            let info = catalog.info(bid).ok_or(AlphabetError::Missing { id, len })?;
            if info.arity != 0 {
                return Err(AlphabetError::TakesArguments { id: bid, name: info.name.to_string(), arity: info.arity });
            }
            kinds.push(info.kind);
            match info.kind {
                LeafKind::Condition => conditions.push(bid),
                LeafKind::Action => actions.push(bid),
            }
        }
        if actions.is_empty() {
            return Err(AlphabetError::NoActions);
        }
        Ok(Self { kinds, conditions, actions })
    }

    /// Number of behaviors (conditions and actions).
    #[must_use]
    pub fn len(&self) -> usize {
        self.kinds.len()
    }

    /// Never true: an alphabet has at least one action.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.kinds.is_empty()
    }

    /// The condition ids, ascending.
    #[must_use]
    pub fn conditions(&self) -> &[BehaviorId] {
        &self.conditions
    }

    /// The action ids, ascending.
    #[must_use]
    pub fn actions(&self) -> &[BehaviorId] {
        &self.actions
    }

    /// Whether behavior `id` is a condition or an action; `None` if unknown.
    #[must_use]
    pub fn kind(&self, id: BehaviorId) -> Option<LeafKind> {
        self.kinds.get(usize::from(id)).copied()
    }

    /// Whether a token is known: control tokens always, a leaf if its id names a
    /// behavior of that kind.
    #[inline]
    #[must_use]
    pub fn knows(&self, token: Token) -> bool {
        match token {
            Token::Sequence | Token::Fallback | Token::Close => true,
            Token::Condition(id) => self.kind(id) == Some(LeafKind::Condition),
            Token::Action(id) => self.kind(id) == Some(LeafKind::Action),
        }
    }

    /// A leaf drawn uniformly from all conditions and actions.
    pub fn random_leaf<R: Rng + ?Sized>(&self, rng: &mut R) -> Token {
        let n = self.conditions.len() + self.actions.len();
        let i = draw(rng, n);
        match self.conditions.get(i) {
            Some(&c) => Token::Condition(c),
            None => Token::Action(self.actions[i - self.conditions.len()]),
        }
    }

    /// An action drawn uniformly.
    pub fn random_action<R: Rng + ?Sized>(&self, rng: &mut R) -> Token {
        Token::Action(self.actions[draw(rng, self.actions.len())])
    }

    /// A random node (Styrud et al., Section III-B): a control node with probability 0.5
    /// (Sequence or Fallback, equally likely), else [`Alphabet::random_leaf`].
    pub fn random_node<R: Rng + ?Sized>(&self, rng: &mut R) -> Token {
        if rng.random::<f64>() < 0.5 { random_control(rng) } else { self.random_leaf(rng) }
    }
}

/// Sequence or Fallback, equally likely.
pub(crate) fn random_control<R: Rng + ?Sized>(rng: &mut R) -> Token {
    if draw(rng, 2) == 0 { Token::Sequence } else { Token::Fallback }
}

/// Uniform in `0..n` (`n >= 1`), drawn as a `u32` so that it is the same on every
/// platform.
#[inline]
pub(crate) fn draw<R: Rng + ?Sized>(rng: &mut R, n: usize) -> usize {
    debug_assert!(n >= 1);
    let n = u32::try_from(n).unwrap_or(u32::MAX);
    rng.random_range(0..n) as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use bt_core::BehaviorInfo;
    use planner::duplo::Task;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn brick_tasks_split_by_kind() {
        let a = Alphabet::from_catalog(&Task::Tower.spec()).unwrap();
        assert_eq!(a.len(), 22);
        assert_eq!(a.conditions(), (0..12).collect::<Vec<_>>());
        assert_eq!(a.actions(), (12..22).collect::<Vec<_>>());
        assert!(a.knows(Token::Condition(3)) && !a.knows(Token::Action(3)) && !a.knows(Token::Action(22)));
    }

    #[test]
    fn refuses_what_gp_cannot_draw() {
        let with_args = [BehaviorInfo::condition("at?", 0), BehaviorInfo::action("MoveTo", 1)];
        assert!(matches!(
            Alphabet::from_catalog(&with_args),
            Err(AlphabetError::TakesArguments { id: 1, arity: 1, .. })
        ));
        assert_eq!(Alphabet::from_catalog(&[BehaviorInfo::condition("at?", 0)]), Err(AlphabetError::NoActions));
    }

    #[test]
    fn random_leaves_cover_the_alphabet_uniformly() {
        let a = Alphabet::from_catalog(&Task::Blocking.spec()).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut counts = vec![0u32; a.len()];
        let draws = 27_000;
        for _ in 0..draws {
            let (Token::Condition(id) | Token::Action(id)) = a.random_leaf(&mut rng) else { panic!("not a leaf") };
            counts[usize::from(id)] += 1;
        }
        // 1000 expected each; 5 sigma is about 160.
        assert!(counts.iter().all(|&c| (840..1160).contains(&c)), "{counts:?}");
        let controls = (0..10_000).filter(|_| !a.random_node(&mut rng).is_leaf()).count();
        assert!((4_800..5_200).contains(&controls), "{controls}");
    }
}
