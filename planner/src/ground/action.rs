//! Ground literals and ground actions, with their effects and cost.

use crate::model::{ObjectId, TemplateId};
use crate::state::State;

/// Index of a ground atom.
pub type AtomId = u32;
/// Index of a ground action in [`super::Grounding::actions`].
pub type ActionId = u32;

/// A ground literal: an atom that must hold (`positive`) or must not.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Lit {
    /// The atom.
    pub atom: AtomId,
    /// True for the atom, false for its negation.
    pub positive: bool,
}

impl Lit {
    /// The literal's index among all literals: `2 * atom + positive`.
    #[must_use]
    pub fn index(self) -> usize {
        self.atom as usize * 2 + usize::from(self.positive)
    }

    /// The literal of index `i` ([`Lit::index`]'s inverse).
    #[must_use]
    pub fn from_index(i: u32) -> Self {
        Self { atom: i / 2, positive: i % 2 == 1 }
    }

    /// The opposite literal.
    #[must_use]
    pub fn negated(self) -> Self {
        Self { atom: self.atom, positive: !self.positive }
    }

    /// Whether it holds in `state`.
    #[inline]
    #[must_use]
    pub fn holds(self, state: &State) -> bool {
        state.holds(self.atom) == self.positive
    }
}

/// A conditional effect of a ground action: when every literal of `when` holds before
/// the action, it adds `add` and deletes `del`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct CondEffect {
    /// The condition, a conjunction.
    pub when: Vec<Lit>,
    /// Atoms it makes true.
    pub add: Vec<AtomId>,
    /// Atoms it makes false.
    pub del: Vec<AtomId>,
}

/// A grounded action.
///
/// ADL preconditions are compiled away: a template whose precondition has several
/// alternatives (`or`, `exists`) grounds into one action per alternative, all with the
/// same template and arguments (so the same bt-core leaf) and the same effects.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GroundAction {
    /// Its template.
    pub template: TemplateId,
    /// The objects bound to the template's parameters.
    pub args: Vec<ObjectId>,
    /// Preconditions that can change (static ones are left out), in the order written.
    pub pre: Vec<Lit>,
    /// Atoms it makes true.
    pub add: Vec<AtomId>,
    /// Atoms it makes false (never also in `add`).
    pub del: Vec<AtomId>,
    /// Conditional effects (`when`), evaluated in the state before the action.
    pub cond: Vec<CondEffect>,
    /// Its cost (1 when the problem has no action costs).
    pub cost: u32,
}

impl GroundAction {
    /// Whether its preconditions hold in `state`.
    #[must_use]
    pub fn applicable(&self, state: &State) -> bool {
        self.pre.iter().all(|l| l.holds(state))
    }

    /// Applies its effects to `state`: conditions of conditional effects are read
    /// before anything changes; then deletions, then additions (an atom both deleted
    /// and added ends up true, as in PDDL). Derived atoms are left as they were:
    /// [`super::Grounding::apply`] also closes the state under the rules.
    pub fn apply(&self, state: &mut State) {
        if self.cond.is_empty() {
            for &d in &self.del {
                state.set(d, false);
            }
            for &a in &self.add {
                state.set(a, true);
            }
            return;
        }
        let fired: Vec<&CondEffect> = self.cond.iter().filter(|c| c.when.iter().all(|l| l.holds(state))).collect();
        for &d in self.del.iter().chain(fired.iter().flat_map(|c| c.del.iter())) {
            state.set(d, false);
        }
        for &a in self.add.iter().chain(fired.iter().flat_map(|c| c.add.iter())) {
            state.set(a, true);
        }
    }

    /// Whether it makes `lit` true, unconditionally or under some condition.
    #[must_use]
    pub fn achieves(&self, lit: Lit) -> bool {
        self.achieving_condition(lit).is_some()
    }

    /// The extra conditions under which it makes `lit` true: `Some(&[])` when its
    /// effects always do, the `when` of the first conditional effect that does, or
    /// `None`.
    #[must_use]
    pub fn achieving_condition(&self, lit: Lit) -> Option<&[Lit]> {
        let has = |add: &[AtomId], del: &[AtomId]| {
            if lit.positive { add.contains(&lit.atom) } else { del.contains(&lit.atom) }
        };
        if has(&self.add, &self.del) {
            return Some(&[]);
        }
        self.cond.iter().find(|c| has(&c.add, &c.del)).map(|c| c.when.as_slice())
    }

    /// Every literal it may make true: its effects and all conditional ones.
    pub fn may_effects(&self) -> impl Iterator<Item = Lit> + '_ {
        let pos = |atom| Lit { atom, positive: true };
        let neg = |atom| Lit { atom, positive: false };
        self.add.iter().map(move |&a| pos(a)).chain(self.del.iter().map(move |&a| neg(a))).chain(
            self.cond
                .iter()
                .flat_map(move |c| c.add.iter().map(move |&a| pos(a)).chain(c.del.iter().map(move |&a| neg(a)))),
        )
    }

    /// The literals it always makes true (conditional effects left out).
    pub fn must_effects(&self) -> impl Iterator<Item = Lit> + '_ {
        self.add
            .iter()
            .map(|&atom| Lit { atom, positive: true })
            .chain(self.del.iter().map(|&atom| Lit { atom, positive: false }))
    }
}
