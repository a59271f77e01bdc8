//! Tick results and per-node states.

/// What a node returns when it is ticked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum Status {
    /// The node reached its goal.
    Success = 1,
    /// The node cannot reach its goal.
    Failure = 2,
    /// The node needs more ticks.
    Running = 3,
    /// The node did nothing this tick and has no result: its parent goes on as if it
    /// were not there (BehaviorTree.CPP's SKIPPED). `RunOnce` with `then_skip` returns it
    /// after its one run, and so does a parent whose children all skipped. A behavior may
    /// return it too; its leaf is then Idle.
    Skipped = 4,
}

impl Status {
    /// The status in capitals, as the renderer and traces print it.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Success => "SUCCESS",
            Self::Failure => "FAILURE",
            Self::Running => "RUNNING",
            Self::Skipped => "SKIPPED",
        }
    }
}

impl core::fmt::Display for Status {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// The state of one node between ticks, as kept by the executor and seen by an
/// [`Observer`](crate::Observer).
///
/// `Idle` means the node has not been ticked since the executor was created, or it was
/// halted or reset since. Any other value is what the node returned the last time it was
/// ticked. A node that is `Idle` has only `Idle` nodes below it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
#[repr(u8)]
pub enum NodeStatus {
    /// Not ticked in the current activation of its parent, or halted.
    #[default]
    Idle = 0,
    /// Returned Success when last ticked.
    Success = 1,
    /// Returned Failure when last ticked.
    Failure = 2,
    /// Returned Running when last ticked and has not been halted since.
    Running = 3,
}

impl NodeStatus {
    /// The status in capitals (`IDLE` for [`NodeStatus::Idle`]).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Idle => "IDLE",
            Self::Success => "SUCCESS",
            Self::Failure => "FAILURE",
            Self::Running => "RUNNING",
        }
    }
}

impl From<Status> for NodeStatus {
    /// The status a leaf takes when it returns `s`: Skipped leaves it Idle.
    #[inline(always)]
    fn from(s: Status) -> Self {
        match s {
            Status::Success => Self::Success,
            Status::Failure => Self::Failure,
            Status::Running => Self::Running,
            Status::Skipped => Self::Idle,
        }
    }
}

impl core::fmt::Display for NodeStatus {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}
