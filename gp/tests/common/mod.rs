//! A synthetic, deterministic fitness for the GP's tests: no world, just the tree.
#![allow(dead_code)]

use std::sync::atomic::{AtomicU64, Ordering};

use bt_core::{Node, NodeKind};
use gp::{Alphabet, Fitness};
use planner::duplo::{Spec, Task};

/// Scores a tree by how much of a target leaf sequence it contains in order (longest
/// common subsequence of leaf ids), minus 0.1 per node, as Eq. (1) penalises length.
/// Counts its calls: each is one episode.
#[derive(Debug)]
pub struct Target {
    target: Vec<u16>,
    calls: AtomicU64,
}

impl Target {
    pub fn new(spec: &Spec, leaves: &[&str]) -> Self {
        let target = leaves.iter().map(|n| spec.id_by_name(n).expect("leaf of the task")).collect();
        Self { target, calls: AtomicU64::new(0) }
    }

    /// The tower's goal leaves, in the order a solution runs them.
    pub fn tower() -> (Spec, Alphabet, Self) {
        let spec = Task::Tower.spec();
        let alphabet = Alphabet::from_catalog(&spec).unwrap();
        let target = Self::new(
            &spec,
            &[
                "0 at pos (0.0, 0.05, 0.0)?",
                "pick 0!",
                "place at (0.0, 0.05, 0.0)!",
                "1 on 0?",
                "pick 1!",
                "place on 0!",
                "apply force 1!",
                "2 on 1?",
                "pick 2!",
                "place on 1!",
            ],
        );
        (spec, alphabet, target)
    }

    pub fn calls(&self) -> u64 {
        self.calls.load(Ordering::Relaxed)
    }

    pub fn score(&self, tree: &[Node]) -> f64 {
        let leaves: Vec<u16> = tree
            .iter()
            .filter_map(|n| match n.kind() {
                NodeKind::Condition(l) | NodeKind::Action(l) => Some(l.behavior()),
                _ => None,
            })
            .collect();
        let mut row = vec![0usize; self.target.len() + 1];
        for &leaf in &leaves {
            let mut diagonal = 0;
            for (j, &t) in self.target.iter().enumerate() {
                let up = row[j + 1];
                row[j + 1] = if leaf == t { diagonal + 1 } else { up.max(row[j]) };
                diagonal = up;
            }
        }
        row[self.target.len()] as f64 - 0.1 * tree.len() as f64
    }
}

impl Fitness for Target {
    fn fitness(&self, tree: &[Node]) -> f64 {
        self.calls.fetch_add(1, Ordering::Relaxed);
        self.score(tree)
    }
}

/// A planner-like baseline for the tower: right leaves, but in a shape that scores low
/// on `Target` unless GP rearranges it.
pub fn tower_baseline(spec: &Spec) -> Vec<Node> {
    bt_formats::tokens::parse(
        "s( f( 2 on 1? s( pick 2! place on 1! ) ) f( 1 on 0? s( pick 1! place on 0! ) ) \
         f( 0 at pos (0.0, 0.05, 0.0)? s( pick 0! place at (0.0, 0.05, 0.0)! ) ) )",
        spec,
    )
    .unwrap()
}
