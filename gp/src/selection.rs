//! Selection (Table I: rank-proportional for reproduction and survival, plus elitism).
//!
//! Ranks order individuals by fitness, best first. **Ties** go to the later
//! individual in the list, as in the reference (it sorts `(fitness, index)` pairs in
//! descending order): lists are built as old population, then crossover offspring,
//! then mutation offspring, so an offspring outranks an equally fit older tree.

use rand::{Rng, RngExt};

/// Indices of `fitness`, best first; equal fitness ranks the later index first.
/// `out` is cleared first.
pub fn rank_order(fitness: &[f64], out: &mut Vec<usize>) {
    // Sort (fitness, index) keys ascending as plain integers, then read them backwards.
    let mut keys: Vec<(u64, usize)> = fitness.iter().enumerate().map(|(i, &f)| (ordered(f), i)).collect();
    keys.sort_unstable();
    out.clear();
    out.extend(keys.iter().rev().map(|&(_, i)| i));
}

/// `f64` to `u64` keeping [`f64::total_cmp`]'s order.
#[inline]
fn ordered(f: f64) -> u64 {
    let bits = f.to_bits();
    if bits >> 63 == 1 { !bits } else { bits | 1 << 63 }
}

/// The `k` best (elitism), best first; all of them if there are fewer.
pub fn select_best(fitness: &[f64], k: usize, out: &mut Vec<usize>) {
    rank_order(fitness, out);
    out.truncate(k);
}

/// Rank-proportional selection of `k` distinct indices (all if fewer), in the order
/// drawn: with `n` candidates the best has weight `n`, the next `n - 1`, ..., the worst
/// 1; each draw picks among those not yet drawn with probability proportional to
/// weight (the reference's sampling without replacement).
pub fn select_by_rank<R: Rng + ?Sized>(fitness: &[f64], k: usize, rng: &mut R, out: &mut Vec<usize>) {
    let mut ranked = Vec::with_capacity(fitness.len());
    rank_order(fitness, &mut ranked);
    let n = ranked.len() as u64;
    // (index, weight) of those not drawn yet, best first.
    let mut left: Vec<(usize, u64)> = ranked.iter().zip((1..=n).rev()).map(|(&i, w)| (i, w)).collect();
    let mut total: u64 = n * (n + 1) / 2;
    out.clear();
    while out.len() < k && !left.is_empty() {
        let mut u = rng.random_range(0..total);
        let mut pick = left.len() - 1;
        for (j, &(_, w)) in left.iter().enumerate() {
            if u < w {
                pick = j;
                break;
            }
            u -= w;
        }
        let (index, w) = left.remove(pick);
        total -= w;
        out.push(index);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn ranks_best_first_ties_to_the_later() {
        let mut out = Vec::new();
        rank_order(&[-3.0, -1.0, -3.0, f64::NEG_INFINITY, -1.0], &mut out);
        assert_eq!(out, [4, 1, 2, 0, 3]);
        select_best(&[-3.0, -1.0, -2.0], 2, &mut out);
        assert_eq!(out, [1, 2]);
        select_best(&[-3.0], 2, &mut out);
        assert_eq!(out, [0]);
    }

    #[test]
    fn weights_are_linear_in_rank() {
        // Four candidates ranked 2 > 0 > 3 > 1: weights 4, 3, 2, 1 out of 10.
        let fitness = [-1.0, -9.0, 0.0, -5.0];
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut out = Vec::new();
        let mut counts = [0u32; 4];
        let draws = 40_000;
        for _ in 0..draws {
            select_by_rank(&fitness, 1, &mut rng, &mut out);
            counts[out[0]] += 1;
        }
        for (index, weight) in [(2, 4.0), (0, 3.0), (3, 2.0), (1, 1.0)] {
            let expected = f64::from(draws) * weight / 10.0;
            // 5 standard deviations at most.
            let sigma = (expected * (1.0 - weight / 10.0)).sqrt();
            assert!((f64::from(counts[index]) - expected).abs() < 5.0 * sigma, "{counts:?}");
        }
    }

    #[test]
    fn draws_without_replacement() {
        let fitness: Vec<f64> = (0..16).map(f64::from).collect();
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let mut out = Vec::new();
        for k in [0, 1, 8, 16, 20] {
            select_by_rank(&fitness, k, &mut rng, &mut out);
            assert_eq!(out.len(), k.min(16));
            let mut sorted = out.clone();
            sorted.sort_unstable();
            sorted.dedup();
            assert_eq!(sorted.len(), out.len());
        }
    }
}
