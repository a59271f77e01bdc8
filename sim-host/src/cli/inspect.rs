//! `sim-host inspect IMAGE`.

use std::path::PathBuf;

use super::catalogs;
use super::output::out;

#[derive(clap::Args, Debug)]
#[command(long_about = "Loads a tree image exactly as a controller would (envelope, CRC, \
    behavior-set fingerprint, node decoding, validation) and prints the tree with its \
    behavior names and the image's facts. A bad image prints its LoadError and exits 2.\n\n\
    The names come from the --nodes models when given, else from the image's names \
    section (which `plan`, `learn` and `import` write and the controller never reads: \
    behaviors, ports as `name={key}` or `name=value`, objects), else from the built-in \
    behavior set with the image's fingerprint; else the tree is shown by ids.")]
pub struct Args {
    /// The image file (as written by `sim-host plan --format image` or `learn`).
    pub image: PathBuf,
    /// For an image imported from BehaviorTree.CPP XML without names (stripped, or made
    /// before images carried them): the files `import` read (its tree file and its
    /// --nodes), whose models name the behaviors.
    #[arg(long = "nodes", value_name = "MODELS.xml")]
    pub nodes: Vec<PathBuf>,
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let path = &args.image;
    let bytes = sim_host::input::read(path, sim_host::input::Limit::IMAGE)?;
    catalogs::load_image(path, &bytes, &args.nodes, |known, header, tree| {
        let note = known.note.as_ref().map(|n| format!("note       {n}\n")).unwrap_or_default();
        out!(
            "image      {}\nformat     version {}\nbehaviors  {:#018x} ({})\nnodes      {} (depth {})\nbytes      {}\n{note}\n{}",
            path.display(),
            header.version,
            header.fingerprint,
            known.name,
            tree.len(),
            tree.depth(),
            header.len,
            tree.display(known.catalog.as_ref())
        )?;
        Ok(())
    })
}
