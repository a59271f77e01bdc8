//! The controller side on arbitrary bytes: `serve` must never panic, whatever arrives
//! (the frame decoder, the session, the loader, the swap, the executor).
#![no_main]

#[path = "common.rs"]
mod common;

use bt_link::{Board, Request};
use common::{SET, World, boot, framed};
use libfuzzer_sys::fuzz_target;

struct Fuzz<'a> {
    input: &'a [u8],
    at: usize,
    reads: u32,
    clock: u32,
}

impl Board for Fuzz<'_> {
    fn read(&mut self) -> Option<u8> {
        // Every 16th read finds nothing, so that the controller ticks between bytes.
        self.reads += 1;
        if self.reads % 16 == 0 {
            return None;
        }
        let b = self.input.get(self.at).copied();
        self.at += 1;
        b
    }
    fn write(&mut self, _: &[u8]) {}
    fn micros(&mut self) -> u32 {
        self.clock = self.clock.wrapping_add(1);
        self.clock
    }
    fn closed(&mut self) -> bool {
        self.at >= self.input.len()
    }
}

fuzz_target!(|data: &[u8]| {
    // Half the inputs as raw bytes, half sealed as frames after a `Start`.
    let input = if data.first().is_some_and(|b| b & 1 == 1) {
        framed(&Request::Start { until: None, period_ms: 0 }, &data[1..])
    } else {
        data.to_vec()
    };
    let mut storage = bt_link::Storage::<24, 256, 16>::new();
    let mut board = Fuzz { input: &input, at: 0, reads: 0, clock: 0 };
    bt_link::serve::<_, _, _, 24, 256, 16, 8>(&mut storage, &SET, Some(&boot()), &mut board, &mut World(0));
});
