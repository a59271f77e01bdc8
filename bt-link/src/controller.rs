//! The controller side: [`serve`] ticks the running tree and answers the link, between
//! ticks, from fixed storage.
//!
//! # Safe swap
//!
//! [`Storage`] has two [`Slot`]s, each an image buffer and the node array it decodes
//! into. The running tree lives in one; a deployment is received into the other while
//! the running tree goes on ticking. At `Commit` the bytes must have the announced
//! length and CRC and pass [`bt_core::load`] into the spare slot's nodes; only then is
//! the image *accepted*. At the first tick boundary at or after its `swap_at` tick, the
//! running tree's actions are halted (each `halt` call and status change reported), and
//! the slots change roles: the next tick is the new tree's first. Nothing a transfer
//! does touches the running slot, so a refused, truncated or corrupted transfer leaves
//! the running tree exactly as it was.

use bt_core::{
    BehaviorSet, Catalog, Executor, LoadError, Node, NodeId, NodeState, NodeStatus, Observer, Status, TickError, Tree,
};

use crate::frame::{self, Decoder, Feed, MAX_ENCODED, MAX_FRAME, crc32};
use crate::wire::{Fault, ImageInfo, MAX_CHUNK, PROTOCOL_VERSION, Reply, Request, WireStatus, load_fault};

/// The controller's byte link, clock and memory probe.
pub trait Board {
    /// The next byte received, if one is waiting. Never blocks.
    fn read(&mut self) -> Option<u8>;
    /// Sends `bytes`, blocking until the link has taken them.
    fn write(&mut self, bytes: &[u8]);
    /// A free-running microsecond clock (wraps).
    fn micros(&mut self) -> u32;
    /// Bytes of stack used since boot, if the board can tell; 0 otherwise.
    fn stack_used(&mut self) -> u32 {
        0
    }
    /// True when [`serve`] should return (the host end closed, in tests and on the
    /// host); a controller never returns.
    fn closed(&mut self) -> bool {
        false
    }
}

/// The world the trees act on, with hooks for the controller's own log.
pub trait App: BehaviorSet {
    /// The boot image was loaded (`Ok` with the tree's nodes) or refused.
    fn booted(&mut self, _result: Result<(ImageInfo, &[Node]), LoadError>) {}
    /// Before tick `tick` is ticked (scripted events, sensor reads).
    fn before_tick(&mut self, _tick: u32) {}
    /// After tick `tick`: what the root returned, and the tree's nodes.
    fn after_tick(&mut self, _tick: u32, _result: Result<Status, TickError>, _nodes: &[Node]) {}
    /// At the boundary before tick `tick`, a new tree replaced the running one, whose
    /// actions were halted just before (through [`BehaviorSet::halt`]).
    fn swapped(&mut self, _tick: u32, _image: ImageInfo, _nodes: &[Node]) {}
    /// `Stop` halted the running tree at the boundary before tick `tick`.
    fn stopped(&mut self, _tick: u32) {}
}

/// One image buffer and the nodes and value table it decodes into.
#[derive(Debug)]
pub struct Slot<const NODES: usize, const BYTES: usize, const VALUES: usize> {
    bytes: [u8; BYTES],
    nodes: [Node; NODES],
    values: [u16; VALUES],
    /// Entries of `values` the loaded tree uses.
    value_count: usize,
    /// The image held, if one was loaded into `nodes`.
    image: Option<ImageInfo>,
}

impl<const NODES: usize, const BYTES: usize, const VALUES: usize> Slot<NODES, BYTES, VALUES> {
    const fn new() -> Self {
        Self { bytes: [0; BYTES], nodes: [Node::EMPTY; NODES], values: [0; VALUES], value_count: 0, image: None }
    }

    /// Loads `len` bytes of the buffer into the nodes.
    fn load<C: Catalog + ?Sized, const DEPTH: usize>(
        &mut self,
        len: usize,
        catalog: &C,
    ) -> Result<ImageInfo, LoadError> {
        self.image = None;
        let bytes = self.bytes.get(..len).ok_or(LoadError::TooManyNodes { count: len, capacity: BYTES })?;
        let tree: Tree<'_, DEPTH> = bt_core::image::load_with(bytes, catalog, &mut self.nodes, &mut self.values)?;
        let info = ImageInfo { crc: crate::image_crc(bytes), len: len as u32, nodes: tree.len() as u16 };
        self.value_count = tree.values().len();
        self.image = Some(info);
        Ok(info)
    }

    /// The tree loaded into this slot (validated again: cheap, and no borrow has to
    /// outlive the load).
    fn tree<C: Catalog + ?Sized, const DEPTH: usize>(&self, catalog: &C) -> Option<Tree<'_, DEPTH>> {
        let nodes = self.nodes.get(..usize::from(self.image?.nodes))?;
        let values = self.values.get(..self.value_count)?;
        Tree::validate_with(nodes, values, catalog).ok()
    }

    /// Image bytes at `offset`, at most [`MAX_CHUNK`].
    fn chunk(&self, offset: u32) -> &[u8] {
        let len = self.image.map_or(0, |i| i.len as usize);
        let start = (offset as usize).min(len);
        self.bytes.get(start..len.min(start + MAX_CHUNK)).unwrap_or(&[])
    }
}

/// Everything [`serve`] keeps: two slots and the running tree's per-node state.
/// `NODES` bounds a tree's node count, `BYTES` an image's length, `VALUES` its value
/// table (leaves with more than three values; 0 refuses such images).
#[derive(Debug)]
pub struct Storage<const NODES: usize, const BYTES: usize, const VALUES: usize> {
    slots: [Slot<NODES, BYTES, VALUES>; 2],
    state: [NodeState; NODES],
}

impl<const NODES: usize, const BYTES: usize, const VALUES: usize> Default for Storage<NODES, BYTES, VALUES> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const NODES: usize, const BYTES: usize, const VALUES: usize> Storage<NODES, BYTES, VALUES> {
    /// Empty storage (`const`: can be a `static`).
    #[must_use]
    pub const fn new() -> Self {
        Self { slots: [Slot::new(), Slot::new()], state: [NodeState::IDLE; NODES] }
    }
}

/// A transfer under way, or an image waiting for its tick.
#[derive(Clone, Copy, Debug)]
enum Incoming {
    None,
    Receiving { len: u32, crc: u32, swap_at: Option<u32>, received: u32 },
    Ready { swap_at: Option<u32> },
}

/// What the link asked the loop to do, beyond answering.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Action {
    None,
    Stop,
}

/// The link's state between frames, apart from the trees.
struct Session {
    fingerprint: u64,
    incoming: Incoming,
    /// The next tick to run.
    tick: u32,
    ticking: bool,
    until: Option<u32>,
    period_us: u32,
    /// When the last tick started, on the board's clock.
    last_tick: Option<u32>,
    /// The tree's clock, in milliseconds: the `now` the next tick gets (see [`serve`]).
    now_ms: u32,
    /// Microseconds of the tree's clock not yet counted in `now_ms`.
    carry_us: u32,
    /// When the previous tick started, on the board's clock (None before the first).
    previous_tick: Option<u32>,
}

/// Sends one reply as a frame.
fn send<B: Board>(board: &mut B, reply: &Reply<'_>) {
    let mut buf = [0u8; MAX_ENCODED];
    // Every reply fits MAX_ENCODED (a unit test holds the largest to it).
    if let Ok(bytes) = frame::encode(reply, &mut buf) {
        board.write(bytes);
    }
}

/// Reports every status change as a `Status` frame.
struct Reporter<'b, B> {
    board: &'b mut B,
    tick: u32,
    changes: u16,
}

impl<B: Board> Observer for Reporter<'_, B> {
    fn on_change(&mut self, node: NodeId, _old: NodeStatus, new: NodeStatus) {
        self.changes = self.changes.saturating_add(1);
        send(self.board, &Reply::Status { tick: self.tick, node, status: new.into() });
    }
}

/// Counts `halt` calls while passing everything on to the app.
struct Halts<'a, A> {
    app: &'a mut A,
    count: u16,
}

impl<A: BehaviorSet> BehaviorSet for Halts<'_, A> {
    fn condition(&mut self, leaf: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> Status {
        self.app.condition(leaf, ctx)
    }
    fn action(&mut self, leaf: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> Status {
        self.app.action(leaf, ctx)
    }
    fn halt(&mut self, leaf: &bt_core::Leaf, node: NodeId) {
        self.count = self.count.saturating_add(1);
        self.app.halt(leaf, node);
    }
}

/// Halts every running action of `exec`, reporting the changes at `tick`; returns how
/// many actions were halted.
fn halt_all<B: Board, A: App, const DEPTH: usize>(
    exec: Option<&mut Executor<'_, '_, DEPTH>>,
    board: &mut B,
    app: &mut A,
    tick: u32,
) -> u16 {
    let Some(exec) = exec else { return 0 };
    let mut halts = Halts { app, count: 0 };
    exec.halt_all_observed(&mut halts, &mut Reporter { board, tick, changes: 0 });
    halts.count
}

/// Runs the controller: boots `boot` (if any) into the first slot, then ticks and
/// answers the link until [`Board::closed`]. Ticking starts on the host's `Start`.
///
/// # The tree's clock
///
/// The executor's `now` (what `Timeout`, `Delay` and `RateController` measure, and
/// [`Context::now`](bt_core::Context::now)) is in milliseconds, 0 at the first tick.
/// Each later tick is one period (`Start`'s `period_ms`) after the one before, so a
/// tree ticked every 100 ms gets tick x 100 ms, the clock of the host's simulated runs:
/// the controller's run is the host's, whatever the jitter of the board's timer. With
/// period 0 (ticks back to back) there is no schedule, and the clock advances by the
/// board's measured time between the two ticks' starts.
///
/// Never panics and never allocates, whatever bytes arrive.
pub fn serve<C, B, A, const NODES: usize, const BYTES: usize, const VALUES: usize, const DEPTH: usize>(
    storage: &mut Storage<NODES, BYTES, VALUES>,
    catalog: &C,
    boot: Option<&[u8]>,
    board: &mut B,
    app: &mut A,
) where
    C: Catalog + ?Sized,
    B: Board,
    A: App,
{
    let Storage { slots: [first, second], state } = storage;
    let (mut run, mut spare) = (first, second);
    if let Some(image) = boot {
        if let Some(buf) = run.bytes.get_mut(..image.len()) {
            buf.copy_from_slice(image);
            // A boot image that does not load leaves the controller without a tree,
            // waiting for a deployment.
            match run.load::<C, DEPTH>(image.len(), catalog) {
                Ok(info) => app.booted(Ok((info, run.nodes.get(..usize::from(info.nodes)).unwrap_or(&[])))),
                Err(e) => app.booted(Err(e)),
            }
        } else {
            app.booted(Err(LoadError::TooManyNodes { count: image.len(), capacity: BYTES }));
        }
    }
    let mut session = Session::new(catalog.fingerprint());
    let mut decoder = Decoder::<MAX_FRAME>::new();
    loop {
        let tree = run.tree::<C, DEPTH>(catalog);
        let mut exec = tree.and_then(|t| Executor::new(t, &mut state[..]).ok());
        if exec.is_none() {
            session.ticking = false;
        }
        // Serve this tree until a swap is due or the board closes.
        let swap = loop {
            while let Some(byte) = board.read() {
                let action = match decoder.feed(byte) {
                    Feed::Pending => Action::None,
                    Feed::Skipped(fault) => {
                        send(board, &Reply::Garbled { fault });
                        Action::None
                    }
                    Feed::Frame(bytes) => match frame::message::<Request<'_>>(bytes) {
                        Ok(request) => {
                            session.handle::<C, B, NODES, BYTES, VALUES, DEPTH>(request, run, spare, catalog, board)
                        }
                        Err(fault) => {
                            send(board, &Reply::Garbled { fault });
                            Action::None
                        }
                    },
                };
                if action == Action::Stop {
                    let halted = halt_all(exec.as_mut(), board, app, session.tick);
                    session.ticking = false;
                    app.stopped(session.tick);
                    let stack = board.stack_used();
                    send(board, &session.state(0, run.image, halted, stack));
                }
                if matches!(session.incoming, Incoming::Ready { .. }) {
                    // Let a due swap happen before the next request is read.
                    break;
                }
            }
            if let Incoming::Ready { swap_at } = session.incoming
                && swap_at.is_none_or(|t| session.tick >= t)
            {
                break true;
            }
            if board.closed() {
                break false;
            }
            if let Some(exec) = exec.as_mut()
                && session.due(board)
            {
                session.tick_once(exec, board, app);
            }
        };
        if !swap {
            return;
        }
        let tick = session.tick;
        let halted = halt_all(exec.as_mut(), board, app, tick);
        // The executor's borrows of the running slot and the state end here.
        let _ = exec;
        core::mem::swap(&mut run, &mut spare);
        session.incoming = Incoming::None;
        spare.image = None;
        if let Some(image) = run.image {
            let count = usize::from(image.nodes);
            app.swapped(tick, image, run.nodes.get(..count).unwrap_or(&[]));
            send(board, &Reply::Swapped { tick, image, halted });
        }
    }
}

impl Session {
    /// A session before any request: not ticking, the tree's clock at 0.
    fn new(fingerprint: u64) -> Self {
        Self {
            fingerprint,
            incoming: Incoming::None,
            tick: 0,
            ticking: false,
            until: None,
            period_us: 0,
            last_tick: None,
            now_ms: 0,
            carry_us: 0,
            previous_tick: None,
        }
    }

    /// Whether a tick is due now (and marks it started).
    fn due<B: Board>(&mut self, board: &mut B) -> bool {
        if !self.ticking || self.until.is_some_and(|u| self.tick >= u) {
            return false;
        }
        let now = board.micros();
        if let Some(last) = self.last_tick
            && now.wrapping_sub(last) < self.period_us
        {
            return false;
        }
        self.last_tick = Some(now);
        true
    }

    fn tick_once<B: Board, A: App, const DEPTH: usize>(
        &mut self,
        exec: &mut Executor<'_, '_, DEPTH>,
        board: &mut B,
        app: &mut A,
    ) {
        let tick = self.tick;
        app.before_tick(tick);
        let started = board.micros();
        let now = self.advance_clock(started);
        let mut reporter = Reporter { board, tick, changes: 0 };
        let result = exec.tick_observed(app, now, &mut reporter);
        let changes = reporter.changes;
        let micros = board.micros().wrapping_sub(started);
        app.after_tick(tick, result, exec.tree().nodes());
        let status = match result {
            Ok(s) => WireStatus::from(s),
            Err(_) => {
                // A behavior broke the executor's rules; the executor halted the tree.
                self.ticking = false;
                WireStatus::Idle
            }
        };
        send(board, &Reply::Tick { tick, status, changes, micros });
        self.tick = tick.wrapping_add(1);
    }

    /// The tree's clock for a tick that started at `started` on the board's clock.
    fn advance_clock(&mut self, started: u32) -> u32 {
        if let Some(previous) = self.previous_tick {
            let step_us = if self.period_us == 0 { started.wrapping_sub(previous) } else { self.period_us };
            let us = u64::from(self.carry_us) + u64::from(step_us);
            // `us / 1000` < 2^33 / 1000 fits u32; wrapping is the clock's contract.
            self.now_ms = self.now_ms.wrapping_add((us / 1000) as u32);
            self.carry_us = (us % 1000) as u32;
        }
        self.previous_tick = Some(started);
        self.now_ms
    }

    fn state(&self, token: u32, running: Option<ImageInfo>, halted: u16, stack_used: u32) -> Reply<'static> {
        Reply::State { token, tick: self.tick, ticking: self.ticking, until: self.until, running, halted, stack_used }
    }

    /// Answers one request. Only ever writes to `spare`.
    fn handle<C, B, const NODES: usize, const BYTES: usize, const VALUES: usize, const DEPTH: usize>(
        &mut self,
        request: Request<'_>,
        run: &Slot<NODES, BYTES, VALUES>,
        spare: &mut Slot<NODES, BYTES, VALUES>,
        catalog: &C,
        board: &mut B,
    ) -> Action
    where
        C: Catalog + ?Sized,
        B: Board,
    {
        let reply = match request {
            Request::Hello { .. } => Reply::Hello {
                version: PROTOCOL_VERSION,
                fingerprint: self.fingerprint,
                node_capacity: NODES.min(usize::from(u16::MAX)) as u16,
                image_capacity: BYTES.min(u32::MAX as usize) as u32,
                running: run.image,
            },
            Request::Deploy { len, crc, swap_at } => {
                if let Some(fault) = self.drop_incoming(spare) {
                    send(board, &Reply::Rejected { fault });
                }
                if len as usize > BYTES || len == 0 {
                    Reply::Rejected { fault: Fault::TooLarge { len, capacity: BYTES as u32 } }
                } else {
                    self.incoming = Incoming::Receiving { len, crc, swap_at, received: 0 };
                    Reply::ChunkAck { received: 0 }
                }
            }
            Request::Chunk { offset, bytes } => self.chunk(offset, bytes, spare),
            Request::Commit => self.commit::<C, NODES, BYTES, VALUES, DEPTH>(spare, catalog),
            Request::Start { until, period_ms } => {
                if run.image.is_none() {
                    Reply::Rejected { fault: Fault::NoTree }
                } else {
                    let period_us = u32::from(period_ms).saturating_mul(1000);
                    // Ticking on at the same period, the schedule goes on: only the
                    // horizon moves (a host that grants ticks as it goes does not
                    // hurry the next one).
                    if !self.ticking || period_us != self.period_us {
                        self.last_tick = None;
                    }
                    self.ticking = true;
                    self.until = until;
                    self.period_us = period_us;
                    let stack = board.stack_used();
                    self.state(0, run.image, 0, stack)
                }
            }
            Request::Stop => return Action::Stop,
            Request::Ping { token } => {
                let stack = board.stack_used();
                self.state(token, run.image, 0, stack)
            }
            Request::Read { offset } => match run.image {
                Some(info) => Reply::Image { offset, total: info.len, bytes: run.chunk(offset) },
                None => Reply::Rejected { fault: Fault::NoTree },
            },
        };
        send(board, &reply);
        Action::None
    }

    /// Drops a transfer under way or an image waiting for its tick.
    fn drop_incoming<const NODES: usize, const BYTES: usize, const VALUES: usize>(
        &mut self,
        spare: &mut Slot<NODES, BYTES, VALUES>,
    ) -> Option<Fault> {
        let crc = match self.incoming {
            Incoming::None => return None,
            Incoming::Receiving { crc, .. } => crc,
            Incoming::Ready { .. } => spare.image.map_or(0, |i| i.crc),
        };
        self.incoming = Incoming::None;
        spare.image = None;
        Some(Fault::Superseded { crc })
    }

    fn chunk<const NODES: usize, const BYTES: usize, const VALUES: usize>(
        &mut self,
        offset: u32,
        bytes: &[u8],
        spare: &mut Slot<NODES, BYTES, VALUES>,
    ) -> Reply<'static> {
        let Incoming::Receiving { len, crc, swap_at, received } = self.incoming else {
            return Reply::Rejected { fault: Fault::NoTransfer };
        };
        let n = bytes.len() as u32;
        let end = offset.checked_add(n).filter(|&e| e <= len);
        let Some(end) = end else {
            return Reply::Rejected { fault: Fault::Overrun { offset, len: n } };
        };
        // Only the chunk that goes on where the received bytes end is taken; a repeat
        // of one already held, or one past a gap, is acked with where to go on.
        if offset == received
            && let Some(dst) = spare.bytes.get_mut(offset as usize..end as usize)
        {
            dst.copy_from_slice(bytes);
            self.incoming = Incoming::Receiving { len, crc, swap_at, received: end };
            return Reply::ChunkAck { received: end };
        }
        Reply::ChunkAck { received }
    }

    fn commit<C, const NODES: usize, const BYTES: usize, const VALUES: usize, const DEPTH: usize>(
        &mut self,
        spare: &mut Slot<NODES, BYTES, VALUES>,
        catalog: &C,
    ) -> Reply<'static>
    where
        C: Catalog + ?Sized,
    {
        let Incoming::Receiving { len, crc, swap_at, received } = self.incoming else {
            return Reply::Rejected { fault: Fault::NoTransfer };
        };
        self.incoming = Incoming::None;
        if received < len {
            return Reply::Rejected { fault: Fault::Incomplete { received, len } };
        }
        let computed = crc32(spare.bytes.get(..len as usize).unwrap_or(&[]));
        if computed != crc {
            return Reply::Rejected { fault: Fault::TransferCrc { expected: crc, computed } };
        }
        match spare.load::<C, DEPTH>(len as usize, catalog) {
            Ok(info) => {
                self.incoming = Incoming::Ready { swap_at };
                Reply::Accepted { crc: info.crc, nodes: info.nodes, swap_at }
            }
            Err(e) => Reply::Rejected { fault: load_fault(&e) },
        }
    }
}

#[cfg(test)]
mod tests;
