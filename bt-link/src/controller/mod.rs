//! The controller side: a sans-IO [`Controller`] that ticks the running tree and
//! answers the link between ticks, from fixed storage, and [`serve`], a blocking loop
//! over it for a polled [`Board`].
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
//!
//! A deployment swaps in at most once: every transfer is named by its `Deploy`'s id, and
//! a `Deploy` or `Commit` that repeats a transfer the controller has (its first answer
//! lost on the line) is answered with where that transfer stands or its verdict, never
//! started or swapped again. Deploying the running image once more under a new id is a
//! new deployment: it swaps in again (a restart).

use bt_core::{BehaviorSet, Catalog, LoadError, Node, Status, TickError};

use crate::wire::ImageInfo;

mod session;
mod storage;
mod tx;

pub use self::session::{Controller, MIN_TX};
pub use self::storage::{Slot, Storage};

/// The controller's clock and memory probe: what [`Controller::poll`] and the answers
/// to `Start`, `Stop` and `Ping` read. Every [`Board`] is one.
pub trait Clock {
    /// A free-running microsecond clock (wraps).
    fn micros(&mut self) -> u32;
    /// Bytes of stack used since boot, if the board can tell; 0 otherwise.
    fn stack_used(&mut self) -> u32 {
        0
    }
}

/// A polled byte link with a clock, for the blocking [`serve`].
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

impl<B: Board + ?Sized> Clock for B {
    fn micros(&mut self) -> u32 {
        Board::micros(self)
    }
    fn stack_used(&mut self) -> u32 {
        Board::stack_used(self)
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

/// The transmit queue of [`serve`], in bytes.
pub const SERVE_TX: usize = 384;

/// Runs a [`Controller`] over a polled [`Board`]: boots `boot` (if any), then feeds it
/// every byte the board has, sends what it queues, and polls it for ticks, until
/// [`Board::closed`]. Ticking starts on the host's `Start`. The transmit queue holds
/// [`SERVE_TX`] bytes, which [`Board::write`] empties after every step: one tick's
/// status changes must fit (20 of them; more are dropped and counted in a `Lost`
/// reply).
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
    let mut controller = Controller::<C, NODES, BYTES, VALUES, DEPTH, SERVE_TX>::new(storage, catalog);
    if let Some(image) = boot {
        // A boot image that does not load leaves the controller waiting for a deployment.
        let _ = controller.boot(image, app);
    }
    loop {
        while controller.wants_input() {
            let Some(byte) = board.read() else { break };
            controller.feed(&[byte], app, board);
            flush(&mut controller, board);
        }
        if board.closed() {
            return;
        }
        controller.poll(app, board);
        flush(&mut controller, board);
    }
}

/// Copies `src` to the start of `dst`, which is at least as long: `copy_from_slice`
/// without its length check, which links a panic where the compiler cannot see that
/// the lengths agree.
fn copy(dst: &mut [u8], src: &[u8]) {
    for (d, s) in dst.iter_mut().zip(src) {
        *d = *s;
    }
}

/// Sends everything the controller queued.
fn flush<C, B, const NODES: usize, const BYTES: usize, const VALUES: usize, const DEPTH: usize, const TX: usize>(
    controller: &mut Controller<'_, C, NODES, BYTES, VALUES, DEPTH, TX>,
    board: &mut B,
) where
    C: Catalog + ?Sized,
    B: Board,
{
    let pending = controller.transmit();
    if !pending.is_empty() {
        let n = pending.len();
        board.write(pending);
        controller.transmitted(n);
    }
}

#[cfg(test)]
mod tests;
