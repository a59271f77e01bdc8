//! Deployments over a line that loses, duplicates, flips and delays bytes: the host
//! client against the controller, both in this process, over a simulated 115200-baud
//! UART with fault injection in both directions (in the manner of smoltcp's
//! `FaultInjector`). Everything runs on a simulated clock, so a run is the same every
//! time and takes seconds, timeouts included.
//!
//! Every deployment must end — accepted, refused, or given up after the client's
//! retries — and the controller must then run exactly the image it was sent, or,
//! refused or given up, the tree it ran before (or the new one, when only the answer
//! was lost); an accepted deployment swaps in exactly once (every other one deploys
//! the image that runs already, a restart), any other at most once; the running tree is
//! halted only at swaps.
//!
//! `LOSSY_TRACE=k` prints deployment `k`'s frames at each rate: what each end sent and
//! received, and what the line did to the bytes in between.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::io::{self, Read, Write};
use std::rc::Rc;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use bt_core::{BehaviorInfo, BehaviorSet, Builder, Context, Leaf, Node, NodeId, Status, fingerprint};
use bt_link::frame::{self, MAX_FRAME};
use bt_link::host::{Client, LinkError, Verdict};
use bt_link::{App, Clock, Controller, Decoder, Feed, ImageInfo, Reply, Request, Storage, image_crc};

const SET: [BehaviorInfo<'static>; 3] =
    [BehaviorInfo::condition("ok?", 0), BehaviorInfo::condition("never?", 0), BehaviorInfo::action("work", 1)];
const NODES: usize = 48;
const BYTES: usize = 512;
const DEPTH: usize = 8;
const TX: usize = 512;
const VALUES: usize = 8;
/// The controller's receive queue (what its UART interrupt fills), in bytes.
const RX: usize = 512;
/// One byte on a 115200-baud line, 8N1, in nanoseconds.
const BYTE_NS: u64 = 86_806;

/// `Fallback[never?, work(a), Sequence[ok?, work(b)], ...]` with `n` branches: images
/// of 40 to 230 bytes, one to four chunks.
fn image(seed: u16, branches: u16) -> Vec<u8> {
    let mut nodes = [Node::EMPTY; NODES];
    let mut b = Builder::<DEPTH>::new(&mut nodes);
    b.fallback().unwrap().condition(1, &[]).unwrap();
    for i in 0..branches {
        b.sequence().unwrap().condition(0, &[]).unwrap();
        b.action(2, &[seed.wrapping_add(i)]).unwrap().end().unwrap();
    }
    b.end().unwrap();
    let nodes = b.finish().unwrap();
    let mut out = vec![0u8; bt_core::image::max_image_len(nodes.len())];
    let n = bt_core::encode(nodes, fingerprint(&SET), &mut out).unwrap();
    out.truncate(n);
    out
}

/// `work` runs for ever; halts are counted, and must come only at swaps.
#[derive(Default)]
struct World {
    halts: u64,
    halts_at_swaps: u64,
    swaps: u64,
    ticks: u64,
}

impl BehaviorSet for World {
    fn condition(&mut self, leaf: &Leaf, _: Context<'_>) -> Status {
        if leaf.behavior() == 0 { Status::Success } else { Status::Failure }
    }
    fn action(&mut self, _: &Leaf, _: Context<'_>) -> Status {
        Status::Running
    }
    fn halt(&mut self, _: &Leaf, _: NodeId) {
        self.halts += 1;
    }
}

impl App for World {
    fn after_tick(&mut self, _: u32, _: Result<Status, bt_core::TickError>, _: &[Node]) {
        self.ticks += 1;
    }
    fn swapped(&mut self, _: u32, _: ImageInfo, _: &[Node]) {
        self.swaps += 1;
        self.halts_at_swaps = self.halts;
    }
}

/// A small deterministic generator (SplitMix64).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn chance(&mut self, rate: f64) -> bool {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64 <= rate
    }
}

/// What the line did to the bytes it carried.
#[derive(Clone, Copy, Debug, Default)]
struct Faults {
    dropped: u64,
    duplicated: u64,
    flipped: u64,
    delayed: u64,
}

/// The frames of one deployment, as each end sent and received them, and the faults
/// in between (`LOSSY_TRACE`).
struct Trace {
    lines: Vec<String>,
    /// Host sent, controller received, controller sent, host received.
    taps: [Decoder<MAX_FRAME>; 4],
    ns: u64,
}

impl Trace {
    const TAPS: [&str; 4] = ["host ->", "ctl  <-", "ctl  ->", "host <-"];

    fn note(&mut self, what: std::fmt::Arguments<'_>) {
        self.lines.push(format!("{:>12.3} ms  {what}", self.ns as f64 / 1e6));
    }

    /// A byte through tap `i`; a frame it completes is noted (status reports left out).
    fn tap(&mut self, i: usize, byte: u8) {
        let text = match self.taps[i].feed(byte) {
            Feed::Pending => return,
            Feed::Skipped(fault) => format!("garbled ({})", fault.code()),
            Feed::Frame(bytes) if i < 2 => match frame::message::<Request<'_>>(bytes) {
                Ok(Request::Chunk { offset, bytes }) => format!("Chunk {{ offset: {offset}, {} bytes }}", bytes.len()),
                r => format!("{r:?}"),
            },
            Feed::Frame(bytes) => match frame::message::<Reply<'_>>(bytes) {
                Ok(Reply::Status { .. } | Reply::Tick { .. }) => return,
                r => format!("{r:?}"),
            },
        };
        self.note(format_args!("{} {text}", Self::TAPS[i]));
    }
}

/// Notes through an optional trace.
fn note(trace: &mut Option<Trace>, what: std::fmt::Arguments<'_>) {
    if let Some(t) = trace {
        t.note(what);
    }
}

fn tap(trace: &mut Option<Trace>, i: usize, byte: u8) {
    if let Some(t) = trace {
        t.tap(i, byte);
    }
}

/// One direction of the line: bytes waiting to go, one per byte time, each faulted
/// with probability `rate`.
struct Wire {
    name: &'static str,
    queue: VecDeque<u8>,
    /// Byte times the line stays silent (a delay).
    stall: u32,
    carried: u64,
}

impl Wire {
    fn new(name: &'static str) -> Self {
        Self { name, queue: VecDeque::new(), stall: 0, carried: 0 }
    }

    /// One byte time: the byte that arrives at the far end, if any.
    fn step(&mut self, rng: &mut Rng, rate: f64, faults: &mut Faults, trace: &mut Option<Trace>) -> Option<u8> {
        if self.stall > 0 {
            self.stall -= 1;
            return None;
        }
        let byte = self.queue.pop_front()?;
        self.carried += 1;
        if !rng.chance(rate) {
            return Some(byte);
        }
        let (name, at) = (self.name, self.carried);
        match rng.next() % 4 {
            0 => {
                faults.dropped += 1;
                note(trace, format_args!("  {name}: byte {at} dropped"));
                None
            }
            1 => {
                faults.duplicated += 1;
                note(trace, format_args!("  {name}: byte {at} duplicated"));
                self.queue.push_front(byte);
                Some(byte)
            }
            2 => {
                faults.flipped += 1;
                note(trace, format_args!("  {name}: byte {at} flipped"));
                Some(byte ^ (1 << (rng.next() % 8)))
            }
            _ => {
                // The rest of the stream waits 1 to 60 ms (a busy USB bridge, a
                // scheduler hiccup): the byte comes after the pause.
                faults.delayed += 1;
                self.stall = 12 + (rng.next() % 680) as u32;
                note(trace, format_args!("  {name}: delayed {} byte times at byte {at}", self.stall));
                self.queue.push_front(byte);
                None
            }
        }
    }
}

/// The simulated time, shared by the line, the controller and the client's deadlines.
#[derive(Clone)]
struct SimClock {
    base: Instant,
    ns: Arc<Mutex<u64>>,
}

impl SimClock {
    fn now(&self) -> Instant {
        self.base + Duration::from_nanos(*self.ns.lock().unwrap())
    }
    fn advance(&self, ns: u64) -> u64 {
        let mut t = self.ns.lock().unwrap();
        *t += ns;
        *t
    }
}

struct Board(SimClock);

impl Clock for Board {
    fn micros(&mut self) -> u32 {
        (*self.0.ns.lock().unwrap() / 1000) as u32
    }
}

type Ctl = Controller<'static, [BehaviorInfo<'static>; 3], NODES, BYTES, VALUES, DEPTH, TX>;

/// The controller and both directions of the line, moved one byte time per host read.
struct Line {
    controller: Ctl,
    world: World,
    board: Board,
    rx: VecDeque<u8>,
    up: Wire,
    down: Wire,
    rng: Rng,
    rate: f64,
    faults: Faults,
    overruns: u64,
    trace: Option<Trace>,
}

impl Line {
    /// One byte time: a byte each way, the controller fed and polled.
    fn step(&mut self) {
        let ns = self.board.0.advance(BYTE_NS);
        if let Some(t) = &mut self.trace {
            t.ns = ns;
        }
        if let Some(b) = self.up.step(&mut self.rng, self.rate, &mut self.faults, &mut self.trace) {
            if self.rx.len() < RX {
                self.rx.push_back(b);
            } else {
                self.overruns += 1;
            }
        }
        while self.controller.wants_input() {
            let Some(b) = self.rx.pop_front() else { break };
            tap(&mut self.trace, 1, b);
            let swaps = self.world.swaps;
            self.controller.feed(&[b], &mut self.world, &mut self.board);
            if self.world.swaps > swaps {
                note(&mut self.trace, format_args!("ctl     swapped in"));
            }
        }
        self.controller.poll(&mut self.world, &mut self.board);
        // The UART's transmit register takes one byte per byte time.
        if let Some(&b) = self.controller.transmit().first() {
            tap(&mut self.trace, 2, b);
            self.down.queue.push_back(b);
            self.controller.transmitted(1);
        }
    }
}

/// The host's end: writes go onto the line, reads move the simulation on.
#[derive(Clone)]
struct HostEnd(Rc<RefCell<Line>>);

impl Read for HostEnd {
    /// As a serial port with a read timeout: the first byte that arrives, or none
    /// after 10 ms.
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let mut line = self.0.borrow_mut();
        let mut n = 0;
        let mut quiet = 0;
        while n == 0 && n < buf.len() && quiet < 115 {
            let Line { down, rng, rate, faults, trace, .. } = &mut *line;
            match down.step(rng, *rate, faults, trace) {
                Some(b) => {
                    tap(trace, 3, b);
                    buf[n] = b;
                    n += 1;
                }
                None => quiet += 1,
            }
            line.step();
        }
        if n == 0 { Err(io::ErrorKind::WouldBlock.into()) } else { Ok(n) }
    }
}

impl Write for HostEnd {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let mut line = self.0.borrow_mut();
        for &b in buf {
            tap(&mut line.trace, 0, b);
        }
        line.up.queue.extend(buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// The outcome of `n` deployments at one fault rate.
#[derive(Debug, Default)]
struct Tally {
    accepted: u64,
    refused: u64,
    gave_up: u64,
    /// Deployments whose image was swapped in twice (none may be).
    twice: u64,
    sim_ns: u64,
    bytes: u64,
}

/// A controller booted with `boot`, on a line faulting bytes at `rate`.
fn line(boot: &[u8], rate: f64, seed: u64) -> (Rc<RefCell<Line>>, SimClock) {
    let storage: &'static mut Storage<NODES, BYTES, VALUES> = Box::leak(Box::new(Storage::new()));
    let clock = SimClock { base: Instant::now(), ns: Arc::new(Mutex::new(0)) };
    let mut controller = Ctl::new(storage, &SET);
    let mut world = World::default();
    controller.boot(boot, &mut world).unwrap();
    let line = Rc::new(RefCell::new(Line {
        controller,
        world,
        board: Board(clock.clone()),
        rx: VecDeque::new(),
        up: Wire::new("up  "),
        down: Wire::new("down"),
        rng: Rng(seed),
        rate,
        faults: Faults::default(),
        overruns: 0,
        trace: None,
    }));
    (line, clock)
}

/// A client at the host's end of `line`, on the simulated clock.
fn client(line: &Rc<RefCell<Line>>, clock: &SimClock) -> Client<HostEnd> {
    let sim = clock.clone();
    Client::new(HostEnd(line.clone())).with_clock(Box::new(move || sim.now()))
}

/// Lets the line settle: answers in flight arrive, a swap due happens.
fn settle(line: &Rc<RefCell<Line>>) {
    for _ in 0..20_000 {
        let mut l = line.borrow_mut();
        if l.up.queue.is_empty() && l.up.stall == 0 && l.rx.is_empty() {
            break;
        }
        l.step();
    }
}

/// `n` deployments at `rate`; the frames of deployment `traced` are printed.
fn run(rate: f64, n: u32, seed: u64, traced: Option<u32>) -> (Tally, Faults, u64) {
    let images: Vec<Vec<u8>> = (0..6).map(|i| image(100 * i, 1 + i * 2)).collect();
    let (line, clock) = line(&images[0], rate, seed);
    let mut client = client(&line, &clock);
    // Ticking every 10 ms while the deployments arrive, on a line without faults at first.
    line.borrow_mut().rate = 0.0;
    client.hello().unwrap();
    client.start(None, 10, &mut |_| {}).unwrap();
    line.borrow_mut().rate = rate;
    let mut tally = Tally::default();
    let mut running = image_crc(&images[0]);
    for k in 0..n {
        // Each image twice in a row: the second deployment restarts the running tree.
        let image = &images[1 + (k as usize / 2 % (images.len() - 1))];
        if traced == Some(k) {
            let ns = *clock.ns.lock().unwrap();
            let mut t = Trace { lines: Vec::new(), taps: std::array::from_fn(|_| Decoder::new()), ns };
            t.note(format_args!(
                "deployment {k} at rate {rate}: image {:08x}, {} bytes",
                image_crc(image),
                image.len()
            ));
            line.borrow_mut().trace = Some(t);
        }
        let before = *clock.ns.lock().unwrap();
        let bytes_before = client.sent + client.received;
        let swaps_before = line.borrow().world.swaps;
        let verdict = client.deploy(image, None, &mut |_| {});
        let after = *clock.ns.lock().unwrap();
        settle(&line);
        if let Some(t) = line.borrow_mut().trace.take() {
            println!("{}\nverdict: {verdict:?}", t.lines.join("\n"));
        }
        let now_running = line.borrow().controller.running().map(|i| i.crc);
        let swaps = line.borrow().world.swaps - swaps_before;
        tally.twice += u64::from(swaps >= 2);
        assert!(swaps <= 1, "deployment {k} at rate {rate}: {swaps} swaps (LOSSY_TRACE={k} prints its frames)");
        match verdict {
            Ok(Verdict::Accepted { crc, .. }) => {
                assert_eq!(crc, image_crc(image), "deployment {k}: accepted another image");
                assert_eq!(now_running, Some(crc), "deployment {k}: accepted, but not running");
                assert_eq!(swaps, 1, "deployment {k} at rate {rate}: accepted, never swapped in (LOSSY_TRACE={k})");
                tally.accepted += 1;
                tally.sim_ns += after - before;
                tally.bytes += client.sent + client.received - bytes_before;
            }
            Ok(Verdict::Rejected(fault)) => {
                assert_eq!(
                    now_running,
                    Some(running),
                    "deployment {k}: refused ({}), yet the tree changed",
                    fault.code()
                );
                assert_eq!(swaps, 0, "deployment {k}: refused ({}), yet swapped in", fault.code());
                tally.refused += 1;
            }
            Err(LinkError::Timeout { .. }) => {
                // Gave up: the old tree, or the new one if only the verdict was lost.
                assert!(
                    now_running == Some(running) || now_running == Some(image_crc(image)),
                    "deployment {k}: gave up, and a third tree runs"
                );
                tally.gave_up += 1;
            }
            Err(e) => panic!("deployment {k}: {e}"),
        }
        running = now_running.unwrap();
    }
    let line = line.borrow();
    assert_eq!(line.world.halts, line.world.halts_at_swaps, "a running action was halted outside a swap");
    // Ticks every 10 ms of the simulated time: the deployments never held the tree up.
    let elapsed_ms = *clock.ns.lock().unwrap() / 1_000_000;
    assert!(line.world.ticks * 10 * 10 >= elapsed_ms * 9, "{} ticks in {elapsed_ms} ms", line.world.ticks);
    (tally, line.faults, line.overruns)
}

/// Deployments at each rate: 10,002 in all (`LOSSY_DEPLOYMENTS` per rate changes it).
#[test]
fn deployments_over_a_faulty_line_end_with_the_sent_tree_or_the_old_one() {
    let per_rate: u32 = std::env::var("LOSSY_DEPLOYMENTS").ok().and_then(|v| v.parse().ok()).unwrap_or(3334);
    let traced: Option<u32> = std::env::var("LOSSY_TRACE").ok().and_then(|v| v.parse().ok());
    println!(
        "rate    deployments accepted refused gave-up swapped-twice  mean deploy  wire time  faults (drop/dup/flip/delay)"
    );
    for (i, rate) in [1e-4, 1e-3, 1e-2].into_iter().enumerate() {
        let (t, f, overruns) = run(rate, per_rate, 0x5eed + i as u64, traced);
        let mean_ms = t.sim_ns as f64 / t.accepted.max(1) as f64 / 1e6;
        let wire_ms = t.bytes as f64 / t.accepted.max(1) as f64 * BYTE_NS as f64 / 1e6;
        println!(
            "{rate:<7} {per_rate:>11} {:>8} {:>7} {:>7} {:>13}  {mean_ms:>8.1} ms {wire_ms:>7.1} ms  {}/{}/{}/{} (rx overruns {overruns})",
            t.accepted, t.refused, t.gave_up, t.twice, f.dropped, f.duplicated, f.flipped, f.delayed
        );
        assert_eq!(t.accepted + t.refused + t.gave_up, u64::from(per_rate));
        assert_eq!(t.refused, 0, "a faithful transfer was refused at rate {rate}");
        assert!(t.accepted * 10 >= u64::from(per_rate) * 9, "fewer than 90 % accepted at rate {rate}");
    }
}

/// Every client numbers its transfers from 1: the `Hello` it says first (itself, before
/// its first deployment, if the caller did not) starts a new session on the controller,
/// so a second client's transfer 1 is a new deployment, not a repeat of the first's.
#[test]
fn a_second_client_deploying_the_running_image_restarts_it() {
    let (a, b) = (image(0, 1), image(100, 3));
    let (line, clock) = line(&a, 0.0, 1);
    for said_hello in [true, false] {
        let mut client = client(&line, &clock);
        if said_hello {
            client.hello().unwrap();
        }
        let verdict = client.deploy(&b, None, &mut |_| {}).unwrap();
        assert!(matches!(verdict, Verdict::Accepted { crc, .. } if crc == image_crc(&b)), "{verdict:?}");
        settle(&line);
    }
    assert_eq!(line.borrow().world.swaps, 2, "swapped in, then restarted");
}
