//! The genetic operators of Styrud et al. (Section III-B and the reference details): random
//! trees, mutation (delete / add / change) and crossover by subtree insertion.
//!
//! Each operator draws from the caller's generator in a fixed order and returns only
//! trees that pass [`check`](crate::genome::check()). The `*_into` forms write into
//! buffers the caller reuses, so that breeding allocates nothing once warm.

use rand::{Rng, RngExt};

use crate::alphabet::{Alphabet, draw, random_control};
use crate::edit::{balance, delete, dissolve, subtree_end};
use crate::genome::{Genome, Token, check};

/// Attempts an operator makes before giving up (the reference's 100).
pub const MAX_ATTEMPTS: usize = 100;

/// Attempts [`random_tree`] makes before giving up. The reference redraws forever; a
/// valid tree always has a positive chance, but it falls fast with the length (on the
/// brick tasks about 1 in 40 draws is valid at 8 nodes, 1 in 3000 at 20), so this
/// stops lengths past about 25 nodes instead of hanging.
pub const RANDOM_TREE_ATTEMPTS: usize = 100_000;

/// How a mutation changes a tree, with what probability (Table I: add 40 %, delete
/// 30 %, change 30 %).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MutationRates {
    /// Insert a random node.
    pub add: f64,
    /// Remove a node with its subtree.
    pub delete: f64,
    /// Replace a node with a random one.
    pub change: f64,
}

impl Default for MutationRates {
    fn default() -> Self {
        Self { add: 0.4, delete: 0.3, change: 0.3 }
    }
}

/// A random valid tree of `length` nodes (closing tokens not counted), as the
/// reference draws it: one action if `length` is 1; else a random control node, then
/// `length - 1` [random nodes](Alphabet::random_node) with a `)` after each action, then
/// balanced. Redrawn until valid; `None` after [`RANDOM_TREE_ATTEMPTS`] or for length 0.
pub fn random_tree<R: Rng + ?Sized>(length: usize, alphabet: &Alphabet, rng: &mut R) -> Option<Genome> {
    let mut tokens = Vec::with_capacity(2 * length + 1);
    random_tree_into(length, alphabet, rng, &mut tokens).then(|| Genome::from(tokens))
}

/// [`random_tree`] into a buffer; returns whether it succeeded.
pub fn random_tree_into<R: Rng + ?Sized>(
    length: usize,
    alphabet: &Alphabet,
    rng: &mut R,
    out: &mut Vec<Token>,
) -> bool {
    if length == 0 {
        return false;
    }
    for _ in 0..RANDOM_TREE_ATTEMPTS {
        out.clear();
        if length == 1 {
            out.push(alphabet.random_action(rng));
        } else {
            out.push(random_control(rng));
            for _ in 1..length {
                let node = alphabet.random_node(rng);
                out.push(node);
                if matches!(node, Token::Action(_)) {
                    out.push(Token::Close);
                }
            }
            balance(out);
        }
        if check(out, alphabet).is_ok() {
            return true;
        }
    }
    false
}

/// A mutation of `parent`: a valid tree different from it, or `None` after
/// [`MAX_ATTEMPTS`] tries.
///
/// Each try copies the parent, draws a token position uniformly (closing tokens
/// included), then deletes (`rates.delete`), adds (`rates.add`) or changes (the rest):
/// - **delete** removes the node with its subtree (nothing at a `)`);
/// - **add** inserts a [random node](Alphabet::random_node) before the position; a
///   control node at position 0 wraps the whole tree, elsewhere it comes as
///   `control(random leaf, random action)`;
/// - **change** (nothing at a `)`) replaces the node with a random node: control by
///   control or leaf by leaf in place; a control node by a leaf drops its subtree; an
///   action `a` by a control node gives `control(random leaf, a)`, a condition `c`
///   gives `control(c, random action)`.
///
/// Then the tokens are balanced (missing `)` appended, surplus ones removed from the
/// right) and control nodes below the root with 0 or 1 child are dissolved into their
/// parent (a lone child of the same kind as the new parent is dissolved too, so no
/// `s(` lands under `s(`).
pub fn mutate<R: Rng + ?Sized>(
    parent: &Genome,
    alphabet: &Alphabet,
    rates: &MutationRates,
    rng: &mut R,
) -> Option<Genome> {
    let mut out = Vec::with_capacity(parent.tokens().len() + 4);
    mutate_into(parent.tokens(), alphabet, rates, rng, &mut out).then(|| Genome::from(out))
}

/// [`mutate`] into a buffer; returns whether it succeeded.
pub fn mutate_into<R: Rng + ?Sized>(
    parent: &[Token],
    alphabet: &Alphabet,
    rates: &MutationRates,
    rng: &mut R,
    out: &mut Vec<Token>,
) -> bool {
    if parent.is_empty() {
        return false;
    }
    for _ in 0..MAX_ATTEMPTS {
        out.clear();
        out.extend_from_slice(parent);
        let at = draw(rng, parent.len());
        let r: f64 = rng.random();
        if r < rates.delete {
            delete(out, at);
        } else if r < rates.delete + rates.add {
            add(out, at, alphabet, rng);
        } else {
            change(out, at, alphabet, rng);
        }
        balance(out);
        dissolve(out);
        if out.as_slice() != parent && check(out, alphabet).is_ok() {
            return true;
        }
    }
    false
}

fn add<R: Rng + ?Sized>(tokens: &mut Vec<Token>, at: usize, alphabet: &Alphabet, rng: &mut R) {
    let node = alphabet.random_node(rng);
    if !node.is_control() {
        tokens.insert(at, node);
    } else if at == 0 {
        tokens.insert(0, node);
        tokens.push(Token::Close);
    } else {
        let leaf = alphabet.random_leaf(rng);
        let action = alphabet.random_action(rng);
        tokens.splice(at..at, [node, leaf, action, Token::Close]);
    }
}

fn change<R: Rng + ?Sized>(tokens: &mut Vec<Token>, at: usize, alphabet: &Alphabet, rng: &mut R) {
    let Some(&old) = tokens.get(at) else { return };
    if old == Token::Close {
        return;
    }
    let new = alphabet.random_node(rng);
    if old.is_control() && new.is_leaf() {
        delete(tokens, at);
        tokens.insert(at, new);
    } else if old.is_leaf() && new.is_control() {
        let children = match old {
            Token::Action(_) => [alphabet.random_leaf(rng), old],
            _ => [old, alphabet.random_action(rng)],
        };
        tokens[at] = new;
        tokens.splice(at + 1..at + 1, [children[0], children[1], Token::Close]);
    } else {
        tokens[at] = new;
    }
}

/// Crossover by insertion: a random subtree of each parent is copied into a random
/// position of the other; the donors keep theirs. `None` unless both parents are valid
/// and a try gives two valid children within [`MAX_ATTEMPTS`].
///
/// The subtree root is drawn uniformly among the non-root nodes (the whole tree if it
/// is a single leaf); the insertion point among token positions `1..len` (before any
/// token but the root, so the subtree lands inside the root), or `0..=1` for a single
/// leaf. Children are not trimmed: a try whose children break a rule is redrawn.
pub fn crossover<R: Rng + ?Sized>(
    a: &Genome,
    b: &Genome,
    alphabet: &Alphabet,
    rng: &mut R,
) -> Option<(Genome, Genome)> {
    let (mut x, mut y) = (Vec::new(), Vec::new());
    crossover_into(a.tokens(), b.tokens(), alphabet, rng, &mut x, &mut y).then(|| (Genome::from(x), Genome::from(y)))
}

/// [`crossover`] into buffers; returns whether it succeeded.
pub fn crossover_into<R: Rng + ?Sized>(
    a: &[Token],
    b: &[Token],
    alphabet: &Alphabet,
    rng: &mut R,
    child_a: &mut Vec<Token>,
    child_b: &mut Vec<Token>,
) -> bool {
    if check(a, alphabet).is_err() || check(b, alphabet).is_err() {
        return false;
    }
    for _ in 0..MAX_ATTEMPTS {
        let from_a = random_subtree(a, rng);
        let from_b = random_subtree(b, rng);
        let into_a = insertion_point(a, rng);
        let into_b = insertion_point(b, rng);
        insert(a, into_a, &b[from_b..subtree_end(b, from_b)], child_a);
        insert(b, into_b, &a[from_a..subtree_end(a, from_a)], child_b);
        if check(child_a, alphabet).is_ok() && check(child_b, alphabet).is_ok() {
            return true;
        }
    }
    false
}

/// A uniformly drawn non-root node (the root if the tree is one leaf).
fn random_subtree<R: Rng + ?Sized>(tokens: &[Token], rng: &mut R) -> usize {
    if tokens.len() == 1 {
        return 0;
    }
    let nodes = tokens.iter().skip(1).filter(|t| **t != Token::Close).count();
    if nodes == 0 {
        return 0;
    }
    let k = draw(rng, nodes);
    tokens.iter().enumerate().skip(1).filter(|(_, t)| **t != Token::Close).nth(k).map_or(0, |(i, _)| i)
}

fn insertion_point<R: Rng + ?Sized>(tokens: &[Token], rng: &mut R) -> usize {
    if tokens.len() == 1 { draw(rng, 2) } else { 1 + draw(rng, tokens.len() - 1) }
}

fn insert(host: &[Token], at: usize, subtree: &[Token], out: &mut Vec<Token>) {
    out.clear();
    out.extend_from_slice(&host[..at]);
    out.extend_from_slice(subtree);
    out.extend_from_slice(&host[at..]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner::duplo::Task;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn setup() -> (planner::duplo::Spec, Alphabet, ChaCha8Rng) {
        let spec = Task::Tower.spec();
        let alphabet = Alphabet::from_catalog(&spec).unwrap();
        (spec, alphabet, ChaCha8Rng::seed_from_u64(3))
    }

    #[test]
    fn random_trees_have_the_length_asked() {
        let (_, a, mut rng) = setup();
        for length in 1..20 {
            for _ in 0..20 {
                let g = random_tree(length, &a, &mut rng).unwrap();
                assert_eq!(g.length(), length);
                assert_eq!(g.check(&a), Ok(()));
            }
        }
        assert_eq!(random_tree(0, &a, &mut rng), None);
    }

    #[test]
    fn add_at_root_wraps_and_elsewhere_brings_two_children() {
        let (spec, a, mut rng) = setup();
        let parent = Genome::parse("s( picked 0? pick 0! )", &spec, &a).unwrap();
        let mut seen_wrap = false;
        let mut seen_inner = false;
        for _ in 0..2000 {
            let mut t = parent.tokens().to_vec();
            let at = draw(&mut rng, t.len());
            add(&mut t, at, &a, &mut rng);
            let grown = t.len() - parent.tokens().len();
            if at == 0 && t[0].is_control() {
                assert_eq!(&t[1..t.len() - 1], parent.tokens());
                seen_wrap = true;
            } else if grown == 4 {
                assert!(t[at].is_control() && t[at + 1].is_leaf());
                assert!(matches!(t[at + 2], Token::Action(_)) && t[at + 3] == Token::Close);
                seen_inner = true;
            } else {
                assert_eq!(grown, 1);
            }
        }
        assert!(seen_wrap && seen_inner);
    }

    #[test]
    fn change_a_leaf_into_a_control_node_keeps_the_leaf() {
        let (spec, a, mut rng) = setup();
        let parent = Genome::parse("s( picked 0? pick 0! )", &spec, &a).unwrap();
        let (cond, act) = (parent.tokens()[1], parent.tokens()[2]);
        let (mut seen_c, mut seen_a) = (false, false);
        for _ in 0..500 {
            for at in [1, 2] {
                let mut t = parent.tokens().to_vec();
                change(&mut t, at, &a, &mut rng);
                if t.len() == 7 {
                    assert!(t[at].is_control() && t[at + 3] == Token::Close);
                    if at == 1 {
                        assert!(t[2] == cond && matches!(t[3], Token::Action(_)));
                        seen_c = true;
                    } else {
                        assert!(t[3].is_leaf() && t[4] == act);
                        seen_a = true;
                    }
                }
            }
        }
        assert!(seen_c && seen_a);
        let mut t = vec![Token::Sequence, Token::Fallback, cond, act, Token::Close, act, Token::Close];
        for _ in 0..50 {
            let before = t.clone();
            change(&mut t, 1, &a, &mut rng);
            if t[1].is_leaf() {
                assert_eq!(t.len(), 4);
                break;
            }
            t = before;
        }
        assert_eq!(t.len(), 4, "a control node never became a leaf");
    }

    #[test]
    fn mutation_gives_up_on_a_tree_it_cannot_change() {
        // One action, no condition: `s( a! )` can only become `s( a! a! )`-like trees,
        // which is possible, so mutation succeeds; an empty parent cannot be mutated.
        let (_, a, mut rng) = setup();
        let mut out = Vec::new();
        assert!(!mutate_into(&[], &a, &MutationRates::default(), &mut rng, &mut out));
    }
}
