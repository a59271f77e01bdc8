//! The controller's replies encoded by hand, byte for byte as postcard encodes them
//! (a test holds every variant to it). postcard writes an enum's tag and a slice's
//! length as varints through a loop whose bounds check the compiler keeps at
//! `opt-level = "z"` on some targets (a Cortex-M3 build linked `panic_bounds_check`
//! for it); every tag and length here is below 128, a single byte.

use crate::wire::{Fault, FrameFault, ImageInfo, Reply, WireStatus};

/// Writes bytes into a fixed buffer, remembering whether they all fit.
struct Out<'b> {
    buf: &'b mut [u8],
    len: usize,
    fits: bool,
}

impl Out<'_> {
    fn byte(&mut self, b: u8) {
        match self.buf.get_mut(self.len) {
            Some(slot) => {
                *slot = b;
                self.len += 1;
            }
            None => self.fits = false,
        }
    }

    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.byte(b);
        }
    }

    fn u16(&mut self, v: u16) {
        self.bytes(&v.to_le_bytes());
    }

    fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }

    fn option_u32(&mut self, v: Option<u32>) {
        match v {
            Some(v) => {
                self.byte(1);
                self.u32(v);
            }
            None => self.byte(0),
        }
    }

    fn image(&mut self, info: ImageInfo) {
        self.u32(info.crc);
        self.u32(info.len);
        self.u16(info.nodes);
    }

    fn status(&mut self, s: WireStatus) {
        self.byte(s as u8);
    }

    /// A byte slice: its length as a varint, then the bytes.
    fn slice(&mut self, bytes: &[u8]) {
        let mut n = bytes.len();
        while n >= 0x80 {
            self.byte((n as u8) | 0x80);
            n >>= 7;
        }
        self.byte(n as u8);
        self.bytes(bytes);
    }

    fn fault(&mut self, f: Fault) {
        match f {
            Fault::Load { code, node } => {
                self.byte(0);
                self.byte(code);
                match node {
                    Some(n) => {
                        self.byte(1);
                        self.u16(n);
                    }
                    None => self.byte(0),
                }
            }
            Fault::TooLarge { len, capacity } => {
                self.byte(1);
                self.u32(len);
                self.u32(capacity);
            }
            Fault::Incomplete { received, len } => {
                self.byte(2);
                self.u32(received);
                self.u32(len);
            }
            Fault::TransferCrc { expected, computed } => {
                self.byte(3);
                self.u32(expected);
                self.u32(computed);
            }
            Fault::Overrun { offset, len } => {
                self.byte(4);
                self.u32(offset);
                self.u32(len);
            }
            Fault::NoTransfer => self.byte(5),
            Fault::Superseded { crc } => {
                self.byte(6);
                self.u32(crc);
            }
            Fault::NoTree => self.byte(7),
        }
    }
}

/// Writes `reply`'s postcard bytes into `buf`; returns their length, or `None` when
/// `buf` is too small.
pub(crate) fn encode(reply: &Reply<'_>, buf: &mut [u8]) -> Option<usize> {
    let mut o = Out { buf, len: 0, fits: true };
    match *reply {
        Reply::Hello { version, fingerprint, node_capacity, image_capacity, running } => {
            o.byte(0);
            o.u16(version);
            o.bytes(&fingerprint.to_le_bytes());
            o.u16(node_capacity);
            o.u32(image_capacity);
            match running {
                Some(i) => {
                    o.byte(1);
                    o.image(i);
                }
                None => o.byte(0),
            }
        }
        Reply::ChunkAck { id, received } => {
            o.byte(1);
            o.u16(id);
            o.u32(received);
        }
        Reply::Accepted { id, crc, nodes, swap_at } => {
            o.byte(2);
            o.u16(id);
            o.u32(crc);
            o.u16(nodes);
            o.option_u32(swap_at);
        }
        Reply::Rejected { fault } => {
            o.byte(3);
            o.fault(fault);
        }
        Reply::Swapped { tick, image, halted } => {
            o.byte(4);
            o.u32(tick);
            o.image(image);
            o.u16(halted);
        }
        Reply::Status { tick, node, status } => {
            o.byte(5);
            o.u32(tick);
            o.u16(node);
            o.status(status);
        }
        Reply::Tick { tick, status, changes, micros } => {
            o.byte(6);
            o.u32(tick);
            o.status(status);
            o.u16(changes);
            o.u32(micros);
        }
        Reply::State { token, tick, ticking, until, running, halted, stack_used } => {
            o.byte(7);
            o.u32(token);
            o.u32(tick);
            o.byte(u8::from(ticking));
            o.option_u32(until);
            match running {
                Some(i) => {
                    o.byte(1);
                    o.image(i);
                }
                None => o.byte(0),
            }
            o.u16(halted);
            o.u32(stack_used);
        }
        Reply::Image { offset, total, bytes } => {
            o.byte(8);
            o.u32(offset);
            o.u32(total);
            o.slice(bytes);
        }
        Reply::Garbled { fault } => {
            o.byte(9);
            o.byte(match fault {
                FrameFault::Cobs => 0,
                FrameFault::TooLong => 1,
                FrameFault::TooShort => 2,
                FrameFault::Crc => 3,
                FrameFault::Message => 4,
            });
        }
        Reply::Lost { tick, frames } => {
            o.byte(10);
            o.u32(tick);
            o.u16(frames);
        }
    }
    o.fits.then_some(o.len)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn same_as_postcard(reply: &Reply<'_>) {
        let mut ours = [0u8; 200];
        let n = encode(reply, &mut ours).expect("fits");
        let mut buf = [0u8; 200];
        let theirs = postcard::to_slice(reply, &mut buf).unwrap();
        assert_eq!(&ours[..n], &theirs[..], "{reply:?}");
    }

    fn image() -> impl Strategy<Value = ImageInfo> {
        (any::<u32>(), any::<u32>(), any::<u16>()).prop_map(|(crc, len, nodes)| ImageInfo { crc, len, nodes })
    }

    fn status() -> impl Strategy<Value = WireStatus> {
        prop_oneof![
            Just(WireStatus::Idle),
            Just(WireStatus::Success),
            Just(WireStatus::Failure),
            Just(WireStatus::Running),
            Just(WireStatus::Skipped)
        ]
    }

    fn fault() -> impl Strategy<Value = Fault> {
        prop_oneof![
            (any::<u8>(), any::<Option<u16>>()).prop_map(|(code, node)| Fault::Load { code, node }),
            (any::<u32>(), any::<u32>()).prop_map(|(len, capacity)| Fault::TooLarge { len, capacity }),
            (any::<u32>(), any::<u32>()).prop_map(|(received, len)| Fault::Incomplete { received, len }),
            (any::<u32>(), any::<u32>()).prop_map(|(expected, computed)| Fault::TransferCrc { expected, computed }),
            (any::<u32>(), any::<u32>()).prop_map(|(offset, len)| Fault::Overrun { offset, len }),
            Just(Fault::NoTransfer),
            any::<u32>().prop_map(|crc| Fault::Superseded { crc }),
            Just(Fault::NoTree),
        ]
    }

    proptest! {
        #[test]
        fn every_reply_encodes_as_postcard_does(
            a in any::<u32>(), b in any::<u32>(), c in any::<u16>(), d in any::<u64>(),
            opt in any::<Option<u32>>(), flag in any::<bool>(), img in image(), run in proptest::option::of(image()),
            st in status(), f in fault(), bytes in proptest::collection::vec(any::<u8>(), 0..=64),
        ) {
            let frame_faults =
                [FrameFault::Cobs, FrameFault::TooLong, FrameFault::TooShort, FrameFault::Crc, FrameFault::Message];
            for reply in [
                Reply::Hello { version: c, fingerprint: d, node_capacity: c, image_capacity: a, running: run },
                Reply::ChunkAck { id: c, received: a },
                Reply::Accepted { id: c, crc: a, nodes: c, swap_at: opt },
                Reply::Rejected { fault: f },
                Reply::Swapped { tick: a, image: img, halted: c },
                Reply::Status { tick: a, node: c, status: st },
                Reply::Tick { tick: a, status: st, changes: c, micros: b },
                Reply::State { token: a, tick: b, ticking: flag, until: opt, running: run, halted: c, stack_used: b },
                Reply::Image { offset: a, total: b, bytes: &bytes },
                Reply::Garbled { fault: frame_faults[(a % 5) as usize] },
                Reply::Lost { tick: a, frames: c },
            ] {
                same_as_postcard(&reply);
            }
        }
    }

    #[test]
    fn a_buffer_too_small_is_refused() {
        let mut buf = [0u8; 3];
        assert_eq!(encode(&Reply::ChunkAck { id: 1, received: 1 }, &mut buf), None);
        assert_eq!(encode(&Reply::Garbled { fault: FrameFault::Crc }, &mut buf), Some(2));
    }
}
