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

/// Any `FnMut(&[u8])` is a sink: handy for collecting lines in tests.
impl<F: FnMut(&[u8])> Sink for F {
    fn line(&mut self, line: &[u8]) {
        self(line);
    }
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
    fn condition(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        let status = self.plant.condition(leaf, ctx);
        // A tick visits each node at most once, so `ran` cannot overflow.
        let _ = self.ran.push(Ran { node: ctx.node, status });
        status
    }

    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
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
///
/// Text and numbers are appended by hand rather than through `core::fmt`: the
/// formatting machinery and its padding code would take a quarter of the controller's
/// 16 KiB of flash.
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

    /// Appends text; what does not fit is dropped and the line marked as cut.
    pub fn text(&mut self, s: &str) -> &mut Self {
        self.push(s.as_bytes())
    }

    /// Appends an unsigned number in decimal.
    pub fn num(&mut self, v: u32) -> &mut Self {
        self.digits(u64::from(v), false, 1)
    }

    /// Appends a count or size in decimal (saturating at `u32::MAX`).
    pub fn size(&mut self, v: usize) -> &mut Self {
        self.num(u32::try_from(v).unwrap_or(u32::MAX))
    }

    /// Appends a signed number in decimal.
    pub fn int(&mut self, v: i32) -> &mut Self {
        if v < 0 {
            self.push(b"-");
        }
        self.num(v.unsigned_abs())
    }

    /// Appends `v` in lowercase hexadecimal, zero-padded to `width` digits.
    pub fn hex(&mut self, v: u64, width: usize) -> &mut Self {
        self.digits(v, true, width)
    }

    /// Appends `v` in hexadecimal, or in decimal (then `v` is at most `u32::MAX`), with
    /// at least `width` digits. Hex digits come from shifts and decimal ones from 32-bit
    /// division, which the Cortex-M4 does in hardware: a 64-bit division would link
    /// compiler-builtins' `u64_div_rem`, about 400 bytes.
    fn digits(&mut self, mut v: u64, hex: bool, width: usize) -> &mut Self {
        let mut out = [b'0'; 20];
        let mut at = out.len();
        while at > 0 && (v > 0 || out.len() - at < width.max(1)) {
            at -= 1;
            let (digit, rest) =
                if hex { (v & 0xf, v >> 4) } else { (u64::from(v as u32 % 10), u64::from(v as u32 / 10)) };
            if let Some(d) = out.get_mut(at) {
                *d = b"0123456789abcdef".get(digit as usize).copied().unwrap_or(b'?');
            }
            v = rest;
        }
        let tail = out.get(at..).unwrap_or_default();
        self.push(tail)
    }

    fn push(&mut self, bytes: &[u8]) -> &mut Self {
        let room = LINE_CAP.saturating_sub(self.buf.len());
        let take = bytes.get(..room).unwrap_or(bytes);
        self.cut |= take.len() < bytes.len();
        // Cannot fail: `take` fits.
        let _ = self.buf.extend_from_slice(take);
        self
    }

    /// The finished line: the text, its last byte replaced by `~` if it was cut.
    pub fn finish(&mut self) -> &[u8] {
        if self.cut {
            self.buf.pop();
            let _ = self.buf.push(b'~');
            self.cut = false;
        }
        &self.buf
    }

    /// Hands the finished line to `sink` and starts a new one.
    pub fn send<S: Sink + ?Sized>(&mut self, sink: &mut S) {
        sink.line(self.finish());
        self.buf.clear();
    }

    /// A point as `x,y` in mm.
    pub(crate) fn point(&mut self, p: Vec2) -> &mut Self {
        self.int(mm(p.x)).text(",").int(mm(p.y))
    }

    /// A leaf as `name(arg, ...)` with object names, `?` after conditions, `!` after
    /// actions; `-` for none.
    pub(crate) fn leaf(&mut self, node: Option<&Node>) -> &mut Self {
        let (leaf, mark) = match node.map(Node::kind) {
            Some(NodeKind::Condition(l)) => (l, "?"),
            Some(NodeKind::Action(l)) => (l, "!"),
            _ => return self.text("-"),
        };
        self.text(BEHAVIORS.get(usize::from(leaf.behavior())).map_or("#", |b| b.name));
        let args = leaf.args();
        for (i, &a) in args.iter().enumerate() {
            self.text(if i == 0 { "(" } else { "," }).text(object_name(a));
        }
        if !args.is_empty() {
            self.text(")");
        }
        self.text(mark)
    }

    /// The `ran=` list: node id and result letter per leaf ticked; `-` for none.
    pub(crate) fn ran(&mut self, ran: &[Ran]) -> &mut Self {
        if ran.is_empty() {
            return self.text("-");
        }
        for (i, r) in ran.iter().enumerate() {
            if i > 0 {
                self.text(",");
            }
            let s = match r.status {
                Status::Success => "S",
                Status::Failure => "F",
                Status::Running => "R",
                Status::Skipped => "K",
            };
            self.num(u32::from(r.node)).text(s);
        }
        self
    }

    /// The `halt=` list; `-` for none.
    pub(crate) fn ids(&mut self, ids: &[NodeId]) -> &mut Self {
        if ids.is_empty() {
            return self.text("-");
        }
        for (i, &id) in ids.iter().enumerate() {
            if i > 0 {
                self.text(",");
            }
            self.num(u32::from(id));
        }
        self
    }

    /// Simulated time of tick `ticks` as seconds with millisecond precision.
    fn seconds(&mut self, ticks: u32) -> &mut Self {
        let ms = ticks.saturating_mul(PERIOD_MS);
        self.num(ms / 1000).text(".").digits(u64::from(ms % 1000), false, 3).text("s")
    }

    /// What went wrong loading an image: its code, the node, and for the faults a
    /// controller meets in the field (a corrupted or foreign image) the numbers.
    ///
    /// Reads only those parts of `e`, here where `e` was made: the compiler can then
    /// leave out what the line never prints (the names of node kinds, say).
    #[inline(always)]
    pub(crate) fn load_error(&mut self, e: &LoadError) -> &mut Self {
        let numbers = match *e {
            LoadError::CrcMismatch { stored, computed } => {
                Some((" stored=", u64::from(stored), " computed=", u64::from(computed), 8))
            }
            LoadError::ForeignBehaviorSet { image, expected } => Some((" image=", image, " expected=", expected, 16)),
            _ => None,
        };
        self.load_fault(e.code(), e.node(), numbers)
    }

    /// The line of [`Line::load_error`].
    fn load_fault(
        &mut self,
        code: &str,
        node: Option<NodeId>,
        numbers: Option<(&str, u64, &str, u64, usize)>,
    ) -> &mut Self {
        self.text(code);
        if let Some(node) = node {
            self.text(" node=").num(u32::from(node));
        }
        if let Some((a, x, b, y, width)) = numbers {
            self.text(a).hex(x, width).text(b).hex(y, width);
        }
        self
    }

    /// The fields of the `done` line.
    fn done(&mut self, ticks: u32, totals: Totals, plant: &Plant) -> &mut Self {
        let c = plant.counters;
        self.text("ticks=").num(ticks).text(" time=").seconds(ticks);
        self.text(" leaves=")
            .num(totals.leaves)
            .text(" halts=")
            .num(c.halts.into())
            .text(" picks=")
            .num(c.picks.into());
        self.text(" drops=").num(c.drops.into()).text(" clears=").num(c.clears.into());
        self.text(" events=").num(totals.events).text("/").size(SCRIPT.len());
        self.text(" cube=").point(plant.cube).text(" dig=").hex(u64::from(plant.digest()), 8)
    }
}

/// Millimetres, rounded: how the trace prints lengths (no float formatting).
#[must_use]
pub fn mm(v: f32) -> i32 {
    libm::roundf(v * 1000.0) as i32
}

/// Runs the whole scenario on `image`: load, validate, tick until done. Prints the
/// trace to `sink` and shows every tick to `watch`.
///
/// Inlined into its one caller on a controller, so that the compiler sees which parts of
/// a load error are never read (see [`Line::load_error`]).
#[inline(always)]
pub fn run<S: Sink, W: FnMut(&TickReport<'_>)>(image: &[u8], sink: &mut S, mut watch: W) -> Outcome {
    let mut line = Line::new();
    let mut storage = [Node::EMPTY; MAX_NODES];
    let tree = match bt_core::load::<_, DEPTH>(image, &BEHAVIORS, &mut storage) {
        Ok(tree) => tree,
        Err(e) => {
            line.text("load error: ").load_error(&e).send(sink);
            line.text("done LOAD-ERROR ticks=0 image=").size(image.len()).text("B").send(sink);
            return Outcome::Load(e);
        }
    };
    let nodes = tree.nodes();
    line.text("boot image=").size(image.len()).text("B nodes=").size(tree.len()).text(" depth=").size(tree.depth());
    line.text(" fp=").hex(FINGERPRINT, 16).text(" hz=").num(1000 / PERIOD_MS).send(sink);
    for (id, node) in nodes.iter().enumerate() {
        if matches!(node.kind(), NodeKind::Condition(_) | NodeKind::Action(_)) {
            line.text("leaf ").size(id).text(" ").leaf(Some(node)).send(sink);
        }
    }
    let mut plant = Plant::new();
    line.text("world robot=").point(plant.robot).text(" cube=").point(plant.cube);
    line.text(" sphere=").point(plant.sphere).text(" goal=").point(plant.goal);
    line.text(" dig=").hex(u64::from(plant.digest()), 8).send(sink);

    let mut state = [NodeState::IDLE; MAX_NODES];
    let mut exec = match Executor::new(tree, &mut state) {
        Ok(exec) => exec,
        // Cannot happen: load() refuses trees larger than the node storage, which has
        // the same capacity as the state. Reported, not assumed.
        Err(_) => {
            let e = LoadError::TooManyNodes { count: tree.len(), capacity: MAX_NODES };
            line.text("load error: ").load_error(&e).send(sink);
            return Outcome::Load(e);
        }
    };

    let mut totals = Totals { leaves: 0, events: 0 };
    for tick in 0..MAX_TICKS {
        let event = script::event_at(tick).map(|e| (e, script::apply(e, &mut plant)));
        if let Some((e, happened)) = event {
            line.text("event ").num(tick).text(" ").text(e.name());
            match happened {
                Ok(()) => {
                    totals.events = totals.events.saturating_add(1);
                    let (what, at) = match e {
                        Event::Help | Event::Slip => ("cube", plant.cube),
                        Event::Block | Event::Unblock => ("sphere", plant.sphere),
                    };
                    line.text(" ").text(what).text("=").point(at).text(": ").text(e.describe());
                }
                Err(why) => {
                    line.text(" skipped: ").text(why.reason());
                }
            }
            line.send(sink);
        }

        let mut rec = Recorder { plant: &mut plant, ran: heapless::Vec::new(), halted: heapless::Vec::new() };
        let result = exec.tick(&mut rec, tick.saturating_mul(PERIOD_MS));
        let Recorder { ran, halted, .. } = rec;
        totals.leaves = totals.leaves.saturating_add(ran.len() as u32);
        let ticks = tick.saturating_add(1);
        let status = match result {
            Ok(status) => status,
            Err(error) => {
                line.text("tick ").num(tick).text(" ERROR ").text(error.code()).send(sink);
                line.text("done ERROR ").done(ticks, totals, &plant).send(sink);
                return Outcome::Tick { tick, error };
            }
        };
        let act = ran.iter().rev().find(|r| r.status == Status::Running).and_then(|r| nodes.get(usize::from(r.node)));
        line.text("tick ").num(tick).text(" ").text(status.name()).text(" ran=").ran(&ran);
        line.text(" act=").leaf(act).text(" halt=").ids(&halted).text(" robot=").point(plant.robot);
        line.text(" hand=").text(plant.hand.name()).text(" dig=").hex(u64::from(plant.digest()), 8).send(sink);
        watch(&TickReport { tick, status, nodes, ran: &ran, halted: &halted, event, plant: &plant });

        let (verdict, outcome) = match status {
            // This tree has no node that skips.
            Status::Running | Status::Skipped => continue,
            Status::Success => ("GOAL", Outcome::Goal { ticks }),
            Status::Failure => ("FAILED", Outcome::RootFailure { ticks }),
        };
        line.text("done ").text(verdict).text(" ").done(ticks, totals, &plant).send(sink);
        return outcome;
    }
    line.text("done TIMEOUT ").done(MAX_TICKS, totals, &plant).send(sink);
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
