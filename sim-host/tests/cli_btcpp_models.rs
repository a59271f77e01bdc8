//! Users' own BehaviorTree.CPP trees through the real binary: node types without models
//! (`catalog --stub`), models that differ between files, and images that `export`,
//! `btlog` and `--format tokens` handle without the model files.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;

mod cli_common;
use cli_common::{ok, one_line_error, sim_host};

/// A version 3 document (no BTCPP_format) as Nav2 humble's users write them: a SubTree
/// remapped by name, SetBlackboard, a Repeat, a Parallel with thresholds, and node
/// types no model declares.
const V3_TREE: &str = r#"<root main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <SetBlackboard output_key="target" value="dock"/>
      <SubTree ID="Go" goal="target"/>
      <Parallel success_threshold="1" failure_threshold="2">
        <IsBatteryLow/>
        <Repeat num_cycles="2"><Beep volume="3"/></Repeat>
      </Parallel>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Go">
    <Fallback><GoalReached at="{goal}"/><MoveTo goal="{goal}" speed="0.5"/></Fallback>
  </BehaviorTree>
</root>"#;

fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

#[test]
fn stub_models_let_a_tree_without_models_import() {
    let dir = tempfile::tempdir().unwrap();
    let tree = write(dir.path(), "tree.xml", V3_TREE);
    // Every node type without a model at once, each with its place.
    let out = sim_host(&["import", &tree, "--out", dir.path().join("t.bt").to_str().unwrap()]);
    one_line_error(&out, "4 node types are neither BehaviorTree.CPP built-ins nor declared in any <TreeNodesModel>");
    let err = String::from_utf8_lossy(&out.stderr);
    for (id, at) in [("IsBatteryLow", "7:9"), ("Beep", "8:32"), ("GoalReached", "13:15"), ("MoveTo", "13:41")] {
        assert!(err.contains(&format!("`{id}` ({tree}:{at})")), "{id}: {err}");
    }
    assert!(err.contains("sim-host catalog --stub TREE.xml"), "{err}");

    let stub = dir.path().join("stub.xml");
    let out = sim_host(&["catalog", "--stub", &tree, "--out", stub.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).contains("4 models for the node types it uses"));
    let models = std::fs::read_to_string(&stub).unwrap();
    // Questions are conditions; a port given a literal is an input, one given only keys
    // is in/out.
    for model in [r#"<Condition ID="IsBatteryLow"/>"#, r#"<Condition ID="GoalReached">"#, r#"<Action ID="MoveTo">"#] {
        assert!(models.contains(model), "{model}: {models}");
    }
    assert!(models.contains(r#"<inout_port name="goal"/>"#) && models.contains(r#"<input_port name="speed"/>"#));
    let image = dir.path().join("t.bt");
    let out = sim_host(&["import", &tree, "--nodes", stub.to_str().unwrap(), "--out", image.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn models_that_differ_are_merged_or_named_with_both_places() {
    let dir = tempfile::tempdir().unwrap();
    let own = |port: &str| {
        format!(
            r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Dock side="left"/></BehaviorTree>
<TreeNodesModel><Action ID="Dock">{port}</Action></TreeNodesModel></root>"#
        )
    };
    let nodes = write(
        dir.path(),
        "nodes.xml",
        r#"<root BTCPP_format="4"><TreeNodesModel><Action ID="Dock"><input_port name="side" type="std::string"/></Action></TreeNodesModel></root>"#,
    );
    // Another type: one model, the --nodes one (what the program registers).
    let tree = write(dir.path(), "a.xml", &own(r#"<input_port name="side" type="int"/>"#));
    let text = ok(&sim_host(&["catalog", &tree, "--nodes", &nodes]));
    assert!(text.contains("Dock(in side: std::string)"), "{text}");
    // Another direction: both named, with their places; --nodes-override takes --nodes'.
    let tree = write(dir.path(), "b.xml", &own(r#"<output_port name="side"/>"#));
    let out = sim_host(&["import", &tree, "--nodes", &nodes, "--format", "ascii"]);
    one_line_error(&out, "the models of `Dock` here and at");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("b.xml:") && err.contains("nodes.xml:"), "{err}");
    assert!(err.contains("--nodes-override"), "{err}");
    ok(&sim_host(&["import", &tree, "--nodes", &nodes, "--nodes-override", "--format", "ascii"]));
}

#[test]
fn an_imported_image_exports_and_logs_as_its_document_without_the_models() {
    let dir = tempfile::tempdir().unwrap();
    let tree = write(dir.path(), "tree.xml", V3_TREE);
    let stub = dir.path().join("stub.xml");
    ok(&sim_host(&["catalog", "--stub", &tree, "--out", stub.to_str().unwrap()]));
    let image = dir.path().join("t.bt");
    let image = image.to_str().unwrap();
    let imported =
        |format: &str| ok(&sim_host(&["import", &tree, "--nodes", stub.to_str().unwrap(), "--format", format]));
    let xml = imported("xml");
    ok(&sim_host(&["import", &tree, "--nodes", stub.to_str().unwrap(), "--out", image]));
    std::fs::remove_file(&stub).unwrap();
    // The document's version, SetBlackboard and Parallel as written, the keys as the
    // flattened tree names them.
    let exported = ok(&sim_host(&["export", image, "--format", "xml"]));
    assert_eq!(exported, xml);
    assert!(!xml.contains("BTCPP_format") && !xml.contains("_uid"), "{xml}");
    assert!(xml.contains(r#"<SetBlackboard value="dock" output_key="target"/>"#), "{xml}");
    assert!(xml.contains(r#"<Parallel success_threshold="1" failure_threshold="2">"#), "{xml}");
    assert!(xml.contains(r#"<MoveTo goal="{target}" speed="0.5"/>"#), "{xml}");
    // It imports back as the same image.
    let again = dir.path().join("again.xml");
    std::fs::write(&again, &exported).unwrap();
    let back = dir.path().join("again.bt");
    ok(&sim_host(&["import", again.to_str().unwrap(), "--out", back.to_str().unwrap()]));
    let strip = |p: &Path| bt_formats::image::strip_names(&std::fs::read(p).unwrap()).unwrap();
    assert_eq!(strip(&back), strip(Path::new(image)));
    // A controller's run (SetBlackboard, GoalReached, MoveTo, IsBatteryLow, Beep twice:
    // nodes 1, 3, 4, 6 and 8)
    // becomes a log with the SubTree node BehaviorTree.CPP has.
    let trace = write(dir.path(), "run.txt", "boot hz=10\ntick 0 SUCCESS ran=1S,3F,4S,6F,8S,8S\n");
    let log = dir.path().join("run.btlog");
    let out = sim_host(&["btlog", "--from-trace", &trace, "--image", image, "--out", log.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let parsed = btcpp::btlog::Log::parse(&std::fs::read(&log).unwrap()).unwrap();
    assert!(parsed.xml.contains(r#"<SubTree ID="Go""#), "{}", parsed.xml);
}

#[test]
fn tokens_name_the_first_node_they_cannot_write() {
    let dir = tempfile::tempdir().unwrap();
    let tree = write(
        dir.path(),
        "tree.xml",
        r#"<root BTCPP_format="4"><BehaviorTree ID="M"><ReactiveSequence><Ready/><RetryUntilSuccessful num_attempts="2"><Go/></RetryUntilSuccessful></ReactiveSequence></BehaviorTree>
<TreeNodesModel><Condition ID="Ready"/><Action ID="Go"/></TreeNodesModel></root>"#,
    );
    one_line_error(
        &sim_host(&["import", &tree, "--format", "tokens"]),
        "--format tokens cannot write node 2, `RetryUntilSuccessful`, a bt-core RetryUntilSuccessful: the notation \
         has only s( f( ) and leaves",
    );
    let image = dir.path().join("t.bt");
    ok(&sim_host(&["import", &tree, "--out", image.to_str().unwrap()]));
    one_line_error(
        &sim_host(&["export", image.to_str().unwrap(), "--format", "tokens"]),
        "cannot write node 2, `RetryUntilSuccessful`, a bt-core RetryUntilSuccessful",
    );
}
