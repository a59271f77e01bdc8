//! A deployment, pipelined: the chunks go out a window ahead of the acknowledgements,
//! and what a faulty line loses is sent again.

use std::io::{Read, Write};

use super::{ANSWER_TIMEOUT, CHUNK_TRIES, Client, LinkError, Transfer, Verdict};
use crate::wire::{Fault, MAX_CHUNK, Reply, Request};

impl<T: Read + Write> Client<T> {
    /// [`Client::transfer`] without the resynchronization around it.
    pub(super) fn pipelined(
        &mut self,
        t: &Transfer<'_>,
        watch: &mut dyn FnMut(&Reply<'_>),
    ) -> Result<Verdict, LinkError> {
        enum Step {
            Ack(u32),
            Accepted(Verdict),
            Incomplete(u32),
            NoTransfer,
            Refused(Fault),
        }
        let deploy = Request::Deploy { len: t.len, crc: t.crc, swap_at: t.swap_at };
        let ours = (t.bytes.len() == t.len as usize).then(|| crate::image_crc(t.bytes));
        let total = t.bytes.len();
        let patience = ANSWER_TIMEOUT / 4;
        self.send(&deploy)?;
        // `opened`: the controller acknowledged our `Deploy` (its `ChunkAck{0}`); acks
        // and refusals before it belong to an earlier transfer.
        let (mut opened, mut acked, mut next, mut committed) = (false, 0usize, 0usize, false);
        let mut rewound_at = None;
        // A `Commit` sent to learn whether a transfer the controller no longer has
        // went through.
        let mut probing = false;
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
            // `Commit` only once the controller has our `Deploy`: a commit that reached
            // it without (our `Deploy` lost, an earlier transfer's ack taken for ours)
            // could not swap in anything but an image it already holds.
            if opened && next >= total && !committed {
                self.send(&Request::Commit)?;
                committed = true;
            }
            let step = match self.next(deadline, "ChunkAck") {
                Ok(reply) => match reply {
                    Reply::ChunkAck { received } => Some(Step::Ack(received)),
                    Reply::Accepted { crc, nodes, swap_at } if ours.is_none_or(|c| c == crc) => {
                        Some(Step::Accepted(Verdict::Accepted { crc, nodes, swap_at }))
                    }
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
                    if probing {
                        // No verdict to the probe: the controller never had our `Deploy`.
                        self.send(&deploy)?;
                        (opened, acked, next, committed, rewound_at, probing) = (false, 0, 0, false, None, false);
                    } else if committed {
                        // The verdict was lost, or the commit: ask again (a controller
                        // answers a repeated `Commit` as the first, and says `incomplete`
                        // if chunks are missing).
                        self.send(&Request::Commit)?;
                    } else if opened {
                        // Resend what is not acknowledged.
                        next = acked;
                    } else {
                        self.send(&deploy)?;
                    }
                    deadline = self.now() + patience;
                    continue;
                }
                Err(e) => return Err(e),
            };
            match step {
                None => {}
                Some(Step::Accepted(verdict)) if opened => return Ok(verdict),
                Some(Step::Refused(fault)) if opened || matches!(fault, Fault::TooLarge { .. }) => {
                    return Ok(Verdict::Rejected(fault));
                }
                Some(Step::Ack(0)) if !opened => {
                    opened = true;
                    deadline = self.now() + patience;
                }
                Some(Step::Ack(received)) if opened => {
                    let received = (received as usize).min(total);
                    if received > acked {
                        (acked, tries, rewound_at) = (received, 0, None);
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
                    (acked, next, committed, probing) = (acked.max(received), received, false, false);
                }
                Some(Step::NoTransfer) if opened && !probing => {
                    // The controller has no transfer open: our commit went through and
                    // its verdict was lost, or our `Deploy` never arrived (the ack taken
                    // for it was an earlier one's). A repeated `Commit` tells: the
                    // verdict again, or nothing (then a timeout starts again).
                    self.send(&Request::Commit)?;
                    probing = true;
                    deadline = self.now() + patience;
                }
                Some(_) => {}
            }
        }
    }
}
