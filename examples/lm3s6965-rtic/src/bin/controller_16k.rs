//! The RTIC program of `src/main.rs` with slots of 16 KiB: `cargo xtask qemu` times the
//! deployment of a 16 KiB image on it. Its statics take 35 KiB of the board's 64: the
//! 8 KiB RAM gate is `controller`'s.
#![no_std]
#![no_main]

use firmware_example::MAX_NODES;
use firmware_example::link::{DEPTH, VALUES};
use lm3s6965_rtic::TX;

/// Longest image a slot holds.
const IMAGE_BYTES: usize = 16 * 1024;

include!("../app.rs");
