//! Why planning stopped.

/// Why a problem could not be grounded, a tree not planned, or not expanded.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum PlanError {
    /// Grounding would make more atoms or actions than the planner handles.
    #[error("the problem is too large to ground: {count} {what} (at most {limit})")]
    TooLarge {
        /// Atoms or actions.
        what: &'static str,
        /// How many.
        count: u64,
        /// The limit.
        limit: u64,
    },
    /// A predicate or action with more parameters than a bt-core leaf carries.
    #[error("`{name}` has {arity} parameters; a bt-core leaf carries at most {max} arguments")]
    TooManyArgs {
        /// The predicate or action.
        name: String,
        /// Its parameter count.
        arity: usize,
        /// `bt_core::MAX_ARGS`.
        max: usize,
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
    #[error("the tree neither reached the goal nor failed within {ticks} ticks (it may oscillate)")]
    NoProgress {
        /// The tick budget.
        ticks: u32,
    },
    /// More expansions than the budget.
    #[error("gave up after {0} expansions")]
    TooManyExpansions(usize),
    /// The tree outgrew what a bt-core tree can hold.
    #[error("the tree grew beyond {limit} nodes or {depth} levels")]
    TreeTooLarge {
        /// Node limit.
        limit: usize,
        /// Depth limit.
        depth: usize,
    },
    /// The tree does not validate against the catalog given.
    #[error("the tree does not fit the behavior set: {0}")]
    InvalidTree(String),
    /// The behavior set broke a rule while the tree was ticked.
    #[error("tick failed: {0}")]
    Tick(#[from] bt_core::TickError),
}
