//! Why planning stopped.

/// Why a problem could not be grounded, a tree not planned, or not expanded.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum PlanError {
    /// Grounding would make more atoms or actions than the planner handles.
    #[error("the problem is too large to ground: more than {limit} {what} (stopped at {count})")]
    TooLarge {
        /// Atoms or actions.
        what: &'static str,
        /// How many.
        count: u64,
        /// The limit.
        limit: u64,
    },
    /// Heuristic search stored more states than its memory bound allows.
    #[error(
        "the search for a plan stopped: its {states} states need more than {limit} bytes \
         (the bound of one search)"
    )]
    SearchMemory {
        /// States stored when it stopped.
        states: u64,
        /// The bound, in bytes.
        limit: u64,
    },
    /// The tree's value table (the values of leaves with more than
    /// `bt_core::MAX_ARGS` arguments) would hold more than an image does.
    #[error("the tree's leaves with more than 3 arguments need more than {limit} values in its value table")]
    TooManyValues {
        /// The most values an image holds.
        limit: usize,
    },
    /// An action whose parameters no precondition binds, with too many groundings.
    #[error("action `{action}` has {count} groundings: its parameters {params} are bound by no precondition")]
    Unbounded {
        /// The action.
        action: String,
        /// The unbound parameters.
        params: String,
        /// How many combinations of objects they take.
        count: u64,
    },
    /// An ADL formula whose compilation has too many alternatives.
    #[error(
        "the {what} of `{action}` expands to more than {limit} alternatives (disjunctions or quantifiers); simplify it"
    )]
    TooComplex {
        /// The ground action (or `the goal`).
        action: String,
        /// Which formula.
        what: &'static str,
        /// The limit.
        limit: usize,
    },
    /// An action cost read from a function that has no value in `:init`.
    #[error("no value for `{term}` in the problem's :init (an action cost needs it)")]
    MissingCost {
        /// The function term.
        term: String,
    },
    /// A goal with a literal and its negation.
    #[error("the goal is contradictory: it asks for `{atom}` and `not {atom}`")]
    ContradictoryGoal {
        /// The atom.
        atom: String,
    },
    /// A problem built in Rust that breaks a rule of the model (PDDL input is checked
    /// while it is read).
    #[error("{0}")]
    Model(#[from] crate::model::ModelError),
    /// The goal cannot be reached, for a reason found before searching.
    #[error("the goal cannot be reached: {0}")]
    Unsolvable(String),
    /// A time budget ran out.
    #[error("the time budget ran out while {stage}")]
    Timeout {
        /// What was running.
        stage: &'static str,
    },
    /// A condition the behavior set has no leaf for.
    #[error("the behavior set has no condition `{condition}`")]
    NoLeaf {
        /// The condition.
        condition: String,
    },
    /// The tree failed and the only failed conditions left have no achieving action.
    #[error("no action achieves `{condition}`")]
    NoAchiever {
        /// The condition (the first such, breadth-first).
        condition: String,
    },
    /// The tree failed, yet no failed condition is left to expand.
    #[error("the tree fails, but every failed condition was expanded before ({failed})")]
    NothingToExpand {
        /// The failed conditions, comma separated (or "none").
        failed: String,
    },
    /// IncreasePriority ran out of positions with the conflict still there.
    #[error("unresolvable conflict: {0}")]
    Unresolvable(String),
    /// The tree kept running without reaching the goal or failing.
    #[error("the tree neither reached the goal nor failed within {}", crate::wording::count(*.ticks, "tick"))]
    NoProgress {
        /// The tick budget.
        ticks: u32,
    },
    /// The tree oscillates: the world comes back to a state it was in, with the same
    /// actions running, and the goal is not reached.
    #[error("the tree oscillates, repeating {}", actions.join(", "))]
    Oscillates {
        /// The repeating actions, in order.
        actions: Vec<String>,
        /// The tree.
        nodes: Vec<bt_core::Node>,
        /// Its value table.
        values: Vec<u16>,
    },
    /// The tree, run in the symbolic world from the initial state (or from the state
    /// given to [`crate::expand_at`]), does not reach the goal.
    #[error("the tree does not reach the goal from {from}: {why}")]
    GoalNotReached {
        /// Where the run started: `the initial state` or `the state given`.
        from: &'static str,
        /// What happened instead.
        why: String,
        /// The tree.
        nodes: Vec<bt_core::Node>,
        /// Its value table.
        values: Vec<u16>,
    },
    /// Search found no plan: the problem has no solution.
    #[error("no plan exists: {0}")]
    NoPlan(String),
    /// More expansions than the budget.
    #[error("gave up after {}", crate::wording::count(*.0, "expansion"))]
    TooManyExpansions(usize),
    /// The tree outgrew what a bt-core tree can hold.
    #[error("the tree grew beyond {limit} nodes or {depth} levels")]
    TreeTooLarge {
        /// Node limit.
        limit: usize,
        /// Depth limit.
        depth: usize,
    },
    /// A search evaluated as many states as it was allowed
    /// ([`crate::search::SearchOptions::max_evaluated`]).
    #[error("the search gave up after evaluating {evaluated} states, its budget")]
    OutOfStates {
        /// States evaluated.
        evaluated: u64,
    },
    /// Algorithm 1's tree outgrew the budget it has before the search-guided methods
    /// take over ([`crate::Options::algorithm1_nodes`]).
    #[error("its tree grew to {nodes} nodes without reaching the goal (its budget is {budget})")]
    OverBudget {
        /// The tree's size.
        nodes: usize,
        /// The budget.
        budget: usize,
    },
    /// Guided backchaining, with a deadline, got too little of the way along its plan
    /// to be done in the time it has, leaving that time to the plan's regression tree.
    #[error(
        "at its pace it would not be done in its {allowed:.1?}: {done} of the plan's {steps} actions executed after {spent:.1?}"
    )]
    Behind {
        /// The most actions of the plan a run of the tree executed.
        done: usize,
        /// The plan's length.
        steps: usize,
        /// The time spent.
        spent: std::time::Duration,
        /// The time it had.
        allowed: std::time::Duration,
    },
    /// The tree does not fit the size asked for ([`crate::Fit`]), even without any
    /// rule of its closure over disturbances.
    #[error("{what}")]
    TooBig {
        /// What does not fit, in a sentence.
        what: String,
    },
    /// The tree has more nodes than a bt-core tree holds.
    #[error("the tree has {nodes} nodes; a bt-core tree holds at most {limit}")]
    TooManyNodes {
        /// Its size.
        nodes: usize,
        /// The limit.
        limit: usize,
    },
    /// The tree is deeper than the executor's stack.
    #[error("the tree is {levels} levels deep; the planner's executor takes at most {limit}")]
    TooDeep {
        /// Its depth (the first level found past the limit).
        levels: usize,
        /// The limit.
        limit: usize,
    },
    /// The tree does not validate against the catalog given.
    #[error("the tree does not fit the behavior set: {0}")]
    InvalidTree(String),
    /// The behavior set broke a rule while the tree was ticked.
    #[error("tick failed: {0}")]
    Tick(#[from] bt_core::TickError),
}

impl PlanError {
    /// The tree the error is about, with its value table, when it carries one: the tree
    /// that oscillates ([`PlanError::Oscillates`]) or does not reach the goal
    /// ([`PlanError::GoalNotReached`]), for the caller to show.
    #[must_use]
    pub fn tree(&self) -> Option<(&[bt_core::Node], &[u16])> {
        match self {
            Self::Oscillates { nodes, values, .. } | Self::GoalNotReached { nodes, values, .. } => {
                Some((nodes, values))
            }
            _ => None,
        }
    }
}
