//! The link controller on both boards, for `cargo xtask qemu`: the link scenario
//! (`link.rs`) on the host build and under QEMU on `mps2-an386` (`firmware-example`'s
//! polled `controller`) and `lm3s6965evb` (the RTIC program in `examples/lm3s6965-rtic`),
//! the traces compared, each board's gates, and deployments timed against their time on
//! the wire.

use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::qemu::{Options, compare, footprint, panic_free};
use crate::{Result, Toolchain, root, step, target_dir, toolchain_for};

/// The program and its gates (issue 18): 32 KiB of flash, 8 KiB of RAM with both image
/// slots and the stack.
const LINK: &str = "controller";
const LINK_FLASH_TARGET: u64 = 32 * 1024;
const LINK_RAM_TARGET: u64 = 8 * 1024;
/// The serial rate the link's throughput is measured at.
const BAUD: u32 = 115_200;
/// The second board: an RTIC v2 program on QEMU's lm3s6965evb (Cortex-M3).
const RTIC_PROJECT: &str = "lm3s6965-rtic";
const RTIC_TARGET: &str = "thumbv7m-none-eabi";
/// Its variant with slots of 16 KiB, for timing a 16 KiB deployment.
const LINK_16K: &str = "controller-16k";

/// The link controller on both boards: the scenario on the host and under QEMU, the
/// traces compared, the gates, and the deployment time at 115200 baud.
pub fn link_scenario(elf: &Path, host_bin: &Path, toolchain: Toolchain, opts: Options) -> Result {
    step("link controller: images (planner: A = end of Example 2, blocked path, B = Fig. 3(e) free path)");
    let images = crate::link::images()?;
    step("link controller: scenario on the host build (TCP)");
    let host = crate::link::host(host_bin, &images, opts.timeout)?;
    step("RTIC board: release build of examples/lm3s6965-rtic for thumbv7m-none-eabi");
    let rtic_dir = build_rtic()?;
    let boards = [(crate::link::MPS2, elf.to_path_buf()), (crate::link::LM3S6965, rtic_dir.join(LINK))];
    let cube = (&images.a[..], &images.b[..]);
    let mut figures = Vec::new();
    for (machine, elf) in &boards {
        step(&format!("link controller on {}: the scenario under QEMU (UART0 on a TCP socket)", machine.name));
        let target = crate::link::qemu(*machine, elf, &images, opts.timeout)?;
        for line in &target.faults {
            eprintln!("  {line}");
        }
        if host.faults.len() != target.faults.len() {
            return Err(format!("the host saw {} cases, QEMU {}", host.faults.len(), target.faults.len()));
        }
        let ticks = compare(&target.trace, &host.trace)?;
        let swaps = target.trace.lines().filter(|l| l.starts_with("swap ")).count();
        eprintln!(
            "link traces identical to the host's ({ticks} ticks, {swaps} swaps); {} fault cases refused or skipped",
            target.faults.iter().filter(|l| l.contains("refused") || l.contains("skipped")).count()
        );
        let (bytes, took) = target.deploy;
        eprintln!(
            "deploying B ({bytes} B) while A ticked took {:.1} ms (socket, not rate-limited)",
            took.as_secs_f64() * 1e3
        );
        if target.stack_used == 0 {
            return Err(format!("the controller on {} did not report its stack use", machine.name));
        }
        panic_free(elf)?;
        eprintln!("no core::panicking symbols");
        let (flash, ram) = footprint(elf, u64::from(target.stack_used), toolchain, LINK_FLASH_TARGET, LINK_RAM_TARGET)?;
        let paced = timed_on(*machine, elf, cube, Some(BAUD), ROUNDS, opts.timeout)?;
        let fast = timed_on(*machine, elf, cube, None, ROUNDS, opts.timeout)?;
        figures.push((machine.name, flash, ram, paced, fast));
    }
    step("link controller: the host build over TCP, unpaced (the software's own time)");
    let port = crate::link::port()?;
    let own =
        crate::link::timed_deploy(crate::link::host_command(host_bin, port), port, cube, None, ROUNDS, opts.timeout)?;
    step(&format!(
        "link controller on {}: a {} B image deployed (the cube tree with a names section), slots of 16 KiB",
        crate::link::LM3S6965.name,
        crate::link::LARGE
    ));
    let large = (&images.large[..], &images.b[..]);
    let big = rtic_dir.join(LINK_16K);
    let large_paced = timed_on(crate::link::LM3S6965, &big, large, Some(BAUD), 1, opts.timeout)?;
    let large_fast = timed_on(crate::link::LM3S6965, &big, large, None, 1, opts.timeout)?;
    step(&format!(
        "link controller: the cube tree deployed, best of {ROUNDS} (host paced to {BAUD} baud, 10 bits a byte)"
    ));
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    eprintln!(
        "{:<32} {:>8} {:>8} {:>12} {:>10} {:>7} {:>10}",
        "board", "flash", "RAM", "at 115200", "wire time", "ratio", "unpaced"
    );
    for (name, flash, ram, paced, fast) in &figures {
        let wire = paced.wire_time(BAUD);
        eprintln!(
            "{name:<32} {flash:>6} B {ram:>6} B {:>9.1} ms {:>7.1} ms {:>6.2}x {:>7.1} ms",
            ms(paced.took),
            ms(wire),
            paced.took.as_secs_f64() / wire.as_secs_f64(),
            ms(fast.took)
        );
    }
    eprintln!(
        "{:<32} {:>8} {:>8} {:>12} {:>10} {:>7} {:>7.1} ms",
        "host build (TCP)",
        "-",
        "-",
        "-",
        "-",
        "-",
        ms(own.took)
    );
    eprintln!(
        "({} B image, {} B on the wire both ways; wire time: those bytes at {BAUD} baud one after the other)",
        own.image, own.wire
    );
    let wire = large_paced.wire_time(BAUD);
    eprintln!(
        "{} B image on {}: {:.1} ms at {BAUD} baud, wire time {:.1} ms ({} B both ways), ratio {:.2}x; unpaced {:.1} ms",
        large_paced.image,
        crate::link::LM3S6965.name,
        ms(large_paced.took),
        ms(wire),
        large_paced.wire,
        large_paced.took.as_secs_f64() / wire.as_secs_f64(),
        ms(large_fast.took)
    );
    Ok(())
}

/// Times `pair` ([`crate::link::timed_deploy`]) on a fresh QEMU running `elf`.
fn timed_on(
    machine: crate::link::Machine,
    elf: &Path,
    pair: (&[u8], &[u8]),
    baud: Option<u32>,
    rounds: usize,
    timeout: Duration,
) -> Result<crate::link::Timed> {
    let port = crate::link::port()?;
    crate::link::timed_deploy(crate::link::qemu_command(machine, elf, port), port, pair, baud, rounds, timeout)
}

/// Deployments of the cube tree timed per board and rate (with B between them).
const ROUNDS: usize = 3;

/// Builds the RTIC programs; returns the folder of their ELFs.
fn build_rtic() -> Result<PathBuf> {
    let dir = root().join("examples").join(RTIC_PROJECT);
    let toolchain = toolchain_for(RTIC_TARGET)?;
    // The firmware's target dir: the build scripts' host dependencies (the planner) are
    // built once for both projects.
    let target_dir = target_dir().join("firmware");
    let mut build = crate::cross_cargo(RTIC_TARGET)?;
    build.arg("--target-dir").arg(&target_dir);
    if matches!(toolchain, Toolchain::Debian) {
        build.env("CARGO_TARGET_THUMBV7M_NONE_EABI_LINKER", "arm-none-eabi-ld");
    }
    crate::run_in(&dir, &mut build)?;
    Ok(target_dir.join(RTIC_TARGET).join("release"))
}
