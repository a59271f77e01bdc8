//! The planner's settings: which method makes the tree, the budgets of each, and the
//! size a tree must fit.

use std::time::Instant;

use crate::refine::Refinement;

/// Which method makes the tree offline.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Method {
    /// Algorithm 1 first; when it cannot finish (it oscillates, meets a dead end or
    /// an unresolvable conflict, or runs out of its share of the time), a plan from
    /// heuristic search guides backchaining; when that tree does not reach the goal,
    /// the plan guides it again without pinning the problem's state variables
    /// ([`crate::variables`]); when even that fails, the plan's regression tree
    /// ([`crate::regress`]).
    #[default]
    Auto,
    /// Algorithm 1 of Colledanchise et al. 2019 alone.
    Algorithm1,
    /// Search first, then guided backchaining (and the regression tree as a last
    /// resort).
    Search,
}

/// Planner settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Options {
    /// How free template parameters are bound.
    pub refinement: Refinement,
    /// Offline: most ticks of the symbolic world in one run of the tree before giving
    /// up.
    pub max_ticks: u32,
    /// Most expansions.
    pub max_expansions: usize,
    /// Offline: keep a copy of the tree after every expansion ([`crate::Plan::steps`]).
    pub record_steps: bool,
    /// Offline: how the tree is made.
    pub method: Method,
    /// Offline: give up at this instant (grounding is the caller's; see
    /// [`crate::ground::Limits`]).
    pub deadline: Option<Instant>,
    /// Keep the goal Sequence at the root even for a single goal condition, as seed
    /// 003's reference planner does (its balance tree is `s( f( ... ) )`, one node
    /// more). Off by default: a Sequence of one child ticks exactly as the child does,
    /// so the shorter tree behaves the same and costs a node less.
    pub goal_sequence: bool,
    /// Offline: most planner nodes a tree made from a search plan (guided or
    /// regression) may grow to while it is closed over disturbances
    /// ([`crate::regress::close`]); 0 leaves the tree as the method makes it (smaller,
    /// and it fails where an external agent moves the world off the plan).
    pub close_nodes: usize,
    /// Offline: close the trees of Algorithm 1 over disturbances too, as guided and
    /// regression trees always are: by rules in front of them for the disturbed states
    /// they fail from, and undo rules behind them (within [`Options::close_nodes`]).
    /// Off by default: Algorithm 1's trees stay as the paper's method makes them (the
    /// paper's figures and the brick tasks' trees among them), and they fail where an
    /// external agent does one of their actions out of turn and leaves no branch that
    /// applies.
    pub close_backchained: bool,
    /// Offline, with [`Method::Auto`]: Algorithm 1 gives up once its tree has more
    /// bt-core nodes than this and does not reach the goal yet, and the search-guided
    /// methods take over (guided backchaining has a budget of its own, this or four
    /// times the plan's regression tree). The largest tree Algorithm 1 finished in the
    /// IPC benchmark of `docs/planning-results.md` had 1,267 nodes, the shipped ones (the
    /// paper's figures, the brick tasks, 40 blocks) have at most 664; where it went on
    /// past a few thousand it did not finish (blocks, pegsol: to the 65,535 nodes a
    /// bt-core tree holds, for seconds).
    pub algorithm1_nodes: usize,
    /// Offline, with [`Method::Auto`]: search for a plan on a second thread while
    /// Algorithm 1 runs, when the machine has two cores or more. The tree is the same
    /// either way (Algorithm 1's when it finishes within its budget, else the one the
    /// search's plan guides); only the time to it changes.
    pub parallel: bool,
    /// Offline: the size the tree must fit ([`Fit`]).
    pub fit: Fit,
    /// Offline: search for the plan that guides the tree with deferred evaluation
    /// ([`crate::search::SearchOptions::lazy`]) as well as eager: eager search with h_FF
    /// gets 20,000 evaluated states, and where it finds no plan within them the
    /// deferred search's plan is taken (both run at once on a machine with two cores,
    /// and the plan never depends on which ends first). On by default, with
    /// [`Options::landmarks`]: in the IPC benchmark of `docs/planning-results.md` eager search
    /// alone missed visitall, childsnack and tetris problems, deferred search alone
    /// parcprinter and maintenance ones.
    pub deferred: bool,
    /// Offline, with [`Options::deferred`]: the search alternates h_FF with the
    /// landmark count ([`crate::search::landmarks`]), as LAMA does (on by default).
    pub landmarks: bool,
}

/// The size a tree must fit: the bytes of its image as a controller holds it (nodes
/// and value table, without the names section that only host tools read) and its
/// bt-core nodes. The closure over disturbances is cut to fit: its rules come in the
/// order it adds them, the states one disturbance away from the tree's path first, so
/// the rules cut are those for the states fewest disturbed episodes reach.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fit {
    /// Most image bytes.
    pub bytes: usize,
    /// Most bt-core nodes.
    pub nodes: usize,
    /// A tree that does not fit even without its closure is an error
    /// ([`crate::PlanError::TooBig`]); otherwise it is kept, and [`crate::Plan::fit`] says it
    /// does not fit.
    pub strict: bool,
}

impl Fit {
    /// 16 KiB, as many nodes as that holds, not strict: the default.
    pub const DEFAULT: Self = Self { bytes: 16 * 1024, nodes: u16::MAX as usize, strict: false };
    /// No bound.
    pub const NONE: Self = Self { bytes: usize::MAX, nodes: usize::MAX, strict: false };

    /// Whether a tree of `size` is within it.
    #[must_use]
    pub const fn admits(self, size: crate::Size) -> bool {
        size.bytes <= self.bytes && size.nodes <= self.nodes
    }
}

impl Default for Fit {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl Default for Options {
    fn default() -> Self {
        Self {
            refinement: Refinement::Cheapest,
            max_ticks: 100_000,
            max_expansions: 10_000,
            record_steps: false,
            method: Method::Auto,
            deadline: None,
            goal_sequence: false,
            close_nodes: crate::regress::Budget::default().nodes,
            close_backchained: false,
            algorithm1_nodes: 4_096,
            parallel: true,
            fit: Fit::DEFAULT,
            deferred: true,
            landmarks: true,
        }
    }
}
