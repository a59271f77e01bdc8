//! Frames over a byte stream: a message's postcard bytes, then their CRC-32
//! (little-endian), COBS-encoded, then a `0x00` delimiter. COBS is the `cobs` crate
//! postcard itself uses for its COBS flavor; decoding feeds one byte at a time to its
//! streaming state machine into a fixed buffer, so a frame is checked the moment its
//! delimiter arrives, with no copy. (postcard's own CRC flavor needs the crc crate's
//! 1 KiB lookup table; the frames share bt-core's table-free CRC-32 instead.)

use serde::Serialize;

use crate::wire::{FrameFault, Reply};

/// Bytes of the CRC-32 at the end of every decoded frame.
pub const CRC_LEN: usize = 4;

/// Decoded bytes (message and CRC) the largest message of this protocol takes, with
/// room to spare: a `Chunk` or `Image` of [`MAX_CHUNK`](crate::MAX_CHUNK) bytes is 77.
pub const MAX_FRAME: usize = 96;

/// Most bytes an encoded frame of [`MAX_FRAME`] decoded bytes takes on the wire:
/// COBS adds one byte per 254 and the delimiter.
pub const MAX_ENCODED: usize = MAX_FRAME + MAX_FRAME / 254 + 2;

const CRC32: crc::Crc<u32, crc::NoTable> = crc::Crc::<u32, crc::NoTable>::new(&crc::CRC_32_ISO_HDLC);

/// The CRC-32 frames and images use (ISO-HDLC, as zlib's `crc32`).
#[must_use]
pub fn crc32(bytes: &[u8]) -> u32 {
    CRC32.checksum(bytes)
}

/// Encodes `msg` as one frame into `out` (delimiter included); returns the bytes to
/// send.
///
/// # Errors
/// [`FrameFault::TooLong`] when the message is longer than [`MAX_FRAME`] or `out` is
/// too small.
pub fn encode<'b, T: Serialize + ?Sized>(msg: &T, out: &'b mut [u8]) -> Result<&'b mut [u8], FrameFault> {
    let mut raw = [0u8; MAX_FRAME];
    let body = postcard::to_slice(msg, &mut raw).map_err(|_| FrameFault::TooLong)?.len();
    seal(&mut raw, body, out)
}

/// [`encode`] for the controller's replies, encoded without serde (`reply.rs` says
/// why); the same bytes.
///
/// # Errors
/// As [`encode`].
pub fn encode_reply<'b>(reply: &Reply<'_>, out: &'b mut [u8]) -> Result<&'b mut [u8], FrameFault> {
    let mut raw = [0u8; MAX_FRAME];
    let body = crate::reply::encode(reply, &mut raw).ok_or(FrameFault::TooLong)?;
    seal(&mut raw, body, out)
}

/// Appends the CRC of `raw`'s first `body` bytes, COBS-encodes them into `out` and
/// ends the frame.
fn seal<'b>(raw: &mut [u8; MAX_FRAME], body: usize, out: &'b mut [u8]) -> Result<&'b mut [u8], FrameFault> {
    let crc = crc32(raw.get(..body).unwrap_or(&[])).to_le_bytes();
    raw.get_mut(body..body + CRC_LEN).ok_or(FrameFault::TooLong)?.copy_from_slice(&crc);
    let decoded = raw.get(..body + CRC_LEN).ok_or(FrameFault::TooLong)?;
    let n = cobs::try_encode(decoded, out).map_err(|_| FrameFault::TooLong)?;
    *out.get_mut(n).ok_or(FrameFault::TooLong)? = 0;
    // `..n + 1`, not `..=n`: the inclusive range keeps an overflow check that links a
    // panic into the firmware.
    out.get_mut(..n + 1).ok_or(FrameFault::TooLong)
}

/// What one byte fed to a [`Decoder`] completed.
#[derive(Debug, PartialEq, Eq)]
pub enum Feed<'a> {
    /// Nothing yet.
    Pending,
    /// A frame whose CRC checked: the message bytes, without the CRC.
    Frame(&'a [u8]),
    /// A frame that ended and was dropped.
    Skipped(FrameFault),
}

/// Reassembles frames from a byte stream into a fixed buffer of `N` bytes.
///
/// Any byte sequence is accepted: a `0x00` always ends the frame under way, so the
/// decoder is back in step after at most one bad frame.
#[derive(Debug)]
pub struct Decoder<const N: usize> {
    buf: [u8; N],
    len: usize,
    state: cobs::DecoderState,
    /// The frame under way is longer than the buffer or is not valid COBS: drop it at
    /// its delimiter.
    dropping: Option<FrameFault>,
    /// Length of the message in the last frame returned, kept until the next byte.
    last: usize,
}

impl<const N: usize> Default for Decoder<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Decoder<N> {
    /// An empty decoder, between frames.
    #[must_use]
    pub const fn new() -> Self {
        Self { buf: [0; N], len: 0, state: cobs::DecoderState::Idle, dropping: None, last: 0 }
    }

    /// Takes one byte off the wire.
    pub fn feed(&mut self, byte: u8) -> Feed<'_> {
        self.last = 0;
        if let Some(fault) = self.dropping {
            if byte == 0 {
                self.restart();
                return Feed::Skipped(fault);
            }
            return Feed::Pending;
        }
        match self.state.feed(byte) {
            Ok(cobs::DecodeResult::NoData) => Feed::Pending,
            Ok(cobs::DecodeResult::DataContinue(b)) => {
                match self.buf.get_mut(self.len) {
                    Some(slot) => {
                        *slot = b;
                        self.len += 1;
                    }
                    None => self.dropping = Some(FrameFault::TooLong),
                }
                Feed::Pending
            }
            Ok(cobs::DecodeResult::DataComplete) => {
                let len = self.len;
                self.restart();
                self.check(len)
            }
            Err(_) => {
                // The state machine went back to idle on the zero that ended the run.
                self.restart();
                Feed::Skipped(FrameFault::Cobs)
            }
        }
    }

    fn restart(&mut self) {
        self.len = 0;
        self.state = cobs::DecoderState::Idle;
        self.dropping = None;
    }

    /// The CRC check of a complete frame of `len` decoded bytes.
    fn check(&mut self, len: usize) -> Feed<'_> {
        let Some(body_len) = len.checked_sub(CRC_LEN).filter(|&n| n > 0) else {
            return Feed::Skipped(FrameFault::TooShort);
        };
        let (Some(body), Some(tail)) = (self.buf.get(..body_len), self.buf.get(body_len..len)) else {
            return Feed::Skipped(FrameFault::TooLong);
        };
        let mut stored = [0u8; CRC_LEN];
        stored.copy_from_slice(tail);
        if u32::from_le_bytes(stored) != crc32(body) {
            return Feed::Skipped(FrameFault::Crc);
        }
        self.last = body_len;
        Feed::Frame(self.buf.get(..body_len).unwrap_or(&[]))
    }

    /// The message bytes of the frame the last [`feed`](Self::feed) returned as
    /// [`Feed::Frame`]; `None` after any other outcome.
    #[must_use]
    pub fn last_frame(&self) -> Option<&[u8]> {
        if self.last == 0 { None } else { self.buf.get(..self.last) }
    }
}

/// Decodes a message from a frame's bytes; trailing bytes are an error.
///
/// # Errors
/// [`FrameFault::Message`].
pub fn message<'a, T: serde::Deserialize<'a>>(bytes: &'a [u8]) -> Result<T, FrameFault> {
    match postcard::take_from_bytes::<T>(bytes) {
        Ok((msg, [])) => Ok(msg),
        _ => Err(FrameFault::Message),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::{Reply, Request};

    fn decode_all<const N: usize>(dec: &mut Decoder<N>, bytes: &[u8]) -> Vec<Result<Vec<u8>, FrameFault>> {
        let mut out = Vec::new();
        for &b in bytes {
            match dec.feed(b) {
                Feed::Pending => {}
                Feed::Frame(f) => out.push(Ok(f.to_vec())),
                Feed::Skipped(e) => out.push(Err(e)),
            }
        }
        out
    }

    #[test]
    fn a_frame_round_trips_and_ends_in_its_only_zero() {
        let msg = Request::Chunk { offset: 7, bytes: &[0, 1, 0, 0, 255, 0] };
        let mut buf = [0u8; MAX_ENCODED];
        let frame = encode(&msg, &mut buf).unwrap().to_vec();
        assert_eq!(frame.last(), Some(&0));
        assert!(!frame[..frame.len() - 1].contains(&0));
        let mut dec = Decoder::<MAX_FRAME>::new();
        let got = decode_all(&mut dec, &frame);
        assert_eq!(got.len(), 1);
        let body = got[0].clone().unwrap();
        assert_eq!(message::<Request<'_>>(&body), Ok(msg));
    }

    #[test]
    fn the_largest_messages_fit_the_buffers() {
        let bytes = [0xAAu8; crate::MAX_CHUNK];
        let mut buf = [0u8; MAX_ENCODED];
        let chunk = Request::Chunk { offset: u32::MAX, bytes: &bytes };
        let image = Reply::Image { offset: u32::MAX, total: u32::MAX, bytes: &bytes };
        let state = Reply::State {
            token: u32::MAX,
            tick: u32::MAX,
            ticking: true,
            until: Some(u32::MAX),
            running: Some(crate::ImageInfo { crc: u32::MAX, len: u32::MAX, nodes: u16::MAX }),
            halted: u16::MAX,
            stack_used: u32::MAX,
        };
        for len in [
            encode(&chunk, &mut buf).unwrap().len(),
            encode(&image, &mut buf).unwrap().len(),
            encode(&state, &mut buf).unwrap().len(),
        ] {
            assert!(len <= MAX_ENCODED, "{len}");
        }
    }

    #[test]
    fn a_flipped_bit_fails_the_crc_and_the_next_frame_still_decodes() {
        let mut buf = [0u8; MAX_ENCODED];
        let good = encode(&Request::Ping { token: 0x1234_5678 }, &mut buf).unwrap().to_vec();
        let mut bad = good.clone();
        bad[3] ^= 0x10;
        let mut dec = Decoder::<MAX_FRAME>::new();
        let got = decode_all(&mut dec, &[bad, good].concat());
        assert_eq!(got[0], Err(FrameFault::Crc));
        assert!(got[1].is_ok());
    }

    #[test]
    fn garbage_between_frames_is_skipped_with_a_reason() {
        let mut buf = [0u8; MAX_ENCODED];
        let good = encode(&Request::Stop, &mut buf).unwrap().to_vec();
        let mut dec = Decoder::<MAX_FRAME>::new();
        // A run that claims 5 bytes and ends after 2, then bytes without a valid CRC,
        // then more than the buffer holds.
        let mut stream = vec![0x05, 0x41, 0x42, 0x00, 0x03, 0x10, 0x20, 0x00];
        stream.extend(std::iter::repeat_n(0x07, 300));
        stream.push(0);
        stream.extend(&good);
        let got = decode_all(&mut dec, &stream);
        assert_eq!(got[0], Err(FrameFault::Cobs));
        assert_eq!(got[1], Err(FrameFault::TooShort));
        assert_eq!(got[2], Err(FrameFault::TooLong));
        assert_eq!(message::<Request<'_>>(got[3].as_ref().unwrap()), Ok(Request::Stop));
        assert_eq!(got.len(), 4);
    }

    #[test]
    fn extra_delimiters_are_ignored() {
        let mut buf = [0u8; MAX_ENCODED];
        let good = encode(&Request::Commit, &mut buf).unwrap().to_vec();
        let mut dec = Decoder::<MAX_FRAME>::new();
        let got = decode_all(&mut dec, &[&[0, 0, 0][..], &good, &[0, 0]].concat());
        assert_eq!(got.len(), 1);
        assert!(got[0].is_ok());
    }

    #[test]
    fn a_frame_of_another_message_kind_or_with_trailing_bytes_is_not_a_message() {
        // A valid frame whose bytes are an unknown tag, and one with a byte too many.
        for body in [&[200u8][..], &[5, 0][..]] {
            let mut framed = body.to_vec();
            framed.extend(crc32(body).to_le_bytes());
            let mut enc = vec![0u8; framed.len() + 2];
            let n = cobs::encode(&framed, &mut enc);
            enc.truncate(n);
            enc.push(0);
            let mut dec = Decoder::<MAX_FRAME>::new();
            let got = decode_all(&mut dec, &enc);
            let bytes = got[0].clone().unwrap();
            assert_eq!(message::<Request<'_>>(&bytes), Err(FrameFault::Message), "{body:?}");
        }
    }
}
