//! What the host can know of the world from a controller's status stream.
//!
//! The host sees no sensor: only the status of each node the controller ticked. A
//! condition's status is a fact about the world at that tick (the literal it checks held,
//! or did not); an action that succeeded tells that its effects now hold, if the
//! domain's model is right. Everything else is belief: the problem's initial state,
//! changed by the effects of the actions that succeeded and corrected by every condition
//! ticked since. A fact no condition has checked since the world last changed it keeps
//! its believed value; the planner refines free parameters (the cheapest grounding) on
//! this belief (`docs/controller.md` argues what that means).
//!
//! A condition that reports a value the belief did not hold, where no action that ran
//! since could have made the change, is *unexpected*: an external agent acted, or an
//! action had an effect the domain does not state (a robot that drove away from the
//! cube is no longer near it; STRIPS has no way to say so). Either way the belief
//! follows what was seen.

use bt_core::{Node, NodeKind, NodeStatus};
use planner::ground::{ActionId, AtomId, Grounding};
use planner::state::State;

/// The host's belief about the world, kept from the statuses the controller reports.
#[derive(Clone, Debug)]
pub struct Belief {
    state: State,
    /// The changes the actions that ran on the previous tick may make: atom, new value.
    moving: Vec<(AtomId, bool)>,
}

impl Belief {
    /// The problem's initial state.
    #[must_use]
    pub fn new(g: &Grounding) -> Self {
        Self { state: g.init().clone(), moving: Vec::new() }
    }

    /// The state believed now.
    #[must_use]
    pub fn state(&self) -> &State {
        &self.state
    }

    /// Reads one tick of a tree of `g`'s leaves (`nodes`, their value table `values`,
    /// each node's status after the tick), in pre-order, the order a tree of reactive
    /// Sequences and Fallbacks ticks its nodes: a condition ticked sets its fact (the
    /// condition's own status, under an Inverter too), an action that succeeded applies
    /// its effects. Returns the facts that changed unexpectedly, each with its new value.
    pub fn observe(
        &mut self,
        g: &Grounding,
        nodes: &[Node],
        values: &[u16],
        statuses: &[NodeStatus],
    ) -> Vec<(AtomId, bool)> {
        // The actions this tick ran, and the changes they (and those of the tick
        // before) may have made.
        let mut ran: Vec<(usize, ActionId)> = Vec::new();
        let mut alternatives = Vec::new();
        for (i, (node, &status)) in nodes.iter().zip(statuses).enumerate() {
            if let NodeKind::Action(leaf) = node.kind()
                && matches!(status, NodeStatus::Running | NodeStatus::Success)
            {
                g.leaf_actions_of(leaf, leaf.args_in(values), &mut alternatives);
                ran.extend(alternatives.first().map(|&a| (i, a)));
            }
        }
        let moving: Vec<(AtomId, bool)> = ran.iter().flat_map(|&(_, a)| changes(g, a)).collect();
        let mut unexpected = Vec::new();
        for (i, (node, &status)) in nodes.iter().zip(statuses).enumerate() {
            match node.kind() {
                NodeKind::Condition(leaf) if matches!(status, NodeStatus::Success | NodeStatus::Failure) => {
                    let Some(atom) = g.leaf_atom_of(leaf, leaf.args_in(values)) else { continue };
                    let value = status == NodeStatus::Success;
                    if self.state.holds(atom) != value {
                        let change = (atom, value);
                        if !self.moving.contains(&change) && !moving.contains(&change) {
                            unexpected.push(change);
                        }
                        self.state.set(atom, value);
                    }
                }
                NodeKind::Action(_) if status == NodeStatus::Success => {
                    if let Some(action) = ran.iter().find(|&&(at, _)| at == i).and_then(|&(_, a)| g.action(a)) {
                        g.apply(action, &mut self.state);
                    }
                }
                _ => {}
            }
        }
        self.moving = moving;
        unexpected
    }
}

/// The changes action `a` may make: each atom it adds (to true) or deletes (to false),
/// its conditional effects included.
fn changes(g: &Grounding, a: ActionId) -> Vec<(AtomId, bool)> {
    g.action(a).map_or_else(Vec::new, |x| {
        let adds = x.add.iter().chain(x.cond.iter().flat_map(|c| &c.add)).map(|&a| (a, true));
        let dels = x.del.iter().chain(x.cond.iter().flat_map(|c| &c.del)).map(|&a| (a, false));
        adds.chain(dels).collect()
    })
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use planner::{Options, domains};

    fn status_of(planner: &planner::Planner, facts: &[(&str, NodeStatus)]) -> Vec<NodeStatus> {
        let catalog = planner::PddlCatalog::new(planner.grounding().problem());
        planner
            .nodes()
            .iter()
            .map(|n| {
                let name = match n.kind() {
                    NodeKind::Condition(l) | NodeKind::Action(l) => {
                        bt_core::render::display_leaf(&catalog, l, &[]).to_string()
                    }
                    _ => String::new(),
                };
                facts.iter().find(|(f, _)| *f == name).map_or(NodeStatus::Idle, |&(_, s)| s)
            })
            .collect()
    }

    #[test]
    fn conditions_set_facts_and_finished_actions_their_effects() {
        let g = Arc::new(domains::cube_sphere().unwrap());
        let planner = planner::plan(g.clone(), Arc::new(planner::PddlCatalog::new(g.problem())), Options::default())
            .unwrap()
            .planner;
        let atom = |p: &str, a: &[&str]| g.atom_by_name(p, a).unwrap();
        let mut belief = Belief::new(&g);
        assert!(belief.state().holds(atom("hand-empty", &[])));
        // Fig. 3(e): the robot is near the cube, and pick(cube) finishes.
        let tick = status_of(
            &planner,
            &[
                ("at(cube, goal)", NodeStatus::Failure),
                ("near(cube)", NodeStatus::Success),
                ("pick(cube)", NodeStatus::Success),
            ],
        );
        let surprises = belief.observe(&g, planner.nodes(), &[], &tick);
        // near(cube) was not in the initial state, and no action that ran makes it.
        assert_eq!(surprises, [(atom("near", &["cube"]), true)]);
        assert!(belief.state().holds(atom("holding", &["cube"])), "pick's effect");
        assert!(!belief.state().holds(atom("hand-empty", &[])), "pick's effect");
        // Next tick an agent has taken the cube: holding(cube) fails, which pick (that
        // ran on the tick before) does not explain: it makes holding true, not false.
        let tick =
            status_of(&planner, &[("at(cube, goal)", NodeStatus::Failure), ("holding(cube)", NodeStatus::Failure)]);
        assert_eq!(belief.observe(&g, planner.nodes(), &[], &tick), [(atom("holding", &["cube"]), false)]);
        // While move-to(goal) runs, near(goal) coming true is its doing.
        let tick = status_of(&planner, &[("near(goal)", NodeStatus::Failure), ("move-to(goal)", NodeStatus::Running)]);
        assert!(belief.observe(&g, planner.nodes(), &[], &tick).is_empty());
        let tick =
            status_of(&planner, &[("near(goal)", NodeStatus::Success), ("place(cube, goal)", NodeStatus::Running)]);
        assert!(belief.observe(&g, planner.nodes(), &[], &tick).is_empty());
        assert!(belief.state().holds(atom("near", &["goal"])));
    }
}
