//! Blended planning and acting, narrated: ticks a tree in a scene on the one runner of
//! [`worlds`] and, when the root fails, lets the planner expand the tree in place
//! ([`planner::Expanding`], Algorithm 1 of Colledanchise et al. 2019 at run time),
//! then goes on from the world as it is. A fixed tree ([`worlds::Fixed`]) runs the same
//! way and ends at its first Failure. The run ends at the root's first Success.
//!
//! The narration is for a robotics engineer following the run ([`super::narrate`]).

use bt_core::{BehaviorSet, Catalog, Context, Status};
use planner::ground::Grounding;
use planner::state::State;
use worlds::end::{Failures, FirstSuccess};
use worlds::{Agent, Clock, RunErrorKind, Runner, Settings, Trees};

use super::narrate::{Narrate, Narration};
pub use super::narrate::{Record, Snapshot};

/// Deepest tree the driver runs.
pub const DEPTH: usize = planner::DEPTH;

/// Named positions in the plane, metres: what the top view draws.
pub type Points = Vec<(&'static str, [f32; 2])>;

/// A world a scenario runs in: a [`worlds::World`] that tells what happens in it.
pub trait Scene: worlds::World {
    /// World event `i` in plain words (events only add up: 0 is the first), if there
    /// was one.
    fn event(&self, i: usize) -> Option<&str>;

    /// Positions for the top view, by name, in metres (empty for worlds without
    /// geometry).
    fn points(&self) -> Points {
        Vec::new()
    }
}

/// What a world's own conditions say about each ground atom of `g`: the planner's
/// belief about a world that keeps no STRIPS state.
pub fn belief_from_conditions<B: BehaviorSet + ?Sized>(world: &mut B, g: &Grounding) -> State {
    let mut state = State::new(g.atom_count());
    for atom in 0..g.atom_count() {
        let Ok(atom) = u32::try_from(atom) else { break };
        if let Some(leaf) = g.condition_leaf(atom) {
            let ctx = Context { node: 0, now: 0, starting: true, values: &[] };
            state.set(atom, world.condition(&leaf, ctx) == Status::Success);
        }
    }
    state
}

/// Runs the tree of `trees` in `world` with `agents` for at most `max_ticks`, writing the
/// narration to `out` and serving the run to Groot2 through `watch` (if it is on): tick
/// `k` at `k * TICK_MS`; after every tick that does not end the run (and after an
/// expansion) the agents act and the world steps.
///
/// # Errors
/// An invalid tree, a behavior that broke the tick rules, or the planner giving up,
/// each naming the tick.
pub fn run<W, T, A, C>(
    world: &mut W,
    trees: &mut T,
    catalog: &C,
    agents: &mut A,
    max_ticks: u32,
    out: &mut String,
    watch: &mut crate::groot2::Watch,
) -> anyhow::Result<Record>
where
    W: Scene,
    T: Trees<W>,
    T::Error: std::fmt::Display,
    T::Growth: Narrate,
    A: Agent<W>,
    C: Catalog + ?Sized,
{
    let settings = Settings {
        moves_on_at_stop: false,
        ..Settings::new(max_ticks, Clock { ms_per_tick: crate::episode::TICK_MS, first: 1 })
    };
    let mut narration = Narration::new(catalog);
    let mut ends = (Failures::first(), FirstSuccess);
    let result = Runner::new(settings).run_growing::<DEPTH, _, _, _, _, _>(
        trees,
        world,
        &mut ends,
        agents,
        &mut (&mut narration, watch),
    );
    out.push_str(&narration.take_text());
    result.map_err(|e| match e.kind {
        RunErrorKind::Grow(g) => anyhow::anyhow!("tick {}: the planner cannot expand the tree: {g}", e.tick),
        RunErrorKind::Invalid(v) => anyhow::anyhow!("tick {}: the tree is not valid: {v}", e.tick),
        RunErrorKind::Tick(t) => anyhow::anyhow!("tick {}: {t}", e.tick),
    })?;
    Ok(narration.into_record())
}

/// The name of a leaf as the catalog renders it.
pub fn leaf_name<C: Catalog + ?Sized>(catalog: &C, leaf: &bt_core::Leaf) -> String {
    bt_core::render::display_leaf(catalog, leaf, &[]).to_string()
}
