//! Episodes of a tree in GP's leaves in the STRIPS world, with or without external
//! agents, and the fitness (see the [parent module](super)).

use std::borrow::{Borrow, BorrowMut};
use std::sync::{Arc, Mutex};

use anyhow::anyhow;
use bt_core::{BehaviorSet, Context, Leaf, Node, NodeId, NodeKind, Status, Tree};
use planner::ground::ActionId;
use planner::strips::StripsWorld;
use planner::strips::disturb::Agents;
use worlds::end::{Failures, SuccessTwice};
use worlds::{Clock, Runner, Settings, Stop, World};

use super::{DEPTH, Disturbance, Letter, StripsFitnessParams, StripsProblem};

/// How one episode ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StripsEnd {
    /// The root returned Failure.
    Failure,
    /// The root returned Success on two ticks in a row.
    Success,
    /// The tick limit was reached.
    Timeout,
}

/// One episode's outcome.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StripsEpisode {
    /// How it ended.
    pub end: StripsEnd,
    /// Ticks run.
    pub ticks: u32,
    /// Goal literals that did not hold at the end.
    pub unmet: usize,
    /// External agents' acts during the episode.
    pub disturbances: u32,
    /// The fitness of this episode alone.
    pub fitness: f64,
}

impl StripsEpisode {
    /// Whether the goal held at the end.
    #[must_use]
    pub fn goal_reached(&self) -> bool {
        self.unmet == 0
    }
}

/// The STRIPS world with GP's leaves: each leaf is one grounded literal or action
/// ([`Letter`]), run with the world's own semantics ([`StripsWorld::check`],
/// [`StripsWorld::act`]).
struct Letters<'a> {
    p: &'a StripsProblem,
    world: &'a mut StripsWorld,
}

impl BehaviorSet for Letters<'_> {
    fn condition(&mut self, leaf: &Leaf, _: Context<'_>) -> Status {
        match self.p.letter(leaf.behavior()) {
            Some(Letter::Condition(l)) => self.world.check(l),
            _ => Status::Failure,
        }
    }

    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        match self.p.letter(leaf.behavior()) {
            Some(Letter::Action(a)) => self.world.act(ctx.node, ctx.starting, &[a]),
            _ => Status::Failure,
        }
    }

    fn halt(&mut self, _: &Leaf, node: NodeId) {
        self.world.stop(node);
    }
}

impl World for Letters<'_> {
    fn reset(&mut self) {
        self.world.reset();
    }
}

impl Borrow<StripsWorld> for Letters<'_> {
    fn borrow(&self) -> &StripsWorld {
        self.world
    }
}

impl BorrowMut<StripsWorld> for Letters<'_> {
    fn borrow_mut(&mut self) -> &mut StripsWorld {
        self.world
    }
}

/// The ground actions of a tree's action leaves, in pre-order, each once: what the
/// helping agents may do ([`planner::strips::disturb`]).
fn tree_actions(p: &StripsProblem, nodes: &[Node]) -> Vec<ActionId> {
    let mut out = Vec::new();
    for n in nodes {
        if let NodeKind::Action(l) = n.kind()
            && let Some(Letter::Action(a)) = p.letter(l.behavior())
            && !out.contains(&a)
        {
            out.push(a);
        }
    }
    out
}

/// Runs episodes of trees in GP's leaves.
#[derive(Debug)]
pub struct StripsRunner {
    p: Arc<StripsProblem>,
    world: StripsWorld,
    runner: Runner,
    params: StripsFitnessParams,
}

impl StripsRunner {
    /// A runner with the default fitness constants and tick limit `tick_limit`.
    #[must_use]
    pub fn new(p: Arc<StripsProblem>, tick_limit: u32) -> Self {
        let world = StripsWorld::new(p.grounding().clone());
        // Tick k (from 1) at k * 100 ms; agents act before ticks, so the world does
        // not move on after the last; what still runs at the limit is halted.
        let settings = Settings {
            moves_on_at_limit: false,
            moves_on_at_stop: false,
            halt_at_limit: true,
            ..Settings::new(tick_limit.max(1), Clock { ms_per_tick: crate::episode::TICK_MS, first: 1 })
        };
        Self { p, world, runner: Runner::new(settings), params: StripsFitnessParams::default() }
    }

    /// One episode: undisturbed with `agents_of = None`, else disturbed by the agents of
    /// episode `k` of `d`.
    ///
    /// # Errors
    /// A tree that does not validate against GP's leaves within [`DEPTH`] levels.
    pub fn episode(&mut self, nodes: &[Node], agents_of: Option<(&Disturbance, u32)>) -> anyhow::Result<StripsEpisode> {
        let tree: Tree<'_, DEPTH> = Tree::validate(nodes, &self.p.catalog).map_err(|e| anyhow!("{e}"))?;
        let Self { p, world, runner, params } = self;
        world.reset();
        let mut agents: Option<Agents> = agents_of.map(|(d, k)| d.model().agents(tree_actions(p, nodes), k));
        let mut letters = Letters { p, world };
        let mut ends = (Failures::first(), SuccessTwice::default());
        let out = runner.run(tree, &mut letters, &mut ends, &mut agents, &mut ()).map_err(|e| anyhow!("{e}"))?;
        let end = match out.stop {
            Stop::Failure => StripsEnd::Failure,
            Stop::Success => StripsEnd::Success,
            _ => StripsEnd::Timeout,
        };
        let unmet = p.grounding().goal().iter().filter(|l| world.holds(l.atom) != l.positive).count();
        let mut cost = params.unmet_goal * unmet as f64;
        cost += params.length * nodes.len() as f64;
        cost += params.tick * f64::from(out.ticks);
        if end == StripsEnd::Failure {
            cost += params.failure;
        }
        if end == StripsEnd::Timeout {
            cost += params.timeout;
        }
        let disturbances = agents.map_or(0, |a| u32::try_from(a.acts()).unwrap_or(u32::MAX));
        Ok(StripsEpisode { end, ticks: out.ticks, unmet, disturbances, fitness: -cost })
    }
}

/// GP's fitness on a PDDL problem: one episode undisturbed, or the mean over the
/// disturbed episodes. A tree that cannot run scores `-inf`.
pub struct StripsFitness {
    p: Arc<StripsProblem>,
    tick_limit: u32,
    disturbance: Option<Disturbance>,
    pool: Mutex<Vec<StripsRunner>>,
}

impl std::fmt::Debug for StripsFitness {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StripsFitness")
            .field("tick_limit", &self.tick_limit)
            .field("disturbance", &self.disturbance)
            .finish_non_exhaustive()
    }
}

impl StripsFitness {
    /// The fitness of `p` with that tick limit and those disturbances.
    #[must_use]
    pub fn new(p: Arc<StripsProblem>, tick_limit: u32, disturbance: Option<Disturbance>) -> Self {
        Self { p, tick_limit, disturbance, pool: Mutex::new(Vec::new()) }
    }

    /// Every episode that scores `tree`, in order.
    ///
    /// # Errors
    /// As [`StripsRunner::episode`].
    pub fn episodes(&self, tree: &[Node]) -> anyhow::Result<Vec<StripsEpisode>> {
        let runner = self.pool.lock().ok().and_then(|mut p| p.pop());
        let mut runner = runner.unwrap_or_else(|| StripsRunner::new(self.p.clone(), self.tick_limit));
        let result = match self.disturbance {
            None => runner.episode(tree, None).map(|e| vec![e]),
            Some(d) => (0..d.episodes).map(|k| runner.episode(tree, Some((&d, k)))).collect(),
        };
        if let Ok(mut p) = self.pool.lock() {
            p.push(runner);
        }
        result
    }

    /// The fitness: the mean of the episodes' fitness, summed in order.
    #[must_use]
    pub fn score(&self, tree: &[Node]) -> f64 {
        match self.episodes(tree) {
            Ok(e) if !e.is_empty() => e.iter().map(|x| x.fitness).sum::<f64>() / e.len() as f64,
            _ => f64::NEG_INFINITY,
        }
    }
}

impl gp::Fitness for StripsFitness {
    fn fitness(&self, tree: &[Node]) -> f64 {
        self.score(tree)
    }

    /// The size of the tree `learn` writes: in the PDDL leaf contract (an Inverter per
    /// negative condition).
    fn size(&self, tree: &[Node]) -> Option<gp::Size> {
        self.p.size(tree)
    }
}
