//! `sim-host catalog MODELS.xml ...`: the behavior set of BehaviorTree.CPP models, or
//! (`--stub TREE.xml`) models for the node types a tree uses that none declares.

use std::path::PathBuf;

use bt_core::Catalog as _;
use btcpp::xml::{Models, document};

use sim_host::text::count;

use super::output::{self, Content, Target};

pub const LONG_ABOUT: &str = "Reads <TreeNodesModel> from the files given and prints the behavior \
    set that `sim-host import` builds from the same files: every Action and Condition model \
    sorted by ID, each with its ports (name, direction, type, default), and the set's \
    fingerprint. Give the files as to `import`: its tree file (or any file read as one: \
    Groot2 projects) as FILES, the model files the program's nodes stand for (Nav2's \
    nav2_tree_nodes.xml) with --nodes. Two models of one node type that differ only in a \
    port's type or default are one, the --nodes one winning; any other difference is an \
    error naming both (--nodes-override: the --nodes model wins).\n\n\
    With --rust, prints it as Rust source a controller crate compiles in: a const per behavior \
    id, the bt_core::Behavior table with its ports, and FINGERPRINT, checked against the table \
    at compile time. An image imported with these models loads on that controller; an image \
    for any other set is refused with `foreign-behavior-set`.\n\n\
    With --stub TREE.xml, writes models for the node types the tree's main tree uses that no \
    model (its own, --nodes) declares, guessed from how it uses them: the kind from the \
    element (<Action ID>, ...), else a decorator for one child and a condition for a leaf \
    named as a question (IsBatteryLow, GoalReached), else an action; a port for every \
    attribute used, an input port where some use gives a literal, else an in/out port. \
    Each model says what was guessed; check them, then give the file to `import` with \
    --nodes. Ports the tree gives to declared node types that their models lack are \
    listed on stderr.";

#[derive(clap::Args, Debug)]
#[command(after_help = "Examples:\n  sim-host catalog --nodes nav2_tree_nodes.xml\n  \
    sim-host catalog tree.xml --nodes nav2_tree_nodes.xml --rust --out src/behaviors.rs\n  \
    sim-host catalog --stub tree.xml --nodes nav2_tree_nodes.xml --out stub.xml")]
pub struct Args {
    /// Files read as `import` reads its tree file: their models are copies, which a
    /// --nodes model of the same node type wins over.
    #[arg(value_name = "FILE.xml", required_unless_present_any = ["nodes", "stub"])]
    pub files: Vec<PathBuf>,
    /// Model files, as `import --nodes` reads them: what the C++ program registers (repeatable).
    #[arg(long = "nodes", value_name = "MODELS.xml")]
    pub nodes: Vec<PathBuf>,
    /// A --nodes model wins over a file's model of the same node type, however they differ.
    #[arg(long)]
    pub nodes_override: bool,
    /// Write models for the node types this tree file's main tree uses that no model declares.
    #[arg(long, value_name = "TREE.xml", conflicts_with_all = ["files", "rust"])]
    pub stub: Option<PathBuf>,
    /// With --stub: the tree to look at instead of main_tree_to_execute.
    #[arg(long, value_name = "ID", requires = "stub")]
    pub main: Option<String>,
    /// Print the Rust table instead of the summary.
    #[arg(long)]
    pub rust: bool,
    /// Write here instead of stdout (a file is written whole or not at all; `-`: stdout).
    #[arg(long, value_parser = Target::parse)]
    pub out: Option<Target>,
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    if let Some(tree) = &args.stub {
        return stub(args, tree);
    }
    let mut doc = document::read_models(&args.nodes)?;
    for f in &args.files {
        let other = document::read(f, &[])?;
        doc.models.extend(other.models);
    }
    let catalog = Models::read(&doc.models, args.nodes_override)?.catalog();
    let names: Vec<String> = args.files.iter().chain(&args.nodes).map(|f| f.display().to_string()).collect();
    let text = if args.rust {
        catalog.to_rust(&names.join(", "))
    } else {
        let mut s = format!(
            "behavior set {:#018x}: {} from {}\n",
            catalog.fingerprint(),
            count(catalog.behaviors().len(), "behavior"),
            names.join(", ")
        );
        for (i, b) in catalog.behaviors().iter().enumerate() {
            let kind = if b.kind == bt_core::LeafKind::Condition { "condition" } else { "action" };
            s.push_str(&format!("{i:>5}  {kind:<9}  {}", b.id));
            let ports: Vec<String> = b
                .ports
                .iter()
                .map(|p| {
                    let dir = match p.direction {
                        bt_core::PortDirection::Input => "in",
                        bt_core::PortDirection::Output => "out",
                        bt_core::PortDirection::InOut => "inout",
                    };
                    format!("{dir} {}: {}", p.name, p.type_name.as_deref().unwrap_or("any"))
                })
                .collect();
            if !ports.is_empty() {
                s.push_str(&format!("({})", ports.join(", ")));
            }
            s.push('\n');
        }
        s
    };
    output::write(args.out.as_ref().unwrap_or(&Target::Stdout), text.as_bytes(), Content::Text)?;
    Ok(())
}

/// `--stub TREE.xml`: models for the node types the tree uses that none declares.
fn stub(args: &Args, tree: &std::path::Path) -> anyhow::Result<()> {
    let doc = document::read(tree, &args.nodes)?;
    let models = Models::read(&doc.models, args.nodes_override)?;
    let stub = btcpp::xml::stub::stub(&doc, args.main.as_deref(), &models)?;
    let mut note = String::new();
    for (id, port, at) in &stub.missing {
        note.push_str(&format!("{at}: `{id}` is given port `{port}`, which its model does not declare\n"));
    }
    let guessed = stub.models.iter().filter(|m| m.guessed).count();
    note.push_str(&format!(
        "{}: {} for the node types it uses that no model declares ({guessed} of them guessed); check them\n",
        tree.display(),
        count(stub.models.len(), "model"),
    ));
    let name = tree.file_name().map_or_else(|| tree.display().to_string(), |f| f.to_string_lossy().into_owned());
    output::write(args.out.as_ref().unwrap_or(&Target::Stdout), stub.to_xml(&name).as_bytes(), Content::Text)?;
    output::stderr(note.as_bytes())?;
    Ok(())
}
