//! The blend scenario of `cargo xtask qemu`: blended planning and acting with the tree
//! growing on the link controller (`sim-host blend`, Colledanchise et al. 2019,
//! Algorithm 1 at run time), under QEMU and on the controller's host build.
//!
//! 1. `sim-host blend` from the goal of `planner/domains/cube-sphere/problem.pddl`,
//!    against the host build and against QEMU. Each must reach the goal; the
//!    controller's first tree has 1 node; every grown tree swaps in at the tick the host
//!    named, as the image it sent; the controller traces of QEMU and the host are
//!    identical, and so are the two sessions as the host recorded them.
//! 2. The trees grown equal, expansion for expansion (condition, achieving actions,
//!    conflicts, the tree after), those `sim-host scenario cube` grows in the symbolic
//!    and the physics world, and the last one is the firmware's own tree (the end of
//!    Example 2), byte for byte.
//! 3. A learned tree reaches the controller: `sim-host learn` on the same problem with
//!    disturbances, `sim-host deploy best.bt`, `sim-host monitor --start`; it must reach
//!    the goal under the plant's scripted events. It is compared with the planner's tree
//!    for the same problem and the firmware's tree: ticks to the goal, nodes, halts.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::{Result, cargo, root, step, target_dir};

/// Milliseconds between ticks: short, for CI's time (the session is the same at any
/// period; only how often the controller waits for the host changes).
const PERIOD_MS: &str = "20";
/// Ticks the controller runs ahead of the host.
const LEAD: &str = "3";
/// Ticks the fixed trees are watched for.
const WATCH: &str = "200";
/// Generations of the learned tree's GP run.
const GENERATIONS: &str = "50";

fn domain() -> PathBuf {
    root().join("planner/domains/cube-sphere/domain.pddl")
}

fn problem() -> PathBuf {
    root().join("planner/domains/cube-sphere/problem.pddl")
}

/// A controller running in the background, its trace read as it prints it.
struct Controller {
    child: Child,
    trace: JoinHandle<String>,
    addr: String,
}

impl Controller {
    fn start(mut cmd: Command, port: u16) -> Result<Self> {
        let shown = format!("{cmd:?}");
        let mut child = cmd
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| format!("cannot start {shown}: {e}"))?;
        let mut stdout = child.stdout.take().ok_or("no stdout")?;
        let trace = std::thread::spawn(move || {
            let mut s = String::new();
            let _ = stdout.read_to_string(&mut s);
            s
        });
        // Wait until it says it listens, without connecting (the host build serves one
        // connection, QEMU boots the firmware on the first) or binding the port (which
        // could take it from the controller): the host build says `listening on`, QEMU
        // `waiting for connection`.
        let stderr = child.stderr.take().ok_or("no stderr")?;
        let (ready, listening) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            for line in std::io::BufRead::lines(std::io::BufReader::new(stderr)).map_while(std::result::Result::ok) {
                if line.contains("listening on") || line.contains("waiting for connection") {
                    let _ = ready.send(());
                }
            }
        });
        if listening.recv_timeout(Duration::from_secs(20)).is_err() {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("{shown} did not say it listens on port {port}"));
        }
        Ok(Self { child, trace, addr: format!("127.0.0.1:{port}") })
    }

    /// Ends the controller (the host build has ended when its connection closed) and
    /// returns its trace.
    fn finish(mut self) -> Result<String> {
        let started = Instant::now();
        while self.child.try_wait().ok().flatten().is_none() && started.elapsed() < Duration::from_millis(300) {
            std::thread::sleep(Duration::from_millis(10));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
        self.trace.join().map_err(|_| "reading the controller's trace failed".into())
    }
}

/// `sim-host ARGS`, its stdout; a failure names the command and shows its output.
fn sim_host(bin: &Path, args: &[&str], timeout: Duration) -> Result<String> {
    let shown = format!("sim-host {}", args.join(" "));
    let mut child = Command::new(bin)
        .args(args)
        .current_dir(root())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start {shown}: {e}"))?;
    let read = |mut r: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut s = String::new();
            let _ = r.read_to_string(&mut s);
            s
        })
    };
    let stdout = read(Box::new(child.stdout.take().ok_or("no stdout")?));
    let stderr = read(Box::new(child.stderr.take().ok_or("no stderr")?));
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| format!("{shown}: {e}"))? {
            break Some(status);
        }
        if started.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let (stdout, stderr) = (stdout.join().unwrap_or_default(), stderr.join().unwrap_or_default());
    match status {
        Some(s) if s.success() => Ok(stdout),
        Some(s) => Err(format!("{shown} failed ({s}):\n{}\n{stderr}", crate::link::tail(&stdout))),
        None => Err(format!("{shown}: no end after {} s:\n{}", timeout.as_secs(), crate::link::tail(&stdout))),
    }
}

/// One blended session: the narration, the session as the host recorded it, and the
/// controller's trace.
struct Session {
    narration: String,
    recorded: String,
    trace: String,
}

fn blend(bin: &Path, controller: Controller, dir: &Path, name: &str, timeout: Duration) -> Result<Session> {
    let recorded = dir.join(format!("blend-{name}.txt"));
    let (d, p) = (domain(), problem());
    let args = [
        "blend",
        "--domain",
        path(&d)?,
        "--problem",
        path(&p)?,
        "--tcp",
        &controller.addr,
        "--period",
        PERIOD_MS,
        "--lead",
        LEAD,
        "--trace",
        path(&recorded)?,
    ];
    let narration = sim_host(bin, &args, timeout);
    let trace = controller.finish()?;
    let narration = narration.map_err(|e| format!("{e}\ncontroller:\n{}", crate::link::tail(&trace)))?;
    let recorded = std::fs::read_to_string(&recorded).map_err(|e| format!("{}: {e}", recorded.display()))?;
    Ok(Session { narration, recorded, trace })
}

fn path(p: &Path) -> Result<&str> {
    p.to_str().ok_or_else(|| format!("{}: not UTF-8", p.display()))
}

/// The swaps of a controller trace: (tick, crc, nodes).
fn swaps(trace: &str) -> Vec<(u32, String, u32)> {
    trace
        .lines()
        .filter_map(|l| l.strip_prefix("swap "))
        .filter_map(|l| {
            let tick = l.split(' ').next()?.parse().ok()?;
            Some((tick, value(l, "crc=")?.to_string(), value(l, "nodes=")?.parse().ok()?))
        })
        .collect()
}

/// The trees the host sent, from its record: (swap tick named, crc, nodes).
fn named(recorded: &str) -> Vec<(u32, String, u32)> {
    recorded
        .lines()
        .filter_map(|l| l.strip_prefix("expand "))
        .filter_map(|l| {
            Some((
                value(l, "swap_at=")?.parse().ok()?,
                value(l, "image=")?.to_string(),
                value(l, "nodes=")?.parse().ok()?,
            ))
        })
        .collect()
}

/// The value after `key` in a line of `key=value` fields.
fn value<'a>(line: &'a str, key: &str) -> Option<&'a str> {
    line.split(' ').find_map(|w| w.strip_prefix(key))
}

/// The expansions of a narration, each with its conflicts and the tree it made.
fn expansions(narration: &str) -> String {
    let mut out = String::new();
    let mut tree = false;
    for l in narration.lines() {
        let own = ["expansion ", "conflict: ", "the tree now "].iter().any(|p| l.trim_start().starts_with(p))
            && l.starts_with("          ")
            && !l.starts_with("           ");
        if own {
            tree = l.trim_start().starts_with("the tree now ");
            out.push_str(l);
            out.push('\n');
        } else if tree && l.starts_with("            ") {
            out.push_str(l);
            out.push('\n');
        } else {
            tree = false;
        }
    }
    out
}

/// The checks of one session, and its figures for the log.
fn check(s: &Session, on: &str) -> Result<Vec<(u32, String, u32)>> {
    if !s.narration.contains("the root succeeds: the goal holds") {
        return Err(format!("{on}: the blended session did not reach the goal:\n{}", crate::link::tail(&s.narration)));
    }
    let swapped = swaps(&s.trace);
    match swapped.first() {
        Some((_, _, 1)) => {}
        other => return Err(format!("{on}: the controller's first tree is {other:?}, not the goal alone (1 node)")),
    }
    let sent = named(&s.recorded);
    if swapped[1..] != sent[..] {
        return Err(format!("{on}: the controller swapped in {:?}; the host named {sent:?}", &swapped[1..]));
    }
    Ok(swapped)
}

/// Runs the scenario (see the module's documentation).
pub fn scenario(elf: &Path, host_bin: &Path, timeout: Duration) -> Result {
    let begun = Instant::now();
    step("blend: sim-host (debug build)");
    crate::run(cargo().args(["build", "--quiet", "-p", "sim-host"]))?;
    let bin = target_dir().join("debug").join("sim-host");
    let dir = target_dir().join("blend");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;

    step("blend: the tree grows from the goal on the host build of the controller (TCP)");
    let port = crate::link::free_port()?;
    let mut cmd = Command::new(host_bin);
    cmd.arg("--listen").arg(format!("127.0.0.1:{port}"));
    let started = Instant::now();
    let host = blend(&bin, Controller::start(cmd, port)?, &dir, "host", timeout)?;
    let host_wall = started.elapsed();
    step("blend: the tree grows from the goal under QEMU (UART0 on a TCP socket)");
    let port = crate::link::free_port()?;
    let started = Instant::now();
    let target = blend(
        &bin,
        Controller::start(crate::link::qemu_command(crate::link::MPS2, elf, port), port)?,
        &dir,
        "qemu",
        timeout,
    )?;
    let qemu_wall = started.elapsed();
    let told = |l: &&str| ["expansion ", "planned in "].iter().any(|p| l.trim_start().starts_with(p));
    for line in target.narration.lines().filter(told) {
        eprintln!("  {}", line.trim_start());
    }
    let swapped = check(&host, "host")?;
    check(&target, "QEMU")?;
    let ticks = crate::qemu::compare(&target.trace, &host.trace)?;
    let unmeasured = |t: &str| t.lines().map(|l| l.split(" us=").next().unwrap_or(l).to_owned()).collect::<Vec<_>>();
    if unmeasured(&target.recorded) != unmeasured(&host.recorded) {
        return Err("the sessions as the host recorded them differ between QEMU and the host build".into());
    }
    eprintln!(
        "controller traces identical ({ticks} ticks), sessions identical; the tree grew from 1 node in {} swaps, \
         each at the tick the host named ({:.1} s under QEMU, {:.1} s on the host, {PERIOD_MS} ms a tick)",
        swapped.len() - 1,
        qemu_wall.as_secs_f64(),
        host_wall.as_secs_f64()
    );
    for line in target.narration.lines().skip_while(|l| !l.starts_with("summary:")) {
        eprintln!("  {}", line.trim_start());
    }

    step("blend: the same expansions as `sim-host scenario cube`, and the firmware's tree");
    let grown = expansions(&target.narration);
    for world in ["symbolic", "physics"] {
        let scenario = sim_host(&bin, &["scenario", "cube", "--world", world], timeout)?;
        if expansions(&scenario) != grown {
            return Err(format!(
                "the trees grown on the controller differ from those of `sim-host scenario cube --world {world}`:\n\
                 controller:\n{grown}\nscenario:\n{}",
                expansions(&scenario)
            ));
        }
    }
    let firmware = crate::firmware_tree::image()?;
    let crc = format!("{:08x}", bt_link::image_crc(&firmware));
    let last = swapped.last().map(|s| s.1.clone()).unwrap_or_default();
    if last != crc {
        return Err(format!("the last tree grown is image {last}, the firmware's tree is {crc}"));
    }
    eprintln!(
        "{} expansions, each as `sim-host scenario cube` grows them (symbolic and physics worlds); the last tree is \
         the firmware's, the end of Example 2 (image {crc})",
        grown.lines().filter(|l| l.trim_start().starts_with("expansion ")).count()
    );
    learned(&bin, elf, &dir, &host, timeout)?;
    eprintln!("blend scenario: {:.0} s", begun.elapsed().as_secs_f64());
    Ok(())
}

/// What a fixed tree did on the controller: ticks to the goal, nodes, halts.
struct Fixed {
    goal: Option<u32>,
    nodes: u32,
    halts: usize,
}

/// The goal tick, the last tree's nodes, and the actions halted up to the goal, of a
/// controller's trace.
fn fixed(trace: &str) -> Fixed {
    let nodes = swaps(trace).last().map_or(0, |s| s.2);
    let mut halts = 0;
    let mut goal = None;
    for l in trace.lines().filter_map(|l| l.strip_prefix("tick ")) {
        let halted = value(l, "halt=").unwrap_or("-");
        if halted != "-" {
            halts += halted.split(',').count();
        }
        if l.split(' ').nth(1) == Some("SUCCESS") {
            goal = l.split(' ').next().and_then(|t| t.parse().ok());
            break;
        }
    }
    Fixed { goal, nodes, halts }
}

/// Deploys `tree` to a fresh controller under QEMU and watches it tick (the CLI's
/// `deploy`, then `monitor --start`).
fn run_fixed(bin: &Path, elf: &Path, tree: &Path, timeout: Duration) -> Result<Fixed> {
    let port = crate::link::free_port()?;
    let controller = Controller::start(crate::link::qemu_command(crate::link::MPS2, elf, port), port)?;
    let addr = controller.addr.clone();
    let result = sim_host(bin, &["deploy", path(tree)?, "--tcp", &addr], timeout).and_then(|_| {
        sim_host(bin, &["monitor", "--tcp", &addr, "--start", "--period", PERIOD_MS, "--ticks", WATCH], timeout)
    });
    let trace = controller.finish()?;
    result?;
    Ok(fixed(&trace))
}

/// Step 3: a learned tree, the planner's and the firmware's, each on the controller.
fn learned(bin: &Path, elf: &Path, dir: &Path, blended: &Session, timeout: Duration) -> Result {
    step("blend: a learned tree on the controller (sim-host learn, deploy, monitor under QEMU)");
    let (d, p) = (domain(), problem());
    let runs = dir.join("runs");
    let learn = [
        "learn",
        "--domain",
        path(&d)?,
        "--problem",
        path(&p)?,
        "--disturb",
        "0.1",
        "--seeds",
        "1",
        "--generations",
        GENERATIONS,
        "--out",
        path(&runs)?,
    ];
    let started = Instant::now();
    sim_host(bin, &learn, timeout)?;
    let learn_wall = started.elapsed();
    let best = std::fs::read_dir(&runs)
        .map_err(|e| format!("{}: {e}", runs.display()))?
        .flatten()
        .map(|e| e.path().join("best.bt"))
        .find(|b| b.exists())
        .ok_or("sim-host learn wrote no best.bt")?;
    let planned = dir.join("planned.bt");
    sim_host(
        bin,
        &["plan", "--domain", path(&d)?, "--problem", path(&p)?, "--format", "image", "--out", path(&planned)?],
        timeout,
    )?;
    let firmware = dir.join("firmware.bt");
    std::fs::write(&firmware, crate::firmware_tree::image()?).map_err(|e| format!("{}: {e}", firmware.display()))?;
    let mut rows = Vec::new();
    for (name, tree) in [
        ("learned (GP, baseline, --disturb 0.1)", &best),
        ("planned offline (Fig. 3(e), the GP's baseline)", &planned),
        ("the firmware's tree (end of Example 2)", &firmware),
    ] {
        rows.push((name, run_fixed(bin, elf, tree, timeout)?));
    }
    let b = fixed(&blended.trace);
    eprintln!(
        "{learn_wall:.1?} to learn ({GENERATIONS} generations); on the controller under QEMU, the plant's scripted events:"
    );
    eprintln!("  {:<48} {:>13} {:>6} {:>6}", "tree", "ticks to goal", "nodes", "halts");
    let show = |g: Option<u32>| g.map_or_else(|| "not reached".to_string(), |t| t.to_string());
    for (name, f) in &rows {
        eprintln!("  {name:<48} {:>13} {:>6} {:>6}", show(f.goal), f.nodes, f.halts);
    }
    eprintln!("  {:<48} {:>13} {:>6} {:>6}", "blended from the goal (sim-host blend)", show(b.goal), b.nodes, b.halts);
    match rows.first() {
        Some((_, f)) if f.goal.is_some() => Ok(()),
        _ => Err("the learned tree did not reach the goal on the controller".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn swaps_and_named_trees_read_the_same_fields() {
        let trace = "boot image=162B nodes=37 crc=c43c2289 fp=1\nswap 0 image=26B nodes=1 crc=5a7b268c halt=-\n\
                     swap 4 image=46B nodes=6 crc=08dbdad6 halt=3,4\n";
        let recorded = "image 5a7b268c nodes=1\nexpand 0 `at(cube, goal)` nodes=6 image=08dbdad6 bytes=46 swap_at=4\n";
        let s = swaps(trace);
        assert_eq!(s, [(0, "5a7b268c".to_string(), 1), (4, "08dbdad6".to_string(), 6)]);
        assert_eq!(named(recorded), s[1..]);
    }

    #[test]
    fn a_fixed_run_counts_halts_up_to_the_goal() {
        let trace = "swap 0 image=26B nodes=15 crc=1 halt=-\ntick 0 FAILURE ran=0F act=- halt=- robot=0,0\n\
                     tick 1 RUNNING ran=0F act=3 halt=2,5 robot=0,0\ntick 2 SUCCESS ran=0S act=- halt=7 robot=0,0\n\
                     tick 3 SUCCESS ran=0S act=- halt=9 robot=0,0\n";
        let f = fixed(trace);
        assert_eq!((f.goal, f.nodes, f.halts), (Some(2), 15, 3));
    }

    #[test]
    fn expansions_keep_the_planner_s_account_and_the_trees() {
        let narration = "tick   0  the root fails: x\n          expansion 1: `x` is replaced\n          planned in 1 ms\n\
                         \x20         the tree now (3 nodes):\n            [o] Fallback\n                --> x\ntick   1  more\n";
        assert_eq!(
            expansions(narration),
            "          expansion 1: `x` is replaced\n          the tree now (3 nodes):\n            [o] Fallback\n                --> x\n"
        );
    }
}
