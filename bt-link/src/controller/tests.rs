//! `serve` driven by a scripted board: every fault a transfer can have, and the swap.

use std::collections::VecDeque;

use bt_core::{
    BehaviorInfo, BehaviorSet, Builder, Context, Leaf, Node, NodeId, Status, fingerprint, image::max_image_len,
};

mod refusals;
mod repeats;

use super::session::Session;
use super::*;
use crate::frame::{Decoder, Feed, MAX_ENCODED, MAX_FRAME, crc32, encode, message};
use crate::wire::{Fault, FrameFault, MAX_CHUNK, PROTOCOL_VERSION, Reply, Request, WireStatus};

const SET: [BehaviorInfo<'static>; 4] = [
    BehaviorInfo::condition("ok?", 0),
    BehaviorInfo::condition("never?", 0),
    BehaviorInfo::action("work", 1),
    BehaviorInfo::action("work4", 4),
];
const OK: u16 = 0;
const NEVER: u16 = 1;
const WORK: u16 = 2;
const DEPTH: usize = 8;
type Store = Storage<16, 256, 8>;

/// `Sequence[ok?, work(a)]`, or with `second`, `Fallback[never?, work(a), work(b)]`.
fn image(a: u16, second: Option<u16>, fp: u64) -> Vec<u8> {
    let mut nodes = [Node::EMPTY; 8];
    let mut b = Builder::<4>::new(&mut nodes);
    match second {
        None => {
            b.sequence().unwrap().condition(OK, &[]).unwrap().action(WORK, &[a]).unwrap().end().unwrap();
        }
        Some(x) => {
            b.fallback().unwrap().condition(NEVER, &[]).unwrap();
            b.action(WORK, &[a]).unwrap().action(WORK, &[x]).unwrap().end().unwrap();
        }
    }
    let nodes = b.finish().unwrap();
    let mut out = vec![0u8; max_image_len(nodes.len())];
    let n = bt_core::encode(nodes, fp, &mut out).unwrap();
    out.truncate(n);
    out
}

fn tree_a() -> Vec<u8> {
    image(1000, None, fingerprint(&SET))
}

fn tree_b() -> Vec<u8> {
    image(1000, Some(7), fingerprint(&SET))
}

/// What the app saw, in order.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Seen {
    Start(NodeId),
    Halt(NodeId),
    Swap(u32, u32),
    Stop(u32),
}

/// `work(n)` runs `n` ticks; every start and halt is logged.
#[derive(Default)]
struct Log {
    seen: Vec<Seen>,
    ticks: Vec<(u32, Result<Status, TickError>)>,
    /// The `now` each condition call saw.
    nows: Vec<u32>,
}

impl BehaviorSet for Log {
    fn condition(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        self.nows.push(ctx.now);
        if leaf.behavior() == OK { Status::Success } else { Status::Failure }
    }
    fn action(&mut self, _leaf: &Leaf, ctx: Context<'_>) -> Status {
        if ctx.starting {
            self.seen.push(Seen::Start(ctx.node));
        }
        Status::Running
    }
    fn halt(&mut self, _: &Leaf, node: NodeId) {
        self.seen.push(Seen::Halt(node));
    }
}

impl App for Log {
    fn after_tick(&mut self, tick: u32, result: Result<Status, TickError>, _: &[Node]) {
        self.ticks.push((tick, result));
    }
    fn swapped(&mut self, tick: u32, image: ImageInfo, _: &[Node]) {
        self.seen.push(Seen::Swap(tick, image.crc));
    }
    fn stopped(&mut self, tick: u32) {
        self.seen.push(Seen::Stop(tick));
    }
}

/// A step of the host's script.
enum Step {
    /// Bytes to send.
    Bytes(Vec<u8>),
    /// Send nothing until the controller reported tick `n - 1` done.
    UntilTick(u32),
}

/// The host end, scripted: feeds the steps and decodes every reply.
struct Host {
    steps: VecDeque<Step>,
    pending: VecDeque<u8>,
    replies: Vec<Reply<'static>>,
    decoder: Decoder<MAX_FRAME>,
    clock: u32,
    /// Microseconds the clock advances per `micros` call.
    clock_step: u32,
    last_tick: Option<u32>,
    /// The board's clock when each `Tick` reply was sent.
    tick_times: Vec<u32>,
}

impl Host {
    fn new(steps: Vec<Step>) -> Self {
        Self {
            steps: steps.into(),
            pending: VecDeque::new(),
            replies: Vec::new(),
            decoder: Decoder::new(),
            clock: 0,
            clock_step: 1,
            last_tick: None,
            tick_times: Vec::new(),
        }
    }

    fn rejections(&self) -> Vec<&'static str> {
        self.replies
            .iter()
            .filter_map(|r| match r {
                Reply::Rejected { fault } => Some(fault.code()),
                _ => None,
            })
            .collect()
    }
}

impl Board for Host {
    fn micros(&mut self) -> u32 {
        self.clock = self.clock.wrapping_add(self.clock_step);
        self.clock
    }

    fn read(&mut self) -> Option<u8> {
        loop {
            if let Some(b) = self.pending.pop_front() {
                return Some(b);
            }
            match self.steps.front() {
                Some(Step::Bytes(_)) => {
                    if let Some(Step::Bytes(b)) = self.steps.pop_front() {
                        self.pending.extend(b);
                    }
                }
                Some(&Step::UntilTick(n)) if n == 0 || self.last_tick.is_some_and(|t| t + 1 >= n) => {
                    self.steps.pop_front();
                }
                Some(Step::UntilTick(_)) => return None,
                None => return None,
            }
        }
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            if let Feed::Frame(f) = self.decoder.feed(b) {
                let reply: Reply<'_> = message(f).expect("the controller sends valid replies");
                let reply = match reply {
                    Reply::Image { offset, total, bytes } => {
                        Reply::Image { offset, total, bytes: Box::leak(bytes.to_vec().into_boxed_slice()) }
                    }
                    Reply::Hello { version, fingerprint, node_capacity, image_capacity, running } => {
                        Reply::Hello { version, fingerprint, node_capacity, image_capacity, running }
                    }
                    Reply::ChunkAck { id, received } => Reply::ChunkAck { id, received },
                    Reply::Accepted { id, crc, nodes, swap_at } => Reply::Accepted { id, crc, nodes, swap_at },
                    Reply::Rejected { fault } => Reply::Rejected { fault },
                    Reply::Swapped { tick, image, halted } => Reply::Swapped { tick, image, halted },
                    Reply::Status { tick, node, status } => Reply::Status { tick, node, status },
                    Reply::Tick { tick, status, changes, micros } => {
                        self.last_tick = Some(tick);
                        self.tick_times.push(self.clock);
                        Reply::Tick { tick, status, changes, micros }
                    }
                    Reply::State { token, tick, ticking, until, running, halted, stack_used } => {
                        Reply::State { token, tick, ticking, until, running, halted, stack_used }
                    }
                    Reply::Garbled { fault } => Reply::Garbled { fault },
                    Reply::Lost { tick, frames } => Reply::Lost { tick, frames },
                };
                self.replies.push(reply);
            }
        }
    }

    fn closed(&mut self) -> bool {
        self.pending.is_empty() && self.steps.is_empty()
    }
}

/// A transfer id no other `Deploy` of the tests uses.
fn transfer_id() -> u16 {
    static NEXT: std::sync::atomic::AtomicU16 = std::sync::atomic::AtomicU16::new(1);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

/// The id of the first `Accepted` reply.
fn accepted_id(host: &Host) -> u16 {
    host.replies
        .iter()
        .find_map(|r| match *r {
            Reply::Accepted { id, .. } => Some(id),
            _ => None,
        })
        .expect("an Accepted reply")
}

fn frame(req: &Request<'_>) -> Vec<u8> {
    let mut buf = [0u8; MAX_ENCODED];
    let mut out = vec![0];
    out.extend_from_slice(encode(req, &mut buf).unwrap());
    out
}

/// The frames of a whole deployment: `Deploy` with `len`/`crc` as announced, `sent`
/// in chunks of 64 (or fewer), `Commit`.
fn deploy(len: usize, crc: u32, sent: &[u8], swap_at: Option<u32>) -> Vec<Step> {
    let mut steps = vec![Step::Bytes(frame(&Request::Deploy { id: transfer_id(), len: len as u32, crc, swap_at }))];
    for (i, c) in sent.chunks(MAX_CHUNK).enumerate() {
        steps.push(Step::Bytes(frame(&Request::Chunk { offset: (i * MAX_CHUNK) as u32, bytes: c })));
    }
    steps.push(Step::Bytes(frame(&Request::Commit)));
    steps
}

fn deploy_image(img: &[u8], swap_at: Option<u32>) -> Vec<Step> {
    deploy(img.len(), crc32(img), img, swap_at)
}

fn start(until: u32) -> Step {
    Step::Bytes(frame(&Request::Start { until: Some(until), period_ms: 0 }))
}

fn ping() -> Step {
    Step::Bytes(frame(&Request::Ping { token: 9 }))
}

/// Runs a controller booted with tree A through `steps`.
fn run(steps: Vec<Step>) -> (Host, Log) {
    let mut storage = Store::new();
    let mut host = Host::new(steps);
    let mut log = Log::default();
    serve::<_, _, _, 16, 256, 8, DEPTH>(&mut storage, &SET, Some(&tree_a()), &mut host, &mut log);
    (host, log)
}

fn last_state(host: &Host) -> (u32, Option<ImageInfo>) {
    host.replies
        .iter()
        .rev()
        .find_map(|r| match *r {
            Reply::State { tick, running, .. } => Some((tick, running)),
            _ => None,
        })
        .expect("a State reply")
}

/// A fault case: tree A ticks 0..5, `steps` happen, then A ticks 5..10. A must have
/// been ticked 10 times, never halted, never swapped, and still be the running image.
fn refused(steps: Vec<Step>) -> Host {
    let mut all = vec![start(5), Step::UntilTick(5)];
    all.extend(steps);
    all.extend([start(10), Step::UntilTick(10), ping()]);
    let (host, log) = run(all);
    assert_eq!(log.ticks.len(), 10, "the running tree kept ticking");
    assert_eq!(log.seen, vec![Seen::Start(2)], "A's action started once and was never halted");
    let a = tree_a();
    let (tick, running) = last_state(&host);
    assert_eq!(tick, 10);
    assert_eq!(running.map(|i| i.crc), Some(crate::image_crc(&a)), "A is still the running image");
    assert!(!host.replies.iter().any(|r| matches!(r, Reply::Swapped { .. })));
    host
}

#[test]
fn hello_names_the_protocol_the_behavior_set_and_the_running_image() {
    let (host, _) = run(vec![Step::Bytes(frame(&Request::Hello { version: 1 }))]);
    let a = tree_a();
    assert_eq!(
        host.replies,
        vec![Reply::Hello {
            version: PROTOCOL_VERSION,
            fingerprint: fingerprint(&SET),
            node_capacity: 16,
            image_capacity: 256,
            running: Some(ImageInfo { crc: crate::image_crc(&a), len: a.len() as u32, nodes: 3 }),
        }]
    );
}

#[test]
fn a_valid_image_swaps_in_at_its_tick_after_the_old_actions_are_halted() {
    let b = tree_b();
    let mut steps = vec![start(3)];
    steps.extend(deploy_image(&b, Some(6)));
    steps.extend([start(9), Step::UntilTick(9)]);
    let (host, log) = run(steps);
    // A's action (node 2) started at tick 0, halted at the swap, then B's first
    // action (node 2 of B) started: halt before start, across trees.
    assert_eq!(log.seen, vec![Seen::Start(2), Seen::Halt(2), Seen::Swap(6, crate::image_crc(&b)), Seen::Start(2)]);
    assert_eq!(log.ticks.len(), 9);
    assert!(host.replies.contains(&Reply::Accepted {
        id: accepted_id(&host),
        crc: crate::image_crc(&b),
        nodes: 4,
        swap_at: Some(6)
    }));
    // On the wire: A's action goes Idle at the boundary before tick 6, then Swapped,
    // then B's changes during tick 6.
    let swapped = host.replies.iter().position(|r| matches!(r, Reply::Swapped { tick: 6, halted: 1, .. })).unwrap();
    assert!(host.replies[..swapped].contains(&Reply::Status { tick: 6, node: 2, status: WireStatus::Idle }));
    let b_first =
        host.replies.iter().position(|r| matches!(r, Reply::Status { tick: 6, status: WireStatus::Running, .. }));
    assert!(b_first.is_some_and(|i| i > swapped));
    assert!(!host.replies[..swapped].iter().any(|r| matches!(r, Reply::Tick { tick: 6.., .. })));
}

#[test]
fn without_a_swap_tick_the_image_swaps_at_the_next_boundary() {
    let b = tree_b();
    let mut steps = deploy_image(&b, None);
    steps.extend([start(2), Step::UntilTick(2)]);
    let (_, log) = run(steps);
    assert_eq!(log.seen, vec![Seen::Swap(0, crate::image_crc(&b)), Seen::Start(2)]);
}

#[test]
fn stop_halts_the_running_actions_and_start_goes_on() {
    let steps = vec![start(3), Step::UntilTick(3), Step::Bytes(frame(&Request::Stop)), start(5), Step::UntilTick(5)];
    let (host, log) = run(steps);
    assert_eq!(log.seen, vec![Seen::Start(2), Seen::Halt(2), Seen::Stop(3), Seen::Start(2)]);
    assert!(host.replies.iter().any(|r| matches!(r, Reply::State { halted: 1, ticking: false, tick: 3, .. })));
    assert_eq!(log.ticks.len(), 5);
}

#[test]
fn the_tree_clock_is_milliseconds_on_the_tick_schedule() {
    // Ticked every 100 ms on a board whose timer moves 7 ms per read: the tree sees
    // tick x 100 ms (the host's simulated clock), not the board's jittered times.
    let steps = vec![
        Step::Bytes(frame(&Request::Start { until: Some(3), period_ms: 100 })),
        Step::UntilTick(3),
        Step::Bytes(frame(&Request::Stop)),
        Step::Bytes(frame(&Request::Start { until: Some(5), period_ms: 250 })),
        Step::UntilTick(5),
    ];
    let mut storage = Store::new();
    let mut host = Host::new(steps);
    host.clock_step = 7_000;
    let mut log = Log::default();
    serve::<_, _, _, 16, 256, 8, DEPTH>(&mut storage, &SET, Some(&tree_a()), &mut host, &mut log);
    // After the stop, the new period counts from the last tick.
    assert_eq!(log.nows, vec![0, 100, 200, 450, 700]);
}

#[test]
fn a_start_while_ticking_moves_the_horizon_and_keeps_the_schedule() {
    // The host grants one tick at a time, as `sim-host blend` does: every tick still
    // comes a whole period after the one before. A new period starts at once.
    let mut steps = vec![Step::Bytes(frame(&Request::Start { until: Some(1), period_ms: 100 }))];
    for until in 2..=4 {
        steps.push(Step::UntilTick(until - 1));
        steps.push(Step::Bytes(frame(&Request::Start { until: Some(until), period_ms: 100 })));
    }
    steps.push(Step::UntilTick(4));
    steps.push(Step::Bytes(frame(&Request::Start { until: Some(5), period_ms: 50 })));
    steps.push(Step::UntilTick(5));
    let mut storage = Store::new();
    let mut host = Host::new(steps);
    host.clock_step = 7_000;
    let mut log = Log::default();
    serve::<_, _, _, 16, 256, 8, DEPTH>(&mut storage, &SET, Some(&tree_a()), &mut host, &mut log);
    let gaps: Vec<u32> = host.tick_times.windows(2).map(|w| w[1] - w[0]).collect();
    assert_eq!(gaps.len(), 4);
    assert!(gaps[..3].iter().all(|&g| g >= 100_000), "a tick came early: {gaps:?} µs apart");
    assert!(gaps[3] < 50_000, "the new period ticks at once: {gaps:?}");
    assert_eq!(log.nows, vec![0, 100, 200, 300, 350]);
}

#[test]
fn without_a_period_the_tree_clock_is_the_boards_time_between_ticks() {
    let mut session = Session::new(0);
    // Starts at 1.5 ms, 2.6 ms, then across the wrap of the microsecond timer.
    let starts = [1_500, 2_600, 4_000, u32::MAX - 199, 1_000];
    let nows: Vec<u32> = starts.iter().map(|&t| session.advance_clock(t)).collect();
    // 0; +1.1 ms (1, 0.1 carried); +1.4 ms (2, 0.5 carried); +4,294,963.096 ms across
    // the wrap (4,294,965, 0.596 carried); +1.2 ms (4,294,966).
    assert_eq!(nows, vec![0, 1, 2, 4_294_965, 4_294_966]);
}

#[test]
fn read_returns_the_running_image() {
    let a = tree_a();
    let (host, _) = run(vec![Step::Bytes(frame(&Request::Read { offset: 0 }))]);
    assert_eq!(host.replies, vec![Reply::Image { offset: 0, total: a.len() as u32, bytes: Box::leak(a.into()) }]);
}

#[test]
fn without_a_tree_start_and_read_are_refused_and_a_deploy_brings_one() {
    let mut storage = Store::new();
    let b = tree_b();
    let mut steps = vec![Step::Bytes(frame(&Request::Start { until: None, period_ms: 0 }))];
    steps.push(Step::Bytes(frame(&Request::Read { offset: 0 })));
    steps.extend(deploy_image(&b, None));
    steps.extend([start(2), Step::UntilTick(2)]);
    let mut host = Host::new(steps);
    let mut log = Log::default();
    let mut broken = tree_a();
    broken[0] = b'X';
    serve::<_, _, _, 16, 256, 8, DEPTH>(&mut storage, &SET, Some(&broken), &mut host, &mut log);
    assert_eq!(host.rejections(), ["no-tree", "no-tree"]);
    assert_eq!(log.seen, vec![Seen::Swap(0, crate::image_crc(&b)), Seen::Start(2)]);
}

/// `Sequence[ok?, work4(1, 2, 3, 4)]`: a leaf whose values live in the value table.
fn tree_with_values() -> Vec<u8> {
    use bt_core::{NodeKind, image::ImageParts};
    let nodes = [
        Node::new(NodeKind::Sequence, 3),
        Node::new(NodeKind::Condition(Leaf::new(OK)), 1),
        Node::new(NodeKind::Action(Leaf::extended(3, 0, 4).unwrap()), 1),
    ];
    let parts = ImageParts::new(&nodes).values(&[1, 2, 3, 4]);
    let mut out = vec![0u8; 128];
    let n = bt_core::encode_with(&parts, fingerprint(&SET), &mut out).unwrap();
    out.truncate(n);
    out
}

#[test]
fn an_image_with_a_value_table_swaps_in_with_its_values() {
    let v = tree_with_values();
    let mut steps = deploy_image(&v, None);
    steps.extend([start(2), Step::UntilTick(2)]);
    let (host, log) = run(steps);
    assert!(host.replies.contains(&Reply::Accepted {
        id: accepted_id(&host),
        crc: crate::image_crc(&v),
        nodes: 3,
        swap_at: None
    }));
    assert_eq!(log.seen, vec![Seen::Swap(0, crate::image_crc(&v)), Seen::Start(2)]);
}

#[test]
fn a_value_table_larger_than_the_slot_is_refused() {
    let v = tree_with_values();
    let mut storage = Storage::<16, 256, 2>::new();
    let mut host = Host::new(deploy_image(&v, None));
    serve::<_, _, _, 16, 256, 2, DEPTH>(&mut storage, &SET, Some(&tree_a()), &mut host, &mut Log::default());
    assert_eq!(host.rejections(), ["too-many-values"]);
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]

    /// Any bytes, spliced into a valid session, neither panic nor touch the running
    /// tree unless the controller itself reported a swap.
    #[test]
    fn no_byte_sequence_changes_the_running_tree_without_a_swap(
        noise in proptest::collection::vec(proptest::prelude::any::<u8>(), 0..600),
        cut in 0usize..600,
    ) {
        let cut = cut.min(noise.len());
        let steps = vec![
            start(3),
            Step::UntilTick(3),
            Step::Bytes(noise[..cut].to_vec()),
            Step::Bytes(vec![0]),
            start(6),
            Step::Bytes(noise[cut..].to_vec()),
            Step::Bytes(vec![0]),
            ping(),
        ];
        let (host, log) = run(steps);
        let swapped = host.replies.iter().any(|r| matches!(r, Reply::Swapped { .. }));
        if !swapped {
            let (_, running) = last_state(&host);
            proptest::prop_assert_eq!(running.map(|i| i.crc), Some(crate::image_crc(&tree_a())));
            proptest::prop_assert!(log.seen.iter().all(|s| matches!(s, Seen::Start(2) | Seen::Halt(2) | Seen::Stop(_))));
        }
    }
}
