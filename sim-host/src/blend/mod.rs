//! Blended planning and acting across the link (Colledanchise, Almeida, Ögren, ICRA 2019,
//! Algorithm 1 at run time, on a real controller architecture): the controller ticks the
//! tree and acts; the host watches its status stream and, whenever the root fails,
//! expands the failed condition with the planner and sends the grown tree, which the
//! controller swaps in between two ticks. A microcontroller cannot plan; the host plans
//! for it while it keeps acting.
//!
//! # The tick the tree swaps at
//!
//! The host names the tick each tree swaps in at, so that what the controller does does
//! not depend on how long planning and sending take. It grants ticks as it reads them:
//! after reading tick `t` it lets the controller run up to tick `t + lead` (bt-link's
//! `Start{until}`), never further. When tick `t` fails, the grown tree swaps in before
//! tick `t + 1 + lead`: the controller ticks on with the old tree (the root failing) for
//! `lead` ticks while the host plans and sends, and cannot pass the swap tick if the
//! host is late (it waits at its horizon instead). The same statuses thus give the same
//! trees at the same ticks, on a board or in QEMU.
//!
//! # What the planner is told
//!
//! Algorithm 1 reads which conditions failed on the failed tick: the statuses the
//! controller reported ([`planner::Planner::on_reported_failure`]). To refine free
//! parameters it needs a state: the host's [`Belief`], built from those same reports.
//!
//! [`run`] reports everything as [`Step`]s to a [`Listener`]: the trees as they swap in
//! and each tick's status changes (what a narration, a trace or a Groot2 view needs).

mod belief;
pub mod narrate;

use std::io::{Read, Write};
use std::time::{Duration, Instant};

use anyhow::{Context as _, bail};
use bt_core::{Catalog as _, Node, NodeKind, NodeStatus, Tree};
use bt_link::host::Verdict;
use bt_link::{Fault, ImageInfo, WireStatus, image_crc};
use planner::ground::AtomId;
use planner::{Expansion, PddlCatalog, PlanError, Planner};

pub use belief::Belief;

use crate::session::{self, Event, Session};
use crate::text::count;

/// A blended session's settings.
#[derive(Debug)]
pub struct Blend {
    /// The planner, holding the tree to start from (the goal, or a given tree).
    pub planner: Planner,
    /// The problem's behavior set: names, and the fingerprint the controller must have.
    pub catalog: PddlCatalog,
    /// Milliseconds between ticks (the tree's clock advances by as much per tick).
    pub period_ms: u16,
    /// Ticks the controller may run ahead of the host; a grown tree swaps in this many
    /// ticks after the tick that failed, plus one.
    pub lead: u32,
    /// Ticks to run at most.
    pub ticks: Option<u32>,
}

/// One expansion: when, what, and what sending it cost.
#[derive(Clone, Debug)]
pub struct Grown {
    /// Its number, from 1.
    pub n: usize,
    /// The tick whose failure it answers.
    pub failed_at: u32,
    /// The tick the grown tree swaps in before.
    pub swap_at: u32,
    /// What the planner did.
    pub expansion: Expansion,
    /// How long the planner took.
    pub planning: Duration,
    /// The grown tree's image.
    pub image: ImageInfo,
    /// How long sending it took, until the controller accepted it.
    pub sending: Duration,
    /// Bytes on the wire both ways while it was sent (status reports included).
    pub wire: u64,
}

/// What [`run`] tells its [`Listener`], in order.
#[derive(Clone, Copy, Debug)]
pub enum Step<'a> {
    /// The controller, before anything else: its next tick, and whether it was ticking
    /// (blend stopped it, halting what ran).
    Connected {
        /// Its next tick.
        tick: u32,
        /// Whether it was ticking.
        was_ticking: bool,
    },
    /// A tree runs from `tick` on: the first one, or that of expansion `grown`.
    Tree {
        /// Its first tick.
        tick: u32,
        /// Its nodes.
        nodes: &'a [Node],
        /// Its value table.
        values: &'a [u16],
        /// Its image.
        image: ImageInfo,
        /// The expansion that made it (none for the first).
        grown: Option<usize>,
    },
    /// An event of the status stream, the tree it is about, and each node's status
    /// before and after it.
    Event {
        /// The event.
        event: &'a Event,
        /// The tree.
        nodes: &'a [Node],
        /// Statuses before.
        before: &'a [NodeStatus],
        /// Statuses after.
        after: &'a [NodeStatus],
        /// Whether a grown tree is on its way (the old one ticks on until it swaps in).
        waiting: bool,
    },
    /// Conditions reported at `tick` that the host's model did not predict: the fact
    /// and its new value.
    Unexpected {
        /// The tick.
        tick: u32,
        /// The facts, as the planner names them, with their values.
        facts: &'a [(AtomId, bool)],
    },
    /// The planner grew the tree; it is sent and accepted.
    Expanded {
        /// What was done.
        grown: &'a Grown,
        /// The grown tree.
        nodes: &'a [Node],
        /// Its value table.
        values: &'a [u16],
    },
    /// The session ends; the controller ticks on to its horizon, then stops.
    Ending {
        /// Why.
        end: &'a End,
        /// The tick it stops before.
        stop_at: u32,
    },
}

/// Sees a blended session.
pub trait Listener {
    /// One step.
    ///
    /// # Errors
    /// Whatever the listener could not do (write its output); the session stops.
    fn step(&mut self, step: Step<'_>) -> anyhow::Result<()>;
}

/// How a session ended.
#[derive(Debug)]
pub enum End {
    /// The root succeeded at this tick.
    Goal(u32),
    /// `--ticks` ran out.
    Ticks,
    /// The root failed at `tick` and the planner could not expand the tree.
    Unexpandable {
        /// The tick.
        tick: u32,
        /// Why.
        error: PlanError,
    },
    /// The root failed at `tick`; the grown tree does not fit the controller, or the
    /// controller refused it.
    Refused {
        /// The tick.
        tick: u32,
        /// Why, in words.
        reason: String,
    },
}

/// What a session did.
#[derive(Debug)]
pub struct Summary {
    /// How it ended.
    pub end: End,
    /// The controller's first tick in the session.
    pub first_tick: u32,
    /// The tick it stopped before.
    pub stopped_at: u32,
    /// The expansions.
    pub grown: Vec<Grown>,
    /// Actions halted by the tree moving to another branch (not by swaps or the stop).
    pub halts: usize,
    /// Actions halted by swaps.
    pub swap_halts: usize,
    /// Times the controller had reached the horizon when the host granted more ticks
    /// (outside swaps): the host fell behind the stream.
    pub waits: u32,
    /// Bytes sent and received on the link in the session.
    pub bytes: (u64, u64),
    /// The last tree.
    pub nodes: Vec<Node>,
}

/// The tree the controller runs, as the host knows it.
struct Running {
    nodes: Vec<Node>,
    values: Vec<u16>,
    statuses: Vec<NodeStatus>,
}

impl Running {
    fn new(nodes: &[Node], values: &[u16]) -> Self {
        Self { nodes: nodes.to_vec(), values: values.to_vec(), statuses: vec![NodeStatus::Idle; nodes.len()] }
    }
}

/// A grown tree sent, waiting for its tick.
struct Pending {
    swap_at: u32,
    crc: u32,
    nodes: Vec<Node>,
    values: Vec<u16>,
    n: usize,
}

/// How long to wait for the controller's next report before calling it gone.
fn silence(period_ms: u16) -> Duration {
    Duration::from_secs(10).max(Duration::from_millis(u64::from(period_ms) * 50))
}

/// The session's state between events.
struct Driver<'a, T, L: ?Sized> {
    link: &'a mut Session<T>,
    /// Most bytes an image may have on the controller.
    capacity: u32,
    listener: &'a mut L,
    blend: Blend,
    belief: Belief,
    running: Running,
    pending: Option<Pending>,
    /// The controller may not run tick `granted` or later.
    granted: u32,
    /// Ticks may not reach this one (`--ticks`).
    last: Option<u32>,
    /// The last tick read.
    read: Option<u32>,
    grown: Vec<Grown>,
    halts: usize,
    swap_halts: usize,
    waits: u32,
    /// The session has ended: no more expansions or grants.
    ending: bool,
}

/// Runs a blended session over `link` to a controller of the problem's behavior set
/// (the caller checked its `Hello`) holding images of at most `capacity` bytes: deploys
/// the planner's tree, starts the controller, and grows the tree whenever its root
/// fails, until the root succeeds, the ticks run out, or a grown tree cannot be made or
/// sent ([`End`]); then lets the controller run to its horizon and stops it.
///
/// # Errors
/// The link failing or closing, the controller refusing the first tree, a swap at
/// another tick or of another image than named, a listener's error.
pub fn run<T: Read + Write, L: Listener + ?Sized>(
    link: &mut Session<T>,
    capacity: u32,
    blend: Blend,
    listener: &mut L,
) -> anyhow::Result<Summary> {
    let bytes_before = link.bytes();
    let state = link.ping(1).context("ping")?;
    let was_ticking = state.ticking;
    let state = if was_ticking { link.stop().context("stop")? } else { state };
    // Whatever the tree before did is not this session's.
    while link.pending().is_some() {}
    listener.step(Step::Connected { tick: state.tick, was_ticking })?;
    let first_tick = state.tick;
    let image = encode(&blend, blend.planner.nodes(), blend.planner.values(), capacity)?.map_err(anyhow::Error::msg)?;
    accept(link.deploy(&image, Some(first_tick)).context("deploying the first tree")?).map_err(anyhow::Error::msg)?;
    let belief = Belief::new(blend.planner.grounding());
    let running = Running::new(blend.planner.nodes(), blend.planner.values());
    let last = blend.ticks.map(|n| first_tick.saturating_add(n));
    let mut d = Driver {
        link,
        capacity,
        listener,
        blend,
        belief,
        running,
        pending: None,
        granted: 0,
        last,
        read: None,
        grown: Vec::new(),
        halts: 0,
        swap_halts: 0,
        waits: 0,
        ending: false,
    };
    d.first_swap(first_tick, image_crc(&image))?;
    let lead = d.blend.lead;
    d.grant(first_tick.saturating_add(1).saturating_add(lead), false)?;
    let end = d.act()?;
    let stopped_at = d.finish(&end)?;
    let bytes = d.link.bytes();
    Ok(Summary {
        end,
        first_tick,
        stopped_at,
        grown: d.grown,
        halts: d.halts,
        swap_halts: d.swap_halts,
        waits: d.waits,
        bytes: (bytes.0 - bytes_before.0, bytes.1 - bytes_before.1),
        nodes: d.running.nodes,
    })
}

/// The image of a tree for the controller, checked against the behavior set and the
/// controller's buffer; the inner error says why the controller cannot take it.
fn encode(blend: &Blend, nodes: &[Node], values: &[u16], capacity: u32) -> anyhow::Result<Result<Vec<u8>, String>> {
    Tree::<'_, { planner::DEPTH }>::validate_with(nodes, values, &blend.catalog)
        .map_err(|e| anyhow::anyhow!("the planner's tree does not validate: {e}"))?;
    let image = bt_formats::Image::new(nodes).values(values).encode(blend.catalog.fingerprint())?;
    if image.len() > capacity as usize {
        return Ok(Err(format!(
            "the tree has {}, an image of {}; the controller holds images of at most {capacity}",
            count(nodes.len(), "node"),
            count(image.len(), "byte")
        )));
    }
    Ok(Ok(image))
}

/// The controller's verdict: the image it accepted, or why it refused.
fn accept(verdict: Verdict) -> Result<ImageInfo, String> {
    match verdict {
        Verdict::Accepted { crc, nodes, .. } => Ok(ImageInfo { crc, len: 0, nodes }),
        Verdict::Rejected(fault) => Err(format!("the controller refused the tree: {}", refusal(&fault))),
    }
}

fn refusal(fault: &Fault) -> String {
    match *fault {
        Fault::Load { node: Some(n), .. } => format!("{} at node {n}", fault.code()),
        _ => fault.code().to_string(),
    }
}

impl<T: Read + Write, L: Listener + ?Sized> Driver<'_, T, L> {
    fn next(&mut self) -> anyhow::Result<Event> {
        let deadline = Instant::now() + silence(self.blend.period_ms);
        self.link.next(deadline).map_err(|e| anyhow::anyhow!("{e}"))
    }

    /// Waits for the first tree's swap (the controller is stopped: at once).
    fn first_swap(&mut self, tick: u32, crc: u32) -> anyhow::Result<()> {
        loop {
            match self.next()? {
                Event::Swapped { tick: t, image, .. } if t == tick && image.crc == crc => {
                    let r = &self.running;
                    let step = Step::Tree { tick, nodes: &r.nodes, values: &r.values, image, grown: None };
                    return self.listener.step(step);
                }
                Event::Swapped { tick: t, image, .. } => {
                    bail!("the controller swapped in image {:08x} at tick {t}, not the first tree at {tick}", image.crc)
                }
                _ => {}
            }
        }
    }

    /// Lets the controller run up to, not including, tick `until` (within `--ticks`);
    /// `count`: count it as a wait if the controller had reached its horizon already.
    ///
    /// The horizon keeps the swap ticks the host names ahead of the controller: before
    /// the host reads tick `t`, the controller may not pass tick `t + 1 + lead`, where a
    /// tree grown on `t`'s failure swaps in. So after reading tick `t`, it may run to
    /// `t + 2 + lead` (or to the swap tick, when `t` failed); after a swap before tick
    /// `s`, to `s + 1 + lead`.
    fn grant(&mut self, until: u32, count: bool) -> anyhow::Result<()> {
        let until = self.last.map_or(until, |last| until.min(last));
        if until <= self.granted {
            return Ok(());
        }
        let next = self.link.start(Some(until), self.blend.period_ms).context("start")?;
        if count && next >= self.granted {
            self.waits += 1;
        }
        self.granted = until;
        Ok(())
    }

    /// Reads the stream and grows the tree until the session ends.
    fn act(&mut self) -> anyhow::Result<End> {
        loop {
            let event = self.next()?;
            if let Some(end) = self.take(&event)? {
                self.ending = true;
                return Ok(end);
            }
        }
    }

    /// Takes one event: statuses, belief, listener; a swap; a failure to expand.
    /// Returns how the session ends, if this event ends it.
    fn take(&mut self, event: &Event) -> anyhow::Result<Option<End>> {
        let before = self.running.statuses.clone();
        let changes = match event {
            Event::Tick { changes, .. } | Event::Swapped { changes, .. } | Event::Stopped { changes, .. } => {
                changes.as_slice()
            }
            Event::Garbled(_) | Event::Lost { .. } => &[],
        };
        session::apply(&mut self.running.statuses, changes);
        let halted = changes.iter().filter(|&&(n, s)| {
            s == NodeStatus::Idle
                && before.get(usize::from(n)) == Some(&NodeStatus::Running)
                && self.running.nodes.get(usize::from(n)).is_some_and(|x| matches!(x.kind(), NodeKind::Action(_)))
        });
        match event {
            Event::Tick { .. } => self.halts += halted.count(),
            Event::Swapped { .. } => self.swap_halts += halted.count(),
            _ => {}
        }
        if let Event::Tick { tick, .. } = *event {
            let r = &self.running;
            let facts = self.belief.observe(self.blend.planner.grounding(), &r.nodes, &r.values, &r.statuses);
            if !facts.is_empty() {
                self.listener.step(Step::Unexpected { tick, facts: &facts })?;
            }
        }
        let r = &self.running;
        let waiting = self.pending.is_some();
        self.listener.step(Step::Event { event, nodes: &r.nodes, before: &before, after: &r.statuses, waiting })?;
        match *event {
            Event::Tick { tick, root, .. } => self.ticked(tick, root),
            Event::Swapped { tick, image, .. } => self.swapped(tick, image).map(|()| None),
            Event::Stopped { tick, .. } if !self.ending => {
                bail!("the controller was stopped before tick {tick} by another host")
            }
            Event::Stopped { .. } => Ok(None),
            Event::Garbled(_) | Event::Lost { .. } => Ok(None),
        }
    }

    fn ticked(&mut self, tick: u32, root: WireStatus) -> anyhow::Result<Option<End>> {
        self.read = Some(tick);
        if self.ending {
            return Ok(None);
        }
        match root {
            WireStatus::Success => return Ok(Some(End::Goal(tick))),
            WireStatus::Idle => {
                bail!("tick {tick} ended in an error on the controller (a behavior broke the tick rules)")
            }
            _ => {}
        }
        let swap_at = tick.saturating_add(1).saturating_add(self.blend.lead);
        let expanding = root == WireStatus::Failure && self.pending.is_none() && self.last.is_none_or(|l| swap_at < l);
        // Ticks are granted as they are read; a reader behind the stream grants once it
        // has caught up (one request for many ticks), and always up to a swap tick.
        if expanding {
            self.grant(swap_at, true)?;
            if let Some(end) = self.expand(tick, swap_at)? {
                return Ok(Some(end));
            }
        } else if self.pending.is_none() && !self.link.behind() {
            self.grant(swap_at.saturating_add(1), true)?;
        }
        Ok(self.last.is_some_and(|l| tick + 1 >= l).then_some(End::Ticks))
    }

    /// Lines 9-12 of Algorithm 1 on the statuses of the failed tick, then the grown tree
    /// sent to swap in before `swap_at`; how the session ends if it cannot be.
    fn expand(&mut self, tick: u32, swap_at: u32) -> anyhow::Result<Option<End>> {
        let started = Instant::now();
        let expansion = match self.blend.planner.on_reported_failure(&self.running.statuses, self.belief.state()) {
            Ok(e) => e,
            Err(error) => return Ok(Some(End::Unexpandable { tick, error })),
        };
        let planning = started.elapsed();
        let (nodes, values) = (self.blend.planner.nodes().to_vec(), self.blend.planner.values().to_vec());
        let n = self.grown.len() + 1;
        let (image, sending, wire) = match self.send(&nodes, &values, swap_at)? {
            Ok(sent) => sent,
            Err(reason) => return Ok(Some(End::Refused { tick, reason })),
        };
        let grown = Grown { n, failed_at: tick, swap_at, expansion, planning, image, sending, wire };
        self.listener.step(Step::Expanded { grown: &grown, nodes: &nodes, values: &values })?;
        self.pending = Some(Pending { swap_at, crc: image.crc, nodes, values, n });
        self.grown.push(grown);
        Ok(None)
    }

    /// Sends a grown tree; its image, how long sending took and the bytes on the wire,
    /// or why the controller cannot take it.
    fn send(
        &mut self,
        nodes: &[Node],
        values: &[u16],
        swap_at: u32,
    ) -> anyhow::Result<Result<(ImageInfo, Duration, u64), String>> {
        let image = match encode(&self.blend, nodes, values, self.capacity)? {
            Ok(image) => image,
            Err(reason) => return Ok(Err(reason)),
        };
        let before = self.link.bytes();
        let started = Instant::now();
        let verdict = self.link.deploy(&image, Some(swap_at)).context("sending the grown tree")?;
        let sending = started.elapsed();
        let after = self.link.bytes();
        Ok(accept(verdict).map(|mut info| {
            info.len = image.len() as u32;
            (info, sending, after.0 - before.0 + after.1 - before.1)
        }))
    }

    fn swapped(&mut self, tick: u32, image: ImageInfo) -> anyhow::Result<()> {
        let Some(p) = self.pending.take() else {
            bail!(
                "the controller swapped in image {:08x} before tick {tick}, which this session did not send",
                image.crc
            )
        };
        if tick != p.swap_at || image.crc != p.crc {
            bail!(
                "the controller swapped in image {:08x} before tick {tick}; this session named image {:08x} before tick {}",
                image.crc,
                p.crc,
                p.swap_at
            );
        }
        self.running = Running::new(&p.nodes, &p.values);
        let r = &self.running;
        self.listener.step(Step::Tree { tick, nodes: &r.nodes, values: &r.values, image, grown: Some(p.n) })?;
        if self.ending {
            return Ok(());
        }
        self.grant(tick.saturating_add(1).saturating_add(self.blend.lead), false)
    }

    /// Lets the controller run to the horizon the ending tick allows (a grown tree on
    /// its way swapping in), then stops it; returns the tick it stopped before. The
    /// horizon is that of the rule in [`Driver::grant`], so that where the controller
    /// stops does not depend on how far the host had granted when the session ended.
    fn finish(&mut self, end: &End) -> anyhow::Result<u32> {
        let horizon = |t: u32| t.saturating_add(1).saturating_add(self.blend.lead);
        let stop_at = match *end {
            End::Goal(t) | End::Unexpandable { tick: t, .. } | End::Refused { tick: t, .. } => horizon(t),
            End::Ticks => self.granted,
        };
        let stop_at = self.last.map_or(stop_at, |l| stop_at.min(l));
        self.grant(stop_at, false)?;
        self.listener.step(Step::Ending { end, stop_at })?;
        while self.read.is_none_or(|r| r + 1 < stop_at) || self.pending.is_some() {
            let event = self.next()?;
            self.take(&event)?;
        }
        let state = self.link.stop().context("stop")?;
        while let Some(event) = self.link.pending() {
            self.take(&event)?;
        }
        Ok(state.tick)
    }
}
