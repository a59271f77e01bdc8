//! The corpus of public BehaviorTree.CPP trees (`tests/fixtures/corpus/`, listed with
//! their repository, commit and licence in `SOURCES.tsv`): each tree is imported as a
//! user would, first with the models its repository ships (its own `<TreeNodesModel>`,
//! the repository's models file, the files defining the SubTrees it calls), then with
//! models `sim-host catalog --stub` writes for the node types none of those declares.
//! The outcome of each (imported, with its node count, or the refusal) is pinned in
//! `OUTCOMES.tsv`; `CORPUS_BLESS=1` rewrites it. Every image imported is then inspected,
//! exported and turned into a Groot2 log by the `sim-host` binary without `--nodes`,
//! and its XML (`import --format xml`) imports as the same image.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use bt_core::NodeKind;
use btcpp::xml::{ImportOptions, Imported, Models, document, import, import_text, stub};

struct Row {
    repository: String,
    r#ref: String,
    path: String,
    role: String,
    r#for: String,
}

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/corpus")
}

fn rows() -> Vec<Row> {
    let text = std::fs::read_to_string(corpus().join("SOURCES.tsv")).expect("SOURCES.tsv");
    text.lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            Row {
                repository: f[0].into(),
                r#ref: f[1].into(),
                path: f[3].into(),
                role: f[5].into(),
                r#for: f.get(6).copied().unwrap_or("").into(),
            }
        })
        .collect()
}

fn file(r: &Row, path: &str) -> PathBuf {
    corpus().join(&r.repository).join(&r.r#ref).join(path)
}

/// An outcome, with paths inside the corpus relative to it.
fn outcome(result: &Result<Imported, btcpp::ImportError>) -> String {
    let base = format!("{}/", corpus().display());
    match result {
        Ok(i) => format!("ok {} nodes", i.nodes.len()),
        Err(e) => format!("refused {}", e.to_string().replace(&base, "")),
    }
}

/// The class of a refusal, for the summary.
fn class(outcome: &str) -> &'static str {
    let o = outcome;
    if o.starts_with("ok") {
        "imported"
    } else if o.contains("neither") && o.contains("BehaviorTree.CPP built-in") {
        "node types without a model"
    } else if o.contains("no <BehaviorTree ID")
        || o.contains("cannot read")
        || o.contains("must have exactly one child")
    {
        "a document BehaviorTree.CPP refuses (a SubTree or include missing, an empty tree)"
    } else if o.contains("is a node type of BehaviorTree.CPP") {
        "a node type of the other BehaviorTree.CPP version than the document's"
    } else if o.contains("has no port") || o.contains("is not a valid") || o.contains("is used as") {
        "ports or values the models do not allow"
    } else if o.contains("plugin control node") {
        "plugin control nodes"
    } else if o.contains("models of") {
        "conflicting models"
    } else {
        "other constructs a controller cannot run"
    }
}

/// Whether an outcome is an import or a refusal that starts with `file:line:column: `.
fn placed(outcome: &str) -> bool {
    let Some(refusal) = outcome.strip_prefix("refused ") else { return outcome.starts_with("ok ") };
    let Some((place, _)) = refusal.split_once(": ") else { return false };
    let mut parts = place.rsplitn(3, ':');
    let number = |p: Option<&str>| p.is_some_and(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit()));
    number(parts.next()) && number(parts.next()) && parts.next().is_some_and(|f| !f.is_empty())
}

struct Case {
    tree: PathBuf,
    name: String,
    version: &'static str,
    shipped: Vec<PathBuf>,
}

fn cases() -> Vec<Case> {
    let rows = rows();
    let mut out = vec![];
    for r in rows.iter().filter(|r| r.role == "tree") {
        let mut shipped: Vec<PathBuf> = rows
            .iter()
            .filter(|m| m.repository == r.repository && m.r#ref == r.r#ref && m.role == "models")
            .map(|m| file(m, &m.path))
            .collect();
        shipped.extend(
            rows.iter()
                .filter(|m| {
                    m.role == "registered" && m.r#for == r.path && m.repository == r.repository && m.r#ref == r.r#ref
                })
                .map(|m| file(m, &m.path)),
        );
        let tree = file(r, &r.path);
        let text = std::fs::read_to_string(&tree).unwrap_or_default();
        let version = if text.contains("BTCPP_format=\"4\"") { "4" } else { "3" };
        out.push(Case { name: format!("{}/{}/{}", r.repository, r.r#ref, r.path), tree, version, shipped });
    }
    out
}

/// The tree imported with the stub of the node types no model declares.
fn with_stub(case: &Case, dir: &Path, k: usize) -> Result<Imported, btcpp::ImportError> {
    let doc = document::read(&case.tree, &case.shipped)?;
    let models = Models::new(&doc.models)?;
    let stub = stub::stub(&doc, None, &models)?;
    let path = dir.join(format!("stub-{k}.xml"));
    std::fs::write(&path, stub.to_xml("tree")).expect("stub written");
    let mut models = case.shipped.clone();
    models.push(path);
    import(&case.tree, &ImportOptions { models, ..ImportOptions::default() })
}

fn sim_host(args: &[&std::ffi::OsStr]) -> Result<String, String> {
    let out = Command::new(env!("CARGO_BIN_EXE_sim-host")).args(args).output().map_err(|e| e.to_string())?;
    if out.status.success() {
        Ok(String::from_utf8_lossy(&out.stdout).into_owned())
    } else {
        Err(String::from_utf8_lossy(&out.stderr).into_owned())
    }
}

/// A controller's run of the image, as firmware-example prints it (`tick N STATUS
/// ran=...`): leaves answer by a hash of their node and the tick, scripts run on a
/// blackboard, `{key}` queues are empty. Ends before a tick that fails (a
/// `ManualSelector`, which asks an operator).
struct Controller<'p> {
    ports: bt_core::PortTable<'p>,
    blackboard: Vec<Option<bt_core::script::Value>>,
    scripts: BTreeMap<usize, bool>,
    tick: u32,
    ran: Vec<String>,
}

impl Controller<'_> {
    /// Success or Failure by a hash of the node and the tick: a run BehaviorTree.CPP
    /// makes too (no action left Running, which halt before start could restart).
    fn leaf(&mut self, node: bt_core::NodeId) -> bt_core::Status {
        let h = (u32::from(node) + 1).wrapping_mul(2_654_435_761) ^ self.tick.wrapping_mul(40_503);
        let s = if (h >> 7).is_multiple_of(3) { bt_core::Status::Failure } else { bt_core::Status::Success };
        self.ran.push(format!("{node}{}", letter(s)));
        s
    }
}

fn letter(s: bt_core::Status) -> &'static str {
    match s {
        bt_core::Status::Success => "S",
        bt_core::Status::Failure => "F",
        bt_core::Status::Running | bt_core::Status::Skipped => "R",
    }
}

impl bt_core::BehaviorSet for Controller<'_> {
    fn condition(&mut self, _: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> bt_core::Status {
        self.leaf(ctx.node)
    }
    fn action(&mut self, _: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> bt_core::Status {
        self.leaf(ctx.node)
    }
    fn halt(&mut self, _: &bt_core::Leaf, _: bt_core::NodeId) {}
    fn script(
        &mut self,
        code: &[u16],
        ctx: bt_core::Context<'_>,
    ) -> Result<bt_core::script::Value, bt_core::script::ScriptFault> {
        let v = bt_core::script::run(code, &self.ports, self.blackboard.as_mut_slice())?;
        let node = usize::from(ctx.node);
        // A `Repeat` reading its count is not a call BehaviorTree.CPP's log shows.
        if let Some(&script) = self.scripts.get(&node) {
            let held = script || bt_core::script::truth(v).unwrap_or(false);
            self.ran.push(format!("{node}{}", if held { "S" } else { "F" }));
        }
        Ok(v)
    }
    fn pop(&mut self, _: u16, _: u16, ctx: bt_core::Context<'_>) -> Result<bool, bt_core::script::ScriptFault> {
        self.ran.push(format!("{}F", ctx.node));
        Ok(false)
    }
}

fn trace_of(imported: &Imported, image: &[u8]) -> String {
    let mut nodes = vec![bt_core::Node::EMPTY; imported.nodes.len()];
    let mut values = vec![0u16; image.len()];
    let Ok((tree, ports)) =
        bt_core::load_with_ports::<_, { bt_formats::DEPTH }>(image, imported, &mut nodes, &mut values)
    else {
        return String::new();
    };
    // Numbers start at zero, as the C++ program would have set them.
    let blackboard = imported
        .slots
        .iter()
        .map(|s| match s.info.ty {
            bt_core::PortType::Int => Some(bt_core::script::Value::Int(0)),
            bt_core::PortType::Double => Some(bt_core::script::Value::Double(0.0)),
            bt_core::PortType::Bool => Some(bt_core::script::Value::Bool(false)),
            _ => None,
        })
        .collect();
    // Nodes whose programs are calls: whether each is a `Script` (which succeeds).
    let scripts = (tree.nodes().iter().enumerate())
        .filter(|(_, n)| !matches!(n.kind(), NodeKind::Cycles { .. }))
        .map(|(i, n)| (i, matches!(n.kind(), NodeKind::Script(_))))
        .collect();
    let mut set = Controller { ports, blackboard, scripts, tick: 0, ran: Vec::new() };
    let mut state = vec![bt_core::NodeState::IDLE; imported.nodes.len()];
    let Ok(mut exec) = bt_core::Executor::new(tree, &mut state) else { return String::new() };
    let mut out = String::from("boot hz=10\n");
    for t in 0..8 {
        set.tick = t;
        set.ran.clear();
        // A fault ends the run, as it stops a controller.
        let Ok(s) = exec.tick(&mut set, t * 100) else { break };
        let ran = if set.ran.is_empty() { "-".to_string() } else { set.ran.join(",") };
        let root = match s {
            bt_core::Status::Success => "SUCCESS",
            bt_core::Status::Failure => "FAILURE",
            bt_core::Status::Running => "RUNNING",
            bt_core::Status::Skipped => "SKIPPED",
        };
        out.push_str(&format!("tick {t} {root} ran={ran}\n"));
    }
    out
}

/// The image `import` writes, inspected, exported and logged by the binary without
/// `--nodes`; its XML imported again gives the same image.
fn check_tools(imported: &Imported, name: &str, dir: &Path, k: usize) -> Result<(), String> {
    let mut names = imported.names();
    names.title = format!("BehaviorTree.CPP tree `{}`", imported.main);
    let image = imported.named_image(&names).map_err(|e| e.to_string())?;
    let path = dir.join(format!("tree-{k}.bt"));
    std::fs::write(&path, &image).map_err(|e| e.to_string())?;
    let p = path.as_os_str();
    sim_host(&["inspect".as_ref(), p]).map_err(|e| format!("{name}: inspect: {e}"))?;
    for format in ["ascii", "dot", "xml"] {
        sim_host(&["export".as_ref(), p, "--format".as_ref(), format.as_ref()])
            .map_err(|e| format!("{name}: export --format {format}: {e}"))?;
    }
    let trace = dir.join(format!("tree-{k}.txt"));
    std::fs::write(&trace, trace_of(imported, &image)).map_err(|e| e.to_string())?;
    let log = dir.join(format!("tree-{k}.btlog"));
    let logged = sim_host(&[
        "btlog".as_ref(),
        "--from-trace".as_ref(),
        trace.as_os_str(),
        "--image".as_ref(),
        p,
        "--out".as_ref(),
        log.as_os_str(),
    ]);
    // A count read from the blackboard is not in a run's trace: the log cannot be made,
    // and btlog says why.
    let reads_count = imported.nodes.iter().any(|n| matches!(n.kind(), NodeKind::Cycles { from_slot: true, .. }));
    match logged {
        Err(e) if reads_count && e.contains("reads its count from the blackboard") => {}
        Err(e) => return Err(format!("{name}: btlog: {e}")),
        Ok(_) if reads_count => return Err(format!("{name}: btlog logged a count it cannot know")),
        Ok(_) => {}
    }
    // `import --format xml`, and back.
    let xml = imported.to_xml().map_err(|e| format!("{name}: --format xml: {e}"))?;
    let again = import_text(Path::new("again.xml"), &xml, &ImportOptions::default())
        .map_err(|e| format!("{name}: its XML does not import: {e}\n{xml}"))?;
    if again.image() != imported.image() {
        return Err(format!("{name}: its XML imports as another image"));
    }
    Ok(())
}

#[test]
fn the_corpus_imports_as_pinned_and_every_image_works_with_the_tools() {
    let dir = tempfile::tempdir().expect("temp dir");
    let cases = cases();
    let mut lines = vec!["tree\tversion\tshipped models\twith stub models".to_string()];
    let mut classes: BTreeMap<(&str, &'static str), usize> = BTreeMap::new();
    let (mut shipped_ok, mut stub_ok, mut repos) = (0usize, 0usize, std::collections::BTreeSet::new());
    let mut tool_failures = vec![];
    for (k, case) in cases.iter().enumerate() {
        repos.insert(case.name.split('/').take(2).collect::<Vec<_>>().join("/"));
        let shipped = import(&case.tree, &ImportOptions { models: case.shipped.clone(), ..ImportOptions::default() });
        let stubbed = with_stub(case, dir.path(), k);
        let (a, b) = (outcome(&shipped), outcome(&stubbed));
        shipped_ok += usize::from(shipped.is_ok());
        stub_ok += usize::from(stubbed.is_ok());
        *classes.entry(("shipped", class(&a))).or_default() += 1;
        *classes.entry(("stub", class(&b))).or_default() += 1;
        for i in shipped.iter().chain(stubbed.iter()) {
            if let Err(e) = check_tools(i, &case.name, dir.path(), k) {
                tool_failures.push(e);
            }
        }
        for o in [&a, &b] {
            assert!(placed(o), "{}: a refusal without its file:line:column: {o}", case.name);
        }
        lines.push(format!("{}\t{}\t{a}\t{b}", case.name, case.version));
    }
    let n = cases.len();
    let pct = |x: usize| 100.0 * x as f64 / n as f64;
    eprintln!(
        "{n} trees from {} repositories ({} version 3, {} version 4): {shipped_ok} ({:.0} %) import with the models \
         their repositories ship, {stub_ok} ({:.0} %) with stub models for the node types none declares",
        repos.len(),
        cases.iter().filter(|c| c.version == "3").count(),
        cases.iter().filter(|c| c.version == "4").count(),
        pct(shipped_ok),
        pct(stub_ok)
    );
    for ((models, class), count) in &classes {
        eprintln!("  {models}: {count} {class}");
    }
    let text = lines.join("\n") + "\n";
    let pinned = corpus().join("OUTCOMES.tsv");
    if std::env::var_os("CORPUS_BLESS").is_some() {
        std::fs::write(&pinned, &text).expect("OUTCOMES.tsv written");
    }
    let want = std::fs::read_to_string(&pinned).unwrap_or_default();
    for (w, g) in want.lines().zip(text.lines()) {
        assert_eq!(w, g, "an outcome changed (CORPUS_BLESS=1 pins the new ones)");
    }
    assert_eq!(want.lines().count(), text.lines().count(), "trees added or removed (CORPUS_BLESS=1)");
    assert!(tool_failures.is_empty(), "{}", tool_failures.join("\n"));
    assert!(n >= 100 && repos.len() >= 10, "{n} trees from {} repositories", repos.len());
}
