//! The sans-IO controller on arbitrary input: `Controller::feed` with arbitrary bytes in
//! arbitrary pieces, `poll` at arbitrary times, and the transmit queue drained by
//! arbitrary amounts (a slow line). It must never panic, and every byte it queues must
//! be a frame the host decodes.
#![no_main]

use bt_core::{BehaviorInfo, BehaviorSet, Context, Leaf, Node, NodeId, Status, fingerprint};
use bt_link::frame::{self, Decoder, Feed};
use bt_link::{App, Clock, Controller, Reply, Request, Storage};
use libfuzzer_sys::fuzz_target;

const SET: [BehaviorInfo<'static>; 3] =
    [BehaviorInfo::condition("c?", 0), BehaviorInfo::condition("d?", 1), BehaviorInfo::action("a!", 1)];

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

struct Time(u32);

impl Clock for Time {
    fn micros(&mut self) -> u32 {
        self.0
    }
}

/// Pieces of input sealed as valid frames (so that requests get past the CRC), as in
/// the `serve` target.
fn framed(data: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    let mut buf = [0u8; frame::MAX_ENCODED];
    if let Ok(f) = frame::encode(&Request::Start { until: None, period_ms: 1 }, &mut buf) {
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
    let Some((&mode, data)) = data.split_first() else { return };
    let boot = {
        let mut nodes = [Node::EMPTY; 3];
        let mut b = bt_core::Builder::<4>::new(&mut nodes);
        let _ = b.sequence().and_then(|b| b.condition(0, &[])).and_then(|b| b.action(2, &[1])).and_then(|b| b.end());
        let nodes = b.finish().expect("a valid tree");
        let mut img = [0u8; 64];
        let n = bt_core::encode(nodes, fingerprint(&SET), &mut img).expect("fits");
        img[..n].to_vec()
    };
    let input = if mode & 1 == 1 { framed(data) } else { data.to_vec() };
    let mut storage = Storage::<24, 256, 16>::new();
    // A small transmit queue, so that it fills and status frames are dropped.
    let mut controller = Controller::<_, 24, 256, 16, 8, 160>::new(&mut storage, &SET);
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
