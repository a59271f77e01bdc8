//! What the RTIC programs of this board share: UART0, the monotonic clock, the panic
//! handler. `src/app.rs` is the application; `controller` (src/main.rs) builds it with
//! slots of 512 bytes, `controller-16k` (src/bin) with slots of 16 KiB, for timing a
//! deployment of a 16 KiB image.
#![no_std]

pub mod uart;

use bt_link::Clock;
use firmware_example::target::stack_usage;
use rtic_monotonics::systick::prelude::*;

// SysTick as the monotonic timer, at 1 kHz: the tick schedule's resolution, and the
// interrupt that wakes the idle loop to look at it.
systick_monotonic!(Mono, 1_000);

/// Bytes the receive queue holds: the host's window of four chunks with their framing
/// (about 330 bytes with its `Deploy` and `Commit`).
pub const RX: usize = 384;
/// The controller's transmit queue: a tick's status frames and a window's acks.
pub const TX: usize = 384;

/// The monotonic's time in microseconds, and the stack's high-water mark.
#[derive(Debug)]
pub struct Time;

impl Clock for Time {
    fn micros(&mut self) -> u32 {
        Mono::now().ticks().wrapping_mul(1_000)
    }

    fn stack_used(&mut self) -> u32 {
        stack_usage().used
    }
}

/// Nothing in this program panics (`cargo xtask qemu` checks the ELF for panic
/// symbols); should it all the same, stop.
#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    cortex_m_semihosting::debug::exit(cortex_m_semihosting::debug::EXIT_FAILURE);
    loop {
        cortex_m::asm::wfi();
    }
}
