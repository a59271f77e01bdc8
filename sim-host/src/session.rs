//! The host's session with a controller over bt-link: every tool that talks to a
//! controller (`deploy`, `monitor`, `blend`) goes through one [`Session`], which turns
//! the replies the controller sends between answers (status changes, tick ends, swaps)
//! into [`Event`]s, whichever request was waiting when they arrived.
//!
//! A controller reports each status change of a tick as it happens and then the tick's
//! end; a swap reports the old tree's halts, then the swap. [`Stream`] gathers them into
//! one event per tick or swap, sans I/O: it is fed replies, wherever they were read.

use std::collections::VecDeque;
use std::io::{Read, Write};
use std::time::Instant;

use bt_core::NodeStatus;
use bt_link::host::{Client, ControllerInfo, LinkError, State, Verdict};
use bt_link::{FrameFault, ImageInfo, Reply, WireStatus};

/// A status change: the node (pre-order index) and its new status.
pub type Change = (u16, NodeStatus);

/// What the controller did, as the host sees it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Event {
    /// Tick `tick` ended: its status changes, in the order they happened, and what the
    /// root returned (`Idle`: the tick ended in an error; `Skipped`: the root skipped).
    Tick {
        /// The tick.
        tick: u32,
        /// What the root returned.
        root: WireStatus,
        /// The tick's status changes.
        changes: Vec<Change>,
        /// How long the tick took on the controller, µs.
        micros: u32,
    },
    /// Before tick `tick` a new tree replaced the running one, after the old tree's
    /// running actions were halted (`changes`, back to Idle).
    Swapped {
        /// The new tree's first tick.
        tick: u32,
        /// The new image.
        image: ImageInfo,
        /// Actions of the old tree halted.
        halted: u16,
        /// The old tree's changes at the swap.
        changes: Vec<Change>,
    },
    /// A `Stop` halted the running actions before tick `tick`.
    Stopped {
        /// The tick the controller stopped before.
        tick: u32,
        /// The changes of the halts.
        changes: Vec<Change>,
    },
    /// The controller skipped a frame it could not read.
    Garbled(FrameFault),
    /// The controller dropped `frames` replies (status changes, mostly) during or before
    /// tick `tick` because its transmit queue was full: the statuses shown may be stale
    /// until the nodes change again.
    Lost {
        /// The tick.
        tick: u32,
        /// How many frames.
        frames: u16,
    },
}

/// Gathers the controller's replies into [`Event`]s (sans I/O).
#[derive(Debug, Default)]
pub struct Stream {
    /// Changes of the tick (or swap) under way, and the tick they are numbered with.
    pending: Vec<Change>,
    pending_tick: u32,
    events: VecDeque<Event>,
}

impl Stream {
    /// An empty stream.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Takes one reply; answers to requests (acks, verdicts, states) are not events.
    pub fn feed(&mut self, reply: &Reply<'_>) {
        match *reply {
            Reply::Status { tick, node, status } => {
                self.pending_tick = tick;
                self.pending.push((node, NodeStatus::from(status)));
            }
            Reply::Tick { tick, status, micros, .. } => {
                let changes = self.take(tick);
                self.events.push_back(Event::Tick { tick, root: status, changes, micros });
            }
            Reply::Swapped { tick, image, halted } => {
                let changes = self.take(tick);
                self.events.push_back(Event::Swapped { tick, image, halted, changes });
            }
            Reply::Garbled { fault } => self.events.push_back(Event::Garbled(fault)),
            Reply::Lost { tick, frames } => self.events.push_back(Event::Lost { tick, frames }),
            _ => {}
        }
    }

    /// The changes gathered for `tick` (changes numbered with another tick belong to no
    /// event the controller finished: they are dropped).
    fn take(&mut self, tick: u32) -> Vec<Change> {
        let changes = std::mem::take(&mut self.pending);
        if self.pending_tick == tick { changes } else { Vec::new() }
    }

    /// Ends a `Stop`: the halts it reported, as an event.
    fn stopped(&mut self, tick: u32) {
        let changes = self.take(tick);
        self.events.push_back(Event::Stopped { tick, changes });
    }

    /// The oldest event not taken yet.
    pub fn pop(&mut self) -> Option<Event> {
        self.events.pop_front()
    }
}

/// A link to a controller and the events read on it.
#[derive(Debug)]
pub struct Session<T> {
    client: Client<T>,
    stream: Stream,
}

impl<T: Read + Write> Session<T> {
    /// A session over a client whose link reads time out.
    pub fn new(client: Client<T>) -> Self {
        Self { client, stream: Stream::new() }
    }

    /// The client (its byte counters, raw writes).
    pub fn client(&mut self) -> &mut Client<T> {
        &mut self.client
    }

    /// Bytes sent and received so far.
    #[must_use]
    pub fn bytes(&self) -> (u64, u64) {
        (self.client.sent, self.client.received)
    }

    /// `Hello`.
    ///
    /// # Errors
    /// As [`Client::hello`].
    pub fn hello(&mut self) -> Result<ControllerInfo, LinkError> {
        self.client.hello()
    }

    /// Sends `image` to swap in before tick `swap_at` (the next boundary when `None`)
    /// and waits for the verdict.
    ///
    /// # Errors
    /// As [`Client::deploy`].
    pub fn deploy(&mut self, image: &[u8], swap_at: Option<u32>) -> Result<Verdict, LinkError> {
        let Self { client, stream } = self;
        client.deploy(image, swap_at, &mut |r| stream.feed(r))
    }

    /// Ticks every `period_ms` up to, not including, tick `until`; returns the next
    /// tick the controller runs.
    ///
    /// # Errors
    /// As [`Client::start`].
    pub fn start(&mut self, until: Option<u32>, period_ms: u16) -> Result<u32, LinkError> {
        let Self { client, stream } = self;
        client.start(until, period_ms, &mut |r| stream.feed(r))
    }

    /// Stops ticking, halting the running actions (an [`Event::Stopped`]).
    ///
    /// # Errors
    /// As [`Client::stop`].
    pub fn stop(&mut self) -> Result<State, LinkError> {
        let Self { client, stream } = self;
        let state = client.stop(&mut |r| stream.feed(r))?;
        stream.stopped(state.tick);
        Ok(state)
    }

    /// The controller's state.
    ///
    /// # Errors
    /// As [`Client::ping`].
    pub fn ping(&mut self, token: u32) -> Result<State, LinkError> {
        let Self { client, stream } = self;
        client.ping(token, &mut |r| stream.feed(r))
    }

    /// The running image's bytes.
    ///
    /// # Errors
    /// As [`Client::read_image`].
    pub fn read_image(&mut self) -> Result<Vec<u8>, LinkError> {
        let Self { client, stream } = self;
        client.read_image(&mut |r| stream.feed(r))
    }

    /// The next event, read from the link if none is waiting, by `deadline`.
    ///
    /// # Errors
    /// [`LinkError::Timeout`] at the deadline, [`LinkError::Closed`], a link error.
    pub fn next(&mut self, deadline: Instant) -> Result<Event, LinkError> {
        loop {
            if let Some(e) = self.stream.pop() {
                return Ok(e);
            }
            let reply = self.client.next(deadline, "a status report")?;
            self.stream.feed(&reply);
        }
    }

    /// The next event if one is waiting, without reading the link.
    pub fn pending(&mut self) -> Option<Event> {
        self.stream.pop()
    }

    /// Whether events are waiting (read while a request waited for its answer): the
    /// reader is behind the controller.
    #[must_use]
    pub fn behind(&self) -> bool {
        !self.stream.events.is_empty()
    }
}

/// Applies `changes` to a tree's statuses (a change for a node the tree does not have
/// is ignored).
pub fn apply(statuses: &mut [NodeStatus], changes: &[Change]) {
    for &(node, status) in changes {
        if let Some(s) = statuses.get_mut(usize::from(node)) {
            *s = status;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn status(tick: u32, node: u16, status: WireStatus) -> Reply<'static> {
        Reply::Status { tick, node, status }
    }

    #[test]
    fn a_tick_gathers_its_changes_and_a_swap_the_halts_before_it() {
        let mut s = Stream::new();
        let image = ImageInfo { crc: 7, len: 30, nodes: 3 };
        for r in [
            status(4, 0, WireStatus::Running),
            status(4, 2, WireStatus::Running),
            Reply::Tick { tick: 4, status: WireStatus::Running, changes: 2, micros: 9 },
            Reply::ChunkAck { id: 1, received: 64 },
            status(5, 2, WireStatus::Idle),
            Reply::Swapped { tick: 5, image, halted: 1 },
            Reply::Garbled { fault: FrameFault::Crc },
            Reply::Lost { tick: 6, frames: 3 },
        ] {
            s.feed(&r);
        }
        let running = [(0, NodeStatus::Running), (2, NodeStatus::Running)];
        assert_eq!(
            s.pop(),
            Some(Event::Tick { tick: 4, root: WireStatus::Running, changes: running.to_vec(), micros: 9 })
        );
        assert_eq!(s.pop(), Some(Event::Swapped { tick: 5, image, halted: 1, changes: vec![(2, NodeStatus::Idle)] }));
        assert_eq!(s.pop(), Some(Event::Garbled(FrameFault::Crc)));
        assert_eq!(s.pop(), Some(Event::Lost { tick: 6, frames: 3 }));
        assert_eq!(s.pop(), None);
        let mut statuses = [NodeStatus::Idle; 3];
        apply(&mut statuses, &running);
        apply(&mut statuses, &[(9, NodeStatus::Failure)]);
        assert_eq!(statuses, [NodeStatus::Running, NodeStatus::Idle, NodeStatus::Running]);
    }
}
