//! Episodes of a tree in GP's leaves in the STRIPS world, with or without external
//! agents, and the fitness (see the [parent module](super)).

use std::sync::{Arc, Mutex};

use anyhow::anyhow;
use bt_core::{BehaviorSet, Context, Executor, Leaf, Node, NodeId, NodeState, Status, Tree};
use planner::ground::ActionId;
use planner::strips::StripsWorld;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

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

/// The world of one episode, as the tree's behavior set: the STRIPS state and the
/// actions the tree has running.
struct Behaviors<'a> {
    p: &'a StripsProblem,
    world: &'a mut StripsWorld,
    running: &'a mut Vec<(NodeId, ActionId)>,
}

impl BehaviorSet for Behaviors<'_> {
    fn condition(&mut self, leaf: &Leaf, _: Context<'_>) -> Status {
        match self.p.letter(leaf.behavior()) {
            Some(Letter::Condition(l)) if self.world.holds(l.atom) == l.positive => Status::Success,
            _ => Status::Failure,
        }
    }

    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        if !ctx.starting
            && let Some(i) = self.running.iter().position(|r| r.0 == ctx.node)
        {
            let (_, a) = self.running.swap_remove(i);
            if let Some(ga) = self.p.g.action(a) {
                for &d in &ga.del {
                    self.world.set(d, false);
                }
                for &x in &ga.add {
                    self.world.set(x, true);
                }
            }
            return Status::Success;
        }
        let Some(Letter::Action(a)) = self.p.letter(leaf.behavior()) else { return Status::Failure };
        match self.p.g.action(a) {
            Some(ga) if ga.applicable(self.world.state()) => {
                self.running.retain(|r| r.0 != ctx.node);
                self.running.push((ctx.node, a));
                Status::Running
            }
            _ => Status::Failure,
        }
    }

    fn halt(&mut self, _: &Leaf, node: NodeId) {
        self.running.retain(|r| r.0 != node);
    }
}

/// The generator of episode `k`'s agents.
fn agents(seed: u64, k: u32) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(gp::islands::island_seed(seed, 1 + k as usize, 0))
}

/// An external agent's act, maybe: see the module docs.
fn disturb(
    p: &StripsProblem,
    world: &mut StripsWorld,
    rate: f64,
    rng: &mut ChaCha8Rng,
    scratch: &mut Vec<ActionId>,
) -> bool {
    if rng.random::<f64>() >= rate {
        return false;
    }
    let undo = rng.random_range(0..2u32) == 1;
    scratch.clear();
    let state = world.state();
    for (i, a) in p.g.actions().iter().enumerate() {
        let ok = if undo {
            a.add.iter().all(|&x| state.holds(x))
                && a.del.iter().all(|&x| !state.holds(x))
                && !(a.add.is_empty() && a.del.is_empty())
        } else {
            a.applicable(state) && (a.add.iter().any(|&x| !state.holds(x)) || a.del.iter().any(|&x| state.holds(x)))
        };
        if ok {
            scratch.push(i as ActionId);
        }
    }
    if scratch.is_empty() {
        return false;
    }
    let pick = scratch[rng.random_range(0..scratch.len() as u32) as usize];
    let Some(a) = p.g.action(pick) else { return false };
    let (on, off) = if undo { (&a.del, &a.add) } else { (&a.add, &a.del) };
    for &x in off {
        world.set(x, false);
    }
    for &x in on {
        world.set(x, true);
    }
    true
}

/// Runs episodes of trees in GP's leaves.
#[derive(Debug)]
pub struct StripsRunner {
    p: Arc<StripsProblem>,
    world: StripsWorld,
    running: Vec<(NodeId, ActionId)>,
    states: Vec<NodeState>,
    scratch: Vec<ActionId>,
    params: StripsFitnessParams,
    tick_limit: u32,
}

impl StripsRunner {
    /// A runner with the default fitness constants and tick limit `tick_limit`.
    #[must_use]
    pub fn new(p: Arc<StripsProblem>, tick_limit: u32) -> Self {
        let world = StripsWorld::new(p.g.clone());
        Self {
            p,
            world,
            running: Vec::new(),
            states: Vec::new(),
            scratch: Vec::new(),
            params: StripsFitnessParams::default(),
            tick_limit: tick_limit.max(1),
        }
    }

    /// One episode: undisturbed with `agents = None`, else disturbed with that rate by
    /// the agents of episode `k` of `seed`.
    ///
    /// # Errors
    /// A tree that does not validate against GP's leaves within [`DEPTH`] levels.
    pub fn episode(&mut self, nodes: &[Node], agents_of: Option<(f64, u64, u32)>) -> anyhow::Result<StripsEpisode> {
        let tree: Tree<'_, DEPTH> = Tree::validate(nodes, &self.p.catalog).map_err(|e| anyhow!("{e}"))?;
        let length = nodes.len();
        let Self { p, world, running, states, scratch, params, tick_limit } = self;
        world.reset();
        running.clear();
        states.clear();
        states.resize(nodes.len(), NodeState::IDLE);
        let mut exec = Executor::new(tree, states).map_err(|_| anyhow!("no room for the tree's state"))?;
        let mut rng = agents_of.map(|(_, seed, k)| agents(seed, k));
        let rate = agents_of.map_or(0.0, |a| a.0);
        let (mut end, mut ticks, mut acts, mut succeeded) = (StripsEnd::Timeout, 0, 0, false);
        while ticks < *tick_limit {
            ticks += 1;
            if let Some(rng) = rng.as_mut() {
                acts += u32::from(disturb(p, world, rate, rng, scratch));
            }
            let mut b = Behaviors { p, world, running };
            let root = exec.tick(&mut b, ticks.saturating_mul(crate::episode::TICK_MS)).map_err(|e| anyhow!("{e}"))?;
            match root {
                Status::Failure => {
                    end = StripsEnd::Failure;
                    break;
                }
                Status::Success if succeeded => {
                    end = StripsEnd::Success;
                    break;
                }
                Status::Success => succeeded = true,
                // (A learned tree has no node that skips; a skipped tick has no result.)
                Status::Running | Status::Skipped => succeeded = false,
            }
        }
        if end == StripsEnd::Timeout {
            exec.halt_all(&mut Behaviors { p, world, running });
        }
        let unmet = p.g.goal().iter().filter(|l| world.holds(l.atom) != l.positive).count();
        let mut cost = params.unmet_goal * unmet as f64;
        cost += params.length * length as f64;
        cost += params.tick * f64::from(ticks);
        if end == StripsEnd::Failure {
            cost += params.failure;
        }
        if end == StripsEnd::Timeout {
            cost += params.timeout;
        }
        Ok(StripsEpisode { end, ticks, unmet, disturbances: acts, fitness: -cost })
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
            Some(d) => (0..d.episodes).map(|k| runner.episode(tree, Some((d.rate, d.seed, k)))).collect(),
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
}
