//! Where the CLI writes, through the real binary: `--out`/`--svg` targets that are not
//! regular files (devices, FIFOs, links, `-`), binary output and terminals, and stdout
//! or stderr closed or full in every subcommand.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::fs::File;
use std::os::unix::fs::{FileTypeExt as _, PermissionsExt as _};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

mod cli_common;
use cli_common::sim_host;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn stderr(out: &Output) -> String {
    String::from_utf8(out.stderr.clone()).unwrap()
}

/// One line, `error: `, exit 2, every part in it.
fn assert_error(out: &Output, parts: &[&str]) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(2), "stderr: {err}");
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(err.starts_with("error: "), "{err}");
    for p in parts {
        assert!(err.contains(p), "`{p}` in: {err}");
    }
}

fn is_root() -> bool {
    Command::new("id").arg("-u").output().is_ok_and(|o| o.stdout.starts_with(b"0\n"))
}

/// A character device like `/dev/full` (1, 7) or `/dev/null` (1, 3). As root, a node of
/// our own in `dir`, so that a regression replaces that node and not the machine's
/// device; otherwise the machine's, which a non-root process cannot replace.
fn device(dir: &Path, name: &str, minor: u32) -> PathBuf {
    if is_root() {
        let path = dir.join(name);
        let ok = Command::new("mknod")
            .args(["-m", "666", s(&path), "c", "1", &minor.to_string()])
            .status()
            .is_ok_and(|st| st.success());
        assert!(ok, "mknod {name}");
        path
    } else {
        PathBuf::from(format!("/dev/{name}"))
    }
}

fn is_char_device(p: &Path) -> bool {
    std::fs::symlink_metadata(p).unwrap().file_type().is_char_device()
}

#[test]
fn devices_are_written_through_never_replaced() {
    let dir = tempfile::tempdir().unwrap();
    let full = device(dir.path(), "full", 7);
    let out = sim_host(&["plan", "--task", "tower", "--out", s(&full)]);
    assert_error(&out, &[s(&full), "No space left on device"]);
    assert!(out.stdout.is_empty(), "no summary as if it worked");
    assert!(is_char_device(&full), "{} is still a device", full.display());

    let null = device(dir.path(), "null", 3);
    let out = sim_host(&["plan", "--task", "tower", "--format", "image", "--out", s(&null)]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(is_char_device(&null));
    let out = sim_host(&["export", "--out", s(&null), s(&tower_image(dir.path()))]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(is_char_device(&null));
}

#[test]
fn a_fifo_is_written_through() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("fifo");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let out = sim_host(&["plan", "--task", "tower", "--format", "tokens", "--out", s(&fifo)]);
    assert!(out.status.success(), "{}", stderr(&out));
    // Checked before joining: a FIFO replaced by a file would leave the reader waiting.
    assert!(std::fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo());
    assert!(reader.join().unwrap().starts_with("s( f( 0 at pos"));
}

#[test]
fn links_are_followed_and_kept() {
    let dir = tempfile::tempdir().unwrap();
    let real = dir.path().join("real.txt");
    std::fs::write(&real, "old").unwrap();
    std::fs::set_permissions(&real, std::fs::Permissions::from_mode(0o600)).unwrap();
    let link = dir.path().join("link.txt");
    std::os::unix::fs::symlink("real.txt", &link).unwrap();
    let out = sim_host(&["plan", "--task", "tower", "--format", "tokens", "--out", s(&link)]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "the link stays");
    assert!(std::fs::read_to_string(&real).unwrap().starts_with("s( f("), "its target is written");
    let mode = std::fs::metadata(&real).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, 0o600, "the file keeps its permissions");

    // A dangling link: the file it names is made.
    let dangling = dir.path().join("dangling.txt");
    std::os::unix::fs::symlink("made.txt", &dangling).unwrap();
    let out = sim_host(&["plan", "--task", "tower", "--format", "tokens", "--out", s(&dangling)]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(std::fs::read_to_string(dir.path().join("made.txt")).unwrap().starts_with("s( f("));
    let names: Vec<String> =
        std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    assert!(names.iter().all(|n| !n.ends_with(".tmp")), "no temporary file left: {names:?}");
}

#[test]
fn dash_is_stdout_and_dev_stdout_is_the_same_stream() {
    let out = sim_host(&["plan", "--task", "tower", "--format", "tokens", "--out", "-"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stderr(&out).contains("planned: 8 expansions"));
    assert!(String::from_utf8(out.stdout).unwrap().starts_with("s( f( 0 at pos"));

    // `--out /dev/stdout > file`: the tree, then the summary after it, not over it.
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("both.txt");
    let status = Command::new(env!("CARGO_BIN_EXE_sim-host"))
        .args(["plan", "--task", "tower", "--out", "/dev/stdout"])
        .stdout(File::create(&file).unwrap())
        .status()
        .unwrap();
    assert!(status.success());
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.starts_with("{-} Sequence\n"), "{text}");
    assert!(text.contains("planned: 8 expansions") && text.ends_with("wrote /dev/stdout (888 bytes)\n"), "{text}");
}

#[test]
fn writing_under_a_file_or_into_a_missing_folder_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("plain");
    std::fs::write(&file, "x").unwrap();
    let under = file.join("t.bt");
    let out = sim_host(&["plan", "--task", "tower", "--out", s(&under)]);
    assert_error(&out, &[]);
    // Exactly this: no temporary file's path.
    assert_eq!(
        stderr(&out),
        format!("error: cannot write {}: {} is a file, not a directory\n", under.display(), file.display())
    );

    let missing = dir.path().join("no").join("such").join("t.bt");
    let out = sim_host(&["plan", "--task", "tower", "--out", s(&missing)]);
    assert_error(&out, &[&format!("directory {} does not exist", dir.path().join("no").display())]);

    let out = sim_host(&["plan", "--task", "tower", "--out", s(dir.path())]);
    assert_error(&out, &["it is a directory"]);
}

/// Runs `sim-host args` with stdout on a pseudo-terminal (util-linux `script`).
fn on_terminal(args: &str) -> Output {
    let cmd = format!("{} {args}", env!("CARGO_BIN_EXE_sim-host"));
    Command::new("script").args(["-qec", &cmd, "/dev/null"]).stdin(Stdio::null()).output().unwrap()
}

#[test]
fn binary_output_is_refused_on_a_terminal() {
    let out = on_terminal("plan --task tower --format image");
    assert_eq!(out.status.code(), Some(2));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("it is a terminal and a tree image is binary"), "{text}");
    assert!(!text.contains("BTIM"), "{text}");
    let out = on_terminal("plan --task tower --format image --out -");
    assert!(String::from_utf8_lossy(&out.stdout).contains("is binary"));
    let out = on_terminal("plan --task tower --format image --out /dev/stdout");
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stdout).contains("is binary"));
    // Text is fine.
    let out = on_terminal("plan --task tower --format tokens");
    assert_eq!(out.status.code(), Some(0));
    // `import` too, before it reads anything.
    let dir = tempfile::tempdir().unwrap();
    let xml = bt_xml(dir.path());
    for args in [format!("import {}", s(&xml)), format!("import {} --out -", s(&xml))] {
        let out = on_terminal(&args);
        assert_eq!(out.status.code(), Some(2), "{args}");
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains("it is a terminal and a tree image is binary"), "{text}");
    }
}

#[test]
fn import_catalog_and_btlog_write_devices_through_and_report_a_full_one() {
    let dir = tempfile::tempdir().unwrap();
    let full = device(dir.path(), "full", 7);
    let xml = bt_xml(dir.path());
    let out = sim_host(&["import", s(&xml), "--out", s(&full)]);
    assert_error(&out, &["cannot write", "No space left on device"]);
    let out = sim_host(&["catalog", s(&nav2_models()), "--out", s(&full)]);
    assert_error(&out, &["cannot write", "No space left on device"]);
    assert!(is_char_device(&full));
    let null = device(dir.path(), "null", 3);
    let out = sim_host(&["import", s(&xml), "--out", s(&null)]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(is_char_device(&null));
}

fn tower_image(dir: &Path) -> PathBuf {
    let path = dir.join("tower.bt");
    if !path.exists() {
        let out = sim_host(&["plan", "--task", "tower", "--format", "image", "--out", s(&path)]);
        assert!(out.status.success(), "{}", stderr(&out));
    }
    path
}

/// BehaviorTree.CPP's models of Nav2's nodes (a fixture of btcpp).
fn nav2_models() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../btcpp/tests/fixtures/nav2/nav2_tree_nodes.xml")
}

/// A small BehaviorTree.CPP tree with its models.
fn bt_xml(dir: &Path) -> PathBuf {
    let path = dir.join("tree.xml");
    std::fs::write(
        &path,
        r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <ReactiveFallback><AtGoal/><Sequence><MoveTo/><Dock side="left"/></Sequence></ReactiveFallback>
  </BehaviorTree>
  <TreeNodesModel>
    <Condition ID="AtGoal"/><Action ID="MoveTo"/>
    <Action ID="Dock"><input_port name="side" type="std::string"/></Action>
  </TreeNodesModel>
</root>"#,
    )
    .unwrap();
    path
}

/// Every command that writes to stdout, with what it needs in `dir`.
fn commands(dir: &Path) -> Vec<Vec<String>> {
    let image = tower_image(dir);
    let runs = dir.join("runs");
    let out = sim_host(&["learn", "--task", "tower", "--seeds", "1", "--generations", "2", "--out", s(&runs)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let fresh = |name: &str| s(&dir.join(name)).to_string();
    let v = |a: &[&str]| a.iter().map(|x| (*x).to_string()).collect::<Vec<_>>();
    let models = nav2_models();
    let xml = bt_xml(dir);
    vec![
        v(&["catalog", s(&models)]),
        v(&["catalog", s(&models), "--rust", "--out", "-"]),
        v(&["import", s(&xml), "--format", "ascii"]),
        v(&["inspect", s(&image)]),
        v(&["export", s(&image), "--format", "dot"]),
        v(&["run", "--task", "tower"]),
        v(&["run", "--task", "tower", "--svg", &fresh("run.svg")]),
        v(&["scenario", "cube", "--world", "symbolic"]),
        v(&["scenario", "--list"]),
        v(&["learn", "--task", "tower", "--seeds", "2", "--generations", "2", "--force", "--out", s(&runs)]),
        v(&["plot", s(&runs), "--out", &fresh("curves.png")]),
        v(&["plan", "--task", "tower"]),
        v(&["plan", "--task", "tower", "--format", "image", "--out", &fresh("t.bt")]),
        v(&["plan", "--task", "tower", "--format", "tokens"]),
        v(&[]), // the demo
        v(&["--help"]),
        v(&["--version"]),
    ]
}

#[test]
fn a_closed_stdout_ends_quietly_with_exit_0() {
    let dir = tempfile::tempdir().unwrap();
    for args in commands(dir.path()) {
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let out = Command::new(env!("CARGO_BIN_EXE_sim-host")).args(&args).stdout(writer).output().unwrap();
        assert_eq!(out.status.code(), Some(0), "{args:?}: {}", stderr(&out));
        let err = stderr(&out);
        assert!(!err.contains("panicked") && !err.contains("error"), "{args:?}: {err}");
    }
}

#[test]
fn a_full_stdout_is_one_error_line_and_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let full = device(dir.path(), "full", 7);
    for args in commands(dir.path()) {
        let out = Command::new(env!("CARGO_BIN_EXE_sim-host"))
            .args(&args)
            .stdout(File::options().write(true).open(&full).unwrap())
            .output()
            .unwrap();
        // `learn` also reports progress on stderr (`done <run>: ...`).
        let err = stderr(&out);
        let errors: Vec<&str> = err.lines().filter(|l| !l.starts_with("done ")).collect();
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(errors, ["error: cannot write stdout: No space left on device (os error 28)"], "{args:?}");
    }
}

#[test]
fn a_full_or_closed_stderr_never_panics() {
    let dir = tempfile::tempdir().unwrap();
    let full = device(dir.path(), "full", 7);
    let image = tower_image(dir.path());
    let cases: [&[&str]; 4] = [
        &["no-such-command"],                               // clap's usage error
        &["inspect", "/no/such/image.bt"],                  // our own error
        &["plan", "--task", "tower", "--format", "tokens"], // the summary goes to stderr
        &["export", s(&image), "--format", "nope"],         // a bad value
    ];
    for args in cases {
        let out = Command::new(env!("CARGO_BIN_EXE_sim-host"))
            .args(args)
            .stdout(Stdio::null())
            .stderr(File::options().write(true).open(&full).unwrap())
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}: nowhere to say it, but exit 2, no panic (101)");

        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let out = Command::new(env!("CARGO_BIN_EXE_sim-host"))
            .args(args)
            .stdout(Stdio::null())
            .stderr(writer)
            .output()
            .unwrap();
        // An error that cannot be told is still exit 2; the summary's broken pipe is the
        // quiet end.
        let expected = if args[0] == "plan" { 0 } else { 2 };
        assert_eq!(out.status.code(), Some(expected), "{args:?}");
    }
}
