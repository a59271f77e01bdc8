//! Random specs and scripts, from a seed: the cases `record.sh` gives BehaviorTree.CPP.

use rand::{Rng, RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::case::{Case, Script};
use super::spec::{FIRST_CONDITION_SCRIPT, HOOKS, Kind, SCRIPTS, Spec};

/// Ticks every random case runs.
pub const TICKS: u32 = 25;
/// Milliseconds between ticks in cases with `Timeout` or `Delay`. Their durations are
/// odd multiples of half of it, so that a timer always expires half-way between two
/// ticks, 50 ms from either (the harness drops a case whose tick came late).
pub const PERIOD_MS: u32 = 100;
/// Deepest tree, root included.
pub const MAX_DEPTH: usize = 8;
/// Largest tree.
pub const MAX_NODES: usize = 48;

/// The random case `index` of the set made from `seed`: the same pair always gives the
/// same case.
#[must_use]
pub fn case(seed: u64, index: u32) -> Case {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ (u64::from(index) << 20) ^ 0x5eed_b7c0);
    let timed = rng.random_bool(0.25);
    let once = rng.random_bool(0.25);
    let mut budget = MAX_NODES;
    let spec = loop {
        let s = node(&mut rng, 1, timed, false, &mut budget);
        if !s.kind.is_leaf() && s.len() >= 4 {
            break s;
        }
        budget = MAX_NODES;
    };
    finish(&mut rng, spec, format!("r{index:04}"), once)
}

/// The scripted case `index` of the set made from `seed`: a `Sequence` of the script
/// that sets the keys up and a random tree whose leaves include `Script` and
/// `ScriptCondition` nodes ([`SCRIPTS`]). Not clocked.
#[must_use]
pub fn scripted_case(seed: u64, index: u32) -> Case {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ (u64::from(index) << 20) ^ 0x5c21_b7ed);
    let once = rng.random_bool(0.25);
    let mut budget = MAX_NODES - 2;
    let mut tree = loop {
        let s = node(&mut rng, 2, false, true, &mut budget);
        if !s.kind.is_leaf() && s.len() >= 4 {
            break s;
        }
        budget = MAX_NODES - 2;
    };
    add_hooks(&mut tree, &mut rng);
    let spec = Spec::new(Kind::Sequence, vec![Spec::leaf(Kind::Script(0)), tree]);
    finish(&mut rng, spec, format!("s{index:04}"), once)
}

/// Gives about one node in five one or two scripted attributes (`_skipIf`, `_onSuccess`,
/// ...): conditions for the checks, assignments for the others.
fn add_hooks(spec: &mut Spec, rng: &mut ChaCha8Rng) {
    let mut stack = vec![spec];
    while let Some(s) = stack.pop() {
        if rng.random_bool(0.2) {
            let count = rng.random_range(1..=2);
            while s.hooks.len() < count {
                let (letter, _) = HOOKS[rng.random_range(0..HOOKS.len())];
                if s.hooks.iter().any(|(h, _)| *h == letter) {
                    continue;
                }
                let n = SCRIPTS.len() as u8;
                let script = if "FSKW".contains(letter) {
                    rng.random_range(FIRST_CONDITION_SCRIPT..n)
                } else {
                    rng.random_range(1..FIRST_CONDITION_SCRIPT)
                };
                s.hooks.push((letter, script));
            }
        }
        stack.extend(s.children.iter_mut());
    }
}

fn finish(rng: &mut ChaCha8Rng, spec: Spec, name: String, once: bool) -> Case {
    let rng = &mut *rng;
    let scripts = spec
        .preorder()
        .iter()
        .enumerate()
        .filter_map(|(id, n)| match n.kind {
            Kind::Condition => Some(Script { node: id, action: false, statuses: script(rng, "SF") }),
            Kind::Action => Some(Script { node: id, action: true, statuses: script(rng, "SFRRR") }),
            _ => None,
        })
        .collect();
    let period_ms = if spec.preorder().iter().any(|n| n.kind.is_timed()) { PERIOD_MS } else { 0 };
    Case { name, spec, ticks: TICKS, period_ms, once, scripts }
}

fn script(rng: &mut ChaCha8Rng, alphabet: &str) -> String {
    let len = rng.random_range(1..=7);
    let letters = alphabet.as_bytes();
    (0..len).map(|_| char::from(letters[rng.random_range(0..letters.len())])).collect()
}

fn pick<T: Copy>(rng: &mut impl Rng, items: &[T]) -> T {
    items[rng.random_range(0..items.len())]
}

fn node(rng: &mut ChaCha8Rng, depth: usize, timed: bool, scripted: bool, budget: &mut usize) -> Spec {
    *budget = budget.saturating_sub(1);
    let leaf_chance = if depth >= MAX_DEPTH || *budget < 3 { 1.0 } else { 0.15 + 0.1 * depth as f64 };
    if rng.random_bool(leaf_chance.min(1.0)) {
        // (Drawn only for scripted cases: the random cases stay what they were.)
        if scripted && rng.random_bool(0.4) {
            let n = SCRIPTS.len() as u8;
            return Spec::leaf(if rng.random_bool(0.5) {
                Kind::Script(rng.random_range(1..FIRST_CONDITION_SCRIPT))
            } else {
                Kind::ScriptCondition(rng.random_range(FIRST_CONDITION_SCRIPT..n))
            });
        }
        let kind = match rng.random_range(0..10) {
            0..=3 => Kind::Condition,
            4..=8 => Kind::Action,
            _ => pick(rng, &[Kind::AlwaysSuccess, Kind::AlwaysFailure]),
        };
        return Spec::leaf(kind);
    }
    if rng.random_bool(0.35) {
        let half = PERIOD_MS / 2;
        let mut kinds = vec![
            Kind::Inverter,
            Kind::ForceSuccess,
            Kind::ForceFailure,
            Kind::Repeat(pick(rng, &[-1, 0, 1, 2, 3])),
            Kind::RetryUntilSuccessful(pick(rng, &[-1, 0, 1, 2, 3])),
            Kind::KeepRunningUntilFailure,
            Kind::RunOnce { then_skip: rng.random_bool(0.5) },
        ];
        if timed {
            kinds.push(Kind::Timeout(pick(rng, &[0, half, 3 * half, 5 * half])));
            kinds.push(Kind::Delay(pick(rng, &[half, 3 * half, 5 * half])));
            kinds.push(Kind::Timeout(pick(rng, &[half, 3 * half, 5 * half, 7 * half])));
        }
        if scripted {
            let n = SCRIPTS.len() as u8;
            let script = rng.random_range(FIRST_CONDITION_SCRIPT..n);
            kinds.push(Kind::Precondition(script, pick(rng, &['S', 'F', 'R', 'K'])));
            kinds.push(Kind::Loop {
                double: rng.random_bool(0.5),
                count: rng.random_range(0..=3),
                if_empty: pick(rng, &['S', 'F', 'R', 'K']),
            });
        }
        let kind = pick(rng, &kinds);
        let child = node(rng, depth + 1, timed, scripted, budget);
        return Spec::new(kind, vec![child]);
    }
    let shape = rng.random_range(0..9);
    let n = match shape {
        7 | 8 => rng.random_range(2..=3),
        _ => rng.random_range(1..=4),
    };
    let mut children = vec![];
    for _ in 0..n {
        if *budget == 0 && !children.is_empty() {
            break;
        }
        children.push(node(rng, depth + 1, timed, scripted, budget));
    }
    let n = children.len() as i32;
    let kind = match shape {
        0 => Kind::Sequence,
        1 => Kind::SequenceWithMemory,
        2 => Kind::Fallback,
        3 => Kind::ReactiveSequence,
        4 => Kind::ReactiveFallback,
        5 => Kind::Parallel { success: threshold(rng, n), failure: threshold(rng, n) },
        6 => {
            let t = threshold(rng, n);
            Kind::ParallelAll { max_failures: pick(rng, &[t, t, 0, -1]) }
        }
        7 => Kind::IfThenElse,
        _ => Kind::WhileDoElse,
    };
    if matches!(kind, Kind::IfThenElse | Kind::WhileDoElse) && children.len() < 2 {
        children.push(Spec::leaf(Kind::Action));
    }
    Spec::new(kind, children)
}

/// A threshold BehaviorTree.CPP accepts for `n` children, written positive or negative.
fn threshold(rng: &mut ChaCha8Rng, n: i32) -> i32 {
    let t = rng.random_range(1..=n);
    if rng.random_bool(0.4) { t - n - 1 } else { t }
}
