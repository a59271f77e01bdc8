//! Greedy best-first search with *deferred* evaluation, as LAMA's first iteration
//! searches: a state is evaluated only when it is taken from an open list, and enters
//! the lists under its parent's h. Where most successors of a state are never taken
//! (many actions, a good heuristic) this evaluates a fraction of the states eager
//! search does.
//!
//! With [`SearchOptions::landmarks`] it alternates, as LAMA does, between h_FF and the
//! landmark count ([`super::landmarks`]): four open lists (each heuristic, and each
//! for the successors by one of the helpful actions of either, or of h_FF only without
//! [`SearchOptions::landmark_preferred`]), taken in turn, the lists of helpful
//! successors given [`SearchOptions::boost`] turns more whenever either heuristic
//! reaches a new best. Without it, two lists (h_FF, and helpful successors) in the same
//! way.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::landmarks::Landmarks;
use super::{Found, Node, Relaxation, SearchOptions, child, path};
use crate::PlanError;
use crate::ground::{ActionId, Grounding};
use crate::search::INFINITE;
use crate::search::registry::Registry;
use crate::search::successors::Successors;
use crate::state::State;

/// An open-list entry: the parent's h, the order it was generated in, the parent and
/// the action that leads from it.
type Entry = Reverse<(u32, u64, u32, ActionId)>;

/// h_FF, h_FF's helpful successors, landmark count, its helpful successors.
const LISTS: usize = 4;

/// Greedy best-first search from `start` with deferred evaluation (see the module
/// docs).
///
/// # Errors
/// As [`super::gbfs`].
pub fn lazy_gbfs_from(g: &Grounding, start: &State, options: &SearchOptions) -> Result<Found, PlanError> {
    let mut h = Relaxation::new(g);
    let lm = if options.landmarks { Landmarks::new(g, options.deadline) } else { None };
    let words = lm.as_ref().map_or(0, Landmarks::words);
    let succ = Successors::new(g);
    let mut reg = Registry::new(g, start);
    let mut helpful = Vec::new();
    let mut lm_helpful = Vec::new();
    let h0 = h.h_ff(start, &mut helpful);
    if h0 == INFINITE {
        return Err(PlanError::NoPlan("the goal is unreachable even when deletes are ignored".into()));
    }
    let (root, _) = reg.insert(start);
    let mut nodes: Vec<Node> = vec![Node { parent: u32::MAX, action: 0 }];
    if g.goal_holds(start) {
        return Ok(Found { plan: Vec::new(), expanded: 0, stored: 1, evaluated: 1, initial_h: h0 });
    }
    // The accepted landmarks of every stored state, `words` each.
    let mut accepted: Vec<u64> = Vec::new();
    let mut scratch: Vec<u64> = Vec::new();
    let mut lm0 = 0;
    if let Some(lm) = &lm {
        lm.initial(start, &mut scratch);
        lm0 = lm.count(g, &scratch, start, &mut lm_helpful);
        accepted.extend_from_slice(&scratch);
    }
    let mut lists: [BinaryHeap<Entry>; LISTS] = Default::default();
    // Turns taken from each list (LAMA's priorities): the least goes next.
    let mut turns = [0i64; LISTS];
    let used = if lm.is_some() { LISTS } else { 2 };
    let mut order: u64 = 0;
    let mut state = start.clone();
    let mut next = State::new(g.atom_count());
    let mut applicable = Vec::new();
    let mut best = (h0, lm0);
    let mut expanded: u64 = 0;
    let mut evaluated: u64 = 1;
    // The state being expanded: its id, h_FF and landmark count.
    let mut current = (root, h0, lm0);
    loop {
        expanded += 1;
        succ.applicable(g, &state, &mut applicable);
        let (id, hf, hl) = current;
        for &a in &applicable {
            let preferred = helpful.contains(&a) || (options.landmark_preferred && lm_helpful.contains(&a));
            order += 1;
            lists[0].push(Reverse((hf, order, id, a)));
            if preferred {
                lists[1].push(Reverse((hf, order, id, a)));
            }
            if lm.is_some() {
                lists[2].push(Reverse((hl, order, id, a)));
                if preferred {
                    lists[3].push(Reverse((hl, order, id, a)));
                }
            }
        }
        let queued: usize = lists.iter().map(BinaryHeap::len).sum();
        if reg.bytes() + queued * 24 + accepted.len() * 8 > options.memory {
            return Err(PlanError::SearchMemory { states: reg.len() as u64, limit: options.memory as u64 });
        }
        // Take entries until one leads to a new state that is not a dead end.
        loop {
            if expanded & 0xFF == 0 && options.over() {
                return Err(PlanError::Timeout { stage: "searching for a plan" });
            }
            let Some(k) = (0..used).filter(|&k| !lists[k].is_empty()).min_by_key(|&k| (turns[k], k)) else {
                return Err(PlanError::NoPlan(format!("every reachable state was expanded ({} states)", reg.len())));
            };
            turns[k] += 1;
            let Some(Reverse((_, _, parent, a))) = lists[k].pop() else { continue };
            reg.load(parent, &mut state);
            let Some(sid) = child(g, &mut reg, &state, a, &mut next) else { continue };
            nodes.push(Node { parent, action: a });
            let mut hn_lm = 0;
            if let Some(lm) = &lm {
                let from = parent as usize * words;
                lm.accept(accepted.get(from..from + words).unwrap_or(&[]), &next, &mut scratch);
                accepted.extend_from_slice(&scratch);
            }
            if g.goal_holds(&next) {
                return Ok(Found {
                    plan: path(&nodes, sid),
                    expanded,
                    stored: reg.len() as u64,
                    evaluated,
                    initial_h: h0,
                });
            }
            if options.over() {
                return Err(PlanError::Timeout { stage: "searching for a plan" });
            }
            if options.evaluated_enough(evaluated) {
                return Err(PlanError::OutOfStates { evaluated });
            }
            let hn = h.h_ff(&next, &mut helpful);
            evaluated += 1;
            if hn == INFINITE {
                continue;
            }
            if let Some(lm) = &lm {
                hn_lm = lm.count(g, &scratch, &next, &mut lm_helpful);
            }
            if hn < best.0 || (lm.is_some() && hn_lm < best.1) {
                best = (best.0.min(hn), best.1.min(hn_lm));
                turns[1] -= i64::from(options.boost);
                turns[3] -= i64::from(options.boost);
            }
            std::mem::swap(&mut state, &mut next);
            current = (sid, hn, hn_lm);
            break;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::domains;

    fn deferred(max_evaluated: Option<u64>, landmark_preferred: bool) -> SearchOptions {
        SearchOptions { lazy: true, landmarks: true, landmark_preferred, max_evaluated, ..SearchOptions::default() }
    }

    #[test]
    fn deferred_search_stops_at_its_budget_of_evaluated_states() {
        let g = domains::blocks_world(6).unwrap();
        let found = lazy_gbfs_from(&g, g.init(), &deferred(None, true)).unwrap();
        assert!(found.evaluated > 3, "{found:?}");
        let e = lazy_gbfs_from(&g, g.init(), &deferred(Some(3), true)).unwrap_err();
        assert!(matches!(e, PlanError::OutOfStates { evaluated: 3 }), "{e:?}");
        let within = lazy_gbfs_from(&g, g.init(), &deferred(Some(found.evaluated), true)).unwrap();
        assert_eq!(within, found);
        // A bound another thread may lower acts as the same bound set from the start.
        let live = |n: u64| SearchOptions {
            max_evaluated_live: Some(std::sync::Arc::new(std::sync::atomic::AtomicU64::new(n))),
            ..deferred(None, true)
        };
        let e = lazy_gbfs_from(&g, g.init(), &live(3)).unwrap_err();
        assert!(matches!(e, PlanError::OutOfStates { evaluated: 3 }), "{e:?}");
        assert_eq!(lazy_gbfs_from(&g, g.init(), &live(found.evaluated)).unwrap(), found);
    }

    #[test]
    fn without_landmark_preference_only_h_ff_helpful_successors_are_preferred() {
        // Both find a valid plan; the searches differ (the preferred lists differ).
        let g = domains::blocks_world(6).unwrap();
        let with = lazy_gbfs_from(&g, g.init(), &deferred(None, true)).unwrap();
        let without = lazy_gbfs_from(&g, g.init(), &deferred(None, false)).unwrap();
        for f in [&with, &without] {
            assert!(g.goal_holds(&crate::search::execute(&g, &f.plan).unwrap()));
        }
        assert_ne!((with.expanded, with.evaluated), (without.expanded, without.evaluated));
    }
}
