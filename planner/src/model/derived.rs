//! Derived predicates (`:derived`): which predicates rules define, and the strata in
//! which their rules are evaluated.
//!
//! A rule's head depends positively on the derived predicates its body names, and
//! negatively on those it names under `not`. The rules are *stratifiable* when no
//! derived predicate depends on its own negation; stratum `s(p)` is then the least
//! number with `s(p) ≥ s(q)` for each positive and `s(p) > s(q)` for each negative
//! dependency `q`, so a stratum reads only the final truth of the ones below it.

use super::{Domain, ModelError, PredicateId};

impl Domain {
    /// The predicate a rule of [`Domain::axioms`] derives.
    #[must_use]
    pub fn axiom_head(&self, axiom: usize) -> Option<PredicateId> {
        self.axioms.get(axiom).and_then(|a| a.effects.first()).map(|e| e.literal.atom.predicate)
    }

    /// Per predicate, whether rules derive it.
    #[must_use]
    pub fn derived_predicates(&self) -> Vec<bool> {
        let mut derived = vec![false; self.predicates.len()];
        for i in 0..self.axioms.len() {
            if let Some(d) = self.axiom_head(i).and_then(|p| derived.get_mut(usize::from(p))) {
                *d = true;
            }
        }
        derived
    }

    /// Per predicate, its stratum: 0 for a basic predicate, 1 and up for derived ones.
    ///
    /// # Errors
    /// [`ModelError::NotStratifiable`].
    pub fn strata(&self) -> Result<Vec<u16>, ModelError> {
        let derived = self.derived_predicates();
        let count = derived.iter().filter(|&&d| d).count();
        let mut stratum: Vec<u16> = derived.iter().map(|&d| u16::from(d)).collect();
        // Dependencies (head, body predicate, negated), each once.
        let mut deps: Vec<(PredicateId, PredicateId, bool)> = Vec::new();
        for (i, a) in self.axioms.iter().enumerate() {
            let Some(head) = self.axiom_head(i) else { continue };
            for c in &a.pre {
                c.for_each_literal(&mut |l| {
                    let q = l.atom.predicate;
                    if derived.get(usize::from(q)).copied().unwrap_or(false) && !deps.contains(&(head, q, !l.positive))
                    {
                        deps.push((head, q, !l.positive));
                    }
                });
            }
        }
        // Raising strata to a fixpoint: a stratum above the number of derived
        // predicates means a cycle through a negation.
        for _ in 0..=count * count.max(1) {
            let mut changed = false;
            for &(head, q, negated) in &deps {
                let need = stratum[usize::from(q)] + u16::from(negated);
                if stratum[usize::from(head)] < need {
                    if usize::from(need) > count {
                        let name = |p: PredicateId| self.predicates[usize::from(p)].name.clone();
                        let through = deps.iter().find(|d| d.2 && d.0 == head).map_or(q, |d| d.1);
                        return Err(ModelError::NotStratifiable { predicate: name(head), through: name(through) });
                    }
                    stratum[usize::from(head)] = need;
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        Ok(stratum)
    }

    /// Checks that no action changes a derived predicate and that the rules are
    /// stratifiable.
    ///
    /// # Errors
    /// [`ModelError::DerivedChanged`], [`ModelError::NotStratifiable`].
    pub fn check_derived(&self) -> Result<(), ModelError> {
        if self.axioms.is_empty() {
            return Ok(());
        }
        let derived = self.derived_predicates();
        for a in &self.actions {
            for e in &a.effects {
                let p = e.literal.atom.predicate;
                if derived.get(usize::from(p)).copied().unwrap_or(false) {
                    let predicate = self.predicates[usize::from(p)].name.clone();
                    return Err(ModelError::DerivedChanged { action: a.name.clone(), predicate });
                }
            }
        }
        self.strata().map(|_| ())
    }
}
