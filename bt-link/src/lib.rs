//! The link between a host and a controller running behavior trees: deploy a new tree
//! while the old one ticks, swap it in only if it is valid and only between ticks, and
//! watch every status change live.
//!
//! - [`wire`]: the messages both ways ([`Request`], [`Reply`]), postcard-encoded;
//! - [`frame`]: COBS framing with a CRC-32 per frame, and a streaming [`Decoder`];
//! - [`controller`]: `#![no_std]`, no allocation, no panics: the [`Controller`], fed
//!   with received bytes and the time, ticks and swaps trees in fixed [`Storage`] and
//!   hands out the bytes to send; [`serve`] is a blocking loop over it for a polled
//!   [`Board`], and `io` (features `embedded-io`, `embedded-io-async`) runs it over a
//!   HAL's UART, blocking or as an async task;
//! - `host` (feature `std`): a blocking [`Client`](host::Client) over any
//!   `Read + Write` (a serial port, a TCP socket to QEMU).
//!
//! The bytes on the wire are specified in `spec/link-protocol.md`, next to this crate's
//! `Cargo.toml`.
//!
//! A separate crate rather than a feature of `bt-core`: the link brings framing, a wire
//! format and a session state machine that a controller without a link never needs,
//! and a host build needs std for its client; `bt-core` stays the executor and the
//! image, with nothing behind features.
#![cfg_attr(not(any(test, feature = "std")), no_std)]
#![forbid(unsafe_code)]
#![deny(missing_docs)]
#![cfg_attr(not(test), deny(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing))]

pub mod controller;
pub mod frame;
#[cfg(feature = "std")]
pub mod host;
#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
pub mod io;
mod reply;
pub mod wire;

pub use controller::{App, Board, Clock, Controller, SERVE_TX, Storage, serve};
pub use frame::{Decoder, Feed};
pub use wire::{Fault, FrameFault, ImageInfo, LOAD_CODES, MAX_CHUNK, PROTOCOL_VERSION, Reply, Request, WireStatus};

/// The CRC-32 an image stores in its last four bytes: what names an image on the link
/// ([`ImageInfo::crc`]). (The CRC-32 over *all* of a valid image's bytes is the same
/// for every image, 0x2144df1c, the CRC's residue: useless as a name.)
#[must_use]
pub fn image_crc(image: &[u8]) -> u32 {
    let mut b = [0u8; 4];
    if let Some(tail) = image.len().checked_sub(4).and_then(|at| image.get(at..)) {
        b.copy_from_slice(tail);
    }
    u32::from_le_bytes(b)
}
