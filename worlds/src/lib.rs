//! One world abstraction and one episode runner.
//!
//! A [`World`] is a behavior set (the conditions and actions a tree's leaves run) over a
//! state that can be reset and stepped: the symbolic STRIPS world of a PDDL problem, the
//! brick worlds of Styrud et al., the mobile manipulator of Colledanchise et al. 2019.
//! A [`Runner`] runs *episodes* in any of them: it ticks the tree, lets external
//! [agents](agent) act, steps the world, shows each tick to a [recorder](record), and
//! stops when an [end rule](end) says so or at the tick limit. Planning, learning, the
//! scenarios, the IPC benchmark and the demo all run their trees through it.
//!
//! One tick of an episode:
//!
//! 1. the tree is ticked once (`now` from the [`Clock`]);
//! 2. the recorder sees the tick ([`Recorder::ticked`]: the root's status, each node's,
//!    the leaf calls and status changes);
//! 3. the end rules look at it ([`Ends::check`]); a root Failure may instead grow the
//!    tree ([`Runner::run_growing`], the run-time expansion of Algorithm 1);
//! 4. the world *moves on*, unless the episode ended there (see [`Settings`]): the
//!    agents act ([`Agent::act`]), the world steps ([`World::step`]), and the recorder
//!    sees the result ([`Recorder::stepped`]).
//!
//! ```
//! use bt_core::{BehaviorInfo, BehaviorSet, Context, Leaf, Node, NodeId, NodeKind, Status, Tree};
//! use worlds::end::{Failures, SuccessTwice};
//! use worlds::{Clock, Runner, Settings, Stop, World};
//!
//! /// A lamp that a `switch-on` action lights in two ticks.
//! #[derive(Default)]
//! struct Lamp { lit: bool, running: bool }
//!
//! impl BehaviorSet for Lamp {
//!     fn condition(&mut self, _: &Leaf, _: Context<'_>) -> Status {
//!         if self.lit { Status::Success } else { Status::Failure }
//!     }
//!     fn action(&mut self, _: &Leaf, ctx: Context<'_>) -> Status {
//!         if self.running && !ctx.starting {
//!             self.lit = true;
//!             self.running = false;
//!             return Status::Success;
//!         }
//!         self.running = true;
//!         Status::Running
//!     }
//!     fn halt(&mut self, _: &Leaf, _: NodeId) {
//!         self.running = false;
//!     }
//! }
//!
//! impl World for Lamp {
//!     fn reset(&mut self) {
//!         *self = Self::default();
//!     }
//! }
//!
//! let catalog = [BehaviorInfo::condition("lit", 0), BehaviorInfo::action("switch-on", 0)];
//! let nodes = [
//!     Node::new(NodeKind::Fallback, 3),
//!     Node::new(NodeKind::Condition(Leaf::new(0)), 1),
//!     Node::new(NodeKind::Action(Leaf::new(1)), 1),
//! ];
//! let tree: Tree<'_, 4> = Tree::validate(&nodes, &catalog)?;
//! let mut runner = Runner::new(Settings::new(30, Clock::TENTHS));
//! let mut lamp = Lamp::default();
//! // Styrud et al.'s episodes: the first Failure, or Success on two ticks in a row.
//! let mut ends = (Failures::first(), SuccessTwice::default());
//! let out = runner.run(tree, &mut lamp, &mut ends, &mut (), &mut ())?;
//! assert_eq!((out.stop, out.ticks), (Stop::Success, 3));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod agent;
pub mod end;
mod kind;
pub mod record;
mod runner;

pub use agent::Agent;
pub use end::{Ends, Stop};
pub use kind::WorldKind;
pub use record::Recorder;
pub use runner::{Clock, Fixed, Outcome, RunError, RunErrorKind, Runner, Settings, Trees};

/// A world a tree runs in: its behaviors over a state that can be put back to the start
/// and advanced one tick at a time.
///
/// An episode alternates ticking the tree (the behaviors act on the state) and
/// [`World::step`] (the world advances by one tick: motions move, physics runs).
/// Symbolic worlds change only through their behaviors and keep the default `step`.
pub trait World: bt_core::BehaviorSet {
    /// Puts the world back in its start state, in place, nothing running: one world
    /// serves any number of episodes.
    fn reset(&mut self);

    /// Advances the world by one tick, after the tree was ticked.
    fn step(&mut self) {}
}

impl<W: World + ?Sized> World for &mut W {
    #[inline(always)]
    fn reset(&mut self) {
        (**self).reset();
    }

    #[inline(always)]
    fn step(&mut self) {
        (**self).step();
    }
}
