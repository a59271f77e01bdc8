//! `sim-host inspect` and `export` on good and bad images, through the real binary.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;

use bt_core::{Catalog, encode, image::max_image_len};
use planner::duplo::Task;

mod cli_common;
use cli_common::sim_host;

const TOWER: &str = "s( f( 0 at pos (0.0, 0.05, 0.0)? s( f( picked 0? pick 0! ) place at (0.0, 0.05, 0.0)! ) ) )";

fn tower_image(dir: &Path) -> std::path::PathBuf {
    let spec = Task::Tower.spec();
    let nodes = bt_formats::tokens::parse(TOWER, &spec).unwrap();
    let mut buf = vec![0u8; max_image_len(nodes.len())];
    let len = encode(&nodes, spec.fingerprint(), &mut buf).unwrap();
    let path = dir.join("tower.bt");
    std::fs::write(&path, &buf[..len]).unwrap();
    path
}

#[test]
fn inspect_prints_the_tree_and_the_facts() {
    let dir = tempfile::tempdir().unwrap();
    let image = tower_image(dir.path());
    let out = sim_host(&["inspect", image.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("nodes      8 (depth 5)"), "{text}");
    assert!(text.contains("brick task `tower`"), "{text}");
    assert!(text.contains("--> pick 0!"), "{text}");
}

#[test]
fn export_round_trips_tokens_and_writes_whole_files() {
    let dir = tempfile::tempdir().unwrap();
    let image = tower_image(dir.path());
    let out = sim_host(&["export", image.to_str().unwrap(), "--format", "tokens"]);
    assert!(out.status.success());
    assert_eq!(String::from_utf8(out.stdout).unwrap().trim_end(), TOWER);

    let target = dir.path().join("tower.txt");
    let out = sim_host(&["export", image.to_str().unwrap(), "--out", target.to_str().unwrap()]);
    assert!(out.status.success());
    assert!(std::fs::read_to_string(&target).unwrap().starts_with("{-} Sequence\n"));

    // An unwritable destination: an error naming it, and nothing left behind.
    let missing = dir.path().join("no-such-dir").join("t.txt");
    let out = sim_host(&["export", image.to_str().unwrap(), "--out", missing.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no-such-dir"));
    assert!(!missing.exists());
}

#[test]
fn a_bad_image_is_one_line_and_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let image = tower_image(dir.path());
    let mut bytes = std::fs::read(&image).unwrap();
    bytes[20] ^= 0xff;
    std::fs::write(&image, &bytes).unwrap();
    let out = sim_host(&["inspect", image.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with("error: ") && err.contains("CRC-32"), "{err}");

    let out = sim_host(&["inspect", dir.path().join("absent.bt").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("absent.bt"));

    let out = sim_host(&["inspect"]);
    assert_eq!(out.status.code(), Some(2), "clap usage errors exit 2 too");
}

/// Plans `problem` on `domain` (file contents) into an image; returns its path.
fn planned_image(dir: &Path, domain: &str, problem: &str) -> std::path::PathBuf {
    let (d, p, img) = (dir.join("d.pddl"), dir.join("p.pddl"), dir.join("t.bt"));
    std::fs::write(&d, domain).unwrap();
    std::fs::write(&p, problem).unwrap();
    let args = ["plan", "--domain", d.to_str().unwrap(), "--problem", p.to_str().unwrap()];
    let out = sim_host(&[&args[..], &["--format", "image", "--out", img.to_str().unwrap()]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    img
}

fn inspect(image: &Path) -> String {
    let out = sim_host(&["inspect", image.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

#[test]
fn images_name_their_own_objects_and_behaviors() {
    let dir = tempfile::tempdir().unwrap();
    let domain = planner::domains::CUBE_SPHERE_DOMAIN;
    // The shipped domain with the objects in another order than the shipped problem's:
    // the image must print this problem's names, not the shipped one's.
    let problem = "(define (problem mine) (:domain cube-sphere)
        (:objects goal - spot sphere cube - item)
        (:init (hand-empty) (path-free cube) (path-free sphere) (path-free goal))
        (:goal (at cube goal)))";
    let text = inspect(&planned_image(dir.path(), domain, problem));
    assert!(text.contains("PDDL problem `mine` of domain `cube-sphere` (names from the image)"), "{text}");
    assert!(text.contains("--> at(cube, goal)"), "{text}");
    let out = sim_host(&["export", dir.path().join("t.bt").to_str().unwrap(), "--format", "tokens"]);
    assert!(String::from_utf8_lossy(&out.stdout).contains("at(cube, goal)?"));

    // A domain this binary has never seen.
    let domain = "(define (domain lamp) (:requirements :strips)
        (:predicates (lit ?l) (has-power ?l))
        (:action switch-on :parameters (?l) :precondition (has-power ?l) :effect (lit ?l)))";
    let problem = "(define (problem hall) (:domain lamp) (:objects ceiling)
        (:init (has-power ceiling)) (:goal (lit ceiling)))";
    let image = planned_image(dir.path(), domain, problem);
    let text = inspect(&image);
    assert!(text.contains("PDDL problem `hall` of domain `lamp`"), "{text}");
    assert!(text.contains("--> switch-on(ceiling)"), "{text}");

    // The same image without its names section: shown by ids, and said so.
    let bytes = std::fs::read(&image).unwrap();
    let mut nodes = vec![bt_core::Node::EMPTY; 64];
    let d = bt_core::image::decode(&bytes, &mut nodes, &mut []).unwrap();
    let mut buf = vec![0u8; max_image_len(d.nodes)];
    let len = encode(&nodes[..d.nodes], d.header.fingerprint, &mut buf).unwrap();
    let bare = dir.path().join("bare.bt");
    std::fs::write(&bare, &buf[..len]).unwrap();
    let text = inspect(&bare);
    assert!(text.contains("not built in and the image carries no names"), "{text}");
    assert!(text.contains("--> #2(0)"), "{text}");
}
