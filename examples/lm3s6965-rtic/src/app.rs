// The RTIC application, included by each program after it defines `IMAGE_BYTES`.

/// The two slots and the running tree's state.
type LinkStorage = bt_link::Storage<MAX_NODES, IMAGE_BYTES, VALUES>;

/// The controller, over the storage of two trees.
type Link<'s> = bt_link::Controller<'s, [bt_core::BehaviorInfo<'static>; 11], MAX_NODES, IMAGE_BYTES, VALUES, DEPTH, TX>;

#[rtic::app(device = lm3s6965)]
mod app {
    use firmware_example::catalog::BEHAVIORS;
    use firmware_example::link::Plant;
    use firmware_example::target::Semihosting;
    use firmware_example::IMAGE;
    use heapless::spsc::{Consumer, Producer, Queue};
    use lm3s6965_rtic::{Mono, RX, Time, uart};

    use super::{Link, LinkStorage};

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

