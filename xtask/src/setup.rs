//! What `cargo xtask ci` needs beyond cargo, checked before anything runs: on a fresh
//! machine it installs what is missing where it may (Debian packages, as root or with
//! password-less sudo), or fails at once naming every missing piece and the one command
//! that installs them.
//!
//! Needed: rustfmt and clippy; for the bare-metal builds, which build `core` from source,
//! rustup's `rust-src` component or Debian's compiler with its std sources (`rustc-web
//! cargo-web rust-web-src`; installed by apt where it may, else `rust-src` by rustup;
//! rustup's prebuilt targets are not enough, see `Toolchain` in main.rs); the ARM binutils
//! (`binutils-arm-none-eabi`: the linker, nm, size, addr2line, objdump) and QEMU
//! (`qemu-system-arm`); a C++ compiler (`g++`: the `zmq` crate builds libzmq for
//! sim-host's Groot2 server). apt never removes a package to install these: a package it
//! would remove is upgraded with them instead, and if that does not settle it the
//! install stops and says which.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::{Result, cargo, step};

/// A missing piece: what it is, and how to get it.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Missing {
    what: String,
    fix: Fix,
}

#[derive(Debug, Clone, PartialEq, Eq)]
enum Fix {
    /// A Debian package.
    Apt(&'static str),
    /// A command to run by hand.
    Command(String),
}

fn works(cmd: &mut Command) -> bool {
    cmd.stdin(Stdio::null()).stdout(Stdio::null()).stderr(Stdio::null()).status().is_ok_and(|s| s.success())
}

fn tool(name: &str) -> bool {
    works(Command::new(name).arg("--version"))
}

/// Asks rustup for its `rust-src` component, giving up after `limit` (rustup may retry
/// a download it cannot make for a long time). Whether the sources are there after.
fn rustup_rust_src_added(limit: Duration) -> bool {
    step("installing rustup's rust-src component (core for Cortex-M, built from source)");
    let Ok(mut child) = Command::new("rustup").args(["component", "add", "rust-src"]).stdin(Stdio::null()).spawn()
    else {
        eprintln!("rustup not found");
        return false;
    };
    let start = Instant::now();
    loop {
        match child.try_wait() {
            Ok(Some(_)) => break,
            Ok(None) if start.elapsed() < limit => std::thread::sleep(Duration::from_millis(200)),
            _ => {
                let _ = child.kill();
                let _ = child.wait();
                eprintln!("rustup component add rust-src did not finish in {} s: stopped", limit.as_secs());
                break;
            }
        }
    }
    crate::rustup_rust_src()
}

/// Everything missing, in one pass.
fn missing() -> Vec<Missing> {
    let mut out = Vec::new();
    for (sub, component) in [("fmt", "rustfmt"), ("clippy", "clippy")] {
        if !works(cargo().args([sub, "--version"])) {
            out.push(Missing {
                what: format!("cargo {sub}"),
                fix: Fix::Command(format!("rustup component add {component}")),
            });
        }
    }
    if !crate::rustup_rust_src() && !crate::debian_toolchain() {
        for (what, path, package) in [
            ("Debian's rustc (core for Cortex-M, built from source)", "/usr/bin/rustc", "rustc-web"),
            ("Debian's cargo", "/usr/bin/cargo", "cargo-web"),
            ("the Rust library sources", "/usr/lib/rustlib/src/rust/library/core", "rust-web-src"),
        ] {
            if !Path::new(path).exists() {
                out.push(Missing { what: what.into(), fix: Fix::Apt(package) });
            }
        }
    }
    for t in [
        "arm-none-eabi-ld",
        "arm-none-eabi-nm",
        "arm-none-eabi-size",
        "arm-none-eabi-addr2line",
        "arm-none-eabi-objdump",
    ] {
        if !tool(t) {
            out.push(Missing { what: t.into(), fix: Fix::Apt("binutils-arm-none-eabi") });
        }
    }
    if !tool("qemu-system-arm") {
        out.push(Missing { what: "qemu-system-arm".into(), fix: Fix::Apt("qemu-system-arm") });
    }
    // sim-host links libzmq (Groot2's transport), which the `zmq` crate builds from
    // source with the C++ compiler.
    if !tool("c++") {
        out.push(Missing { what: "a C++ compiler (libzmq for sim-host's Groot2 server)".into(), fix: Fix::Apt("g++") });
    }
    // sim-host's `learn --list` test runs the listed commands through GNU parallel.
    if !tool("parallel") {
        out.push(Missing { what: "GNU parallel".into(), fix: Fix::Apt("parallel") });
    }
    out
}

/// The Debian packages among `missing`, each once, in order.
fn packages(missing: &[Missing]) -> Vec<&'static str> {
    let mut p: Vec<&'static str> = Vec::new();
    for m in missing {
        if let Fix::Apt(name) = m.fix
            && !p.contains(&name)
        {
            p.push(name);
        }
    }
    p
}

/// How to run apt as root here: directly, with `sudo -n`, or not at all.
fn apt_prefix() -> Option<Vec<&'static str>> {
    if !Path::new("/usr/bin/apt-get").exists() {
        return None;
    }
    let root = Command::new("/usr/bin/id").arg("-u").output().is_ok_and(|o| o.stdout.starts_with(b"0\n"));
    if root {
        Some(vec![])
    } else if works(Command::new("/usr/bin/sudo").args(["-n", "true"])) {
        Some(vec!["/usr/bin/sudo", "-n"])
    } else {
        None
    }
}

fn apt(prefix: &[&str], args: &[&str]) -> Command {
    let mut c = match prefix.split_first() {
        None => Command::new("/usr/bin/apt-get"),
        Some((sudo, rest)) => {
            let mut c = Command::new(sudo);
            // sudo passes on no environment unless told: name it on its command line.
            c.args(rest).args(["DEBIAN_FRONTEND=noninteractive", "/usr/bin/apt-get"]);
            c
        }
    };
    // apt runs dpkg, gpgv and the like: give it the system's PATH, whatever ours is.
    c.env("DEBIAN_FRONTEND", "noninteractive").env("PATH", "/usr/sbin:/usr/bin:/sbin:/bin").args(args);
    c
}

/// The packages `apt-get -s install` would remove (`Remv NAME ...` lines).
pub(crate) fn removals(simulation: &str) -> Vec<String> {
    simulation
        .lines()
        .filter_map(|l| l.strip_prefix("Remv "))
        .filter_map(|l| l.split_whitespace().next())
        .map(str::to_owned)
        .collect()
}

/// The backports release the machine's `qemu-utils` came from (`bookworm-backports`
/// for a version such as `1:10.0.2+ds-2+deb13u1~bpo12+1`), if it came from one.
/// `qemu-system-arm` must then come from the same release: the release's own QEMU
/// declares that it breaks with the newer `qemu-utils`, and apt cannot resolve it.
fn qemu_backports() -> Option<String> {
    let out = Command::new("/usr/bin/dpkg-query").args(["-W", "-f=${Version}", "qemu-utils"]).output().ok()?;
    let version = String::from_utf8_lossy(&out.stdout).into_owned();
    if !out.status.success() || !version.contains("~bpo") {
        return None;
    }
    let release = std::fs::read_to_string("/etc/os-release").ok()?;
    let codename = release.lines().find_map(|l| l.strip_prefix("VERSION_CODENAME="))?.trim_matches('"').to_owned();
    (!codename.is_empty()).then(|| format!("{codename}-backports"))
}

/// Installs `qemu-system-arm` from `release` (a backports release), adding Debian's
/// source for it when apt does not know it yet (`/etc/apt/sources.list.d/xtask-RELEASE.list`).
fn install_qemu_from(prefix: &[&str], release: &str) -> Result {
    let policy = apt_cache(&["policy", "qemu-system-arm"]);
    if !policy.contains(&format!(" {release}/")) {
        let list = format!("/etc/apt/sources.list.d/xtask-{release}.list");
        eprintln!("qemu-utils comes from {release}: adding {list} for a matching qemu-system-arm");
        let line = format!("deb http://deb.debian.org/debian {release} main\n");
        let mut tee = match prefix.split_first() {
            None => Command::new("/usr/bin/tee"),
            Some((sudo, rest)) => {
                let mut c = Command::new(sudo);
                c.args(rest).arg("/usr/bin/tee");
                c
            }
        };
        let mut child = tee
            .arg(&list)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .spawn()
            .map_err(|e| format!("cannot write {list}: {e}"))?;
        if let Some(mut stdin) = child.stdin.take() {
            use std::io::Write as _;
            stdin.write_all(line.as_bytes()).map_err(|e| format!("cannot write {list}: {e}"))?;
        }
        let status = child.wait().map_err(|e| format!("cannot write {list}: {e}"))?;
        if !status.success() {
            return Err(format!("cannot write {list} ({status})"));
        }
        crate::run(&mut apt(prefix, &["update", "-qq"]))?;
    }
    crate::run(&mut apt(
        prefix,
        &["install", "-y", "-qq", "--no-remove", "--no-install-recommends", "-t", release, "qemu-system-arm"],
    ))
}

fn apt_cache(args: &[&str]) -> String {
    Command::new("/usr/bin/apt-cache")
        .args(args)
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
        .unwrap_or_default()
}

/// Installs `wanted` with apt, removing nothing: what apt would remove is upgraded along
/// with them; if apt would still remove something, nothing is installed. QEMU comes
/// from the release the machine's `qemu-utils` came from ([`qemu_backports`]).
fn install(prefix: &[&str], wanted: &[&'static str]) -> Result {
    let shown = wanted.join(" ");
    step(&format!("installing Debian packages: {shown}"));
    crate::run(&mut apt(prefix, &["update", "-qq"]))?;
    let mut wanted = wanted.to_vec();
    if wanted.contains(&"qemu-system-arm")
        && let Some(release) = qemu_backports()
    {
        install_qemu_from(prefix, &release)?;
        wanted.retain(|&p| p != "qemu-system-arm");
        if wanted.is_empty() {
            return Ok(());
        }
    }
    let mut list: Vec<String> = wanted.iter().map(|s| (*s).to_owned()).collect();
    for _ in 0..3 {
        let mut sim = apt(prefix, &["-s", "install", "-y"]);
        sim.args(&list);
        let out = sim.output().map_err(|e| format!("cannot run apt-get -s: {e}"))?;
        let gone = removals(&String::from_utf8_lossy(&out.stdout));
        if gone.is_empty() {
            let mut c = apt(prefix, &["install", "-y", "-qq", "--no-remove"]);
            return crate::run(c.args(&list));
        }
        if gone.iter().all(|g| list.contains(g)) {
            break;
        }
        // Upgrade, rather than remove, what the machine already has.
        for g in gone {
            if !list.contains(&g) {
                list.push(g);
            }
        }
    }
    Err(format!(
        "installing {shown} would remove packages this machine has (apt-get -s install {}); \
         nothing was installed: resolve the conflict, then run cargo xtask ci again",
        list.join(" ")
    ))
}

/// Checks the prerequisites and installs what is missing when it may (`install`).
///
/// # Errors
/// Something is missing that cannot be installed here: the message names every missing
/// piece and the command that installs them all.
pub fn prerequisites(install_missing: bool) -> Result {
    step("prerequisites");
    let mut gaps = missing();
    if gaps.is_empty() {
        eprintln!("all there: rustfmt, clippy, a Cortex-M toolchain, ARM binutils, QEMU");
        return Ok(());
    }
    let wanted = packages(&gaps);
    let apt_prefix = apt_prefix();
    if install_missing
        && !wanted.is_empty()
        && let Some(prefix) = &apt_prefix
    {
        install(prefix, &wanted)?;
        gaps = missing();
        if gaps.is_empty() {
            return Ok(());
        }
    }
    // Without apt (another system, or no root), rustup's sources do what Debian's
    // compiler would.
    if install_missing
        && apt_prefix.is_none()
        && gaps.iter().any(|g| matches!(g.fix, Fix::Apt(p) if p.starts_with("rust")))
        && tool("rustup")
        && rustup_rust_src_added(Duration::from_secs(300))
    {
        gaps = missing();
        if gaps.is_empty() {
            return Ok(());
        }
    }
    let mut fixes: Vec<String> = Vec::new();
    let still = packages(&gaps);
    if !still.is_empty() {
        let sudo = if Command::new("/usr/bin/id").arg("-u").output().is_ok_and(|o| o.stdout.starts_with(b"0\n")) {
            ""
        } else {
            "sudo "
        };
        fixes.push(format!("{sudo}apt-get install -y --no-remove {}", still.join(" ")));
    }
    for g in &gaps {
        if let Fix::Command(c) = &g.fix
            && !fixes.contains(c)
        {
            fixes.push(c.clone());
        }
    }
    let whats: Vec<&str> = gaps.iter().map(|g| g.what.as_str()).collect();
    Err(format!(
        "missing: {}. Install with: {}{}",
        whats.join(", "),
        fixes.join(" && "),
        if !still.iter().any(|p| p.starts_with("rust")) {
            String::new()
        } else {
            " (or, where rustup can download, `rustup component add rust-src` in place of rustc-web, \
             cargo-web and rust-web-src)"
                .to_owned()
        }
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn apt_simulations_name_what_would_go() {
        let sim = "Reading package lists...\nRemv qemu-utils [1:7.2+dfsg-7+deb12u15]\n\
                   Inst qemu-system-arm (1:7.2+dfsg-7+deb12u18)\nRemv foo [1]\n";
        assert_eq!(removals(sim), ["qemu-utils", "foo"]);
        assert!(removals("Inst x (1)\nConf x (1)\n").is_empty());
    }

    #[test]
    fn each_package_is_named_once() {
        let m = |p| Missing { what: "x".into(), fix: Fix::Apt(p) };
        let gaps = [m("a"), m("b"), m("a"), Missing { what: "y".into(), fix: Fix::Command("c".into()) }];
        assert_eq!(packages(&gaps), ["a", "b"]);
    }
}
