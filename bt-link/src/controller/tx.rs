//! The controller's transmit queue: replies encoded as frames, waiting for the shell
//! to send them.

use bt_core::{BehaviorSet, NodeId, NodeStatus, Observer};

use crate::frame::{self, MAX_ENCODED};
use crate::wire::Reply;

/// Frames to send, in a fixed buffer of `N` bytes. A frame goes in whole or not at all;
/// one that does not fit is counted in [`Tx::lost`] (and reported to the host in the
/// next `Tick`).
#[derive(Debug)]
pub(super) struct Tx<const N: usize> {
    buf: [u8; N],
    start: usize,
    end: usize,
    /// Frames dropped for want of room since the last `Tick` reply.
    pub(super) lost: u16,
}

impl<const N: usize> Tx<N> {
    pub(super) const fn new() -> Self {
        Self { buf: [0; N], start: 0, end: 0, lost: 0 }
    }

    /// The bytes waiting to be sent, oldest first.
    pub(super) fn pending(&self) -> &[u8] {
        self.buf.get(self.start..self.end).unwrap_or(&[])
    }

    /// `n` of the [`pending`](Self::pending) bytes were sent.
    pub(super) fn consume(&mut self, n: usize) {
        self.start = self.start.saturating_add(n).min(self.end);
        if self.start == self.end {
            self.start = 0;
            self.end = 0;
        }
    }

    /// Bytes that can be queued.
    pub(super) fn free(&self) -> usize {
        N.saturating_sub(self.end.saturating_sub(self.start))
    }

    /// Queues `reply` as a frame if it fits with `reserve` bytes to spare; counts it
    /// lost otherwise.
    pub(super) fn push_reserving(&mut self, reply: &Reply<'_>, reserve: usize) {
        let mut buf = [0u8; MAX_ENCODED];
        // Every reply fits MAX_ENCODED (a unit test of `frame` holds the largest to it).
        let Ok(bytes) = frame::encode_reply(reply, &mut buf) else { return };
        let n = bytes.len();
        if self.free() < n.saturating_add(reserve) {
            self.lost = self.lost.saturating_add(1);
            return;
        }
        if N.saturating_sub(self.end) < n {
            // By hand: `copy_within` keeps a bounds check that links a panic.
            let live = self.end.saturating_sub(self.start);
            for i in 0..live {
                if let Some(b) = self.buf.get(self.start + i).copied()
                    && let Some(d) = self.buf.get_mut(i)
                {
                    *d = b;
                }
            }
            self.start = 0;
            self.end = live;
        }
        if let Some(dst) = self.buf.get_mut(self.end..self.end + n) {
            super::copy(dst, bytes);
            self.end += n;
        } else {
            self.lost = self.lost.saturating_add(1);
        }
    }

    /// Queues `reply` as a frame if it fits.
    pub(super) fn push(&mut self, reply: &Reply<'_>) {
        self.push_reserving(reply, 0);
    }
}

/// Queues every status change as a `Status` frame, keeping room for the reply that
/// ends the step (a `Tick`, `Swapped` or `State`).
pub(super) struct Reporter<'q, const N: usize> {
    pub(super) tx: &'q mut Tx<N>,
    pub(super) tick: u32,
    pub(super) changes: u16,
}

impl<const N: usize> Observer for Reporter<'_, N> {
    fn on_change(&mut self, node: NodeId, _old: NodeStatus, new: NodeStatus) {
        self.changes = self.changes.saturating_add(1);
        self.tx.push_reserving(&Reply::Status { tick: self.tick, node, status: new.into() }, MAX_ENCODED);
    }
}

/// Counts `halt` calls while passing everything on to the app.
pub(super) struct Halts<'a, A> {
    pub(super) app: &'a mut A,
    pub(super) count: u16,
}

impl<A: BehaviorSet> BehaviorSet for Halts<'_, A> {
    fn condition(&mut self, leaf: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> bt_core::Status {
        self.app.condition(leaf, ctx)
    }
    fn action(&mut self, leaf: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> bt_core::Status {
        self.app.action(leaf, ctx)
    }
    fn halt(&mut self, leaf: &bt_core::Leaf, node: NodeId) {
        self.count = self.count.saturating_add(1);
        self.app.halt(leaf, node);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_queue_whole_and_the_buffer_compacts() {
        let mut tx = Tx::<30>::new();
        let ping = Reply::ChunkAck { id: 1, received: 7 };
        tx.push(&ping);
        let one = tx.pending().len();
        assert_eq!(one, 13);
        tx.push(&ping);
        tx.push(&ping);
        assert_eq!(tx.pending().len(), 2 * one, "the third did not fit whole");
        assert_eq!(tx.lost, 1);
        tx.consume(one);
        tx.push(&ping);
        assert_eq!(tx.pending().len(), 2 * one, "room made at the front is used");
        tx.consume(usize::MAX);
        assert!(tx.pending().is_empty());
        assert_eq!(tx.free(), 30);
    }
}
