//! The [`Controller`] over a UART that implements the `embedded-io` traits (feature
//! `embedded-io`) or the `embedded-io-async` ones (feature `embedded-io-async`): what
//! embassy's, the RP2040's and the ESP HALs' UARTs and USB CDC-ACM classes implement. A
//! board with such a UART writes no glue.
//!
//! Both read only the bytes that are ready (`ReadReady`), so that a quiet line never
//! holds up a tick: the blocking [`step`] returns at once when nothing is waiting, and
//! [`run_async`] sleeps on the caller's timer between rounds, at most
//! [`MAX_SLEEP_US`], so a byte waits at most that long before it is read.

use crate::controller::{App, Clock, Controller};
use bt_core::Catalog;

/// Longest [`run_async`] sleeps between rounds, in microseconds: at 115200 baud about
/// 11 bytes arrive meanwhile, well within a UART's FIFO or a HAL's receive buffer.
pub const MAX_SLEEP_US: u32 = 1_000;

/// Shortest [`run_async`] sleeps while bytes wait to be sent or taken, in microseconds.
pub const MIN_SLEEP_US: u32 = 50;

/// One round of the link over a blocking UART: every byte that is ready (while the
/// controller takes input), a poll (a due swap or tick), and what the transmit queue
/// holds, as far as the UART takes it. Returns the microseconds until the next tick is
/// due, `None` when not ticking: a superloop calls it again after at most that long.
///
/// # Errors
/// The UART's read or write error (the controller is unharmed and can go on).
#[cfg(feature = "embedded-io")]
pub fn step<
    U,
    C,
    A,
    K,
    const NODES: usize,
    const BYTES: usize,
    const VALUES: usize,
    const DEPTH: usize,
    const TX: usize,
>(
    controller: &mut Controller<'_, C, NODES, BYTES, VALUES, DEPTH, TX>,
    uart: &mut U,
    app: &mut A,
    clock: &mut K,
) -> Result<Option<u32>, U::Error>
where
    U: embedded_io::Read + embedded_io::ReadReady + embedded_io::Write,
    C: Catalog + ?Sized,
    A: App,
    K: Clock,
{
    let mut byte = [0u8; 1];
    while controller.wants_input() && uart.read_ready()? {
        if uart.read(&mut byte)? == 1 {
            controller.feed(&byte, app, clock);
        }
    }
    let next = controller.poll(app, clock);
    let pending = controller.transmit();
    if !pending.is_empty() {
        let n = uart.write(pending)?;
        controller.transmitted(n);
    }
    Ok(next)
}

/// The link over an async UART, for ever: an `async fn` to spawn as an embassy or RTIC
/// task. Each round reads the bytes that are ready, polls the controller, writes what
/// it queued, and sleeps on `delay` until the next tick is due (at most
/// [`MAX_SLEEP_US`]).
///
/// # Errors
/// The UART's read or write error: the controller is unharmed, and the caller may call
/// this again.
#[cfg(feature = "embedded-io-async")]
pub async fn run_async<
    U,
    D,
    C,
    A,
    K,
    const NODES: usize,
    const BYTES: usize,
    const VALUES: usize,
    const DEPTH: usize,
    const TX: usize,
>(
    controller: &mut Controller<'_, C, NODES, BYTES, VALUES, DEPTH, TX>,
    uart: &mut U,
    delay: &mut D,
    app: &mut A,
    clock: &mut K,
) -> Result<core::convert::Infallible, U::Error>
where
    U: embedded_io_async::Read + embedded_io_async::ReadReady + embedded_io_async::Write,
    D: embedded_hal_async::delay::DelayNs,
    C: Catalog + ?Sized,
    A: App,
    K: Clock,
{
    let mut byte = [0u8; 1];
    loop {
        while controller.wants_input() && uart.read_ready()? {
            if uart.read(&mut byte).await? == 1 {
                controller.feed(&byte, app, clock);
            }
        }
        let next = controller.poll(app, clock);
        let pending = controller.transmit();
        if !pending.is_empty() {
            let n = uart.write(pending).await?;
            controller.transmitted(n);
        }
        let busy = !controller.transmit().is_empty();
        let sleep = if busy { MIN_SLEEP_US } else { next.unwrap_or(MAX_SLEEP_US).clamp(MIN_SLEEP_US, MAX_SLEEP_US) };
        delay.delay_us(sleep).await;
    }
}
