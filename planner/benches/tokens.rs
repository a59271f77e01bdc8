//! Reading the token notation: time against text size, to keep the reader linear.
//! `cargo bench -p planner --bench tokens` (the notation is `bt_formats::tokens`). Trees are a Sequence of `n - 1` tower leaves
//! with long names (`0 at pos (0.0, 0.05, 0.0)?`), up to the largest tree a `u16`
//! node count allows.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use planner::duplo::Task;

fn text(nodes: usize) -> String {
    let leaves = ["0 at pos (0.0, 0.05, 0.0)?", "pick 0!", "picked 0?", "place at (0.0, 0.05, 0.0)!"];
    let mut t = String::from("s(\n");
    for i in 0..nodes - 1 {
        t.push_str(leaves[i % leaves.len()]);
        t.push(if i % 8 == 7 { '\n' } else { ' ' });
    }
    t.push_str(")\n");
    t
}

fn parse(c: &mut Criterion) {
    let spec = Task::Tower.spec();
    let mut group = c.benchmark_group("tokens::parse");
    group.sample_size(10);
    for nodes in [1_000, 4_000, 16_000, 65_535] {
        let t = text(nodes);
        group.throughput(Throughput::Bytes(t.len() as u64));
        group.bench_with_input(BenchmarkId::from_parameter(nodes), &t, |b, t| {
            b.iter(|| black_box(bt_formats::tokens::parse(black_box(t), &spec).expect("parses")));
        });
    }
    group.finish();
}

criterion_group!(benches, parse);
criterion_main!(benches);
