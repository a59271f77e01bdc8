//! The rules of a [`Policy`] by the addition they came with (a *group*: the first
//! plan's rules, a way back's, an undo rule), so that a tree that must fit a controller
//! can keep some of a closure's groups and leave the others out ([`Policy::only`]).

use super::{Policy, Rule};
use crate::ground::{ActionId, Grounding};
use crate::state::State;

/// One addition of rules, as it was asked for (before [`Policy::insert`] dropped any).
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Group {
    /// The rules, in the order they were inserted.
    pub(super) rules: Vec<Rule>,
    /// Whether it is an undo rule ([`Policy::undo_rules`]).
    pub(super) undo: bool,
    /// The plan to the goal it added, if it was one.
    pub(super) plan: Option<Vec<ActionId>>,
}

impl Policy {
    /// How many groups of rules were added: the first plan's is group 0, and each way
    /// back or undo rule a closure adds is the next.
    #[must_use]
    pub fn group_count(&self) -> u32 {
        u32::try_from(self.log.len()).unwrap_or(u32::MAX)
    }

    /// Adds `group`'s rules and logs it; returns how many rules were kept.
    pub(super) fn apply(&mut self, group: Group) -> usize {
        let mut kept = 0;
        if group.undo {
            self.undo.extend(group.rules.iter().cloned());
            kept = group.rules.len();
        } else {
            for r in &group.rules {
                if self.insert(r.clone()) {
                    kept += 1;
                }
            }
        }
        if let Some(plan) = &group.plan {
            self.plans.push(plan.clone());
        }
        self.log.push(group);
        kept
    }

    /// The policy with only the groups `keep` admits, added in their first order: the
    /// same rules as the closure would have left, had it added only those.
    #[must_use]
    pub fn only(&self, keep: impl Fn(u32) -> bool) -> Self {
        let mut out = Self::empty();
        for (k, group) in self.log.iter().enumerate() {
            if u32::try_from(k).is_ok_and(&keep) {
                out.apply(group.clone());
            }
        }
        out
    }

    /// The groups whose rules the tree acts on from `s` until the goal (or until no rule
    /// holds), each once, in the order first acted on.
    #[must_use]
    pub fn groups_on_path(&self, g: &Grounding, s: &State) -> Vec<u32> {
        let mut out = Vec::new();
        for state in self.path(g, s) {
            if let Some(r) = self.next(&state)
                && !out.contains(&r.group)
            {
                out.push(r.group);
            }
        }
        out
    }

    /// Roughly the planner nodes each group adds to the tree: a Sequence, its conditions
    /// and its action per rule asked for (conditions shared with neighbours are counted
    /// in full).
    #[must_use]
    pub fn group_nodes(&self) -> Vec<usize> {
        self.log.iter().map(|grp| grp.rules.iter().map(|r| r.when.len() + 2).sum()).collect()
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::indexing_slicing)]

    use std::path::Path;

    use crate::ground::Grounding;
    use crate::guide::Trace;
    use crate::pddl::{parse_domain, parse_problem};
    use crate::regress::{Budget, Policy, close};

    #[test]
    fn replaying_every_group_gives_the_same_rules_and_none_but_the_first_the_plain_ones() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/ipc/transport-sat08-strips");
        let d = std::fs::read_to_string(dir.join("domain.pddl")).unwrap();
        let p = std::fs::read_to_string(dir.join("p01.pddl")).unwrap();
        let problem = parse_domain("domain.pddl", &d).and_then(|d| parse_problem("p01.pddl", &p, &d)).unwrap();
        let g = Grounding::new(&problem).unwrap();
        let plan = crate::search::gbfs(&g, &crate::search::SearchOptions::default()).unwrap().plan;
        let plain = Policy::of_trace(&g, &Trace::new(&g, &plan).unwrap());
        let mut closed = plain.clone();
        let report = close(&g, &mut closed, &Budget::default()).unwrap();
        assert!(report.plans + report.undo > 0, "{report}");
        assert_eq!(closed.group_count() as usize, 1 + report.plans + report.undo);
        let all = closed.only(|_| true);
        assert_eq!((all.rules(), all.undo_rules()), (closed.rules(), closed.undo_rules()));
        let first = closed.only(|k| k == 0);
        assert_eq!((first.rules(), first.undo_rules()), (plain.rules(), plain.undo_rules()));
        assert_eq!(closed.group_nodes().len(), closed.group_count() as usize);
    }
}
