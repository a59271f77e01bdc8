//! The sans-IO controller on arbitrary input: `Controller::feed` with arbitrary bytes in
//! arbitrary pieces, `poll` at arbitrary times, and the transmit queue drained by
//! arbitrary amounts (a slow line). It must never panic, and every byte it queues must
//! be a frame the host decodes.
#![no_main]

#[path = "common.rs"]
mod common;

use bt_link::frame::{self, Decoder, Feed};
use bt_link::{Clock, Controller, Reply, Request, Storage};
use common::{SET, World, boot, framed};
use libfuzzer_sys::fuzz_target;

struct Time(u32);

impl Clock for Time {
    fn micros(&mut self) -> u32 {
        self.0
    }
}

fuzz_target!(|data: &[u8]| {
    let Some((&mode, data)) = data.split_first() else { return };
    let boot = boot();
    let input = if mode & 1 == 1 { framed(&Request::Start { until: None, period_ms: 1 }, data) } else { data.to_vec() };
    let mut storage = Storage::<24, 256, 16>::new();
    // A small transmit queue, so that it fills, input waits and status frames are
    // dropped.
    let mut controller = Controller::<_, 24, 256, 16, 8, { bt_link::controller::MIN_TX + 40 }>::new(&mut storage, &SET);
    let mut world = World(mode);
    let _ = controller.boot(&boot, &mut world);
    let mut time = Time(0);
    let mut host = Decoder::<{ frame::MAX_FRAME }>::new();
    let mut at = 0;
    let mut step = 0u32;
    while at < input.len() {
        step = step.wrapping_add(1);
        let piece = usize::from(input[at] % 16) + 1;
        let end = (at + piece).min(input.len());
        at += controller.feed(&input[at..end], &mut world, &mut time).max(1);
        time.0 = time.0.wrapping_add(u32::from(mode) * 37 + step % 1500);
        let _ = controller.poll(&mut world, &mut time);
        // The line takes some of what is queued; the host decodes it.
        let pending = controller.transmit();
        let n = (pending.len() / (usize::from(mode >> 4) + 1)).max(pending.len().min(1));
        for &b in &pending[..n] {
            match host.feed(b) {
                Feed::Pending => {}
                Feed::Frame(f) => {
                    assert!(frame::message::<Reply<'_>>(f).is_ok(), "the controller sent a frame the host cannot read");
                }
                Feed::Skipped(fault) => panic!("the controller sent a broken frame: {fault:?}"),
            }
        }
        controller.transmitted(n);
    }
});
