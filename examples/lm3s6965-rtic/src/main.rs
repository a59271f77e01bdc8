//! The link controller of `firmware-example` (the same plant, behavior set and trace)
//! written the way a user writes the controller of their own board: an RTIC v2
//! application on the TI LM3S6965 (Cortex-M3, QEMU's `lm3s6965evb`).
//!
//! - UART0's receive interrupt moves bytes into a lock-free queue (`heapless::spsc`);
//! - the idle loop feeds them to bt-link's sans-IO [`Controller`], polls it with the
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

mod uart;

use bt_link::{Clock, Controller};
use firmware_example::catalog::BEHAVIORS;
use firmware_example::link::{DEPTH, IMAGE_BYTES, LinkStorage, Plant, VALUES};
use firmware_example::target::{Semihosting, stack_usage};
use firmware_example::{IMAGE, MAX_NODES};
use rtic_monotonics::systick::prelude::*;

// SysTick as the monotonic timer, at 1 kHz: the tick schedule's resolution, and the
// interrupt that wakes the idle loop to look at it.
systick_monotonic!(Mono, 1_000);

/// Bytes the receive queue holds: the host's window of four chunks with their framing.
const RX: usize = 512;
/// The controller's transmit queue.
const TX: usize = 512;

/// The controller, over the storage of two trees.
type Link<'s> = Controller<'s, [bt_core::BehaviorInfo<'static>; 11], MAX_NODES, IMAGE_BYTES, VALUES, DEPTH, TX>;

/// The monotonic's time in microseconds, and the stack's high-water mark.
struct Time;

impl Clock for Time {
    fn micros(&mut self) -> u32 {
        Mono::now().ticks().wrapping_mul(1_000)
    }

    fn stack_used(&mut self) -> u32 {
        stack_usage().used
    }
}

#[rtic::app(device = lm3s6965)]
mod app {
    use heapless::spsc::{Consumer, Producer, Queue};

    use super::*;

    #[shared]
    struct Shared {}

    #[local]
    struct Local {
        received: Producer<'static, u8>,
        incoming: Consumer<'static, u8>,
        storage: &'static mut LinkStorage,
    }

    #[init(local = [queue: Queue<u8, RX> = Queue::new(), trees: LinkStorage = LinkStorage::new()])]
    fn init(cx: init::Context) -> (Shared, Local) {
        Mono::start(cx.core.SYST, 12_000_000);
        uart::init();
        let (received, incoming) = cx.local.queue.split();
        (Shared {}, Local { received, incoming, storage: cx.local.trees })
    }

    /// A byte arrived: into the queue (a full queue drops it; the host resends).
    #[task(binds = UART0, priority = 2, local = [received])]
    fn uart0(cx: uart0::Context) {
        while let Some(b) = uart::receive() {
            let _ = cx.local.received.enqueue(b);
        }
        uart::clear();
    }

    /// The link and the tree, at the lowest priority: feed, poll, send, and sleep
    /// (`wfi`) until an interrupt (a byte, the monotonic's millisecond) when there is
    /// nothing to do.
    #[idle(local = [incoming, storage])]
    fn idle(cx: idle::Context) -> ! {
        let mut trace = Semihosting::stdout();
        let mut plant = Plant::new(&mut trace);
        let mut link = Link::new(&mut **cx.local.storage, &BEHAVIORS);
        // A boot image that does not load leaves the controller waiting for a deployment.
        let _ = link.boot(IMAGE, &mut plant);
        let mut time = Time;
        loop {
            while link.wants_input() {
                let Some(b) = cx.local.incoming.dequeue() else { break };
                link.feed(&[b], &mut plant, &mut time);
            }
            link.poll(&mut plant, &mut time);
            let sent = uart::send(link.transmit());
            link.transmitted(sent);
            if link.transmit().is_empty() && !(cx.local.incoming.ready() && link.wants_input()) {
                cortex_m::asm::wfi();
            }
        }
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
