//! `sim-host plan`: backchaining planning (Colledanchise et al. 2019) of a PDDL problem or a brick task.

use std::path::PathBuf;
use std::sync::Arc;

use anyhow::{Context as _, bail};
use bt_core::{Catalog, Node};
use bt_formats::{Names, ascii, dot, image::Image, tokens};
use planner::duplo::Task;
use planner::{Expansion, Method, Options, PddlCatalog, PlanError, Refinement};

use super::output::{self, Content, Target, out};
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
    /// The token notation of Styrud et al.: `s( f( 0 on 1? put 0 on 1! ) )`.
    Tokens,
    /// The deployable image (binary; needs --out).
    Image,
}

/// Which method makes the tree.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum MethodArg {
    /// Algorithm 1; when it cannot finish, guided by a plan of heuristic search (the
    /// conditions that plan made true on the way, which the tree only checks, get the
    /// step that made them true, acting only where the tree would fail); when that
    /// fails, guided again with state variables (a count of free stacks, a robot's
    /// place) not pinned to the plan's values; as a last resort that plan's regression
    /// tree.
    Auto,
    /// Algorithm 1 of Colledanchise et al. 2019 alone: fails where it cannot finish.
    #[value(name = "algorithm-1")]
    Algorithm1,
    /// Heuristic search first, then backchaining guided by its plan.
    Search,
}

/// How the search that guides the tree evaluates states.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum SearchArg {
    /// Each state when it is generated.
    Eager,
    /// Each state when it is taken from an open list, entering under its parent's h
    /// (as LAMA's first iteration does).
    Deferred,
    /// Deferred, alternating h_FF with a landmark count, each with helpful
    /// successors first after progress (as LAMA's first iteration does).
    Landmarks,
}

impl SearchArg {
    /// (deferred, landmarks) of [`planner::Options`].
    pub fn options(self) -> (bool, bool) {
        match self {
            Self::Eager => (false, false),
            Self::Deferred => (true, false),
            Self::Landmarks => (true, true),
        }
    }
}

/// How free action parameters are bound.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum RefinementArg {
    /// One grounding per achieving action: the cheapest from the current state.
    Cheapest,
    /// Every grounding of every achieving action.
    All,
}

/// `sim-host plan --help`: what the command does.
pub const LONG_ABOUT: &str = "Synthesizes a reactive behavior tree by backchaining from the goal \
    (Colledanchise, Almeida, Ögren, ICRA 2019, Algorithm 1): start from the goal \
    conditions, tick the tree in the problem's symbolic world, replace each failed \
    condition by its atomic BT (a Fallback of the condition and one Sequence of \
    preconditions and action per achieving action), and move a new subtree left and up \
    until no action executed before it undoes its preconditions.\n\n\
    Input is a PDDL domain and problem (STRIPS with types, constants, equality, \
    negative preconditions, action costs, ADL's or/forall/exists/when compiled away \
    at grounding, and derived predicates (:derived, stratified; the tree checks a derived \
    condition as the world derives it); numeric fluents other than total-cost are refused \
    with file:line:column), or one of the four brick \
    tasks of Styrud et al. Prints the \
    tree, the expansions made, and whether the final tree, run from the initial state \
    in the symbolic world, reaches the goal and in how many ticks. A tree that does not \
    reach the goal is never written: the command prints it (ascii, to stderr) with the \
    reason, such as the actions it repeats when it oscillates, and exits with code 2.\n\n\
    --expand-at STATE goes on as a robot would at run time (Example 2 of Colledanchise et al. 2019): the \
    tree is run from the initial state changed by STATE and expanded whenever it fails \
    (Algorithm 1, lines 9-12), until it reaches the goal. Fig. 4 of Colledanchise et al. 2019 is such a \
    run-time expansion: the tree of Fig. 3(e) meets the cube in the hand and the path \
    blocked.\n\n\
    The tree goes to stdout or --out FILE (written whole or not at all; `-` is stdout); \
    with --out the summary goes to stdout, otherwise (but for ascii) to stderr. An image \
    is never written to a terminal. Leaves of PDDL \
    trees are behavior ids in the domain's order (predicates, then actions) with \
    object indices as arguments.";

#[derive(clap::Args, Debug)]
#[command(
    long_about = LONG_ABOUT,
    after_help = "Examples:\n  sim-host plan --domain planner/domains/cube-sphere/domain.pddl \\\n      \
    --problem planner/domains/cube-sphere/problem-blocked.pddl\n  \
    sim-host plan --task tower --format tokens\n  \
    sim-host plan --domain d.pddl --problem p.pddl --format image --out tree.bt\n  \
    # Example 2: the cube in the hand when the sphere blocks the path (Fig. 4, then on to the goal)\n  \
    sim-host plan --domain planner/domains/cube-sphere/domain.pddl \\\n      \
    --problem planner/domains/cube-sphere/problem.pddl \\\n      \
    --expand-at 'holding(cube), not hand-empty, not path-free(goal)'"
)]
pub struct Args {
    /// The PDDL domain file.
    #[arg(long, requires = "problem", conflicts_with = "task")]
    pub domain: Option<PathBuf>,
    /// The PDDL problem file.
    #[arg(long, requires = "domain")]
    pub problem: Option<PathBuf>,
    /// A brick task of Styrud et al. instead of PDDL.
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
    /// Which method makes the tree (PDDL only).
    #[arg(long, value_enum, default_value_t = MethodArg::Auto, conflicts_with = "task")]
    pub method: MethodArg,
    /// Keep the goal Sequence at the root even for a single goal condition, as seed
    /// 003's reference planner does (the published brick trees node for node).
    #[arg(long)]
    pub goal_sequence: bool,
    /// After planning, expand the tree at run time from this state (PDDL only): the
    /// initial state with these facts changed, in the notation of the tree's
    /// conditions, e.g. 'holding(cube), not hand-empty'.
    #[arg(long, value_name = "STATE", conflicts_with = "task")]
    pub expand_at: Option<String>,
    /// When the tree is made from a search plan (guided backchaining, or as the last
    /// resort the plan's regression tree), the most nodes it may grow to while rules
    /// are added for the states external agents can move the world to: ways back to
    /// the plan's rules, or rules after all the others that undo the agent's action
    /// (PDDL only; 0: the tree as the method makes it, smaller and less robust).
    #[arg(long, value_name = "NODES", default_value_t = planner::Options::default().close_nodes, conflicts_with = "task")]
    pub close_nodes: usize,
    /// Close the trees of Algorithm 1 over disturbances too, as guided and regression
    /// trees always are (PDDL only): where an external agent doing one of the tree's
    /// actions out of turn leaves the world in a state the tree fails from, rules for
    /// those states go in front of it (and rules that undo the agent's action behind
    /// it), within --close-nodes (a backchained tree whose closure runs out of that
    /// budget before it has looked at every such state stays as it was: it copes with
    /// many of them alone, and rules for only some would give the agent new actions;
    /// one cut short by --timeout keeps the rules it found where they do better).
    /// Off by default, so that Algorithm 1's trees stay as the paper's method makes
    /// them (the paper's figures among them).
    #[arg(long, conflicts_with = "task")]
    pub close_backchained: bool,
    /// The most bytes the tree's image may have as a controller holds it (without the
    /// names section; `deploy --strip-names` sends exactly that). The closure over
    /// disturbances is cut to fit, its rules for the states fewest disturbances reach
    /// first; a tree that does not fit even without its closure is an error. Default:
    /// 16 KiB where the tree without its closure fits, else the smallest tree made
    /// (PDDL only).
    #[arg(long, value_name = "BYTES", conflicts_with = "task")]
    pub max_bytes: Option<usize>,
    /// The most bt-core nodes the tree may have, as --max-bytes (PDDL only).
    #[arg(long, value_name = "NODES", conflicts_with = "task")]
    pub max_nodes: Option<usize>,
    /// Seconds to plan for (PDDL only): Algorithm 1 and the search run side by side,
    /// and the closure over disturbances gets as long as the first tree took (at
    /// least 0.6 s, at most half the time left), leaving the tree it has made by then
    /// (less robust, never wrong); a tree not made in time is an error. Default: no
    /// limit (the tree then does not depend on the machine's speed).
    #[arg(long, value_name = "SECONDS", conflicts_with = "task")]
    pub timeout: Option<f64>,
    /// How the greedy best-first search that guides the tree evaluates states (PDDL
    /// only).
    #[arg(long, value_enum, default_value_t = SearchArg::Landmarks, conflicts_with = "task")]
    pub search: SearchArg,
}

/// The size a tree must fit from --max-bytes and --max-nodes (strict when either is
/// given).
pub fn fit(max_bytes: Option<usize>, max_nodes: Option<usize>) -> planner::Fit {
    match (max_bytes, max_nodes) {
        (None, None) => planner::Fit::DEFAULT,
        (b, n) => planner::Fit { bytes: b.unwrap_or(usize::MAX), nodes: n.unwrap_or(usize::MAX), strict: true },
    }
}

fn render<C: Catalog + ?Sized>(
    format: Format,
    nodes: &[Node],
    values: &[u16],
    catalog: &C,
    names: Option<&Names>,
) -> anyhow::Result<Vec<u8>> {
    Ok(match format {
        Format::Ascii => ascii::to_ascii_with(nodes, values, catalog)?.into_bytes(),
        Format::Dot => dot::to_dot_with(nodes, values, catalog).into_bytes(),
        Format::Xml => {
            let options = btcpp::xml::XmlOptions { values, ..btcpp::xml::XmlOptions::default() };
            btcpp::xml::to_xml_with(nodes, catalog, &options)?.into_bytes()
        }
        Format::Tokens if !values.is_empty() => {
            bail!(
                "--format tokens cannot write leaves with more than 3 arguments (this tree has some); \
                 use ascii, dot, xml or image"
            )
        }
        Format::Tokens => {
            let mut t = tokens::to_string(nodes, catalog).map_err(|e| {
                anyhow::anyhow!("--format tokens: {e}; write it with --format ascii, dot, xml or image")
            })?;
            t.push('\n');
            t.into_bytes()
        }
        Format::Image => {
            let image = Image::new(nodes).values(values);
            match names {
                Some(n) => image.names(n).encode(catalog.fingerprint())?,
                None => image.encode(catalog.fingerprint())?,
            }
        }
    })
}

fn summary(expansions: &[Expansion], nodes: usize, verdict: &str) -> String {
    let mut s = format!("planned: {}, {}\n", count(expansions.len(), "expansion"), count(nodes, "node"));
    s.push_str(&numbered(expansions));
    s.push_str(verdict);
    s.push('\n');
    s
}

fn numbered(expansions: &[Expansion]) -> String {
    let mut s = String::new();
    for (i, e) in expansions.iter().enumerate() {
        s.push_str(&format!("  {}. {e}\n", i + 1));
    }
    s
}

/// A tree as indented ascii lines, each prefixed by `indent`.
fn indented<C: Catalog + ?Sized>(nodes: &[Node], values: &[u16], catalog: &C, indent: &str) -> String {
    let text =
        ascii::to_ascii_with(nodes, values, catalog).unwrap_or_else(|e| format!("(the tree cannot be shown: {e})\n"));
    text.lines().map(|l| format!("{indent}{l}\n")).collect()
}

/// A planning error; when it is about a tree (one that oscillates or does not reach
/// the goal), the tree goes to stderr first, so that the error line gives the reason
/// under it.
fn failed<C: Catalog + ?Sized>(e: PlanError, catalog: &C, doing: String) -> anyhow::Error {
    if let Some((nodes, values)) = e.tree() {
        let head = format!("the tree ({}), which does not reach the goal:\n", count(nodes.len(), "node"));
        let _ = output::stderr(format!("{head}{}", indented(nodes, values, catalog, "    ")).as_bytes());
    }
    anyhow::Error::new(e).context(doing)
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
        method: match args.method {
            MethodArg::Auto => Method::Auto,
            MethodArg::Algorithm1 => Method::Algorithm1,
            MethodArg::Search => Method::Search,
        },
        goal_sequence: args.goal_sequence,
        close_nodes: args.close_nodes,
        close_backchained: args.close_backchained,
        fit: fit(args.max_bytes, args.max_nodes),
        deferred: args.search.options().0,
        landmarks: args.search.options().1,
        ..Options::default()
    };
    let deadline = match args.timeout {
        Some(t) if !(t.is_finite() && t > 0.0) => bail!("--timeout must be a number of seconds above 0, not {t}"),
        Some(t) => Some(std::time::Instant::now() + std::time::Duration::from_secs_f64(t.min(1e9))),
        None => None,
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
        let bytes = render(args.format, &plan.nodes, &plan.values, plan.catalog.as_ref(), None);
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
        let limits = planner::ground::Limits { deadline, ..planner::ground::Limits::default() };
        let g = Arc::new(
            planner::ground::Grounding::with_limits(&problem, &limits)
                .with_context(|| format!("grounding {}", ppath.display()))?,
        );
        let options = Options { deadline, ..options };
        let catalog = Arc::new(PddlCatalog::new(&problem));
        // Read before planning: a typo in the state should not wait for the planner.
        let changes = match &args.expand_at {
            Some(text) => Some(planner::parse_changes(&g, text).with_context(|| format!("--expand-at `{text}`"))?),
            None => None,
        };
        let doing = || format!("planning {}", ppath.display());
        let mut plan = planner::plan(g, catalog.clone(), options).map_err(|e| failed(e, catalog.as_ref(), doing()))?;
        let ticks = plan.goal_ticks.unwrap_or(0);
        let mut verdict =
            format!("symbolic world: the tree reaches the goal in {} from the initial state", count(ticks, "tick"));
        let mut made = String::new();
        for gave_up in &plan.gave_up {
            let why: String = gave_up.error.to_string().chars().take(300).collect();
            made.push_str(&format!("{} gave up: {why}\n", gave_up.method.name()));
            if let PlanError::Oscillates { nodes, values, .. } = &gave_up.error {
                made.push_str(&format!("  the tree that oscillates ({}):\n", count(nodes.len(), "node")));
                made.push_str(&indented(nodes, values, catalog.as_ref(), "    "));
            }
        }
        let offline_nodes = plan.nodes.len();
        let mut verdict_head = format!("{made}made by {}: {}\n", plan.method.name(), plan.method.describe());
        if !plan.variables.is_empty() {
            verdict_head.push_str(&format!("{}\n", planner::variables_line(&plan.variables)));
        }
        if plan.covered > 0 {
            verdict_head.push_str(&format!("{}\n", planner::covered_line(plan.covered)));
        }
        if let Some(c) = plan.closed {
            verdict_head.push_str(&format!("{c}\n"));
        }
        verdict_head.push_str(&format!("{}\n", plan.fit));
        if let (Some(changes), Some(text)) = (changes, &args.expand_at) {
            let at =
                planner::expand_at(&mut plan.planner, catalog.as_ref(), &changes, options.max_ticks).map_err(|e| {
                    failed(e, catalog.as_ref(), format!("expanding the tree at run time from --expand-at `{text}`"))
                })?;
            plan.nodes = plan.planner.nodes().to_vec();
            plan.values = plan.planner.values().to_vec();
            verdict_head.push_str(&format!(
                "at run time from `{text}`: {}, {}\n{}",
                count(at.expansions.len(), "expansion"),
                count(plan.nodes.len(), "node"),
                numbered(&at.expansions)
            ));
            verdict = format!(
                "symbolic world: the tree reaches the goal in {} from the initial state and in {} from --expand-at",
                count(at.goal_ticks_initial, "tick"),
                count(at.goal_ticks_given, "tick")
            );
        }
        let verdict = format!("{verdict_head}{verdict}");
        // The problem's own names travel with the image: another problem of the same
        // domain has the same fingerprint but other objects.
        let title = format!("PDDL problem `{}` of domain `{}`", problem.name, domain.name);
        let names = Names::of(&title, catalog.as_ref(), catalog.objects());
        let bytes = render(args.format, &plan.nodes, &plan.values, catalog.as_ref(), Some(&names));
        (bytes, summary(&plan.expansions, offline_nodes, &verdict))
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
