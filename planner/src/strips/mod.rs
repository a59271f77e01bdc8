//! The symbolic STRIPS world: a [`BehaviorSet`] over a set of true ground atoms.
//!
//! A condition leaf succeeds when its atom holds. An action leaf runs its ground
//! action: on the tick it starts it returns Failure if its preconditions do not hold
//! (or it was sabotaged), else Running; on the next tick its effects are applied and it
//! returns Success. A halted action has no effect. Under a custom vocabulary a leaf may
//! name several groundings (`place at P!` for whichever brick is held): the first
//! applicable one runs.
//!
//! The same semantics runs every tree that acts in a STRIPS world: the planner's runs
//! ([`run_to_goal`], Algorithm 1), the learner's episodes (through
//! [`StripsWorld::act`], for leaves of its own), the scenarios and the IPC benchmark.
//! Effects are the grounded action's, conditional ones included
//! ([`crate::ground::GroundAction::apply`]).
//!
//! Episodes run on the one runner of [`worlds`]: [`run`] and [`run_to_goal`] set it up
//! for the planner. External agents act through [`StripsWorld::set`] (and the by-name
//! variants) between ticks, as a [`worlds::Agent`]: scripts, or the seeded
//! [`disturb`]ances of the IPC benchmark and of learning.
//!
//! ```
//! use std::sync::Arc;
//! use planner::{domains, strips::StripsWorld};
//! let g = Arc::new(domains::cube_sphere()?);
//! let mut world = StripsWorld::new(g.clone());
//! assert!(world.holds_named("hand-empty", &[]));
//! world.set_named("path-free", &["goal"], false);
//! assert!(!world.holds_named("path-free", &["goal"]));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::sync::Arc;

use bt_core::{BehaviorSet, Context, Leaf, NodeId, Status};

use crate::ground::{ActionId, AtomId, Grounding, Lit};
use crate::state::State;

pub mod disturb;
mod run;

pub use run::{Ends, Outcome, Verdict, run, run_to_goal};

/// The symbolic world of a grounded problem.
#[derive(Clone, Debug)]
pub struct StripsWorld {
    g: Arc<Grounding>,
    state: State,
    running: Vec<(NodeId, ActionId)>,
    sabotaged: Vec<bool>,
    starts: Vec<u32>,
    done: Vec<u32>,
    executed: Vec<ActionId>,
    scratch: Vec<ActionId>,
    checked: bool,
    /// The atom each condition node checked last, by node id, with the leaf it was
    /// found for: a tree ticks the same conditions over and over, and a lookup by
    /// key hashes it (see [`StripsWorld::atom_of`]).
    atoms: Vec<Option<(Leaf, Option<AtomId>)>>,
}

impl StripsWorld {
    /// The world in the problem's initial state.
    #[must_use]
    pub fn new(g: Arc<Grounding>) -> Self {
        let n = g.actions().len();
        Self {
            state: g.init().clone(),
            g,
            running: Vec::new(),
            sabotaged: vec![false; n],
            starts: vec![0; n],
            done: vec![0; n],
            executed: Vec::new(),
            scratch: Vec::new(),
            checked: false,
            atoms: Vec::new(),
        }
    }

    /// The grounding it runs.
    #[must_use]
    pub fn grounding(&self) -> &Arc<Grounding> {
        &self.g
    }

    /// The atoms that hold.
    #[must_use]
    pub fn state(&self) -> &State {
        &self.state
    }

    /// Whether `atom` holds.
    #[must_use]
    pub fn holds(&self, atom: AtomId) -> bool {
        self.state.holds(atom)
    }

    /// Whether `predicate(objects)` holds (false for unknown names).
    #[must_use]
    pub fn holds_named(&self, predicate: &str, objects: &[&str]) -> bool {
        self.g.atom_by_name(predicate, objects).is_some_and(|a| self.state.holds(a))
    }

    /// An external change of the whole state (the actions running go on); derived
    /// atoms follow its basic ones.
    pub fn set_state(&mut self, state: State) {
        self.state = state;
        self.g.close(&mut self.state);
    }

    /// An external change: makes `atom` true or false. Derived atoms follow the basic
    /// ones: setting one directly changes nothing.
    pub fn set(&mut self, atom: AtomId, value: bool) {
        self.state.set(atom, value);
        self.g.close(&mut self.state);
    }

    /// An external change by names; returns false (and changes nothing) for unknown names.
    pub fn set_named(&mut self, predicate: &str, objects: &[&str], value: bool) -> bool {
        match self.g.atom_by_name(predicate, objects) {
            Some(a) => {
                self.set(a, value);
                true
            }
            None => false,
        }
    }

    /// Makes ground action `action` fail whenever it starts (an external condition the
    /// model does not know, e.g. a jammed door), or work again. Note that a reactive
    /// Fallback retries a failing alternative every tick, preempting the ones after it:
    /// an external condition the tree can check is better modelled as a precondition.
    pub fn sabotage(&mut self, action: ActionId, on: bool) {
        if let Some(s) = self.sabotaged.get_mut(action as usize) {
            *s = on;
        }
    }

    /// How often `action` started (returned Running on its first tick).
    #[must_use]
    pub fn starts(&self, action: ActionId) -> u32 {
        self.starts.get(action as usize).copied().unwrap_or(0)
    }

    /// How often `action` completed (its effects applied).
    #[must_use]
    pub fn completions(&self, action: ActionId) -> u32 {
        self.done.get(action as usize).copied().unwrap_or(0)
    }

    /// With `true`, an action whose preconditions an external change made false while
    /// it ran fails when it would complete, without effects (the change interrupted
    /// it); by default it completes as started.
    pub fn set_checked_completion(&mut self, on: bool) {
        self.checked = on;
    }

    /// The actions completed so far, in order (the plan the tree executed).
    #[must_use]
    pub fn executed(&self) -> &[ActionId] {
        &self.executed
    }

    /// The actions running now, with the nodes that run them, sorted by node.
    #[must_use]
    pub fn running(&self) -> Vec<(NodeId, ActionId)> {
        let mut r = self.running.clone();
        r.sort_unstable();
        r
    }

    /// Back to the initial state, nothing running, counters cleared.
    pub fn reset(&mut self) {
        self.state.clone_from(self.g.init());
        self.running.clear();
        self.starts.fill(0);
        self.done.fill(0);
        self.executed.clear();
    }

    /// Whether every goal condition holds.
    #[must_use]
    pub fn goal_reached(&self) -> bool {
        self.g.goal_holds(&self.state)
    }

    /// Whether literal `lit` holds: a condition leaf's status.
    #[must_use]
    pub fn check(&self, lit: Lit) -> Status {
        if lit.holds(&self.state) { Status::Success } else { Status::Failure }
    }

    /// An action leaf at `node` that runs one of `candidates` (the ground actions its
    /// leaf names, in order): the semantics of every action in this world (see the
    /// module docs). `starting` is bt-core's [`Context::starting`].
    pub fn act(&mut self, node: NodeId, starting: bool, candidates: &[ActionId]) -> Status {
        match self.complete(node, starting) {
            Some(done) => done,
            None => self.start(node, candidates),
        }
    }

    /// The action running at `node` completes, if one does: its effects are applied.
    fn complete(&mut self, node: NodeId, starting: bool) -> Option<Status> {
        if starting {
            return None;
        }
        let i = self.running.iter().position(|r| r.0 == node)?;
        let (_, a) = self.running.swap_remove(i);
        if let Some(ga) = self.g.action(a) {
            if self.checked && !ga.applicable(&self.state) {
                return Some(Status::Failure);
            }
            self.g.apply(ga, &mut self.state);
        }
        if let Some(d) = self.done.get_mut(a as usize) {
            *d += 1;
        }
        self.executed.push(a);
        Some(Status::Success)
    }

    /// The first of `candidates` that is not sabotaged and applicable starts at `node`.
    fn start(&mut self, node: NodeId, candidates: &[ActionId]) -> Status {
        let chosen = candidates.iter().copied().find(|&a| {
            !self.sabotaged.get(a as usize).copied().unwrap_or(false)
                && self.g.action(a).is_some_and(|ga| ga.applicable(&self.state))
        });
        match chosen {
            Some(a) => {
                self.running.retain(|r| r.0 != node);
                self.running.push((node, a));
                if let Some(s) = self.starts.get_mut(a as usize) {
                    *s += 1;
                }
                Status::Running
            }
            None => Status::Failure,
        }
    }

    /// The action running at `node` stops, without effects.
    pub fn stop(&mut self, node: NodeId) {
        self.running.retain(|r| r.0 != node);
    }
}

impl StripsWorld {
    /// The atom condition leaf `leaf` at `ctx.node` checks. The answer depends only on
    /// the leaf where its values are inline, so it is kept by node and used again while
    /// that node holds the same leaf (any tree, any number of trees in turn).
    fn atom_of(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Option<AtomId> {
        let args = ctx.args(leaf);
        if args != leaf.args() {
            return self.g.leaf_atom_of(leaf, args);
        }
        let i = usize::from(ctx.node);
        if let Some(Some((seen, atom))) = self.atoms.get(i)
            && seen == leaf
        {
            return *atom;
        }
        let atom = self.g.leaf_atom_of(leaf, args);
        if self.atoms.len() <= i {
            self.atoms.resize(i + 1, None);
        }
        if let Some(slot) = self.atoms.get_mut(i) {
            *slot = Some((*leaf, atom));
        }
        atom
    }
}

impl BehaviorSet for StripsWorld {
    fn condition(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        match self.atom_of(leaf, ctx) {
            Some(a) if self.state.holds(a) => Status::Success,
            _ => Status::Failure,
        }
    }

    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        if let Some(done) = self.complete(ctx.node, ctx.starting) {
            return done;
        }
        let mut candidates = std::mem::take(&mut self.scratch);
        self.g.leaf_actions_of(leaf, ctx.args(leaf), &mut candidates);
        let status = self.start(ctx.node, &candidates);
        self.scratch = candidates;
        status
    }

    fn halt(&mut self, _: &Leaf, node: NodeId) {
        self.stop(node);
    }
}

impl worlds::World for StripsWorld {
    fn reset(&mut self) {
        StripsWorld::reset(self);
    }
}

impl worlds::end::Goal for StripsWorld {
    fn goal_reached(&self) -> bool {
        StripsWorld::goal_reached(self)
    }
}

/// A situation is the state with the actions running: ticking on from an equal one
/// repeats what was done since.
impl worlds::end::Progress for StripsWorld {
    type Key = (State, Vec<(NodeId, ActionId)>);

    fn progress(&self) -> usize {
        self.executed.len()
    }

    fn key(&self) -> Self::Key {
        (self.state.clone(), self.running())
    }
}
