//! `sim-host export IMAGE --format ... [--out FILE]`.

use std::path::PathBuf;

use bt_core::{MAX_ARGS, Node, Tree};
use planner::DEPTH;

use super::catalogs;
use super::output::{self, Content, Target};

/// What to turn the tree into.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// The indented py_trees-style view.
    Ascii,
    /// The token notation of seed 003: `s( f( 0 on 1? put 0 on 1! ) )`.
    Tokens,
    /// Graphviz DOT (`dot -Tsvg`).
    Dot,
    /// BehaviorTree.CPP v4 XML, with a TreeNodesModel for Groot2.
    Xml,
}

#[derive(clap::Args, Debug)]
#[command(long_about = "Loads and validates a tree image, then writes the tree in another \
    notation: to stdout, or to --out FILE (written whole or not at all).")]
pub struct Args {
    /// The image file.
    pub image: PathBuf,
    /// The notation to write.
    #[arg(long, value_enum, default_value_t = Format::Ascii)]
    pub format: Format,
    /// Write here instead of stdout (`-`: stdout).
    #[arg(long, value_name = "FILE", value_parser = Target::parse)]
    pub out: Option<Target>,
    /// For an image imported from BehaviorTree.CPP XML: the files `import` read (its tree
    /// file and its --nodes), whose models name the behaviors.
    #[arg(long = "nodes", value_name = "MODELS.xml")]
    pub nodes: Vec<PathBuf>,
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let path = &args.image;
    let bytes = sim_host::input::read(path, sim_host::input::Limit::IMAGE)?;
    let (known, header) = catalogs::for_image_with(path, &bytes, &args.nodes)?;
    let mut storage = vec![Node::EMPTY; usize::from(header.node_count)];
    let mut values = vec![0u16; usize::from(u16::MAX)];
    let tree: Tree<'_, DEPTH> = bt_core::load_with(&bytes, known.catalog.as_ref(), &mut storage, &mut values)
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let values = tree.values();
    let text = match args.format {
        Format::Ascii => tree.display(known.catalog.as_ref()).to_string(),
        Format::Tokens if !values.is_empty() => anyhow::bail!(
            "{}: --format tokens cannot write leaves with more than {MAX_ARGS} arguments (this tree has some); \
             write it with --format ascii, dot or xml",
            path.display()
        ),
        Format::Tokens => {
            let mut t = planner::tokens::to_string(tree.nodes(), known.catalog.as_ref()).map_err(|e| {
                anyhow::anyhow!("{}: --format tokens: {e}; write it with --format ascii, dot or xml", path.display())
            })?;
            t.push('\n');
            t
        }
        Format::Dot => planner::output::to_dot_with(tree.nodes(), values, known.catalog.as_ref()),
        Format::Xml => {
            let ports: &dyn planner::Ports = match &known.ports {
                Some(p) => p.as_ref(),
                None => &planner::NoPorts,
            };
            let options = planner::output::XmlOptions { values, ..planner::output::XmlOptions::default() };
            planner::output::to_xml_with(tree.nodes(), known.catalog.as_ref(), ports, &options)
                .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?
        }
    };
    output::write(args.out.as_ref().unwrap_or(&Target::Stdout), text.as_bytes(), Content::Text)?;
    Ok(())
}
