//! `sim-host deploy IMAGE --port PATH|--tcp HOST:PORT`.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::bail;
use bt_link::host::{ControllerInfo, Verdict};
use sim_host::session::Event;

use bt_formats::DEPTH;
use sim_host::input::{self, Limit};

use super::link::{self, Line, Target};
use super::output::out;
use sim_host::text::count;

#[derive(clap::Args, Debug)]
#[command(
    long_about = "Sends a tree image to a running controller over its serial link and \
    waits for the verdict. The controller receives it into its spare slot while the \
    running tree goes on ticking, checks length, CRC and the whole image (as `inspect` \
    does), and only then swaps it in, between two ticks, after halting the running \
    tree's actions. A refused image leaves the running tree untouched; the reason is \
    printed and the exit code is 2.\n\n\
    The controller never reads an image's names section (what `inspect`, `export` and \
    `btlog` name the tree with); --strip-names sends the image without it.",
    after_help = "Examples:\n  sim-host deploy tree.bt --tcp 127.0.0.1:4321          # QEMU\n  \
    sim-host deploy tree.bt --port /dev/ttyACM0 --at-tick 200\n  \
    sim-host deploy tree.bt --tcp 127.0.0.1:4321 --start\n  \
    sim-host deploy nav.bt --port /dev/ttyACM0 --strip-names"
)]
pub struct Args {
    /// The image file (`sim-host plan --format image`).
    pub image: PathBuf,
    #[command(flatten)]
    pub target: Target,
    #[command(flatten)]
    pub line: Line,
    /// Swap the new tree in before this tick (default: the next tick boundary).
    #[arg(long, value_name = "TICK")]
    pub at_tick: Option<u32>,
    /// Then start ticking (every --period ms).
    #[arg(long)]
    pub start: bool,
    /// Milliseconds between ticks with --start (0: back to back). The tree's clock
    /// (what Timeout and Delay measure) advances by this much per tick.
    #[arg(long, default_value_t = 100)]
    pub period: u16,
    /// Send the image without its names section (behavior, port and key names for
    /// `inspect`, `export` and `btlog`), which the controller never reads: a smaller
    /// image, the same tree. The file is left as it is.
    #[arg(long)]
    pub strip_names: bool,
}

/// An image file read whole, checked against the controller it goes to: the behavior
/// set it was built for and the bytes the controller holds.
pub struct Checked {
    /// The bytes to send (without the names section with `strip_names`).
    pub image: Vec<u8>,
    /// Its header.
    pub header: bt_core::image::Header,
}

impl Checked {
    /// Reads `path` whole; its header must read.
    ///
    /// # Errors
    /// The file, or a header that does not read, naming the file.
    pub fn read(path: &Path) -> anyhow::Result<(Vec<u8>, bt_core::image::Header)> {
        let image = input::read(path, Limit::IMAGE)?;
        let header = bt_core::image::read_header(&image).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        Ok((image, header))
    }

    /// Checks `image` (read from `path`) against `info`, the controller at `name`
    /// running `set`.
    ///
    /// # Errors
    /// Another behavior set, or an image larger than the controller holds, naming the
    /// file.
    pub fn check(
        path: &Path,
        (image, header): (Vec<u8>, bt_core::image::Header),
        strip_names: bool,
        info: &ControllerInfo,
        set: &str,
        name: &str,
    ) -> anyhow::Result<Self> {
        // The names section is the host tools' alone: the same nodes, values and ports.
        let image = if strip_names {
            bt_formats::image::strip_names(&image).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?
        } else {
            image
        };
        if header.fingerprint != info.fingerprint {
            bail!(
                "{}: built for behavior set {:#018x}, the controller at {name} runs {set}",
                path.display(),
                header.fingerprint
            );
        }
        if image.len() > info.image_capacity as usize {
            let names = bt_core::image::section(&image, bt_core::image::SECTION_NAMES).ok().flatten();
            let hint = names.map_or(String::new(), |n| {
                format!("; --strip-names leaves out the {} of names the controller never reads", count(n.len(), "byte"))
            });
            bail!(
                "{}: {}, the controller at {name} holds images of at most {}{hint}",
                path.display(),
                count(image.len(), "byte"),
                count(info.image_capacity, "byte")
            );
        }
        Ok(Self { image, header })
    }
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let path = &args.image;
    // The file's own faults first, before the link is opened.
    let file = Checked::read(path)?;
    let (mut link, name) = link::open(&args.target, &args.line)?;
    let (info, set) = link::hello(&mut link, &name)?;
    let Checked { image, header } = Checked::check(path, file, args.strip_names, &info, &set, &name)?;
    out!("controller {name}: link protocol {}, behavior set {set}\n", info.version)?;
    let started = Instant::now();
    let verdict = link.deploy(&image, args.at_tick).map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
    let took = started.elapsed();
    match verdict {
        Verdict::Accepted { crc, nodes, swap_at } => {
            let when = swap_at.map_or_else(|| "at the next tick".to_string(), |t| format!("before tick {t}"));
            out!(
                "accepted: {} ({}, {}, CRC {crc:08x}) in {} ms; swaps in {when}\n",
                path.display(),
                count(image.len(), "byte"),
                count(nodes, "node"),
                took.as_millis()
            )?;
        }
        Verdict::Rejected(fault) => {
            // bt-core's own sentence for it, when this binary knows the behavior set.
            let local = super::catalogs::by_fingerprint(header.fingerprint)
                .and_then(|k| {
                    let mut nodes = vec![bt_core::Node::EMPTY; usize::from(header.node_count)];
                    let mut values = vec![0u16; image.len()];
                    bt_core::load_with::<_, DEPTH>(&image, k.catalog.as_ref(), &mut nodes, &mut values).err()
                })
                .map(|e| format!(" ({e})"))
                .unwrap_or_default();
            bail!("the controller at {name} rejected {}: {}{local}", path.display(), link::describe(&fault));
        }
    }
    if args.at_tick.is_none() {
        // Swapped comes at the next boundary; wait a moment for it.
        let deadline = Instant::now() + Duration::from_secs(2);
        while let Ok(event) = link.next(deadline) {
            if let Event::Swapped { tick, halted, .. } = event {
                out!(
                    "swapped in before tick {tick}; {} of the old tree halted first\n",
                    count(halted, "running action")
                )?;
                break;
            }
        }
    }
    if args.start {
        let tick = link.start(None, args.period).map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
        out!("ticking from tick {tick} every {} ms\n", args.period)?;
    }
    Ok(())
}
