//! Seeded disturbances: the external agents of Problem 1 in Colledanchise et al. 2019,
//! acting on a STRIPS world at random ticks. The IPC benchmark measures trees under them
//! ([`crate::coverage`]), and learning scores trees under them.
//!
//! Before each tick, with chance `rate` (and while fewer than `max` acts were made and
//! the goal does not hold), an agent acts, with even odds:
//! - it *undoes* the robot's last completed action: the world goes back to the state at
//!   the start of the tick in which that action completed;
//! - it *helps*: it does an action of the tree that is applicable at that moment (the
//!   world jumps to its result, conditional effects included).
//!
//! Both leave the world in a state the domain can produce. During disturbed episodes
//! an action whose preconditions were changed under it fails instead of completing
//! ([`StripsWorld::set_checked_completion`]). The agents of episode `k` draw from a
//! generator seeded by the seed and `k` ([`Disturbance::agents`]), so a tree meets the
//! same disturbed episodes whenever it is run.
//!
//! ```
//! use std::sync::Arc;
//! use planner::strips::{self, StripsWorld, disturb::Disturbance};
//! use planner::{Options, PddlCatalog, domains, plan};
//!
//! let g = Arc::new(domains::cube_sphere()?);
//! let c = Arc::new(PddlCatalog::new(g.problem()));
//! let p = plan(g.clone(), c.clone(), Options::default())?;
//! let d = Disturbance { rate: 0.3, ..Disturbance::default() };
//! let helpers = strips::disturb::tree_actions(&p.nodes, &p.values, &g);
//! let mut world = StripsWorld::new(g.clone());
//! let mut agents = d.agents(helpers, 0);
//! let ends = strips::Ends { on_loop: false, failures: 2 };
//! let verdict = strips::run_to_goal((&p.nodes, &p.values), c.as_ref(), &mut world, 300, ends, &mut agents, &mut Vec::new())?;
//! assert!(agents.acts() <= 3);
//! assert_eq!(verdict.reached(), world.goal_reached());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::borrow::BorrowMut;

use bt_core::{Node, NodeKind};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use worlds::Agent;
use worlds::agent::TreeState;

use super::StripsWorld;
use crate::ground::{ActionId, Grounding};
use crate::state::State;

/// How often agents act, how often at most, and their seed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disturbance {
    /// Chance of an act before each tick, in `[0, 1]` (clamped).
    pub rate: f64,
    /// Most acts in one episode.
    pub max: u32,
    /// Seed of the agents.
    pub seed: u64,
}

impl Default for Disturbance {
    /// The IPC benchmark's: chance 0.2, at most 3 acts, seed 1.
    fn default() -> Self {
        Self { rate: 0.2, max: 3, seed: 1 }
    }
}

impl Disturbance {
    /// The agents of episode `episode`, helping with the actions `helpers` (a tree's
    /// actions, [`tree_actions`]).
    #[must_use]
    pub fn agents(&self, helpers: Vec<ActionId>, episode: u32) -> Agents {
        let rate = if self.rate.is_nan() { 0.0 } else { self.rate.clamp(0.0, 1.0) };
        let seed = self.seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ u64::from(episode);
        Agents {
            rate,
            max: self.max,
            helpers,
            rng: ChaCha8Rng::seed_from_u64(seed),
            last: None,
            undo: None,
            changes: Vec::new(),
            options: Vec::new(),
        }
    }
}

/// The ground actions of a tree's action leaves, in pre-order, each once.
#[must_use]
pub fn tree_actions(nodes: &[Node], values: &[u16], g: &Grounding) -> Vec<ActionId> {
    let mut out = Vec::new();
    let mut buf = Vec::new();
    for n in nodes {
        if let NodeKind::Action(leaf) = n.kind() {
            g.leaf_actions_of(leaf, leaf.args_in(values), &mut buf);
            for &a in &buf {
                if !out.contains(&a) {
                    out.push(a);
                }
            }
        }
    }
    out
}

/// The agents of one disturbed episode (see the module docs): a [`worlds::Agent`] of
/// any world that is, or holds, a [`StripsWorld`].
#[derive(Clone, Debug)]
pub struct Agents {
    rate: f64,
    max: u32,
    helpers: Vec<ActionId>,
    rng: ChaCha8Rng,
    /// The state at the start of the last tick, and the actions completed by then.
    last: Option<(State, usize)>,
    /// The state at the start of the tick in which the last action completed.
    undo: Option<State>,
    changes: Vec<(State, State)>,
    options: Vec<ActionId>,
}

impl Agents {
    /// Acts made so far.
    #[must_use]
    pub fn acts(&self) -> usize {
        self.changes.len()
    }

    /// The state before and after each act, in order.
    #[must_use]
    pub fn changes(&self) -> &[(State, State)] {
        &self.changes
    }

    /// [`Agents::changes`], taken.
    #[must_use]
    pub fn into_changes(self) -> Vec<(State, State)> {
        self.changes
    }

    /// Before a tick: maybe an act.
    fn before_tick(&mut self, w: &mut StripsWorld) {
        let done = w.executed().len();
        match &mut self.last {
            Some((state, before)) => {
                if *before < done {
                    // The last tick completed an action: its start is where an undo goes.
                    std::mem::swap(state, self.undo.get_or_insert_with(State::default));
                }
                state.clone_from(w.state());
                *before = done;
            }
            None => self.last = Some((w.state().clone(), done)),
        }
        if self.changes.len() as u32 >= self.max || w.goal_reached() || !self.rng.random_bool(self.rate) {
            return;
        }
        let before = w.state().clone();
        if self.rng.random_bool(0.5) {
            if let Some(earlier) = &self.undo {
                w.set_state(earlier.clone());
                self.changes.push((before, w.state().clone()));
            }
        } else {
            let g = w.grounding().clone();
            self.options.clear();
            self.options
                .extend(self.helpers.iter().copied().filter(|&a| g.action(a).is_some_and(|x| x.applicable(w.state()))));
            if !self.options.is_empty() {
                let a = self.options[self.rng.random_range(0..self.options.len())];
                let mut s = w.state().clone();
                if let Some(x) = g.action(a) {
                    g.apply(x, &mut s);
                }
                w.set_state(s);
                self.changes.push((before, w.state().clone()));
            }
        }
    }
}

impl<W: BorrowMut<StripsWorld>> Agent<W> for Agents {
    fn start(&mut self, world: &mut W) {
        let w = world.borrow_mut();
        w.set_checked_completion(true);
        self.before_tick(w);
    }

    fn act(&mut self, _: u32, world: &mut W, _: &TreeState<'_>) {
        self.before_tick(world.borrow_mut());
    }
}
