//! The link scenario of `cargo xtask qemu`: the link controller under QEMU and on the
//! host, driven over TCP through the same sequence of deployments.
//!
//! 1. Boot with tree A (the firmware's tree: the blocked cube problem at the end of Example 2), tick
//!    it up to tick 40 while tree B (the planner's tree for the free path, Fig. 3(e))
//!    is deployed to swap in at tick 40. From the status stream: every action of A
//!    that was Running is reported Idle before `Swapped`, and no node of B changes
//!    before it (halt before start, across trees).
//! 2. While B ticks on to tick 60, the faults: B with one bit flipped (the loader's
//!    CRC), B corrupted in transit (the transfer CRC), B's transfer cut short, B's image
//!    cut short, B for a foreign behavior set, an image larger than the buffer, and
//!    garbage bytes on the wire, between frames and between the chunks of a transfer.
//!    Each is refused (or the garbage skipped) with its reason, and B keeps ticking:
//!    after each, `Ping` must report B as the running image and the tick count moving
//!    on.
//! 3. A is deployed back to swap in at tick 60, checked the same way, and ticks to
//!    tick 130; `Stop` halts it.
//!
//! The controller ticks only up to the tick the host names, and swaps at the tick the
//! host names, so both traces are identical whatever the link's timing: the QEMU trace
//! (semihosting) must equal the host's (stdout) byte for byte.

use std::io::Read;
use std::net::{Shutdown, TcpListener, TcpStream};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::time::{Duration, Instant};

use bt_core::Catalog as _;
use bt_link::host::{Client, Paced, Transfer, Verdict};
use bt_link::{Fault, FrameFault, Reply, WireStatus, image_crc};

use crate::Result;

/// Milliseconds between ticks in the scenario: fast, yet slow enough that transfers
/// overlap ticks.
const PERIOD_MS: u16 = 2;
/// Tick at which B replaces A, then A replaces B.
const SWAP_B: u32 = 30;
const SWAP_A: u32 = 48;
/// The scenario's last tick + 1.
const END: u32 = 130;

/// The images the scenario deploys.
pub struct Images {
    /// The firmware's tree (the blocked cube problem at the end of Example 2).
    pub a: Vec<u8>,
    /// The free path's tree (Fig. 3(e)).
    pub b: Vec<u8>,
    /// A's action node ids, B's action node ids.
    actions: (Vec<u16>, Vec<u16>),
    foreign: Vec<u8>,
    fingerprint: u64,
    /// A with a names section that makes the image 16 KiB: for timing a large
    /// deployment (the controller never reads the names).
    pub large: Vec<u8>,
}

fn plan(grounding: planner::ground::Grounding) -> Result<(Vec<u8>, Vec<bt_core::Node>)> {
    let grounding = Arc::new(grounding);
    let catalog = Arc::new(planner::PddlCatalog::new(grounding.problem()));
    let plan = planner::plan(grounding, catalog.clone(), planner::Options::default()).map_err(|e| e.to_string())?;
    let image = bt_formats::Image::new(&plan.nodes)
        .encode(bt_core::Catalog::fingerprint(catalog.as_ref()))
        .map_err(|e| e.to_string())?;
    Ok((image, plan.nodes))
}

fn actions(nodes: &[bt_core::Node]) -> Vec<u16> {
    (0..nodes.len() as u16).filter(|&i| matches!(nodes[usize::from(i)].kind(), bt_core::NodeKind::Action(_))).collect()
}

/// The size of the large image.
pub const LARGE: usize = 16 * 1024;

/// `nodes` with a names section of filler that makes the image exactly `len` bytes.
fn padded(nodes: &[bt_core::Node], fingerprint: u64, len: usize) -> Result<Vec<u8>> {
    let encode = |names: usize| -> Result<Vec<u8>> {
        let filler: Vec<u8> = (0..names).map(|i| b"names "[i % 6]).collect();
        let parts = bt_core::image::ImageParts::new(nodes).names(&filler);
        let mut out = vec![0u8; len + 64];
        let n = bt_core::encode_with(&parts, fingerprint, &mut out).map_err(|e| e.to_string())?;
        out.truncate(n);
        Ok(out)
    };
    // The section's length prefix grows with it: try the lengths around the estimate.
    let estimate = len.saturating_sub(encode(0)?.len());
    for names in estimate.saturating_sub(8)..=estimate + 8 {
        let image = encode(names)?;
        if image.len() == len {
            return Ok(image);
        }
    }
    Err(format!("no names section makes the image {len} bytes"))
}

/// A and B from the planner, and B for the tower task's behavior set.
pub fn images() -> Result<Images> {
    let blocked = planner::domains::cube_sphere_blocked().map_err(|e| e.to_string())?;
    let catalog = planner::PddlCatalog::new(blocked.problem());
    let fingerprint = catalog.fingerprint();
    // A is the firmware's boot tree: the planner's, expanded for the cube in the hand.
    let a = crate::firmware_tree::image()?;
    let header = bt_core::image::read_header(&a).map_err(|e| e.to_string())?;
    let mut a_nodes = vec![bt_core::Node::EMPTY; usize::from(header.node_count)];
    let a_tree: bt_core::Tree<'_, { planner::DEPTH }> =
        bt_core::load(&a, &catalog, &mut a_nodes).map_err(|e| e.to_string())?;
    let a_nodes = a_tree.nodes().to_vec();
    let (b, b_nodes) = plan(planner::domains::cube_sphere().map_err(|e| e.to_string())?)?;
    let tower = planner::duplo::Task::Tower.spec().fingerprint();
    let mut foreign = vec![0u8; bt_core::image::max_image_len(b_nodes.len())];
    let n = bt_core::encode(&b_nodes, tower, &mut foreign).map_err(|e| e.to_string())?;
    foreign.truncate(n);
    let large = padded(&a_nodes, fingerprint, LARGE)?;
    Ok(Images { a, b, actions: (actions(&a_nodes), actions(&b_nodes)), foreign, fingerprint, large })
}

/// What the driver saw on the link, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Seen {
    Status { tick: u32, node: u16, status: WireStatus },
    Tick(u32),
    Swapped { tick: u32, crc: u32, halted: u16 },
    Garbled(FrameFault),
    Lost(u16),
}

fn record(log: &mut Vec<Seen>, r: &Reply<'_>) {
    match *r {
        Reply::Status { tick, node, status } => log.push(Seen::Status { tick, node, status }),
        Reply::Tick { tick, .. } => log.push(Seen::Tick(tick)),
        Reply::Swapped { tick, image, halted } => log.push(Seen::Swapped { tick, crc: image.crc, halted }),
        Reply::Garbled { fault } => log.push(Seen::Garbled(fault)),
        Reply::Lost { frames, .. } => log.push(Seen::Lost(frames)),
        _ => {}
    }
}

/// What one scenario run produced.
pub struct Outcome {
    /// The controller's trace.
    pub trace: String,
    /// Fault cases refused or skipped with the right reason.
    pub faults: Vec<String>,
    /// Stack the controller reported using.
    pub stack_used: u32,
    /// Bytes of B and how long its deployment took (unpaced).
    pub deploy: (usize, Duration),
}

/// Waits until `pred` holds for a recorded event, reading replies meanwhile.
fn wait_for(
    link: &mut Client<TcpStream>,
    log: &mut Vec<Seen>,
    what: &'static str,
    pred: impl Fn(&Seen) -> bool,
) -> Result {
    let deadline = Instant::now() + Duration::from_secs(20);
    while !log.iter().any(&pred) {
        let r = link.next(deadline, what).map_err(|e| e.to_string())?;
        record(log, &r);
    }
    Ok(())
}

/// Halt before start across trees, from the status stream: at the swap before tick
/// `tick`, the actions of the old tree that were Running after its last tick are
/// reported Idle before `Swapped`, there was at least one, their count is the
/// `halted` of `Swapped`, and no node of the new tree changes before `Swapped`.
fn check_swap(log: &[Seen], tick: u32, old_actions: &[u16]) -> Result<usize> {
    let swapped = log
        .iter()
        .position(|s| matches!(s, Seen::Swapped { tick: t, .. } if *t == tick))
        .ok_or(format!("no Swapped at tick {tick}"))?;
    let last_tick = log[..swapped]
        .iter()
        .rposition(|s| matches!(s, Seen::Tick(t) if t + 1 == tick))
        .ok_or(format!("no tick {} before the swap", tick - 1))?;
    let mut status = std::collections::BTreeMap::new();
    let tree_start = log[..last_tick].iter().rposition(|s| matches!(s, Seen::Swapped { .. })).map_or(0, |i| i + 1);
    for s in &log[tree_start..=last_tick] {
        if let Seen::Status { node, status: st, .. } = *s {
            status.insert(node, st);
        }
    }
    let running: Vec<u16> =
        old_actions.iter().copied().filter(|n| status.get(n) == Some(&WireStatus::Running)).collect();
    if running.is_empty() {
        return Err(format!("no action of the old tree was running at tick {}: nothing to check", tick - 1));
    }
    for s in &log[last_tick + 1..swapped] {
        match *s {
            Seen::Status { tick: t, node, status: WireStatus::Idle } if t == tick => {
                status.insert(node, WireStatus::Idle);
            }
            Seen::Status { .. } => {
                return Err(format!("a node changed to a status other than Idle at the swap: {s:?}"));
            }
            _ => {}
        }
    }
    if let Some(n) = running.iter().find(|n| status.get(n) != Some(&WireStatus::Idle)) {
        return Err(format!("action node {n} of the old tree was not halted before the swap at tick {tick}"));
    }
    let Seen::Swapped { halted, .. } = log[swapped] else { unreachable!() };
    if usize::from(halted) != running.len() {
        return Err(format!("Swapped reports {halted} halted actions, the stream shows {}", running.len()));
    }
    Ok(running.len())
}

/// Drives one controller (QEMU or host) through the scenario over `stream`.
fn drive(stream: TcpStream, img: &Images, report: &mut Vec<String>) -> Result<(u32, (usize, Duration))> {
    stream.set_read_timeout(Some(Duration::from_millis(20))).map_err(|e| e.to_string())?;
    let _ = stream.set_nodelay(true);
    let mut link = Client::new(stream);
    let mut log: Vec<Seen> = Vec::new();
    let e = |e: bt_link::host::LinkError| e.to_string();

    let hello = link.hello().map_err(e)?;
    if hello.fingerprint != img.fingerprint {
        return Err(format!("controller behavior set {:#018x}, expected {:#018x}", hello.fingerprint, img.fingerprint));
    }
    if hello.running.map(|r| r.crc) != Some(image_crc(&img.a)) {
        return Err(format!("the controller does not run tree A at boot: {:?}", hello.running));
    }

    // 1. A ticks while B arrives; B swaps in at tick SWAP_B.
    link.start(Some(SWAP_B), PERIOD_MS, &mut |r| record(&mut log, r)).map_err(e)?;
    let started = Instant::now();
    let verdict = link.deploy(&img.b, Some(SWAP_B), &mut |r| record(&mut log, r)).map_err(e)?;
    let took = started.elapsed();
    if !matches!(verdict, Verdict::Accepted { .. }) {
        return Err(format!("tree B was not accepted: {verdict:?}"));
    }
    let during = log.iter().filter(|s| matches!(s, Seen::Tick(_))).count();
    wait_for(&mut link, &mut log, "Swapped", |s| matches!(s, Seen::Swapped { tick, .. } if *tick == SWAP_B))?;
    let halted = check_swap(&log, SWAP_B, &img.actions.0)?;
    report.push(format!(
        "A -> B at tick {SWAP_B}: {} of A halted before B's first tick ({} of A ran while B was sent)",
        halted_actions(halted),
        count(during, "tick", "ticks")
    ));

    // 2. Faults while B ticks on.
    link.start(Some(SWAP_A), PERIOD_MS, &mut |r| record(&mut log, r)).map_err(e)?;
    let b_crc = image_crc(&img.b);
    let mut bad_crc = img.b.clone();
    bad_crc[bt_core::image::HEADER_LEN] ^= 1;
    let half = img.b.len() / 2;
    let junk: Vec<u8> = (0..300u32).map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8).collect();
    let cases: Vec<(&str, Transfer<'_>, &str)> = vec![
        ("B with one bit flipped", Transfer::of(&bad_crc, None), "crc-mismatch"),
        ("B corrupted in transit", Transfer { flip: Some(half), ..Transfer::of(&img.b, None) }, "transfer-crc"),
        ("B's transfer cut short", Transfer { bytes: &img.b[..half], ..Transfer::of(&img.b, None) }, "incomplete"),
        ("B's image cut short (16 bytes)", Transfer::of(&img.b[..16], None), "truncated"),
        ("B for a foreign behavior set", Transfer::of(&img.foreign, None), "foreign-behavior-set"),
        (
            "an image larger than the buffer",
            Transfer { len: hello.image_capacity + 1, ..Transfer::of(&img.b, None) },
            "too-large",
        ),
        (
            "garbage between the chunks of B with one bit flipped",
            Transfer { garbage: Some((1, &junk)), ..Transfer::of(&bad_crc, None) },
            "crc-mismatch",
        ),
    ];
    let mut last_tick = 0;
    for (what, transfer, expected) in &cases {
        let verdict = link.transfer(transfer, &mut |r| record(&mut log, r)).map_err(e)?;
        let Verdict::Rejected(fault) = verdict else {
            return Err(format!("{what}: accepted, expected {expected}"));
        };
        if fault.code() != *expected {
            return Err(format!("{what}: refused with {}, expected {expected}", fault.code()));
        }
        let state = link.ping(7, &mut |r| record(&mut log, r)).map_err(e)?;
        if state.running.map(|r| r.crc) != Some(b_crc) {
            return Err(format!("{what}: the running image changed to {:?}", state.running));
        }
        report.push(format!("{what}: refused ({}), B still running at tick {}", detail(&fault), state.tick));
        last_tick = state.tick;
    }
    // Garbage between frames, outside any transfer: each bad frame is skipped with its
    // reason, and the next frame is understood.
    let before = log.len();
    link.raw(&[0x00, 0x05, 0x41, 0x00]).map_err(e)?; // a COBS run cut short
    link.raw(&[0x03, 0x13, 0x37, 0x00]).map_err(e)?; // too short for a CRC
    link.raw(&[0x07, 1, 2, 3, 4, 5, 6, 0x00]).map_err(e)?; // a wrong CRC
    link.raw(&junk).map_err(e)?;
    link.raw(&[0x00]).map_err(e)?;
    let state = link.ping(8, &mut |r| record(&mut log, r)).map_err(e)?;
    let garbled: Vec<&str> = log[before..]
        .iter()
        .filter_map(|s| match s {
            Seen::Garbled(f) => Some(f.code()),
            _ => None,
        })
        .collect();
    if garbled.len() < 3 || garbled[..3] != ["bad-cobs", "frame-too-short", "frame-crc"] {
        return Err(format!("garbage between frames: skipped as {garbled:?}"));
    }
    if state.running.map(|r| r.crc) != Some(b_crc) || state.tick < last_tick {
        return Err(format!("garbage between frames: the controller's state changed: {state:?}"));
    }
    report.push(format!(
        "garbage between frames: {} frames skipped ({}), B still running",
        garbled.len(),
        garbled.join(", ")
    ));

    // 3. A comes back at tick SWAP_A and runs to the end.
    let verdict = link.deploy(&img.a, Some(SWAP_A), &mut |r| record(&mut log, r)).map_err(e)?;
    if !matches!(verdict, Verdict::Accepted { .. }) {
        return Err(format!("tree A was not accepted back: {verdict:?}"));
    }
    wait_for(&mut link, &mut log, "Swapped", |s| matches!(s, Seen::Swapped { tick, .. } if *tick == SWAP_A))?;
    let halted = check_swap(&log, SWAP_A, &img.actions.1)?;
    report.push(format!("B -> A at tick {SWAP_A}: {} of B halted before A's first tick", halted_actions(halted)));
    link.start(Some(END), PERIOD_MS, &mut |r| record(&mut log, r)).map_err(e)?;
    wait_for(&mut link, &mut log, "the last Tick", |s| matches!(s, Seen::Tick(t) if t + 1 == END))?;
    let stopped = link.stop(&mut |r| record(&mut log, r)).map_err(e)?;
    let state = link.ping(9, &mut |r| record(&mut log, r)).map_err(e)?;
    let ticks: Vec<u32> = log.iter().filter_map(|s| if let Seen::Tick(t) = s { Some(*t) } else { None }).collect();
    if ticks != (0..END).collect::<Vec<_>>() {
        return Err(format!("ticks reported: {} (expected 0..{END} once each, in order)", ticks.len()));
    }
    let lost: u32 = log.iter().map(|s| if let Seen::Lost(n) = s { u32::from(*n) } else { 0 }).sum();
    if lost > 0 {
        return Err(format!("the controller dropped {lost} status frames: its transmit queue is too small"));
    }
    report.push(format!("stop at tick {}: {} halted", stopped.tick, halted_actions(stopped.halted as usize)));
    let _ = link.io().shutdown(Shutdown::Both);
    Ok((state.stack_used, (img.b.len(), took)))
}

fn detail(f: &Fault) -> String {
    match *f {
        Fault::Load { node: Some(n), .. } => format!("{} at node {n}", f.code()),
        Fault::TransferCrc { expected, computed } => {
            format!("{}: announced {expected:08x}, received {computed:08x}", f.code())
        }
        Fault::Incomplete { received, len } => format!("{}: {received} of {len} bytes", f.code()),
        Fault::TooLarge { len, capacity } => format!("{}: {len} bytes, buffer {capacity}", f.code()),
        _ => f.code().to_string(),
    }
}

trait ReadWrite: Read + std::io::Write {}
impl<T: Read + std::io::Write> ReadWrite for T {}

/// A free TCP port on the loopback interface.
pub(crate) fn free_port() -> Result<u16> {
    let l = TcpListener::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
    Ok(l.local_addr().map_err(|e| e.to_string())?.port())
}

fn connect(port: u16, child: &mut Child, timeout: Duration) -> Result<TcpStream> {
    let started = Instant::now();
    loop {
        if let Ok(s) = TcpStream::connect(("127.0.0.1", port)) {
            return Ok(s);
        }
        if let Ok(Some(status)) = child.try_wait() {
            return Err(format!("the controller exited before accepting a connection ({status})"));
        }
        if started.elapsed() > timeout {
            return Err(format!("could not connect to the controller on port {port}"));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Runs the scenario against `cmd`, a controller that listens on `port`.
fn run(mut cmd: Command, port: u16, img: &Images, timeout: Duration, exits: bool) -> Result<Outcome> {
    let shown = format!("{cmd:?}");
    let mut child =
        cmd.stdin(Stdio::null()).stdout(Stdio::piped()).spawn().map_err(|e| format!("cannot start {shown}: {e}"))?;
    let mut stdout = child.stdout.take().ok_or("no stdout")?;
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = stdout.read_to_string(&mut s);
        s
    });
    let result = connect(port, &mut child, timeout).and_then(|stream| {
        let mut faults = Vec::new();
        drive(stream, img, &mut faults).map(|(stack, deploy)| (faults, stack, deploy))
    });
    if exits && result.is_ok() {
        let started = Instant::now();
        while child.try_wait().ok().flatten().is_none() && started.elapsed() < timeout {
            std::thread::sleep(Duration::from_millis(10));
        }
    }
    // QEMU never exits on its own: everything the scenario checks has been traced by
    // the time the last Ping is answered.
    let _ = child.kill();
    let _ = child.wait();
    let trace = reader.join().map_err(|_| "reading the trace failed")?;
    let (faults, stack_used, deploy) = result.map_err(|e| format!("{e}\n{}", tail(&trace)))?;
    Ok(Outcome { trace, faults, stack_used, deploy })
}

pub(crate) fn tail(out: &str) -> String {
    let lines: Vec<&str> = out.lines().collect();
    lines[lines.len().saturating_sub(6)..].join("\n")
}

/// The scenario on the host build of the controller.
pub fn host(bin: &Path, img: &Images, timeout: Duration) -> Result<Outcome> {
    let port = free_port()?;
    run(host_command(bin, port), port, img, timeout, true)
}

/// A QEMU board a controller runs on.
#[derive(Clone, Copy, Debug)]
pub struct Machine {
    /// How the reports name it.
    pub name: &'static str,
    /// `qemu-system-arm`'s CPU, machine and semihosting arguments.
    pub args: &'static [&'static str],
}

/// The MPS2 AN386 (Cortex-M4F): `firmware-example`'s programs.
pub const MPS2: Machine = Machine { name: "mps2-an386 (Cortex-M4F)", args: &crate::qemu::QEMU_ARGS };
/// The LM3S6965 evaluation board (Cortex-M3): the RTIC program in `examples/lm3s6965-rtic`.
pub const LM3S6965: Machine = Machine {
    name: "lm3s6965evb (Cortex-M3, RTIC)",
    args: &[
        "-cpu",
        "cortex-m3",
        "-machine",
        "lm3s6965evb",
        "-nographic",
        "-semihosting-config",
        "enable=on,target=native",
    ],
};

/// The QEMU command line for the controller ELF on `machine`, its UART0 on a TCP
/// server `port`.
pub fn qemu_command(machine: Machine, elf: &Path, port: u16) -> Command {
    let mut cmd = Command::new("qemu-system-arm");
    // `-nographic` would put QEMU's monitor on stdout, among the trace: none.
    cmd.args(machine.args)
        .args(["-monitor", "none"])
        .arg("-serial")
        .arg(format!("tcp:127.0.0.1:{port},server=on,wait=on,nodelay=on"))
        .arg("-kernel")
        .arg(elf);
    cmd
}

/// The scenario under QEMU.
pub fn qemu(machine: Machine, elf: &Path, img: &Images, timeout: Duration) -> Result<Outcome> {
    let port = free_port()?;
    run(qemu_command(machine, elf, port), port, img, timeout, false)
}

/// One timed deployment of the cube tree.
#[derive(Clone, Copy, Debug)]
pub struct Timed {
    /// Image bytes.
    pub image: usize,
    /// Bytes on the wire, both ways.
    pub wire: u64,
    /// From `Deploy` to `Accepted`.
    pub took: Duration,
}

impl Timed {
    /// The time the wire bytes take at `baud` (10 bits a byte), one way after the other.
    pub fn wire_time(&self, baud: u32) -> Duration {
        Duration::from_secs_f64(self.wire as f64 * 10.0 / f64::from(baud))
    }
}

/// Deploys `measured` to a controller, `rounds` times with `other` in between (so that
/// every deployment swaps), through a link paced at `baud` (10 bits per byte) as a
/// serial line would carry it, or unpaced; returns the best of `measured`'s. `cmd`
/// starts the controller listening on `port`.
pub fn timed_deploy(
    mut cmd: Command,
    port: u16,
    (measured, other): (&[u8], &[u8]),
    baud: Option<u32>,
    rounds: usize,
    timeout: Duration,
) -> Result<Timed> {
    let mut child = cmd.stdin(Stdio::null()).stdout(Stdio::null()).spawn().map_err(|e| e.to_string())?;
    let result = (|| {
        let stream = connect(port, &mut child, timeout)?;
        stream.set_read_timeout(Some(Duration::from_millis(1))).map_err(|e| e.to_string())?;
        let _ = stream.set_nodelay(true);
        let io: Box<dyn ReadWrite> = match baud {
            Some(baud) => Box::new(Paced::new(stream, baud)),
            None => Box::new(stream),
        };
        let mut link = Client::new(io);
        link.hello().map_err(|e| e.to_string())?;
        let mut best: Option<Timed> = None;
        for _ in 0..rounds {
            for image in [other, measured] {
                let (sent, received) = (link.sent, link.received);
                let started = Instant::now();
                let verdict = link.deploy(image, None, &mut |_| {}).map_err(|e| e.to_string())?;
                let took = started.elapsed();
                if !matches!(verdict, Verdict::Accepted { .. }) {
                    return Err(format!("the tree was not accepted: {verdict:?}"));
                }
                if image == measured {
                    let t = Timed { image: image.len(), wire: link.sent - sent + link.received - received, took };
                    best = Some(best.map_or(t, |b| if t.took < b.took { t } else { b }));
                }
            }
        }
        best.ok_or_else(|| "no deployment timed".to_string())
    })();
    let _ = child.kill();
    let _ = child.wait();
    result
}

/// A command for the host build of the controller, listening on `port`.
pub fn host_command(bin: &Path, port: u16) -> Command {
    let mut cmd = Command::new(bin);
    cmd.arg("--listen").arg(format!("127.0.0.1:{port}"));
    cmd
}

/// A free TCP port, for [`timed_deploy`].
pub fn port() -> Result<u16> {
    free_port()
}

/// `n` with its noun: `1 tick`, `2 ticks`.
fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// `1 action halted`-style counts of actions.
fn halted_actions(n: usize) -> String {
    count(n, "action", "actions")
}
