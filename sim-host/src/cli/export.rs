//! `sim-host export IMAGE --format ... [--out FILE]`.

use std::path::PathBuf;

use bt_core::{Catalog, MAX_ARGS, Node, NodeKind, PortTable, Tree};
use bt_formats::{DEPTH, dot, tokens};

use super::catalogs;
use super::output::{self, Content, Target};

/// What to turn the tree into.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// The indented py_trees-style view.
    Ascii,
    /// The token notation of Styrud et al.: `s( f( 0 on 1? put 0 on 1! ) )`.
    Tokens,
    /// Graphviz DOT (`dot -Tsvg`).
    Dot,
    /// BehaviorTree.CPP v4 XML, with a TreeNodesModel for Groot2.
    Xml,
}

#[derive(clap::Args, Debug)]
#[command(long_about = "Loads and validates a tree image, then writes the tree in another \
    notation: to stdout, or to --out FILE (written whole or not at all). The names come \
    from the image's names section, as `inspect` finds them.\n\n\
    --format xml of an image imported from BehaviorTree.CPP writes the tree as `import \
    --format xml` does (scripts, loops and node names as the document wrote them, a version 3 \
    document as version 3) and declares every model of its behavior set, so that `sim-host \
    import` of the document gives the same image back; an image whose names were stripped \
    keeps the programs of its scripts, not their text, and is refused.\n\n\
    --format tokens names the first node the notation cannot write.")]
pub struct Args {
    /// The image file.
    pub image: PathBuf,
    /// The notation to write.
    #[arg(long, value_enum, default_value_t = Format::Ascii)]
    pub format: Format,
    /// Write here instead of stdout (`-`: stdout).
    #[arg(long, value_name = "FILE", value_parser = Target::parse)]
    pub out: Option<Target>,
    /// For an image imported from BehaviorTree.CPP XML without names (stripped, or made
    /// before images carried them): the files `import` read (its tree file and its
    /// --nodes), whose models name the behaviors.
    #[arg(long = "nodes", value_name = "MODELS.xml")]
    pub nodes: Vec<PathBuf>,
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let path = &args.image;
    let bytes = sim_host::input::read(path, sim_host::input::Limit::IMAGE)?;
    let text = catalogs::load_image(path, &bytes, &args.nodes, |known, _, tree| {
        let values = tree.values();
        Ok(match args.format {
            Format::Ascii => tree.display(known.catalog.as_ref()).to_string(),
            Format::Tokens => {
                let imported = btcpp::xml::Imported::from_image(&bytes).ok().flatten();
                let ids: Vec<&str> =
                    imported.as_ref().map(|i| i.meta.iter().map(|m| m.id.as_str()).collect()).unwrap_or_default();
                let mut t = token_text(tree.nodes(), known.catalog.as_ref(), &ids).map_err(|e| {
                    anyhow::anyhow!("{}: {e}; write it with --format ascii, dot or xml", path.display())
                })?;
                t.push('\n');
                t
            }
            Format::Dot => dot::to_dot_with(tree.nodes(), values, known.catalog.as_ref()),
            Format::Xml => xml(path, &bytes, &tree, &known)?,
        })
    })?;
    output::write(args.out.as_ref().unwrap_or(&Target::Stdout), text.as_bytes(), Content::Text)?;
    Ok(())
}

/// The tree in the token notation of Styrud et al., or what it cannot write: the first
/// node (in pre-order) of a kind the notation lacks, or a leaf with more than
/// [`MAX_ARGS`] arguments, named by `ids` (the document's registration IDs, when the
/// tree was imported from one).
pub(super) fn token_text(nodes: &[Node], catalog: &dyn Catalog, ids: &[&str]) -> Result<String, String> {
    let named = |i: usize| ids.get(i).map_or_else(|| format!("node {i}"), |id| format!("node {i}, `{id}`"));
    let leaf = |n: &Node| match *n.kind() {
        NodeKind::Gate(leaf) => Some(leaf),
        ref other => other.leaf().map(|(_, leaf)| leaf),
    };
    let wide = nodes.iter().position(|n| leaf(n).is_some_and(|l| l.is_extended()));
    match tokens::to_string(nodes, catalog) {
        Err(tokens::TokenError::NotExpressible { node, kind }) if wide.is_none_or(|w| node < w) => Err(format!(
            "--format tokens cannot write {}, a bt-core {kind}: the notation has only s( f( ) and leaves",
            named(node)
        )),
        _ if wide.is_some() => {
            let w = wide.unwrap_or_default();
            let argc = nodes.get(w).and_then(leaf).map_or(0, |l| l.argc());
            Err(format!(
                "--format tokens cannot write {}: it has {}, the notation at most {MAX_ARGS}",
                named(w),
                sim_host::text::count(argc, "argument")
            ))
        }
        Err(e) => Err(format!("--format tokens: {e}")),
        Ok(t) => Ok(t),
    }
}

/// The tree as BehaviorTree.CPP XML. A behavior set that declares ports is declared
/// whole, so that importing the document gives the same set (and fingerprint) back.
fn xml(
    path: &std::path::Path,
    bytes: &[u8],
    tree: &Tree<'_, DEPTH>,
    known: &catalogs::Known,
) -> anyhow::Result<String> {
    let catalog = known.catalog.as_ref();
    let fail = |e: &dyn std::fmt::Display| anyhow::anyhow!("{}: {e}", path.display());
    // An image `import` wrote carries what its document said of each node: written back
    // as the document wrote it (scripts, loops, SubTree nodes, node names).
    if let Some(imported) = btcpp::xml::Imported::from_image(bytes).map_err(|e| fail(&e))? {
        return imported.to_xml().map_err(|e| fail(&e));
    }
    // A key that starts at a literal was given it by a SubTree, which the document of a
    // flattened tree does not have.
    let table = PortTable::of_image(bytes).map_err(|e| fail(&e))?;
    if let Some(slot) = (0..table.slot_count()).find(|&s| table.slot(s).is_some_and(|s| s.initial.is_some())) {
        anyhow::bail!(
            "{}: blackboard slot {slot} starts at a literal that a SubTree gave it, which the flattened tree \
             cannot write; export the imported document instead (sim-host import TREE.xml --format xml)",
            path.display()
        );
    }
    let declares_ports = (0..catalog.len())
        .filter_map(|b| u16::try_from(b).ok())
        .any(|b| catalog.info(b).is_some_and(|i| (0..usize::from(i.arity)).any(|p| catalog.port(b, p).is_some())));
    let options = btcpp::xml::XmlOptions {
        values: tree.values(),
        all_behaviors: declares_ports,
        tree_id: &known.tree_id,
        ..btcpp::xml::XmlOptions::default()
    };
    btcpp::xml::to_xml_with(tree.nodes(), catalog, &options).map_err(|e| fail(&e))
}
