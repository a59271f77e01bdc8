//! The applicable actions of a state, found through one positive precondition of each
//! action instead of testing every action.

use crate::ground::{ActionId, Grounding};
use crate::state::State;

/// Actions indexed by their *trigger*: the positive precondition with the fewest
/// actions sharing it; actions without a positive precondition are always tested.
#[derive(Debug)]
pub(super) struct Successors {
    by_atom: Vec<Vec<ActionId>>,
    always: Vec<ActionId>,
}

impl Successors {
    pub(super) fn new(g: &Grounding) -> Self {
        let mut uses = vec![0u32; g.atom_count()];
        for a in g.actions() {
            for l in a.pre.iter().filter(|l| l.positive) {
                uses[l.atom as usize] += 1;
            }
        }
        let mut by_atom = vec![Vec::new(); g.atom_count()];
        let mut always = Vec::new();
        for (i, a) in g.actions().iter().enumerate() {
            match a.pre.iter().filter(|l| l.positive).min_by_key(|l| uses[l.atom as usize]) {
                Some(l) => by_atom[l.atom as usize].push(i as ActionId),
                None => always.push(i as ActionId),
            }
        }
        Self { by_atom, always }
    }

    /// The actions applicable in `state`, in id order.
    pub(super) fn applicable(&self, g: &Grounding, state: &State, out: &mut Vec<ActionId>) {
        out.clear();
        let ok = |a: ActionId| g.action(a).is_some_and(|x| x.applicable(state));
        out.extend(self.always.iter().copied().filter(|&a| ok(a)));
        for atom in state.iter() {
            if let Some(list) = self.by_atom.get(atom as usize) {
                out.extend(list.iter().copied().filter(|&a| ok(a)));
            }
        }
        out.sort_unstable();
    }
}
