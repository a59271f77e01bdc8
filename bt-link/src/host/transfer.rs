//! A deployment, pipelined: the chunks go out a window ahead of the acknowledgements,
//! and what a faulty line loses is sent again.

use std::io::{Read, Write};

use super::{ANSWER_TIMEOUT, CHUNK_TRIES, Client, LinkError, Transfer, Verdict};
use crate::wire::{Fault, MAX_CHUNK, Reply, Request};

/// A reply, as it bears on the transfer under way.
enum Step {
    Ack(u32),
    Accepted(Verdict),
    Incomplete(u32),
    NoTransfer,
    Refused(Fault),
}

impl<T: Read + Write> Client<T> {
    /// [`Client::transfer`] without the resynchronization around it.
    pub(super) fn pipelined(
        &mut self,
        t: &Transfer<'_>,
        watch: &mut dyn FnMut(&Reply<'_>),
    ) -> Result<Verdict, LinkError> {
        self.transfer_id = self.transfer_id.wrapping_add(1);
        let id = self.transfer_id;
        let deploy = Request::Deploy { id, len: t.len, crc: t.crc, swap_at: t.swap_at };
        let total = t.bytes.len();
        let patience = ANSWER_TIMEOUT / 4;
        self.send(&deploy)?;
        // `opened`: the controller acknowledged our transfer (a `ChunkAck` naming it),
        // so it has our `Deploy`, and a refusal from then on is ours (one before it is
        // an earlier transfer's).
        let (mut opened, mut acked, mut next, mut committed) = (false, 0usize, 0usize, false);
        let mut rewound_at = None;
        let mut index = 0usize;
        let mut tries = 0;
        let mut deadline = self.now() + patience;
        let mut wire = [0u8; MAX_CHUNK];
        loop {
            while next < total && next - acked < self.window {
                let end = (next + MAX_CHUNK).min(total);
                let chunk = &mut wire[..end - next];
                chunk.copy_from_slice(&t.bytes[next..end]);
                if let Some(at) = t.flip.filter(|&at| (next..end).contains(&at)) {
                    chunk[at - next] ^= 1;
                }
                if let Some((_, garbage)) = t.garbage.filter(|&(i, _)| i == index) {
                    self.raw(garbage)?;
                }
                self.send(&Request::Chunk { offset: next as u32, bytes: chunk })?;
                index += 1;
                next = end;
            }
            // `Commit` only once the controller has our `Deploy`: before, it would be
            // answered with an earlier transfer's verdict.
            if opened && next >= total && !committed {
                self.send(&Request::Commit)?;
                committed = true;
            }
            let step = match self.next(deadline, "ChunkAck") {
                Ok(reply) => match reply {
                    // Acknowledgements and verdicts name their transfer: an earlier
                    // one's, still on the line, are not ours.
                    Reply::ChunkAck { id: of, received } if of == id => Some(Step::Ack(received)),
                    Reply::Accepted { id: of, crc, nodes, swap_at } if of == id => {
                        Some(Step::Accepted(Verdict::Accepted { crc, nodes, swap_at }))
                    }
                    Reply::ChunkAck { .. } | Reply::Accepted { .. } => None,
                    Reply::Rejected { fault: Fault::Incomplete { received, .. } } => Some(Step::Incomplete(received)),
                    Reply::Rejected { fault: Fault::NoTransfer } => Some(Step::NoTransfer),
                    Reply::Rejected { fault: Fault::Superseded { .. } } => None,
                    Reply::Rejected { fault } => Some(Step::Refused(fault)),
                    ref other => {
                        watch(other);
                        None
                    }
                },
                Err(LinkError::Timeout { .. }) => {
                    tries += 1;
                    if tries >= CHUNK_TRIES {
                        return Err(LinkError::Timeout { waiting_for: "ChunkAck", after: patience * CHUNK_TRIES });
                    }
                    // Ask again. The controller answers a repeated `Deploy` with where
                    // our transfer stands (or opens it, if the first never arrived), a
                    // repeated `Commit` with its verdict or `incomplete`: neither starts
                    // or swaps it twice.
                    if !opened {
                        self.send(&deploy)?;
                    } else if committed {
                        self.send(&Request::Commit)?;
                    } else {
                        next = acked;
                    }
                    rewound_at = None;
                    deadline = self.now() + patience;
                    continue;
                }
                Err(e) => return Err(e),
            };
            match step {
                None => {}
                Some(Step::Accepted(verdict)) => return Ok(verdict),
                Some(Step::Refused(fault)) if opened || matches!(fault, Fault::TooLarge { .. }) => {
                    return Ok(Verdict::Rejected(fault));
                }
                Some(Step::Ack(received)) => {
                    // The first is the answer to our `Deploy`, sent before any chunk
                    // arrived: not a sign of a gap.
                    let first = !opened;
                    opened = true;
                    let received = (received as usize).min(total);
                    if received > acked || first {
                        (acked, tries, rewound_at) = (acked.max(received), 0, None);
                        next = next.max(acked);
                        deadline = self.now() + patience;
                    } else if received == acked && next > acked && rewound_at != Some(acked) {
                        // A chunk past a gap: go back to the gap, once per gap.
                        (next, committed, rewound_at) = (acked, false, Some(acked));
                    }
                }
                Some(Step::Incomplete(received)) if opened => {
                    let received = (received as usize).min(total);
                    if received >= total {
                        // Everything there was to send arrived: the transfer is short.
                        return Ok(Verdict::Rejected(Fault::Incomplete { received: received as u32, len: t.len }));
                    }
                    (acked, next, committed) = (acked.max(received), received, false);
                }
                Some(Step::NoTransfer) if opened && !committed => {
                    // A chunk came after the controller closed our transfer: it had
                    // every byte and our `Commit`, whose verdict is on its way or was
                    // lost. Ask for it; sending chunks is over.
                    (acked, next) = (total, total);
                    self.send(&Request::Commit)?;
                    committed = true;
                    deadline = self.now() + patience;
                }
                Some(_) => {}
            }
        }
    }
}
