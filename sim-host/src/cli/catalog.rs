//! `sim-host catalog MODELS.xml ...`: the behavior set of BehaviorTree.CPP models.

use std::path::PathBuf;

use bt_core::Catalog as _;
use btcpp::xml::{Models, document};

use sim_host::text::count;

use super::output::{self, Content, Target};

pub const LONG_ABOUT: &str = "Reads <TreeNodesModel> from the files given (model files such as \
    Nav2's nav2_tree_nodes.xml, Groot2 projects, tree files) and prints the behavior set that \
    `sim-host import` builds from the same files: every Action and Condition model sorted by \
    ID, each with its ports (name, direction, type, default), and the set's fingerprint.\n\n\
    With --rust, prints it as Rust source a controller crate compiles in: a const per behavior \
    id, the bt_core::Behavior table with its ports, and FINGERPRINT, checked against the table \
    at compile time. An image imported with these models loads on that controller; an image \
    for any other set is refused with `foreign-behavior-set`.";

#[derive(clap::Args, Debug)]
#[command(after_help = "Examples:\n  sim-host catalog nav2_tree_nodes.xml\n  \
    sim-host catalog nav2_tree_nodes.xml --rust --out src/behaviors.rs")]
pub struct Args {
    /// Files with <TreeNodesModel>; give the same files as to `import` (its tree file and --nodes).
    #[arg(required = true, value_name = "MODELS.xml")]
    pub files: Vec<PathBuf>,
    /// Print the Rust table instead of the summary.
    #[arg(long)]
    pub rust: bool,
    /// Write here instead of stdout (a file is written whole or not at all; `-`: stdout).
    #[arg(long, value_parser = Target::parse)]
    pub out: Option<Target>,
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let doc = document::read_models(&args.files)?;
    let catalog = Models::new(&doc.models)?.catalog();
    let names: Vec<String> = args.files.iter().map(|f| f.display().to_string()).collect();
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
