//! What the link's fuzz targets share: a behavior set, a world whose behaviors answer
//! from a running hash, and inputs sealed as valid frames.

use bt_core::{BehaviorInfo, BehaviorSet, Context, Leaf, Node, NodeId, Status, fingerprint};
use bt_link::{App, Request, frame};

pub const SET: [BehaviorInfo<'static>; 3] =
    [BehaviorInfo::condition("c?", 0), BehaviorInfo::condition("d?", 1), BehaviorInfo::action("a!", 1)];

pub struct World(pub u8);

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

/// `Sequence[c?, a!(1)]`: the boot tree.
pub fn boot() -> Vec<u8> {
    let mut nodes = [Node::EMPTY; 3];
    let mut b = bt_core::Builder::<4>::new(&mut nodes);
    let _ = b.sequence().and_then(|b| b.condition(0, &[])).and_then(|b| b.action(2, &[1])).and_then(|b| b.end());
    let nodes = b.finish().expect("a valid tree");
    let mut img = [0u8; 64];
    let n = bt_core::encode(nodes, fingerprint(&SET), &mut img).expect("fits");
    img[..n].to_vec()
}

/// `start` as a frame, then the input cut into pieces, each sealed as a valid frame,
/// so that the fuzzer gets past the CRC into the session and the loader.
pub fn framed(start: &Request<'_>, data: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    let mut buf = [0u8; frame::MAX_ENCODED];
    if let Ok(f) = frame::encode(start, &mut buf) {
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
