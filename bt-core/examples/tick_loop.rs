//! Ticks one of the benchmark trees (W100, D50, Cube; see `benches/trees`) a fixed
//! number of times: for instruction counts under `valgrind --tool=callgrind`, which are
//! repeatable, unlike wall time on a shared machine. It uses the benchmark's own world
//! type, so the executor is compiled exactly as in `cargo bench -p bt-core`.
//!
//! `cargo build --release -p bt-core --example tick_loop &&
//!  valgrind --tool=callgrind target/release/examples/tick_loop 110000 W100`
//!
//! The count includes about 1 ms of setup; per tick, divide by the ticks.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing, missing_docs)]

use std::hint::black_box;
use std::process::ExitCode;

use bt_core::{Executor, Node, NodeState, Tree};

#[path = "../benches/trees/mod.rs"]
mod trees;

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let ticks: u32 = match args.next().map(|a| a.parse()) {
        None => 100_000,
        Some(Ok(n)) => n,
        Some(Err(e)) => {
            eprintln!("tick_loop: the tick count must be a whole number: {e}");
            return ExitCode::FAILURE;
        }
    };
    let name = args.next().unwrap_or_else(|| "W100".into());
    let Some(&(_, make, visited)) = trees::TREES.iter().find(|(n, _, _)| *n == name) else {
        eprintln!("tick_loop: no tree named {name:?}; the trees are W100, D50 and Cube");
        return ExitCode::FAILURE;
    };
    let mut storage = vec![Node::EMPTY; 512];
    let nodes = make(&mut storage);
    let tree = Tree::<64>::validate(nodes, &trees::SET).unwrap();
    let mut state = vec![NodeState::IDLE; nodes.len()];
    let mut exec = Executor::new(tree, &mut state).unwrap();
    let mut w = trees::world();
    trees::first_tick(&mut exec, &mut w, &name, visited);
    let start = std::time::Instant::now();
    for t in 1..=ticks {
        black_box(exec.tick(&mut w, black_box(t)).unwrap());
    }
    let ns = start.elapsed().as_nanos() as f64 / f64::from(ticks);
    println!(
        "{ticks} ticks of {name}: {ns:.0} ns/tick, {:.2} ns/visited node (counter {})",
        ns / visited as f64,
        w.counter
    );
    ExitCode::SUCCESS
}
