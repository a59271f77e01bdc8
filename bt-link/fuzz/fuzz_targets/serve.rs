//! The controller side on arbitrary bytes: `serve` must never panic, whatever arrives
//! (the frame decoder, the session, the loader, the swap, the executor).
#![no_main]

use bt_core::{BehaviorInfo, BehaviorSet, Context, Leaf, Node, NodeId, Status, fingerprint};
use bt_link::{App, Board, Request, frame};
use libfuzzer_sys::fuzz_target;

const SET: [BehaviorInfo<'static>; 3] =
    [BehaviorInfo::condition("c?", 0), BehaviorInfo::condition("d?", 1), BehaviorInfo::action("a!", 1)];

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

struct World(u8);

impl BehaviorSet for World {
    fn condition(&mut self, _: &Leaf, _: Context<'_>) -> Status {
        self.0 = self.0.wrapping_mul(31).wrapping_add(7);
        if self.0 & 1 == 0 { Status::Success } else { Status::Failure }
    }
    fn action(&mut self, _: &Leaf, _: Context<'_>) -> Status {
        self.0 = self.0.wrapping_mul(31).wrapping_add(7);
        [Status::Success, Status::Failure, Status::Running][usize::from(self.0 % 3)]
    }
    fn halt(&mut self, _: &Leaf, _: NodeId) {}
}

impl App for World {}

/// Half the inputs as raw bytes; the other half cut into pieces, each sealed as a valid
/// frame, so that the fuzzer gets past the CRC into the session and the loader. A
/// `Start` goes first so that trees tick.
fn framed(data: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    let mut buf = [0u8; frame::MAX_ENCODED];
    if let Ok(f) = frame::encode(&Request::Start { until: None, period_ms: 0 }, &mut buf) {
        out.extend_from_slice(f);
    }
    let mut rest = data;
    while let Some((&n, tail)) = rest.split_first() {
        let n = usize::from(n % 80).min(tail.len());
        let (body, tail) = tail.split_at(n);
        let mut raw = body.to_vec();
        raw.extend_from_slice(&frame::crc32(body).to_le_bytes());
        let mut enc = vec![0u8; raw.len() + raw.len() / 254 + 2];
        let len = cobs::encode(&raw, &mut enc);
        out.extend_from_slice(&enc[..len]);
        out.push(0);
        rest = tail;
    }
    out
}

fuzz_target!(|data: &[u8]| {
    let boot = {
        let mut nodes = [Node::EMPTY; 3];
        let mut b = bt_core::Builder::<4>::new(&mut nodes);
        let _ = b.sequence().and_then(|b| b.condition(0, &[])).and_then(|b| b.action(2, &[1])).and_then(|b| b.end());
        let nodes = b.finish().expect("a valid tree");
        let mut img = [0u8; 64];
        let n = bt_core::encode(nodes, fingerprint(&SET), &mut img).expect("fits");
        img[..n].to_vec()
    };
    let input = if data.first().is_some_and(|b| b & 1 == 1) { framed(&data[1..]) } else { data.to_vec() };
    let mut storage = bt_link::Storage::<24, 256, 16>::new();
    let mut board = Fuzz { input: &input, at: 0, reads: 0, clock: 0 };
    bt_link::serve::<_, _, _, 24, 256, 16, 8>(&mut storage, &SET, Some(&boot), &mut board, &mut World(0));
});
