//! A backchained tree run behind a closure's rules ([`crate::regress::close_with`]).

use std::sync::Arc;

use bt_core::Catalog;

use crate::PlanError;
use crate::ground::{ActionId, Grounding};
use crate::strips::{self, StripsWorld};
use crate::tree::PlanTree;

/// A backchained tree behind a closure's rules, run by the bt-core executor in the
/// symbolic world ([`crate::regress::Closable`]).
pub(super) struct Behind<'a, C: ?Sized> {
    g: Arc<Grounding>,
    catalog: &'a C,
    base: &'a PlanTree,
    base_actions: Vec<ActionId>,
    base_nodes: usize,
    max_ticks: u32,
    /// The whole tree for the rules it was built with.
    built: Option<(RulesKey, crate::tree::Flat)>,
    states: Vec<bt_core::NodeState>,
}

/// The rules and undo rules a [`Behind`] tree was built with.
type RulesKey = (Vec<crate::regress::Rule>, Vec<crate::regress::Rule>);

impl<'a, C: Catalog + ?Sized> Behind<'a, C> {
    pub(super) fn new(g: Arc<Grounding>, catalog: &'a C, base: &'a PlanTree, max_ticks: u32) -> Self {
        let order = base.preorder(base.root());
        let mut base_actions = Vec::new();
        for &n in &order {
            if let crate::tree::Kind::Action(a) = base.kind(n)
                && !base_actions.contains(&a)
            {
                base_actions.push(a);
            }
        }
        Self { g, catalog, base, base_actions, base_nodes: order.len(), max_ticks, built: None, states: Vec::new() }
    }
}

impl<C: Catalog + ?Sized> crate::regress::Closable for Behind<'_, C> {
    fn run(
        &mut self,
        g: &Grounding,
        policy: &crate::regress::Policy,
        s: &crate::state::State,
    ) -> Result<(Vec<crate::state::State>, bool), PlanError> {
        let flat = match &mut self.built {
            Some(((rules, undo), flat))
                if rules.as_slice() == policy.rules() && undo.as_slice() == policy.undo_rules() =>
            {
                flat
            }
            built => {
                let key = (policy.rules().to_vec(), policy.undo_rules().to_vec());
                &built.insert((key, policy.tree_before_by_halves(g, self.base).flatten(g)?)).1
            }
        };
        let mut world = StripsWorld::new(self.g.clone());
        world.set_state(s.clone());
        let mut path = vec![s.clone()];
        let mut done = 0;
        let verdict = strips::run_to_goal(
            (&flat.nodes, &flat.values),
            self.catalog,
            &mut world,
            self.max_ticks,
            strips::Ends::DETERMINISTIC,
            worlds::agent::BeforeTicks(|_, w: &mut StripsWorld| {
                if w.executed().len() != done {
                    done = w.executed().len();
                    path.push(w.state().clone());
                }
            }),
            &mut self.states,
        )?;
        if world.executed().len() != done {
            path.push(world.state().clone());
        }
        Ok((path, verdict.reached()))
    }

    fn actions(&self, policy: &crate::regress::Policy) -> Vec<ActionId> {
        let mut out = self.base_actions.clone();
        for a in policy.actions() {
            if !out.contains(&a) {
                out.push(a);
            }
        }
        out
    }

    fn nodes(&self, g: &Grounding, policy: &crate::regress::Policy) -> usize {
        if policy.rules().is_empty() && policy.undo_rules().is_empty() {
            self.base_nodes
        } else {
            policy.nodes(g) + self.base_nodes
        }
    }
}
