//! `sim-host plan`: backchaining planning (seed 000) of a PDDL problem or a brick task.

use std::path::PathBuf;
use std::sync::Arc;

use anyhow::{Context as _, bail};
use bt_core::{Catalog, Node};
use planner::duplo::Task;
use planner::names::NameTable;
use planner::{Expansion, NoPorts, Options, PddlCatalog, Ports, Refinement};

use super::output::{self, Content, Target, out};
use planner::output as notation;
use sim_host::text::count;

/// What to write the tree as.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// The indented py_trees-style view.
    Ascii,
    /// Graphviz DOT (`dot -Tsvg`).
    Dot,
    /// BehaviorTree.CPP v4 XML, with a TreeNodesModel for Groot2.
    Xml,
    /// The token notation of seed 003: `s( f( 0 on 1? put 0 on 1! ) )`.
    Tokens,
    /// The deployable image (binary; needs --out).
    Image,
}

/// How free action parameters are bound.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum RefinementArg {
    /// One grounding per achieving action: the cheapest from the current state.
    Cheapest,
    /// Every grounding of every achieving action.
    All,
}

#[derive(clap::Args, Debug)]
#[command(
    long_about = "Synthesizes a reactive behavior tree by backchaining from the goal \
    (Colledanchise, Almeida, Ögren, ICRA 2019, Algorithm 1): start from the goal \
    conditions, tick the tree in the problem's symbolic world, replace each failed \
    condition by its atomic BT (a Fallback of the condition and one Sequence of \
    preconditions and action per achieving action), and move a new subtree left and up \
    until no action executed before it undoes its preconditions.\n\n\
    Input is a PDDL domain and problem (STRIPS with :typing and \
    :negative-preconditions), or one of the four brick tasks of seed 003. Prints the \
    tree, the expansions made, and whether the final tree, run from the initial state \
    in the symbolic world, reaches the goal and in how many ticks.\n\n\
    The tree goes to stdout or --out FILE (written whole or not at all; `-` is stdout); \
    with --out the summary goes to stdout, otherwise (but for ascii) to stderr. An image \
    is never written to a terminal. Leaves of PDDL \
    trees are behavior ids in the domain's order (predicates, then actions) with \
    object indices as arguments.",
    after_help = "Examples:\n  sim-host plan --domain planner/domains/cube-sphere/domain.pddl \\\n      \
    --problem planner/domains/cube-sphere/problem-blocked.pddl\n  \
    sim-host plan --task tower --format tokens\n  \
    sim-host plan --domain d.pddl --problem p.pddl --format image --out tree.bt"
)]
pub struct Args {
    /// The PDDL domain file.
    #[arg(long, requires = "problem", conflicts_with = "task")]
    pub domain: Option<PathBuf>,
    /// The PDDL problem file.
    #[arg(long, requires = "domain")]
    pub problem: Option<PathBuf>,
    /// A brick task of seed 003 instead of PDDL.
    #[arg(long, value_parser = ["tower", "croissant", "balance", "blocking"], required_unless_present = "domain")]
    pub task: Option<String>,
    /// The notation to write the tree in.
    #[arg(long, value_enum, default_value_t = Format::Ascii)]
    pub format: Format,
    /// Write the tree here instead of stdout (`-`: stdout).
    #[arg(long, value_name = "FILE", value_parser = Target::parse)]
    pub out: Option<Target>,
    /// How free action parameters are bound (PDDL only).
    #[arg(long, value_enum, default_value_t = RefinementArg::Cheapest)]
    pub refinement: RefinementArg,
}

fn render<C: Catalog + ?Sized, P: Ports + ?Sized>(
    format: Format,
    nodes: &[Node],
    values: &[u16],
    catalog: &C,
    ports: &P,
    names: Option<&NameTable>,
) -> anyhow::Result<Vec<u8>> {
    Ok(match format {
        Format::Ascii => notation::to_ascii_with(nodes, values, catalog)?.into_bytes(),
        Format::Dot => notation::to_dot_with(nodes, values, catalog).into_bytes(),
        Format::Xml => {
            let options = notation::XmlOptions { values, ..notation::XmlOptions::default() };
            notation::to_xml_with(nodes, catalog, ports, &options)?.into_bytes()
        }
        Format::Tokens if !values.is_empty() => {
            bail!(
                "--format tokens cannot write leaves with more than 3 arguments (this tree has some); \
                 use ascii, dot, xml or image"
            )
        }
        Format::Tokens => {
            let mut t = planner::tokens::to_string(nodes, catalog).map_err(|e| {
                anyhow::anyhow!("--format tokens: {e}; write it with --format ascii, dot, xml or image")
            })?;
            t.push('\n');
            t.into_bytes()
        }
        Format::Image => notation::to_image_parts(nodes, values, catalog, names)?,
    })
}

fn summary(expansions: &[Expansion], nodes: usize, verdict: &str) -> String {
    let mut s = format!("planned: {}, {}\n", count(expansions.len(), "expansion"), count(nodes, "node"));
    for (i, e) in expansions.iter().enumerate() {
        s.push_str(&format!("  {}. {e}\n", i + 1));
    }
    s.push_str(verdict);
    s.push('\n');
    s
}

fn read(path: &std::path::Path) -> anyhow::Result<String> {
    Ok(sim_host::input::read_text(path, sim_host::input::Limit::PDDL)?)
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let target = args.out.clone().unwrap_or(Target::Stdout);
    let content = if args.format == Format::Image { Content::Binary("a tree image") } else { Content::Text };
    output::check(&target, content)?;
    let options = Options {
        refinement: match args.refinement {
            RefinementArg::Cheapest => Refinement::Cheapest,
            RefinementArg::All => Refinement::All,
        },
        ..Options::default()
    };
    let (bytes, text) = if let Some(task) = &args.task {
        let task = Task::from_name(task).with_context(|| format!("unknown task `{task}`"))?;
        let plan = planner::duplo_plan_with(task, options).with_context(|| format!("planning `{}`", task.name()))?;
        let model = match plan.goal_ticks {
            Some(t) => format!("the planner's own model of the task reaches the goal in {}", count(t, "tick")),
            None => "the planner's own model of the task does not reach the goal".to_string(),
        };
        let verdict = format!(
            "symbolic world: not run here; `sim-host run` checks the tree in the brick world \
             (which has the physics the planner does not know); {model}"
        );
        // A brick task's behavior set and names are fixed by its fingerprint: no names
        // section needed.
        let bytes = render(args.format, &plan.nodes, &plan.values, plan.catalog.as_ref(), &NoPorts, None);
        (bytes, summary(&plan.expansions, plan.nodes.len(), &verdict))
    } else {
        let (Some(dpath), Some(ppath)) = (&args.domain, &args.problem) else {
            bail!("give --domain D.pddl --problem P.pddl, or --task NAME");
        };
        let (domain, dwarn) = planner::pddl::read_domain(&dpath.display().to_string(), &read(dpath)?)?;
        let (problem, pwarn) = planner::pddl::read_problem(&ppath.display().to_string(), &read(ppath)?, &domain)?;
        for w in dwarn.iter().chain(&pwarn) {
            let _ = output::stderr(format!("{w}\n").as_bytes());
        }
        let g = Arc::new(
            planner::ground::Grounding::new(&problem).with_context(|| format!("grounding {}", ppath.display()))?,
        );
        let catalog = Arc::new(PddlCatalog::new(&problem));
        let plan =
            planner::plan(g, catalog.clone(), options).with_context(|| format!("planning {}", ppath.display()))?;
        let verdict = match plan.goal_ticks {
            Some(t) => {
                format!("symbolic world: the tree reaches the goal in {} from the initial state", count(t, "tick"))
            }
            None => "symbolic world: the tree does NOT reach the goal from the initial state \
                     (planning reached it along another path)"
                .to_string(),
        };
        let mut made = String::new();
        for gave_up in &plan.gave_up {
            let why: String = gave_up.error.to_string().chars().take(300).collect();
            made.push_str(&format!("{} gave up: {why}\n", gave_up.method.name()));
        }
        let verdict = format!("{made}made by {}: {}\n{verdict}", plan.method.name(), plan.method.describe());
        // The problem's own names travel with the image: another problem of the same
        // domain has the same fingerprint but other objects.
        let title = format!("PDDL problem `{}` of domain `{}`", problem.name, domain.name);
        let names = NameTable::of_pddl(&title, &catalog);
        let bytes = render(args.format, &plan.nodes, &plan.values, catalog.as_ref(), catalog.as_ref(), Some(&names));
        (bytes, summary(&plan.expansions, plan.nodes.len(), &verdict))
    };
    let bytes = match bytes {
        Ok(bytes) => bytes,
        Err(e) => {
            // The plan stands; only its notation failed. Keep the summary, then say why.
            output::stderr(text.as_bytes())?;
            return Err(e);
        }
    };
    match &target {
        Target::File(path) => {
            output::write_file(path, &bytes, content)?;
            out!("{text}wrote {} ({})\n", path.display(), count(bytes.len(), "byte"))?;
        }
        Target::Stdout => {
            output::write(&target, &bytes, content)?;
            if args.format == Format::Ascii {
                out!("\n{text}")?;
            } else {
                output::stderr(text.as_bytes())?;
            }
        }
    }
    Ok(())
}
