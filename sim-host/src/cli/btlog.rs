//! `sim-host btlog --from-trace TRACE --image IMAGE`: a controller's trace as a Groot2
//! replay log.

use std::path::PathBuf;

use anyhow::{anyhow, bail};
use btcpp::btlog::{LogTree, RunLog, replay::status};

use sim_host::input::{self, Limit};
use sim_host::text::count;

use super::catalogs;
use super::output::{self, Content};

pub const LONG_ABOUT: &str = "Turns the trace a controller printed (firmware-example's `tick N \
    STATUS ran=...` lines, on QEMU or the board) into a Groot2 replay log: the format \
    BehaviorTree.CPP's FileLogger2 writes, with the tree of the image the controller ran, \
    numbered as `sim-host export --format xml` numbers it (_uid), and every status \
    transition BehaviorTree.CPP's nodes would make for the leaf results in the trace. \
    Timestamps are the controller's ticks at the rate its `boot` line gives (hz=), so \
    the same trace gives the same log. Nodes and ports are named from the image's names \
    section, as `inspect` finds them.";

#[derive(clap::Args, Debug)]
#[command(after_help = "Example:\n  cargo run -p firmware-example --target x86_64-unknown-linux-gnu > run.txt\n  \
    sim-host btlog --from-trace run.txt --image tree.bt --out run.btlog")]
pub struct Args {
    /// The controller's trace.
    #[arg(long, value_name = "TRACE")]
    pub from_trace: PathBuf,
    /// The image the controller ran.
    #[arg(long, value_name = "IMAGE")]
    pub image: PathBuf,
    /// The log to write (give it the .btlog extension Groot2 expects).
    #[arg(long, value_name = "FILE.btlog")]
    pub out: PathBuf,
    /// For an image imported from BehaviorTree.CPP XML without names (stripped, or made
    /// before images carried them): the files `import` read (its tree file and its
    /// --nodes), whose models name the behaviors in the log.
    #[arg(long = "nodes", value_name = "MODELS.xml")]
    pub nodes: Vec<PathBuf>,
}

/// The leaf calls of a `ran=` list: `2F,4S,9R` or `-`.
fn ran(list: &str) -> Option<Vec<(usize, u8)>> {
    if list == "-" {
        return Some(Vec::new());
    }
    list.split(',')
        .map(|item| {
            let (id, s) = item.split_at_checked(item.len().checked_sub(1)?)?;
            let s = match s {
                "S" => status::SUCCESS,
                "F" => status::FAILURE,
                "R" => status::RUNNING,
                _ => return None,
            };
            Some((id.parse().ok()?, s))
        })
        .collect()
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let bytes = input::read(&args.image, Limit::IMAGE)?;
    let fail = |e: &dyn std::fmt::Display| anyhow!("{}: {e}", args.image.display());
    let log_tree = catalogs::load_image(&args.image, &bytes, &args.nodes, |known, _, tree| {
        // An image `import` wrote is logged as its document numbers it (SubTree nodes,
        // scripts, node names); others as `export --format xml` writes them.
        match btcpp::xml::Imported::from_image(&bytes).map_err(|e| fail(&e))? {
            Some(imported) => LogTree::of_imported(&imported),
            None => LogTree::with_values(tree.nodes(), tree.values(), known.catalog.as_ref()),
        }
        .map_err(|e| fail(&e))
    })?;
    let text = input::read_text(&args.from_trace, Limit::TRACE)?;
    let mut period_usec: i64 = 100_000;
    let mut log = RunLog::new(&log_tree, 0);
    let mut ticks = 0u32;
    for (n, line) in text.lines().enumerate() {
        let at = || format!("{}:{}", args.from_trace.display(), n + 1);
        let words: Vec<&str> = line.split(' ').collect();
        match words.first() {
            Some(&"boot") => {
                if let Some(hz) = words.iter().find_map(|w| w.strip_prefix("hz=")) {
                    let hz: i64 = hz.parse().ok().filter(|&h| h > 0).ok_or_else(|| anyhow!("{}: bad hz={hz}", at()))?;
                    period_usec = 1_000_000 / hz;
                }
            }
            Some(&"tick") => {
                let k: u32 =
                    words.get(1).and_then(|w| w.parse().ok()).ok_or_else(|| anyhow!("{}: bad tick line", at()))?;
                if words.get(2) == Some(&"ERROR") {
                    bail!("{}: the controller stopped with an error at tick {k}", at());
                }
                let list = words
                    .iter()
                    .find_map(|w| w.strip_prefix("ran="))
                    .ok_or_else(|| anyhow!("{}: tick line without ran=", at()))?;
                let calls = ran(list).ok_or_else(|| anyhow!("{}: cannot read ran={list} (cut line?)", at()))?;
                // The controller gives bt-core milliseconds: tick k at k periods.
                let now = u32::try_from(i64::from(k) * period_usec / 1000).unwrap_or(u32::MAX);
                log.tick(k, i64::from(k) * period_usec, now, &calls).map_err(|e| anyhow!("{}: {e}", at()))?;
                ticks += 1;
            }
            _ => {}
        }
    }
    if ticks == 0 {
        bail!("{}: no `tick` lines", args.from_trace.display());
    }
    let bytes = log.into_bytes();
    output::write_file(&args.out, &bytes, Content::Binary("a replay log"))?;
    output::stderr(
        format!("wrote {} ({}, {})\n", args.out.display(), count(ticks, "tick"), count(bytes.len(), "byte")).as_bytes(),
    )?;
    Ok(())
}
