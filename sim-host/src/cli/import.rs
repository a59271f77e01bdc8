//! `sim-host import TREE.xml`: a BehaviorTree.CPP document to an image (or another
//! notation).

use std::path::PathBuf;

use bt_core::Catalog;
use bt_formats::{ascii, dot, image::Image, tokens};
use btcpp::xml::{ImportOptions, Imported, import};

use sim_host::text::count;

use super::catalogs;
use super::output::{self, Content, Target};

/// What to write.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// The deployable image (binary; give --out or redirect stdout).
    Image,
    /// The indented view, leaves with their ports.
    Ascii,
    /// Graphviz DOT.
    Dot,
    /// BehaviorTree.CPP XML again: one tree, SubTrees expanded, every model declared.
    Xml,
    /// The token notation of Styrud et al. (reactive Sequence, Fallback and leaves only).
    Tokens,
}

pub const LONG_ABOUT: &str = "Imports a BehaviorTree.CPP XML document and writes the image a \
    controller loads, or the tree in another notation. A document with BTCPP_format=\"4\" is read \
    by BehaviorTree.CPP 4's rules; one without it by BehaviorTree.CPP 3.8's, as Nav2 humble and \
    older ship them (SubTree remapping by name, __shared_blackboard, SubTreePlus, ${key}, 3.8's \
    SequenceStar, Parallel thresholds, Repeat, RetryUntilSuccessful and BlackboardCheck*).\n\n\
    The main tree is --main, else the document's main_tree_to_execute, else its only tree. \
    <include path> is read relative to the including file; <SubTree> nodes are expanded per \
    instance with their port remapping ({parent_key}, literals, _autoremap, {=}, {@root_key}).\n\n\
    Leaf types and their ports come from <TreeNodesModel> in the document and in the --nodes \
    files (Nav2's nav2_tree_nodes.xml, a Groot2 project): the behavior set is every Action and \
    Condition model, sorted by ID, and its fingerprint covers every port. Two models of one node \
    type that differ only in a port's type or default are one, the --nodes one winning (as \
    BehaviorTree.CPP goes by what the program registers); other differences are an error \
    naming both. `sim-host catalog` \
    prints the same set as the Rust table a controller compiles in. Port values become image \
    data: literals are constants typed as the model declares the port, {key}s are blackboard \
    slot numbers, ports left out are unset (the behavior's default).\n\n\
    The image carries a names section that the controller never reads: the behavior set's \
    names and ports (name, direction, type, default), the blackboard keys, the scripting \
    enums, each node as the document wrote it (ID, name, parameters, scripts, SubTree nodes) \
    and a title naming the tree, so that `inspect`, `export` and `btlog` show the tree as it \
    is written here without the model files (`deploy --strip-names` sends the image \
    without it).\n\n\
    Script, ScriptCondition, Precondition and the scripted attributes (_skipIf, _while, \
    _onSuccess, ...) run on the controller: their scripts are compiled at import into small \
    programs the image carries (keys become blackboard slots; --enum gives the scripting \
    enums the C++ program registers). A script that does not parse is refused with its \
    place.\n\n\
    LoopInt, LoopBool, LoopDouble and LoopString run on the controller too: a literal queue \
    (queue=\"1;2;3\") is compiled into the image, a {key} queue is popped by the controller's \
    behavior set (BehaviorSet::pop); --loop ID reads a LoopNode<T> the C++ program registers \
    for a type of its own (t18's LoopPose).\n\n\
    ManualSelector runs on the controller: instead of asking a person at a terminal, it asks \
    the controller's behavior set (BehaviorSet::select: a teleoperation command, a button) on \
    every tick which child to tick or which status to return.\n\n\
    What a controller cannot run is refused with file:line:column and the construct named, \
    and nothing is written: Switch, UnsetBlackboard, building strings in scripts, ports a \
    model does not declare, literals on version 4 output ports. Node types no model declares \
    are listed all at once; `sim-host catalog --stub TREE.xml` writes models for them.\n\n\
    --behaviors NAME reads XML that `sim-host plan/export --format xml` wrote for a built-in \
    behavior set (a brick task or PDDL domain) back into that set, giving the same image.";

#[derive(clap::Args, Debug)]
#[command(after_help = "Examples:\n  \
    sim-host import navigate_to_pose.xml --nodes nav2_tree_nodes.xml --out nav.bt\n  \
    sim-host import tree.xml --format ascii\n  \
    sim-host import tower.xml --behaviors tower --out tower.bt\n  \
    sim-host import t09_scripting.xml --nodes nodes.xml --enum RED=1 --enum BLUE=2 --enum THE_ANSWER=42\n  \
    sim-host import main.xml --nodes nodes.xml --nodes subtrees.xml --cast Cat::Ptr=Animal::Ptr\n  \
    sim-host import t18_waypoints.xml --nodes nodes.xml --loop LoopPose")]
pub struct Args {
    /// The BehaviorTree.CPP XML file.
    pub tree: PathBuf,
    /// Files with <TreeNodesModel> declaring the node types, or with more <BehaviorTree>s
    /// for the tree's SubTrees, as a C++ program registers several files before it
    /// creates the tree (repeatable).
    #[arg(long = "nodes", value_name = "MODELS.xml")]
    pub nodes: Vec<PathBuf>,
    /// A --nodes model wins over the tree file's model of the same node type, however
    /// they differ (without it, models that differ in more than a port's type or default
    /// are an error naming both).
    #[arg(long)]
    pub nodes_override: bool,
    /// The tree to import instead of main_tree_to_execute.
    #[arg(long, value_name = "ID")]
    pub main: Option<String>,
    /// What to write.
    #[arg(long, value_enum, default_value_t = Format::Image)]
    pub format: Format,
    /// Write here instead of stdout (a file is written whole or not at all; `-`: stdout).
    #[arg(long, value_parser = Target::parse)]
    pub out: Option<Target>,
    /// Read leaves against this built-in behavior set instead of the document's models.
    #[arg(long, value_name = "NAME")]
    pub behaviors: Option<String>,
    /// A scripting enum, as the C++ program registers it (registerScriptingEnum or
    /// registerScriptingEnums): scripts read NAME as the number VALUE (repeatable).
    #[arg(long = "enum", value_name = "NAME=VALUE", value_parser = parse_enum)]
    pub enums: Vec<(String, i64)>,
    /// A polymorphic cast, as the C++ program registers it
    /// (registerPolymorphicCast<Derived, Base>), with the port types as the models write
    /// them: an input port of type BASE may then read a key written as DERIVED
    /// (repeatable; casts chain upwards).
    #[arg(long = "cast", value_name = "DERIVED=BASE", value_parser = parse_cast)]
    pub casts: Vec<(String, String)>,
    /// A node type the C++ program registers as a loop over a type of its own
    /// (registerNodeType<LoopNode<Pose2D>>("LoopPose")): read with the ports and the
    /// semantics of LoopInt and the others, over a {key} queue that the controller's
    /// behavior set keeps (repeatable).
    #[arg(long = "loop", value_name = "ID")]
    pub loops: Vec<String>,
}

fn parse_cast(text: &str) -> Result<(String, String), String> {
    match text.split_once('=') {
        Some((derived, base)) if !derived.trim().is_empty() && !base.trim().is_empty() => {
            Ok((derived.trim().to_string(), base.trim().to_string()))
        }
        _ => Err(format!("`{text}`: expected DERIVED=BASE, like Cat::Ptr=Animal::Ptr")),
    }
}

fn parse_enum(text: &str) -> Result<(String, i64), String> {
    let (name, value) = text.split_once('=').ok_or_else(|| format!("`{text}`: expected NAME=VALUE, like RED=1"))?;
    let ok = name.chars().next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    if !ok {
        return Err(format!("`{name}` is not a script identifier (letters, digits, _)"));
    }
    let value = value.trim().parse().map_err(|_| format!("`{value}` is not an integer"))?;
    Ok((name.to_string(), value))
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let target = args.out.clone().unwrap_or(Target::Stdout);
    let content = if args.format == Format::Image { Content::Binary("a tree image") } else { Content::Text };
    // Before any work: binary output is refused on a terminal.
    output::check(&target, content)?;
    let known = match &args.behaviors {
        Some(name) => Some(catalogs::by_name(name).ok_or_else(|| {
            anyhow::anyhow!(
                "--behaviors {name}: no such built-in behavior set (known: {})",
                catalogs::names().join(", ")
            )
        })?),
        None => None,
    };
    let options = ImportOptions {
        models: args.nodes.clone(),
        main: args.main.clone(),
        known: known.as_ref().map(|k| k.catalog.as_ref()),
        enums: args.enums.clone(),
        casts: args.casts.clone(),
        loops: args.loops.clone(),
        nodes_override: args.nodes_override,
    };
    let imported = import(&args.tree, &options)?;
    let bytes = match &known {
        Some(k) => render_known(args.format, &imported, k.catalog.as_ref())?,
        None => {
            let file =
                args.tree.file_name().map_or_else(|| args.tree.display().to_string(), |f| f.to_string_lossy().into());
            render(args.format, &imported, &format!("BehaviorTree.CPP tree `{}` of {file}", imported.main))?
        }
    };
    let summary = format!(
        "imported `{}` from {}: {}, {}, {}; behavior set {:#018x} ({})",
        imported.main,
        args.tree.display(),
        count(imported.nodes.len(), "node"),
        count(imported.constants.len(), "constant"),
        count(imported.slots.len(), "blackboard slot"),
        imported.fingerprint,
        count(known.as_ref().map_or(imported.catalog.behaviors().len(), |k| k.catalog.len()), "behavior"),
    );
    output::write(&target, &bytes, content)?;
    match &target {
        Target::File(path) => output::stderr(
            format!("{summary}\nwrote {} ({})\n", path.display(), count(bytes.len(), "byte")).as_bytes(),
        )?,
        Target::Stdout => output::stderr(format!("{summary}\n").as_bytes())?,
    }
    Ok(())
}

/// Text that ends its last line (the view has none after its last node).
fn lines(mut text: String) -> Vec<u8> {
    if !text.ends_with('\n') {
        text.push('\n');
    }
    text.into_bytes()
}

/// The tree imported against its models, with its names (titled `title`) in the image.
fn render(format: Format, imported: &Imported, title: &str) -> anyhow::Result<Vec<u8>> {
    Ok(match format {
        Format::Image => {
            let mut names = imported.names();
            title.clone_into(&mut names.title);
            imported.named_image(&names)?
        }
        Format::Ascii => lines(ascii::to_ascii_with(&imported.nodes, &imported.values, imported)?),
        Format::Dot => dot::to_dot_with(&imported.nodes, &imported.values, imported).into_bytes(),
        Format::Xml => imported.to_xml()?.into_bytes(),
        Format::Tokens => {
            let ids: Vec<&str> = imported.meta.iter().map(|m| m.id.as_str()).collect();
            let mut t = super::export::token_text(&imported.nodes, imported, &ids)
                .map_err(|e| anyhow::anyhow!("{e}; write it with --format ascii, dot, xml or image"))?;
            t.push('\n');
            t.into_bytes()
        }
    })
}

/// The tree read back into a built-in behavior set, which `inspect` knows by its
/// fingerprint: the image needs no names.
fn render_known(format: Format, imported: &Imported, catalog: &dyn Catalog) -> anyhow::Result<Vec<u8>> {
    let (nodes, values) = (&imported.nodes, &imported.values);
    Ok(match format {
        Format::Image => Image::new(nodes).values(values).encode(catalog.fingerprint())?,
        Format::Ascii => lines(ascii::to_ascii_with(nodes, values, catalog)?),
        Format::Dot => dot::to_dot_with(nodes, values, catalog).into_bytes(),
        Format::Xml => {
            let options = btcpp::xml::XmlOptions { values, ..btcpp::xml::XmlOptions::default() };
            btcpp::xml::to_xml_with(nodes, catalog, &options)?.into_bytes()
        }
        Format::Tokens => {
            let mut t = tokens::to_string(nodes, catalog)?;
            t.push('\n');
            t.into_bytes()
        }
    })
}
