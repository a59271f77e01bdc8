//! `cargo xtask qemu`: the firmware on an emulated Cortex-M4F, checked against the host.
//!
//! 1. Builds `firmware-example` in release for thumbv7em-none-eabihf (rustup's target,
//!    or Debian's compiler with `-Zbuild-std=core` and the GNU ARM linker).
//! 2. Runs it under QEMU (mps2-an386, semihosting) with a timeout, and the same loop on
//!    the host; compares the traces byte for byte (QEMU's `fw ` lines excepted).
//! 3. Runs the firmware with the corrupted image: it must print the `LoadError`, tick
//!    nothing and exit non-zero, on QEMU and on the host alike.
//! 4. Gates: no `core::panicking` symbol in either ELF; flash and RAM (static + stack
//!    high-water mark) within their limits. Reports the footprint and bt-core's share.

use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::{Result, Toolchain, cargo, host_triple, root, step, target_dir, toolchain_for};

/// The firmware's target: Cortex-M4F with hardware floating point.
const TARGET: &str = "thumbv7em-none-eabihf";
/// The firmware binary and the one embedding the corrupted image.
const FIRMWARE: &str = "firmware-example";
const CORRUPT: &str = "firmware-corrupt-image";
/// The QEMU machine: the same as the runner in firmware-example/.cargo/config.toml.
pub(crate) const QEMU_ARGS: [&str; 7] =
    ["-cpu", "cortex-m4", "-machine", "mps2-an386", "-nographic", "-semihosting-config", "enable=on,target=native"];
/// The targets of issue 3, enforced: the whole firmware in 16 KiB of flash and 4 KiB
/// of RAM, stack included. A `{}` on a float or a `core::fmt` padding spec in the trace
/// code is enough to cross the flash line (see DEVELOPERS.md, "Firmware").
const FLASH_TARGET: u64 = 16 * 1024;
const RAM_TARGET: u64 = 4 * 1024;
/// The link controller's program (its scenario, gates and timing: `boards.rs`).
const LINK: &str = "controller";

/// Options of `cargo xtask qemu`.
#[derive(Debug, Clone, Copy)]
pub struct Options {
    /// Longest a QEMU run may take.
    pub timeout: Duration,
}

pub fn qemu(opts: Options) -> Result {
    let fw = root().join("firmware-example");
    require_tools()?;

    step(&format!("firmware: release build for {TARGET}"));
    let (toolchain, elf_dir) = build_firmware(&fw)?;
    let elf = elf_dir.join(FIRMWARE);
    let corrupt_elf = elf_dir.join(CORRUPT);

    step("firmware: host reference run");
    let host_dir = target_dir().join("firmware-host");
    let host = host_triple()?;
    crate::run_in(
        &fw,
        cargo().args(["build", "--quiet", "--release", "--bins", "--target", &host, "--target-dir"]).arg(&host_dir),
    )?;
    let host_bin = |name: &str| host_dir.join(&host).join("release").join(name);
    let host_run = capture(Command::new(host_bin(FIRMWARE)), opts.timeout)?;
    if host_run.code != Some(0) {
        return Err(format!(
            "the host run did not reach its goal (exit {:?}):\n{}",
            host_run.code,
            tail(&host_run.out)
        ));
    }

    step("firmware: QEMU run (mps2-an386, Cortex-M4)");
    let mut qemu = Command::new("qemu-system-arm");
    qemu.args(QEMU_ARGS).arg("-kernel").arg(&elf);
    let target_run = capture(qemu, opts.timeout)?;
    eprintln!("{}", tail(&target_run.out));
    if target_run.code != Some(0) {
        return Err(format!("the firmware did not reach its goal under QEMU (exit {:?})", target_run.code));
    }
    let ticks = compare(&target_run.out, &host_run.out)?;
    eprintln!("traces identical ({ticks} ticks)");

    step("firmware: corrupted image");
    let mut qemu = Command::new("qemu-system-arm");
    qemu.args(QEMU_ARGS).arg("-kernel").arg(&corrupt_elf);
    let refused = capture(qemu, opts.timeout)?;
    let refused_host = capture(Command::new(host_bin(CORRUPT)), opts.timeout)?;
    let error = check_refused(&refused, "QEMU")?;
    check_refused(&refused_host, "host")?;
    compare(&refused.out, &refused_host.out)?;
    eprintln!("refused on QEMU and host alike, exit {:?}, no tick: {error}", refused.code.unwrap_or(-1));

    step("firmware: panic freedom");
    for path in [&elf, &corrupt_elf] {
        panic_free(path)?;
    }
    eprintln!("no core::panicking symbols in {FIRMWARE} or {CORRUPT}");
    for path in [&elf, &corrupt_elf] {
        no_costly_helpers(path)?;
    }
    eprintln!("no 64-bit division or double-precision helpers from compiler-builtins");

    step("firmware: footprint");
    let hwm = field(&target_run.out, "fw stack_hwm=")
        .and_then(|v| v.trim_end_matches('B').parse::<u64>().ok())
        .ok_or("the firmware did not report its stack high-water mark")?;
    footprint(&elf, hwm, toolchain, FLASH_TARGET, RAM_TARGET)?;
    eprintln!(
        "QEMU wall time: {:.3} s for {ticks} ticks (corrupted image: {:.3} s)",
        target_run.wall.as_secs_f64(),
        refused.wall.as_secs_f64()
    );
    crate::boards::link_scenario(&elf_dir.join(LINK), &host_bin(LINK), toolchain, opts)?;
    crate::blend::scenario(&elf_dir.join(LINK), &host_bin(LINK), opts.timeout)
}

/// The ARM binutils and QEMU, with the package that has them.
fn require_tools() -> Result {
    for (tool, package) in [
        ("qemu-system-arm", "qemu-system-arm"),
        ("arm-none-eabi-nm", "binutils-arm-none-eabi"),
        ("arm-none-eabi-size", "binutils-arm-none-eabi"),
        ("arm-none-eabi-addr2line", "binutils-arm-none-eabi"),
        ("arm-none-eabi-objdump", "binutils-arm-none-eabi"),
    ] {
        if Command::new(tool).arg("--version").output().is_err() {
            return Err(format!("{tool} not found: apt-get install -y {package} (see DEVELOPERS.md)"));
        }
    }
    Ok(())
}

/// Builds both firmware binaries; returns the toolchain used and their directory.
fn build_firmware(fw: &Path) -> Result<(Toolchain, PathBuf)> {
    let toolchain = toolchain_for(TARGET)?;
    let target_dir = target_dir().join("firmware");
    let mut build = crate::cross_cargo(TARGET)?;
    build.args(["--bins", "--target-dir"]).arg(&target_dir);
    if matches!(toolchain, Toolchain::Debian) {
        // Debian's rustc ships no rust-lld: link with the GNU ARM linker instead.
        build.env("CARGO_TARGET_THUMBV7EM_NONE_EABIHF_LINKER", "arm-none-eabi-ld");
    }
    crate::run_in(fw, &mut build)?;
    eprintln!(
        "built with {}",
        match toolchain {
            Toolchain::RustupSource => "rustup's rustc, core built from source (-Zbuild-std=core), rust-lld",
            Toolchain::Debian => "Debian's rustc, core built from source (-Zbuild-std=core), arm-none-eabi-ld",
        }
    );
    Ok((toolchain, target_dir.join(TARGET).join("release")))
}

/// What a program printed, how it exited, how long it took.
struct Captured {
    out: String,
    code: Option<i32>,
    wall: Duration,
}

/// Runs `cmd` with stdout captured, killing it after `timeout`.
fn capture(mut cmd: Command, timeout: Duration) -> Result<Captured> {
    let shown = format!("{cmd:?}");
    let started = Instant::now();
    let mut child =
        cmd.stdin(Stdio::null()).stdout(Stdio::piped()).spawn().map_err(|e| format!("cannot start {shown}: {e}"))?;
    let mut stdout = child.stdout.take().ok_or("no stdout")?;
    let reader = std::thread::spawn(move || {
        let mut bytes = Vec::new();
        let _ = stdout.read_to_end(&mut bytes);
        bytes
    });
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| format!("{shown}: {e}"))? {
            break status;
        }
        if started.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("timed out after {} s: {shown}", timeout.as_secs()));
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let wall = started.elapsed();
    let bytes = reader.join().map_err(|_| "reading the output failed")?;
    Ok(Captured { out: String::from_utf8_lossy(&bytes).into_owned(), code: status.code(), wall })
}

/// The last lines of a trace, for the log.
fn tail(out: &str) -> String {
    let lines: Vec<&str> = out.lines().collect();
    lines[lines.len().saturating_sub(4)..].join("\n")
}

/// The value after `prefix` on the first line that starts with it, up to a space.
fn field<'a>(out: &'a str, prefix: &str) -> Option<&'a str> {
    out.lines().find_map(|l| l.strip_prefix(prefix)).and_then(|v| v.split_whitespace().next())
}

/// Compares the target's trace (without its `fw ` lines) with the host's, byte for
/// byte; returns the number of ticks.
pub(crate) fn compare(target: &str, host: &str) -> Result<usize> {
    let target: Vec<&str> = target.lines().filter(|l| !l.starts_with("fw ")).collect();
    let host: Vec<&str> = host.lines().collect();
    for (i, pair) in target.iter().zip(&host).enumerate() {
        if pair.0 != pair.1 {
            let tick = host[..=i].iter().rev().find_map(|l| l.strip_prefix("tick ")?.split(' ').next()).unwrap_or("-");
            return Err(format!(
                "traces differ at line {} (last tick {tick}):\n  qemu: {}\n  host: {}",
                i + 1,
                pair.0,
                pair.1
            ));
        }
    }
    if target.len() != host.len() {
        let (longer, name) = if target.len() > host.len() { (&target, "qemu") } else { (&host, "host") };
        return Err(format!(
            "traces differ in length: qemu {} lines, host {}; {name} goes on with:\n  {}",
            target.len(),
            host.len(),
            longer[target.len().min(host.len())]
        ));
    }
    Ok(host.iter().filter(|l| l.starts_with("tick ")).count())
}

/// The corrupted image must be refused: a `load error:` line, no tick, exit non-zero.
fn check_refused(run: &Captured, on: &str) -> Result<String> {
    let error = run
        .out
        .lines()
        .find(|l| l.starts_with("load error: "))
        .ok_or_else(|| format!("corrupted image on {on}: no `load error:` line in\n{}", tail(&run.out)))?;
    if run.out.lines().any(|l| l.starts_with("tick ")) {
        return Err(format!("corrupted image on {on}: the firmware ticked the tree"));
    }
    if run.code == Some(0) {
        return Err(format!("corrupted image on {on}: exit status 0"));
    }
    Ok(error.to_owned())
}

/// Fails on any `core::panicking` symbol: bt-core and the plant are panic-free, and a
/// bounds check, an overflow check or a float format slipping in would show here.
pub(crate) fn panic_free(elf: &Path) -> Result {
    let out =
        Command::new("arm-none-eabi-nm").arg("-C").arg(elf).output().map_err(|e| format!("arm-none-eabi-nm: {e}"))?;
    let text = String::from_utf8_lossy(&out.stdout);
    let hits: Vec<&str> = text.lines().filter(|l| l.contains("core::panicking")).collect();
    if hits.is_empty() {
        Ok(())
    } else {
        let symbols = if hits.len() == 1 { "symbol" } else { "symbols" };
        Err(format!("{}: {} panic {symbols}:\n  {}", elf.display(), hits.len(), hits.join("\n  ")))
    }
}

/// compiler-builtins' helpers for 64-bit division and double-precision floats. On the
/// Cortex-M4F, 32-bit division is one instruction and `f32` has the FPU; these helpers
/// are library code, and rustup's prebuilt `compiler_builtins` is optimised for speed,
/// not size: `u64` division alone took 518 B when `core` was built from source at
/// `opt-level = "z"` and about twice that from rustup's build, enough to cross the flash
/// line on one toolchain and not the other.
const COSTLY_HELPERS: [&str; 12] = [
    "__aeabi_uldivmod",
    "__aeabi_ldivmod",
    "__udivmoddi4",
    "__divmoddi4",
    "__aeabi_d",
    "__aeabi_f2d",
    "__aeabi_i2d",
    "__aeabi_ui2d",
    "__aeabi_l2d",
    "__aeabi_ul2d",
    "__aeabi_l2f",
    "__aeabi_ul2f",
];

/// Fails when the firmware links any of [`COSTLY_HELPERS`].
fn no_costly_helpers(elf: &Path) -> Result {
    let out = Command::new("arm-none-eabi-nm").arg(elf).output().map_err(|e| format!("arm-none-eabi-nm: {e}"))?;
    let text = String::from_utf8_lossy(&out.stdout);
    let hits = costly(&text);
    if hits.is_empty() {
        return Ok(());
    }
    Err(format!(
        "{} links compiler-builtins helpers it should not need ({}): a u64 division or an f64 \
         somewhere; use u32 or shifts, f32 (see DEVELOPERS.md, \"Firmware\")",
        elf.display(),
        hits.join(", ")
    ))
}

/// The symbols of `nm` output that are [`COSTLY_HELPERS`].
fn costly(nm: &str) -> Vec<&str> {
    nm.lines()
        .filter_map(|l| l.split_whitespace().last())
        .filter(|sym| COSTLY_HELPERS.iter().any(|h| sym.starts_with(h)))
        .collect()
}

/// The compiler that built the firmware, as `rustc -V` prints it.
fn compiler(toolchain: Toolchain) -> String {
    let rustc = match toolchain {
        Toolchain::RustupSource => "rustc",
        Toolchain::Debian => "/usr/bin/rustc",
    };
    Command::new(rustc)
        .arg("-V")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_owned())
        .unwrap_or_else(|e| format!("{rustc}: {e}"))
}

/// Prints flash and RAM against the targets, bt-core's share of the code, and gates
/// on both targets.
pub(crate) fn footprint(
    elf: &Path,
    stack_hwm: u64,
    toolchain: Toolchain,
    flash_target: u64,
    ram_target: u64,
) -> Result<(u64, u64)> {
    let out = Command::new("arm-none-eabi-size").arg(elf).output().map_err(|e| format!("arm-none-eabi-size: {e}"))?;
    let text = String::from_utf8_lossy(&out.stdout);
    let nums: Vec<u64> =
        text.lines().nth(1).unwrap_or_default().split_whitespace().take(3).filter_map(|n| n.parse().ok()).collect();
    let [text_b, data, bss] = nums[..] else {
        return Err(format!("cannot read arm-none-eabi-size output:\n{text}"));
    };
    let flash = text_b + data;
    let ram = data + bss + stack_hwm;
    let verdict = |used: u64, target: u64| {
        if used <= target {
            format!("within the {} KiB target", target / 1024)
        } else {
            format!("OVER the {} KiB target by {} B", target / 1024, used - target)
        }
    };
    eprintln!("compiler: {} (core built from source)", compiler(toolchain));
    eprintln!("arm-none-eabi-size: text {text_b} B, data {data} B, bss {bss} B");
    eprintln!("flash (text + data):                 {flash:>6} B  {}", verdict(flash, flash_target));
    eprintln!(
        "RAM (data + bss + stack high-water): {ram:>6} B  {} (static {} B, stack {stack_hwm} B)",
        verdict(ram, ram_target),
        data + bss
    );
    let share = code_by_crate(elf)?;
    let total: u64 = share.values().sum();
    let mut rows: Vec<(&String, &u64)> = share.iter().collect();
    rows.sort_by(|a, b| b.1.cmp(a.1).then(a.0.cmp(b.0)));
    eprintln!(
        "code by crate ({toolchain:?} toolchain; .text only: the other {} B of flash, vector table and .rodata, are not attributed; inlined code \
         counts for the crate that wrote it, core helpers for the crate that called them):",
        text_b.saturating_sub(total)
    );
    for (name, bytes) in rows {
        eprintln!("  {name:<22} {bytes:>6} B  {:>5.1}%", percent(*bytes, total));
    }
    let bt = share.get("bt-core").copied().unwrap_or(0);
    let deps: u64 =
        ["postcard", "serde_core", "serde", "crc", "crc-catalog", "cobs"].iter().filter_map(|c| share.get(*c)).sum();
    eprintln!(
        "bt-core's share of flash: {bt} B of code ({:.1}% of flash), {} B with postcard/serde/crc ({:.1}%)",
        percent(bt, flash),
        bt + deps,
        percent(bt + deps, flash)
    );
    if let Some(link) = share.get("bt-link") {
        eprintln!("bt-link's code: {link} B ({:.1}% of flash)", percent(*link, flash));
    }
    if ram > ram_target {
        return Err(format!("RAM {ram} B is over the {ram_target} B target"));
    }
    if flash > flash_target {
        return Err(format!("flash {flash} B is over the {flash_target} B target"));
    }
    Ok((flash, ram))
}

fn percent(part: u64, whole: u64) -> f64 {
    if whole == 0 { 0.0 } else { part as f64 * 100.0 / whole as f64 }
}

/// Bytes of `.text` per crate, from the DWARF line tables: every halfword of `.text`
/// (Thumb instructions are 2 or 4 bytes) is looked up with `addr2line -i`, and counted
/// for the innermost source frame outside `core` — so bt-core code inlined into the
/// firmware counts as bt-core, and core's `Option`/`Result` helpers inlined into
/// bt-core count as bt-core too. Bytes with no line information (hand-written
/// assembly, padding) count as `(no line info)`.
fn code_by_crate(elf: &Path) -> Result<BTreeMap<String, u64>> {
    let out = Command::new("arm-none-eabi-objdump")
        .arg("-h")
        .arg(elf)
        .output()
        .map_err(|e| format!("arm-none-eabi-objdump: {e}"))?;
    let headers = String::from_utf8_lossy(&out.stdout);
    let (size, start) = headers
        .lines()
        .find_map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (f.get(1) == Some(&".text"))
                .then(|| Some((u64::from_str_radix(f.get(2)?, 16).ok()?, u64::from_str_radix(f.get(3)?, 16).ok()?)))?
        })
        .ok_or("no .text section")?;
    let addrs: String = (start..start + size).step_by(2).map(|a| format!("{a:#x}\n")).collect();
    let mut child = Command::new("arm-none-eabi-addr2line")
        .args(["-a", "-i", "-e"])
        .arg(elf)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .map_err(|e| format!("arm-none-eabi-addr2line: {e}"))?;
    let mut stdin = child.stdin.take().ok_or("no stdin")?;
    let writer = std::thread::spawn(move || std::io::Write::write_all(&mut stdin, addrs.as_bytes()));
    let out = child.wait_with_output().map_err(|e| format!("arm-none-eabi-addr2line: {e}"))?;
    let _ = writer.join();
    let text = String::from_utf8_lossy(&out.stdout);
    let mut share = BTreeMap::new();
    // `addr2line -a -i` prints each address, then its frames from the innermost out.
    let mut owner: Option<String> = None;
    let mut count = |owner: &mut Option<String>| {
        if let Some(name) = owner.take() {
            *share.entry(name).or_insert(0u64) += 2;
        }
    };
    for line in text.lines() {
        if line.starts_with("0x") {
            count(&mut owner);
            owner = Some("(no line info)".into());
        } else if let Some(current) = owner.as_mut() {
            let name = crate_of(line);
            let settled = current != "core" && current != "(no line info)";
            if !settled && name != "(no line info)" {
                *current = name;
            }
        }
    }
    count(&mut owner);
    Ok(share)
}

/// The crate a source path belongs to.
fn crate_of(path: &str) -> String {
    let file = path.rsplit_once(':').map_or(path, |(f, _)| f);
    if file.starts_with("??") {
        return "(no line info)".into();
    }
    if file.contains("/bt-core/src/") {
        return "bt-core".into();
    }
    if file.contains("/bt-link/src/") {
        return "bt-link".into();
    }
    if file.contains("/lm3s6965-rtic/") {
        return "lm3s6965-rtic".into();
    }
    if file.contains("/firmware-example/") {
        return "firmware-example".into();
    }
    if file.contains("compiler-builtins") || file.contains("compiler_builtins") {
        return "compiler-builtins".into();
    }
    if file.contains("library/core/") {
        return "core".into();
    }
    // Registry sources: .../registry/src/<index>/<name>-<version>/...
    if let Some(rest) = file.split("/registry/src/").nth(1)
        && let Some(dir) = rest.split('/').nth(1)
        && let Some((name, _)) = dir.rsplit_once('-')
    {
        return name.into();
    }
    "other".into()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_traces_count_their_ticks_and_ignore_fw_lines() {
        let host = "boot x\ntick 0 RUNNING\ntick 1 SUCCESS\ndone GOAL\n";
        let target = "boot x\ntick 0 RUNNING\ntick 1 SUCCESS\ndone GOAL\nfw stack_hwm=12B\nfw exit=0\n";
        assert_eq!(compare(target, host), Ok(2));
    }

    #[test]
    fn the_first_difference_is_shown_with_both_lines() {
        let host = "boot x\ntick 0 RUNNING dig=1\ntick 1 RUNNING dig=2\n";
        let target = "boot x\ntick 0 RUNNING dig=1\ntick 1 RUNNING dig=3\n";
        let e = compare(target, host).unwrap_err();
        assert!(e.contains("line 3 (last tick 1)"), "{e}");
        assert!(e.contains("qemu: tick 1 RUNNING dig=3") && e.contains("host: tick 1 RUNNING dig=2"), "{e}");
    }

    #[test]
    fn a_trace_that_stops_early_differs() {
        let e = compare("boot x\ntick 0 RUNNING\n", "boot x\ntick 0 RUNNING\ntick 1 SUCCESS\n").unwrap_err();
        assert!(e.contains("qemu 2 lines, host 3") && e.contains("host goes on with:\n  tick 1 SUCCESS"), "{e}");
    }

    #[test]
    fn a_refusal_needs_the_error_no_tick_and_a_failing_exit() {
        let run = |out: &str, code| Captured { out: out.into(), code: Some(code), wall: Duration::ZERO };
        let refused = run("load error: image corrupted\ndone LOAD-ERROR ticks=0\n", 1);
        assert_eq!(check_refused(&refused, "qemu"), Ok("load error: image corrupted".into()));
        assert!(check_refused(&run("load error: x\n", 0), "qemu").unwrap_err().contains("exit status 0"));
        assert!(check_refused(&run("load error: x\ntick 0 RUNNING\n", 1), "qemu").unwrap_err().contains("ticked"));
        assert!(check_refused(&run("boot\n", 1), "qemu").unwrap_err().contains("no `load error:`"));
    }

    #[test]
    fn costly_helpers_are_found_in_nm_output() {
        let nm = "0000321c W __aeabi_uldivmod\n000035de W __aeabi_llsl\n00003278 T memcpy\n\
                  00001000 T __aeabi_dmul\n00002000 T __aeabi_fmul\n";
        assert_eq!(costly(nm), ["__aeabi_uldivmod", "__aeabi_dmul"]);
    }

    #[test]
    fn source_paths_map_to_crates_on_both_toolchains() {
        let cases = [
            ("/work/x/bt-core/src/exec.rs:12", "bt-core"),
            ("/work/x/firmware-example/src/plant.rs:3", "firmware-example"),
            ("/usr/lib/rustlib/src/rust/library/core/src/fmt/mod.rs:2872", "core"),
            ("/rustc/59807616e1fa2540724bfbac14d7976d7e4a3860/library/core/src/option.rs:9", "core"),
            (
                "/usr/lib/rustlib/src/rust/library/compiler-builtins/compiler-builtins/src/mem/impls.rs:1",
                "compiler-builtins",
            ),
            (
                "/root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/cortex-m-rt-0.7.7/src/lib.rs:5",
                "cortex-m-rt",
            ),
            (
                "/root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/nalgebra-0.35.0/src/base/ops.rs:?",
                "nalgebra",
            ),
            ("??:0", "(no line info)"),
        ];
        for (path, expected) in cases {
            assert_eq!(crate_of(path), expected, "{path}");
        }
    }
}
