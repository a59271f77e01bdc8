//! The link controller of `firmware-example` (the same plant, behavior set and trace)
//! written the way a user writes the controller of their own board: an RTIC v2
//! application on the TI LM3S6965 (Cortex-M3, QEMU's `lm3s6965evb`).
//!
//! - UART0's receive interrupt moves bytes into a lock-free queue (`heapless::spsc`);
//! - the idle loop feeds them to bt-link's sans-IO `Controller`, polls it with the
//!   time of the SysTick monotonic (it ticks the tree when a tick is due), and hands
//!   what it queues to UART0's transmit FIFO; with nothing to do it waits in `wfi`
//!   for the next byte or the monotonic's next millisecond.
//!
//! The work runs in `idle` rather than an async task: the state machine of an `async
//! fn` keeps a "resumed after completion" panic, and this program links none.
//!
//! Nothing here blocks: a byte arriving while the tree ticks waits in the queue, a
//! status frame waits in the controller's transmit queue.
#![no_std]
#![no_main]

use firmware_example::MAX_NODES;
use firmware_example::link::{DEPTH, VALUES};
use lm3s6965_rtic::TX;

/// Longest image a slot holds: the planner's trees for this behavior set take 4-5 bytes
/// a node, 320 bytes for the 64 nodes a slot has.
const IMAGE_BYTES: usize = 512;

include!("app.rs");
