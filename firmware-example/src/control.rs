//! The control loop: load and validate the image, then tick the tree against the plant
//! at a fixed rate, applying the scripted events, until the root succeeds, fails, or
//! the time runs out. Everything it says goes to a [`Sink`] as trace lines; the
//! controller and the host print the same lines, byte for byte.
//!
//! # Trace
//!
//! One line per tick, `key=value` fields after the tick number and root status:
//!
//! ```text
//! tick 52 RUNNING ran=2F,4S,6F,8S,9R act=move-to(sphere)! halt=32 robot=1660,1422 hand=cube dig=8f9599a7
//! ```
//!
//! - `ran`: every leaf ticked, in order, as node id and result (`S`uccess, `F`ailure,
//!   `R`unning); the `leaf` lines printed after loading name each id.
//! - `act`: the action left Running, `-` when none.
//! - `halt`: the actions halted during the tick (preempted before another started).
//! - `robot`: base x and y in mm; `hand`: what the gripper holds.
//! - `dig`: FNV-1a over the exact bits of the whole plant state after the tick.
//!
//! Before the ticks: `boot` (image size, node count, depth, behavior-set fingerprint),
//! one `leaf` line per leaf, and `world` (initial positions in mm). Scripted events print
//! an `event` line before the tick they happen at, with the position of the object they
//! moved. The last line starts with `done`: the verdict (`GOAL`, `FAILED`, `TIMEOUT`,
//! `ERROR`, `LOAD-ERROR`), ticks and simulated time, leaves ticked, actions halted and
//! completed, events applied, the cube's final position and the final digest.

use core::fmt::{self, Write};

use bt_core::{BehaviorSet, Context, Executor, Leaf, LoadError, Node, NodeId, NodeKind, NodeState, Status, TickError};

use crate::catalog::{BEHAVIORS, FINGERPRINT, object_name};
use crate::plant::{PERIOD_MS, Plant, Vec2};
use crate::script::{self, Event, SCRIPT, Skipped};

/// Most nodes an image may have: the node and state arrays are sized for it.
pub const MAX_NODES: usize = 64;
/// Deepest tree the executor accepts (root at level 1).
pub const DEPTH: usize = 16;
/// The run gives up after this many ticks (60 s at 10 Hz).
pub const MAX_TICKS: u32 = 600;
/// Longest trace line, in bytes; longer lines are cut and end in `~`.
pub const LINE_CAP: usize = 256;

/// Where trace lines go: semihosting on the controller, stdout or a buffer on the host.
pub trait Sink {
    /// One line of ASCII text, without its line break.
    fn line(&mut self, line: &[u8]);
}

/// A leaf that was ticked, and what it returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ran {
    /// The leaf's node id.
    pub node: NodeId,
    /// What it returned.
    pub status: Status,
}

/// What happened in one tick, for observers of the run (the tests).
#[derive(Debug)]
pub struct TickReport<'a> {
    /// Tick number, from 0.
    pub tick: u32,
    /// What the root returned.
    pub status: Status,
    /// The tree's nodes (the `node` of [`Ran`] and `halted` index them).
    pub nodes: &'a [Node],
    /// Leaves ticked, in order.
    pub ran: &'a [Ran],
    /// Actions halted, in order.
    pub halted: &'a [NodeId],
    /// The scripted event applied before this tick, and whether it could happen.
    pub event: Option<(Event, Result<(), Skipped>)>,
    /// The plant after the tick.
    pub plant: &'a Plant,
}

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// The root returned Success: the cube is on the goal.
    Goal {
        /// Ticks run.
        ticks: u32,
    },
    /// The root returned Failure.
    RootFailure {
        /// Ticks run.
        ticks: u32,
    },
    /// [`MAX_TICKS`] ran out with the root still Running.
    Timeout,
    /// The image was refused; nothing was ticked.
    Load(LoadError),
    /// A behavior broke the executor's rules.
    Tick {
        /// The tick it happened in.
        tick: u32,
        /// What went wrong.
        error: TickError,
    },
}

impl Outcome {
    /// True when the run reached its goal.
    #[must_use]
    pub const fn reached_goal(&self) -> bool {
        matches!(self, Self::Goal { .. })
    }
}

/// The leaf behind a ticked node, recording calls for the trace.
struct Recorder<'p> {
    plant: &'p mut Plant,
    ran: heapless::Vec<Ran, MAX_NODES>,
    halted: heapless::Vec<NodeId, MAX_NODES>,
}

impl BehaviorSet for Recorder<'_> {
    fn condition(&mut self, leaf: &Leaf, ctx: Context) -> Status {
        let status = self.plant.condition(leaf, ctx);
        // A tick visits each node at most once, so `ran` cannot overflow.
        let _ = self.ran.push(Ran { node: ctx.node, status });
        status
    }

    fn action(&mut self, leaf: &Leaf, ctx: Context) -> Status {
        let status = self.plant.action(leaf, ctx);
        let _ = self.ran.push(Ran { node: ctx.node, status });
        status
    }

    fn halt(&mut self, leaf: &Leaf, node: NodeId) {
        self.plant.halt(leaf, node);
        let _ = self.halted.push(node);
    }
}

/// A trace line being written into a fixed buffer: ASCII text, cut (ending in `~`) if
/// longer than [`LINE_CAP`]. Writing never fails.
#[derive(Debug, Default)]
pub struct Line {
    buf: heapless::Vec<u8, LINE_CAP>,
    cut: bool,
}

impl Line {
    /// An empty line.
    #[must_use]
    pub const fn new() -> Self {
        Self { buf: heapless::Vec::new(), cut: false }
    }

    /// Formats `args` into the buffer, replacing what was there, and returns the bytes.
    pub fn format(&mut self, args: fmt::Arguments<'_>) -> &[u8] {
        self.buf.clear();
        self.cut = false;
        let _ = self.write_fmt(args);
        if self.cut {
            self.buf.pop();
            let _ = self.buf.push(b'~');
        }
        &self.buf
    }

    /// Formats `args` and hands the line to `sink`.
    pub fn say<S: Sink + ?Sized>(&mut self, sink: &mut S, args: fmt::Arguments<'_>) {
        let line = self.format(args);
        sink.line(line);
    }
}

impl Write for Line {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let room = LINE_CAP.saturating_sub(self.buf.len());
        let bytes = s.as_bytes();
        let take = bytes.get(..room).unwrap_or(bytes);
        self.cut |= take.len() < bytes.len();
        // Cannot fail: `take` fits.
        let _ = self.buf.extend_from_slice(take);
        Ok(())
    }
}

/// Millimetres, rounded: how the trace prints lengths (no float formatting).
#[must_use]
pub fn mm(v: f32) -> i32 {
    libm::roundf(v * 1000.0) as i32
}

/// A point as `x,y` in mm.
struct Mm(Vec2);

impl fmt::Display for Mm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{}", mm(self.0.x), mm(self.0.y))
    }
}

/// A leaf as `name(arg, ...)` with object names, `?` after conditions, `!` after
/// actions; `-` for none.
struct LeafText<'a>(Option<&'a Node>);

impl fmt::Display for LeafText<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (leaf, mark) = match self.0.map(Node::kind) {
            Some(NodeKind::Condition(l)) => (l, "?"),
            Some(NodeKind::Action(l)) => (l, "!"),
            _ => return f.write_str("-"),
        };
        let name = BEHAVIORS.get(usize::from(leaf.behavior())).map_or("#", |b| b.name);
        f.write_str(name)?;
        let args = leaf.args();
        if !args.is_empty() {
            f.write_str("(")?;
            for (i, &a) in args.iter().enumerate() {
                if i > 0 {
                    f.write_str(",")?;
                }
                f.write_str(object_name(a))?;
            }
            f.write_str(")")?;
        }
        f.write_str(mark)
    }
}

/// The `ran=` list.
struct RanList<'a>(&'a [Ran]);

impl fmt::Display for RanList<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_empty() {
            return f.write_str("-");
        }
        for (i, r) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str(",")?;
            }
            let s = match r.status {
                Status::Success => "S",
                Status::Failure => "F",
                Status::Running => "R",
            };
            write!(f, "{}{s}", r.node)?;
        }
        Ok(())
    }
}

/// The `halt=` list.
struct Ids<'a>(&'a [NodeId]);

impl fmt::Display for Ids<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_empty() {
            return f.write_str("-");
        }
        for (i, id) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str(",")?;
            }
            write!(f, "{id}")?;
        }
        Ok(())
    }
}

/// Simulated time of tick `ticks` as seconds with millisecond precision.
struct Seconds(u32);

impl fmt::Display for Seconds {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let ms = self.0.saturating_mul(PERIOD_MS);
        write!(f, "{}.{:03}s", ms / 1000, ms % 1000)
    }
}

/// Runs the whole scenario on `image`: load, validate, tick until done. Prints the
/// trace to `sink` and shows every tick to `watch`.
pub fn run<S: Sink, W: FnMut(&TickReport<'_>)>(image: &[u8], sink: &mut S, mut watch: W) -> Outcome {
    let mut line = Line::new();
    let mut storage = [Node::EMPTY; MAX_NODES];
    let tree = match bt_core::load::<_, DEPTH>(image, &BEHAVIORS, &mut storage) {
        Ok(tree) => tree,
        Err(e) => {
            line.say(sink, format_args!("load error: {e}"));
            line.say(sink, format_args!("done LOAD-ERROR ticks=0 image={}B", image.len()));
            return Outcome::Load(e);
        }
    };
    let nodes = tree.nodes();
    line.say(
        sink,
        format_args!(
            "boot image={}B nodes={} depth={} fp={:016x} hz={}",
            image.len(),
            tree.len(),
            tree.depth(),
            FINGERPRINT,
            1000 / PERIOD_MS
        ),
    );
    for (id, node) in nodes.iter().enumerate() {
        if matches!(node.kind(), NodeKind::Condition(_) | NodeKind::Action(_)) {
            line.say(sink, format_args!("leaf {id} {}", LeafText(Some(node))));
        }
    }
    let mut plant = Plant::new();
    line.say(
        sink,
        format_args!(
            "world robot={} cube={} sphere={} goal={} dig={:08x}",
            Mm(plant.robot),
            Mm(plant.cube),
            Mm(plant.sphere),
            Mm(plant.goal),
            plant.digest()
        ),
    );

    let mut state = [NodeState::IDLE; MAX_NODES];
    let mut exec = match Executor::new(tree, &mut state) {
        Ok(exec) => exec,
        // Cannot happen: load() refuses trees larger than the node storage, which has
        // the same capacity as the state. Reported, not assumed.
        Err(_) => {
            let e = LoadError::TooManyNodes { count: tree.len(), capacity: MAX_NODES };
            line.say(sink, format_args!("load error: {e}"));
            return Outcome::Load(e);
        }
    };

    let mut totals = Totals { leaves: 0, events: 0 };
    for tick in 0..MAX_TICKS {
        let event = script::event_at(tick).map(|e| (e, script::apply(e, &mut plant)));
        match event {
            Some((e, Ok(()))) => {
                totals.events = totals.events.saturating_add(1);
                let (what, at) = match e {
                    Event::Help | Event::Slip => ("cube", plant.cube),
                    Event::Block | Event::Unblock => ("sphere", plant.sphere),
                };
                line.say(sink, format_args!("event {tick} {} {what}={}: {}", e.name(), Mm(at), e.describe()));
            }
            Some((e, Err(why))) => line.say(sink, format_args!("event {tick} {} skipped: {}", e.name(), why.reason())),
            None => {}
        }

        let mut rec = Recorder { plant: &mut plant, ran: heapless::Vec::new(), halted: heapless::Vec::new() };
        let result = exec.tick(&mut rec, tick.saturating_mul(PERIOD_MS));
        let Recorder { ran, halted, .. } = rec;
        totals.leaves = totals.leaves.saturating_add(ran.len() as u32);
        let ticks = tick.saturating_add(1);
        let status = match result {
            Ok(status) => status,
            Err(error) => {
                line.say(sink, format_args!("tick {tick} ERROR {error}"));
                line.say(sink, format_args!("done ERROR {}", Done { ticks, totals, plant: &plant }));
                return Outcome::Tick { tick, error };
            }
        };
        let act = ran.iter().rev().find(|r| r.status == Status::Running).and_then(|r| nodes.get(usize::from(r.node)));
        line.say(
            sink,
            format_args!(
                "tick {tick} {status} ran={} act={} halt={} robot={} hand={} dig={:08x}",
                RanList(&ran),
                LeafText(act),
                Ids(&halted),
                Mm(plant.robot),
                plant.hand.name(),
                plant.digest()
            ),
        );
        watch(&TickReport { tick, status, nodes, ran: &ran, halted: &halted, event, plant: &plant });

        let (verdict, outcome) = match status {
            Status::Running => continue,
            Status::Success => ("GOAL", Outcome::Goal { ticks }),
            Status::Failure => ("FAILED", Outcome::RootFailure { ticks }),
        };
        line.say(sink, format_args!("done {verdict} {}", Done { ticks, totals, plant: &plant }));
        return outcome;
    }
    line.say(sink, format_args!("done TIMEOUT {}", Done { ticks: MAX_TICKS, totals, plant: &plant }));
    Outcome::Timeout
}

/// Counts kept by the loop for the summary.
#[derive(Clone, Copy)]
struct Totals {
    /// Leaves ticked.
    leaves: u32,
    /// Scripted events applied.
    events: u32,
}

/// The fields of the `done` line.
struct Done<'a> {
    ticks: u32,
    totals: Totals,
    plant: &'a Plant,
}

impl fmt::Display for Done<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let c = self.plant.counters;
        write!(
            f,
            "ticks={} time={} leaves={} halts={} picks={} drops={} clears={} events={}/{} cube={} dig={:08x}",
            self.ticks,
            Seconds(self.ticks),
            self.totals.leaves,
            c.halts,
            c.picks,
            c.drops,
            c.clears,
            self.totals.events,
            SCRIPT.len(),
            Mm(self.plant.cube),
            self.plant.digest()
        )
    }
}
