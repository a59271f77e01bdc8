//! The sans-IO controller: a value fed with received bytes and the time, which ticks
//! the running tree, swaps trees, and queues the bytes to send. It never blocks and
//! never touches a peripheral; [`serve`](super::serve), an interrupt handler or an
//! RTIC or embassy task moves the bytes.

use bt_core::{Carry, Catalog, Executor, LoadError, NodeState};

use super::storage::{Slot, Storage};
use super::tx::{Halts, Reporter, Tx};
use super::{App, Clock};
use crate::frame::{self, Decoder, Feed, MAX_ENCODED, MAX_FRAME, crc32};
use crate::wire::{Fault, ImageInfo, PROTOCOL_VERSION, Reply, Request, WireStatus, load_fault};

/// Room the transmit queue must have before another received byte is taken: the
/// replies one request can cause (a `Deploy` or `Hello` answers with up to two frames).
const INPUT_RESERVE: usize = 2 * MAX_ENCODED;

/// The smallest transmit queue a [`Controller`] takes (a smaller `TX` does not
/// compile): room for the answers to one request, or it would never take a byte.
pub const MIN_TX: usize = INPUT_RESERVE;

/// The controller's side of the link, without I/O.
///
/// It owns the session (the transfer under way, the tick count, the schedule) and
/// borrows the [`Storage`] of the two trees. The shell around it does three things, in
/// any order and as often as it likes:
///
/// - hands it received bytes with [`feed`](Self::feed), as long as
///   [`wants_input`](Self::wants_input) (bytes it does not take stay with the shell:
///   its receive queue is the flow control);
/// - calls [`poll`](Self::poll) with the board's clock, which swaps in an accepted tree
///   and ticks when a tick is due, and says when to call again;
/// - sends [`transmit`](Self::transmit)'s bytes and reports them with
///   [`transmitted`](Self::transmitted).
///
/// `TX` is the transmit queue in bytes. A tick reports every status change as a frame
/// of 14 bytes; when the queue is full they are dropped and counted, and a `Lost`
/// reply before the tick's `Tick` says how many. Ticks keep their schedule whatever the
/// line carries: a line too slow for the status stream loses status frames, never
/// ticks. Size `TX` for one tick's changes and the answers of a window of chunks, with
/// what the line has not yet sent: status frames are queued while they leave room for
/// the largest reply (98 bytes), so an empty queue of 256 bytes takes 11 of them, 512
/// bytes 29. At least [`MIN_TX`].
///
/// Never panics and never allocates, whatever bytes arrive.
#[derive(Debug)]
pub struct Controller<
    'a,
    C: ?Sized,
    const NODES: usize,
    const BYTES: usize,
    const VALUES: usize,
    const DEPTH: usize,
    const TX: usize,
> {
    storage: &'a mut Storage<NODES, BYTES, VALUES>,
    catalog: &'a C,
    /// The slot the running tree is in (0 or 1); the other receives.
    run: usize,
    session: Session,
    decoder: Decoder<MAX_FRAME>,
    tx: Tx<TX>,
    /// What the running tree's executor carries from one tick to the next.
    carry: Carry,
}

/// A transfer under way (named by its `Deploy`'s id), or an image waiting for its tick.
#[derive(Clone, Copy, Debug)]
enum Incoming {
    None,
    Receiving { id: u16, len: u32, crc: u32, swap_at: Option<u32>, received: u32 },
    Ready { swap_at: Option<u32> },
}

/// How a transfer ended: what every repeat of its `Deploy` or `Commit` is answered.
#[derive(Clone, Copy, Debug)]
enum Verdict {
    Accepted { info: ImageInfo, swap_at: Option<u32> },
    Refused(Fault),
}

impl Verdict {
    fn reply(self, id: u16) -> Reply<'static> {
        match self {
            Self::Accepted { info, swap_at } => Reply::Accepted { id, crc: info.crc, nodes: info.nodes, swap_at },
            Self::Refused(fault) => Reply::Rejected { fault },
        }
    }
}

/// What a request asks beyond an answer.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Action {
    None,
    Stop,
}

/// The link's state between frames, apart from the trees.
#[derive(Debug)]
pub(super) struct Session {
    fingerprint: u64,
    incoming: Incoming,
    /// The last transfer's id and verdict, once it has one: a repeated `Deploy` or
    /// `Commit` of it (its first answer lost) is answered with the verdict again, and
    /// swaps nothing. Cleared by a new `Deploy` and by `Hello`.
    verdict: Option<(u16, Verdict)>,
    /// The next tick to run.
    tick: u32,
    ticking: bool,
    until: Option<u32>,
    period_us: u32,
    /// When the last tick started, on the board's clock.
    last_tick: Option<u32>,
    /// The tree's clock, in milliseconds: the `now` the next tick gets.
    now_ms: u32,
    /// Microseconds of the tree's clock not yet counted in `now_ms`.
    carry_us: u32,
    /// When the previous tick started, on the board's clock (None before the first).
    previous_tick: Option<u32>,
}

/// An executor over the tree in slot `run`, going on from `carry`.
fn executor<
    's,
    C: Catalog + ?Sized,
    const NODES: usize,
    const BYTES: usize,
    const VALUES: usize,
    const DEPTH: usize,
>(
    storage: &'s mut Storage<NODES, BYTES, VALUES>,
    run: usize,
    catalog: &C,
    carry: Carry,
) -> Option<Executor<'s, 's, DEPTH>> {
    let Storage { slots, state } = storage;
    let tree = slots.get(run)?.tree::<C, DEPTH>(catalog)?;
    Executor::resume(tree, &mut state[..], carry).ok()
}

impl<'a, C, const NODES: usize, const BYTES: usize, const VALUES: usize, const DEPTH: usize, const TX: usize>
    Controller<'a, C, NODES, BYTES, VALUES, DEPTH, TX>
where
    C: Catalog + ?Sized,
{
    /// A controller over `storage`, for trees of `catalog`'s behavior set; without a
    /// tree until [`boot`](Self::boot) or a deployment brings one.
    pub fn new(storage: &'a mut Storage<NODES, BYTES, VALUES>, catalog: &'a C) -> Self {
        const { assert!(TX >= MIN_TX, "the transmit queue TX must hold at least MIN_TX bytes") };
        let fingerprint = catalog.fingerprint();
        Self {
            storage,
            catalog,
            run: 0,
            session: Session::new(fingerprint),
            decoder: Decoder::new(),
            tx: Tx::new(),
            carry: Carry::default(),
        }
    }

    /// Loads `image` as the running tree, before any request; reports the outcome to
    /// `app` ([`App::booted`]) and returns it. A controller whose boot image does not
    /// load waits for a deployment.
    ///
    /// # Errors
    /// The loader's error; [`LoadError::TooManyNodes`] when the image is longer than
    /// the slot.
    pub fn boot<A: App>(&mut self, image: &[u8], app: &mut A) -> Result<ImageInfo, LoadError> {
        self.storage.state.fill(NodeState::IDLE);
        self.carry = Carry::default();
        let catalog = self.catalog;
        let Some(slot) = self.storage.slots.get_mut(self.run) else { return Err(LoadError::EmptyTree) };
        let result = match slot.bytes.get_mut(..image.len()) {
            Some(buf) => {
                super::copy(buf, image);
                slot.load::<C, DEPTH>(image.len(), catalog)
            }
            None => Err(LoadError::TooManyNodes { count: image.len(), capacity: BYTES }),
        };
        match result {
            Ok(info) => app.booted(Ok((info, slot.nodes()))),
            Err(e) => app.booted(Err(e)),
        }
        result
    }

    /// The running tree's image, if there is one.
    #[must_use]
    pub fn running(&self) -> Option<ImageInfo> {
        self.storage.slots.get(self.run).and_then(|s| s.image)
    }

    /// The next tick to run.
    #[must_use]
    pub fn tick(&self) -> u32 {
        self.session.tick
    }

    /// Whether [`feed`](Self::feed) takes another byte now: the transmit queue has
    /// room for the answers to one more request.
    #[must_use]
    pub fn wants_input(&self) -> bool {
        self.tx.free() >= INPUT_RESERVE
    }

    /// Takes received bytes while [`wants_input`](Self::wants_input), answering every
    /// request they complete; returns how many it took (the rest is the caller's, to
    /// feed again once [`transmit`](Self::transmit)'s bytes are sent). An accepted
    /// tree whose swap tick has come is swapped in at once (the controller is between
    /// ticks whenever it is fed), and `Stop` halts the running tree through `app`.
    pub fn feed<A: App, K: Clock>(&mut self, bytes: &[u8], app: &mut A, clock: &mut K) -> usize {
        let mut taken = 0;
        for &byte in bytes {
            if !self.wants_input() {
                break;
            }
            taken += 1;
            self.byte(byte, app, clock);
        }
        taken
    }

    /// Swaps in an accepted tree whose tick has come, then ticks if a tick is due.
    /// Returns the microseconds until the next tick is due, or `None` when not ticking.
    pub fn poll<A: App, K: Clock>(&mut self, app: &mut A, clock: &mut K) -> Option<u32> {
        self.swap_if_due(app);
        let s = &mut self.session;
        if !s.ticking || s.until.is_some_and(|u| s.tick >= u) {
            return None;
        }
        let now = clock.micros();
        if let Some(last) = s.last_tick {
            let since = now.wrapping_sub(last);
            if since < s.period_us {
                return Some(s.period_us - since);
            }
        }
        s.last_tick = Some(now);
        self.tick_once(app, clock);
        Some(self.session.period_us)
    }

    /// Bytes waiting to be sent, oldest first.
    #[must_use]
    pub fn transmit(&self) -> &[u8] {
        self.tx.pending()
    }

    /// The first `n` bytes of [`transmit`](Self::transmit) were sent.
    pub fn transmitted(&mut self, n: usize) {
        self.tx.consume(n);
    }

    fn byte<A: App, K: Clock>(&mut self, byte: u8, app: &mut A, clock: &mut K) {
        let action = {
            let Self { storage, catalog, run, session, decoder, tx, .. } = self;
            let [first, second] = &mut storage.slots;
            let (running, spare) = if *run == 0 { (&*first, second) } else { (&*second, first) };
            match decoder.feed(byte) {
                Feed::Pending => Action::None,
                Feed::Skipped(fault) => {
                    tx.push(&Reply::Garbled { fault });
                    Action::None
                }
                Feed::Frame(bytes) => match frame::message::<Request<'_>>(bytes) {
                    Ok(request) => session
                        .handle::<C, K, NODES, BYTES, VALUES, DEPTH, TX>(request, running, spare, *catalog, tx, clock),
                    Err(fault) => {
                        tx.push(&Reply::Garbled { fault });
                        Action::None
                    }
                },
            }
        };
        if action == Action::Stop {
            let halted = self.halt_all(app);
            self.session.ticking = false;
            app.stopped(self.session.tick);
            let stack = clock.stack_used();
            let reply = self.session.state(0, self.running(), halted, stack);
            self.tx.push(&reply);
        }
        self.swap_if_due(app);
    }

    /// Halts every running action of the running tree, reporting the changes at the
    /// upcoming tick; returns how many actions were halted.
    fn halt_all<A: App>(&mut self, app: &mut A) -> u16 {
        let Self { storage, catalog, run, session, tx, carry, .. } = self;
        let Some(mut exec) = executor::<C, NODES, BYTES, VALUES, DEPTH>(storage, *run, *catalog, *carry) else {
            return 0;
        };
        let mut halts = Halts { app, count: 0 };
        exec.halt_all_observed(&mut halts, &mut Reporter { tx, tick: session.tick, changes: 0 });
        *carry = exec.carry();
        halts.count
    }

    /// At a tick boundary: swaps in the accepted tree if its tick has come.
    fn swap_if_due<A: App>(&mut self, app: &mut A) {
        let Incoming::Ready { swap_at } = self.session.incoming else { return };
        if swap_at.is_some_and(|t| self.session.tick < t) {
            return;
        }
        let tick = self.session.tick;
        let halted = self.halt_all(app);
        self.run ^= 1;
        self.session.incoming = Incoming::None;
        self.storage.state.fill(NodeState::IDLE);
        self.carry = Carry::default();
        let [first, second] = &mut self.storage.slots;
        let (running, spare) = if self.run == 0 { (&*first, second) } else { (&*second, first) };
        spare.image = None;
        if let Some(image) = running.image {
            app.swapped(tick, image, running.nodes());
            self.tx.push(&Reply::Swapped { tick, image, halted });
        }
    }

    fn tick_once<A: App, K: Clock>(&mut self, app: &mut A, clock: &mut K) {
        let Self { storage, catalog, run, session, tx, carry, .. } = self;
        let Some(mut exec) = executor::<C, NODES, BYTES, VALUES, DEPTH>(storage, *run, *catalog, *carry) else {
            session.ticking = false;
            return;
        };
        let tick = session.tick;
        app.before_tick(tick);
        let started = clock.micros();
        let now = session.advance_clock(started);
        let mut reporter = Reporter { tx, tick, changes: 0 };
        let result = exec.tick_observed(app, now, &mut reporter);
        let changes = reporter.changes;
        *carry = exec.carry();
        let micros = clock.micros().wrapping_sub(started);
        app.after_tick(tick, result, exec.tree().nodes());
        let status = match result {
            Ok(s) => WireStatus::from(s),
            Err(_) => {
                // A behavior broke the executor's rules; the executor halted the tree.
                session.ticking = false;
                WireStatus::Idle
            }
        };
        let lost = core::mem::take(&mut tx.lost);
        if lost > 0 {
            tx.push_reserving(&Reply::Lost { tick, frames: lost }, MAX_ENCODED);
        }
        tx.push(&Reply::Tick { tick, status, changes, micros });
        session.tick = tick.wrapping_add(1);
    }
}

impl Session {
    /// A session before any request: not ticking, the tree's clock at 0.
    pub(super) const fn new(fingerprint: u64) -> Self {
        Self {
            fingerprint,
            incoming: Incoming::None,
            verdict: None,
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

    /// The tree's clock for a tick that started at `started` on the board's clock.
    pub(super) fn advance_clock(&mut self, started: u32) -> u32 {
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

    /// Answers one request into `tx`. Only ever writes to `spare`.
    #[allow(clippy::too_many_arguments)]
    fn handle<C, K, const NODES: usize, const BYTES: usize, const VALUES: usize, const DEPTH: usize, const TX: usize>(
        &mut self,
        request: Request<'_>,
        run: &Slot<NODES, BYTES, VALUES>,
        spare: &mut Slot<NODES, BYTES, VALUES>,
        catalog: &C,
        tx: &mut Tx<TX>,
        clock: &mut K,
    ) -> Action
    where
        C: Catalog + ?Sized,
        K: Clock,
    {
        // A transfer this request drops, reported before its answer.
        let mut dropped = None;
        let reply = match request {
            Request::Hello { .. } => {
                // A new session, whose transfer ids are its own: the last transfer's
                // verdict is forgotten, and a transfer under way, which the new host
                // cannot name, is dropped. An accepted image still swaps at its tick.
                self.verdict = None;
                if matches!(self.incoming, Incoming::Receiving { .. }) {
                    dropped = self.drop_incoming(spare);
                }
                Reply::Hello {
                    version: PROTOCOL_VERSION,
                    fingerprint: self.fingerprint,
                    node_capacity: NODES.min(usize::from(u16::MAX)) as u16,
                    image_capacity: BYTES.min(u32::MAX as usize) as u32,
                    running: run.image,
                }
            }
            Request::Deploy { id, len, crc, swap_at } => match self.repeat(id) {
                Some(state) => state,
                None => {
                    self.verdict = None;
                    dropped = self.drop_incoming(spare);
                    if len as usize > BYTES || len == 0 {
                        self.refuse(id, Fault::TooLarge { len, capacity: BYTES as u32 })
                    } else {
                        self.incoming = Incoming::Receiving { id, len, crc, swap_at, received: 0 };
                        Reply::ChunkAck { id, received: 0 }
                    }
                }
            },
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
                    self.state(0, run.image, 0, clock.stack_used())
                }
            }
            Request::Stop => return Action::Stop,
            Request::Ping { token } => self.state(token, run.image, 0, clock.stack_used()),
            Request::Read { offset } => match run.image {
                Some(info) => Reply::Image { offset, total: info.len, bytes: run.chunk(offset) },
                None => Reply::Rejected { fault: Fault::NoTree },
            },
        };
        if let Some(fault) = dropped {
            tx.push(&Reply::Rejected { fault });
        }
        tx.push(&reply);
        Action::None
    }

    /// The answer to a `Deploy` of transfer `id` if it is a repeat: where the transfer
    /// under way stands, or the verdict of the last one; `None` for a new transfer.
    fn repeat(&self, id: u16) -> Option<Reply<'static>> {
        if let Incoming::Receiving { id: open, received, .. } = self.incoming {
            return (open == id).then_some(Reply::ChunkAck { id, received });
        }
        let (last, verdict) = self.verdict?;
        (last == id).then(|| verdict.reply(id))
    }

    /// Closes transfer `id` with a refusal, remembered for its repeats.
    fn refuse(&mut self, id: u16, fault: Fault) -> Reply<'static> {
        self.verdict = Some((id, Verdict::Refused(fault)));
        Reply::Rejected { fault }
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
        let Incoming::Receiving { id, len, crc, swap_at, received } = self.incoming else {
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
            super::copy(dst, bytes);
            self.incoming = Incoming::Receiving { id, len, crc, swap_at, received: end };
            return Reply::ChunkAck { id, received: end };
        }
        Reply::ChunkAck { id, received }
    }

    fn commit<C, const NODES: usize, const BYTES: usize, const VALUES: usize, const DEPTH: usize>(
        &mut self,
        spare: &mut Slot<NODES, BYTES, VALUES>,
        catalog: &C,
    ) -> Reply<'static>
    where
        C: Catalog + ?Sized,
    {
        let Incoming::Receiving { id, len, crc, swap_at, received } = self.incoming else {
            // A repeated `Commit` (its answer lost): the verdict again.
            return match self.verdict {
                Some((id, verdict)) => verdict.reply(id),
                None => Reply::Rejected { fault: Fault::NoTransfer },
            };
        };
        if received < len {
            // The transfer stays open: the host sends what is missing and commits again.
            return Reply::Rejected { fault: Fault::Incomplete { received, len } };
        }
        self.incoming = Incoming::None;
        let computed = crc32(spare.bytes.get(..len as usize).unwrap_or(&[]));
        if computed != crc {
            return self.refuse(id, Fault::TransferCrc { expected: crc, computed });
        }
        match spare.load::<C, DEPTH>(len as usize, catalog) {
            Ok(info) => {
                self.incoming = Incoming::Ready { swap_at };
                let verdict = Verdict::Accepted { info, swap_at };
                self.verdict = Some((id, verdict));
                verdict.reply(id)
            }
            Err(e) => self.refuse(id, load_fault(&e)),
        }
    }
}
