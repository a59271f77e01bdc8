//! Every operator keeps trees valid, on random trees of each brick task's alphabet.

use gp::operators::{crossover, mutate, random_tree};
use gp::{Alphabet, Genome, MutationRates, Token};
use planner::duplo::Task;
use proptest::prelude::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn alphabet(task: usize) -> Alphabet {
    Alphabet::from_catalog(&Task::ALL[task].spec()).unwrap()
}

/// Index one past the subtree starting at `at`.
fn subtree_end(t: &[Token], at: usize) -> usize {
    if !t[at].is_control() {
        return at + 1;
    }
    let mut depth = 0;
    for (i, tok) in t.iter().enumerate().skip(at) {
        if tok.is_control() {
            depth += 1;
        } else if *tok == Token::Close {
            depth -= 1;
            if depth == 0 {
                return i + 1;
            }
        }
    }
    t.len()
}

/// Whether `child` is `host` with one whole subtree of `donor` inserted after the root
/// token (or the donor's only leaf, for a one-leaf donor).
fn is_insertion(child: &[Token], host: &[Token], donor: &[Token]) -> bool {
    let Some(k) = child.len().checked_sub(host.len()).filter(|&k| k > 0) else { return false };
    let donor_subtrees: Vec<&[Token]> = (0..donor.len())
        .filter(|&j| donor[j] != Token::Close && (j > 0 || donor.len() == 1))
        .map(|j| &donor[j..subtree_end(donor, j)])
        .collect();
    (0..=host.len()).any(|i| {
        child[..i] == host[..i] && child[i + k..] == host[i..] && donor_subtrees.iter().any(|s| *s == &child[i..i + k])
    })
}

/// Every control node but the root has at least two children.
fn no_lone_children(t: &[Token]) -> bool {
    (1..t.len()).filter(|&i| t[i].is_control()).all(|i| {
        let end = subtree_end(t, i) - 1;
        let mut children = 0;
        let mut c = i + 1;
        while c < end {
            children += 1;
            c = subtree_end(t, c);
        }
        children >= 2
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn random_trees_are_valid_with_the_length_asked(task in 0..4usize, length in 1..=16usize, seed: u64) {
        let a = alphabet(task);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let g = random_tree(length, &a, &mut rng).unwrap();
        prop_assert_eq!(g.check(&a), Ok(()));
        prop_assert_eq!(g.length(), length);
        prop_assert_eq!(g.to_nodes().unwrap().len(), length);
    }

    /// A chain of mutations (each of the previous result) stays valid, never returns
    /// its parent, and leaves no control node below the root with fewer than two
    /// children.
    #[test]
    fn mutation_keeps_trees_valid(task in 0..4usize, length in 1..16usize, seed: u64) {
        let a = alphabet(task);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut parent = random_tree(length, &a, &mut rng).unwrap();
        for _ in 0..30 {
            let Some(child) = mutate(&parent, &a, &MutationRates::default(), &mut rng) else { break };
            prop_assert_eq!(child.check(&a), Ok(()), "{:?}", child);
            prop_assert_ne!(&child, &parent);
            prop_assert!(no_lone_children(child.tokens()), "{:?}", child);
            parent = child;
        }
    }

    /// Crossover children are valid and each is its parent with a whole subtree of the
    /// other inserted; the parents are untouched. Children are fed back in, so the
    /// parents include crossover-shaped trees too.
    #[test]
    fn crossover_inserts_a_subtree_of_the_other(task in 0..4usize, la in 2..14usize, lb in 2..14usize, seed: u64) {
        let a = alphabet(task);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut x = random_tree(la, &a, &mut rng).unwrap();
        let mut y = random_tree(lb, &a, &mut rng).unwrap();
        for _ in 0..6 {
            let (x0, y0) = (x.clone(), y.clone());
            let Some((cx, cy)) = crossover(&x, &y, &a, &mut rng) else { break };
            prop_assert_eq!((&x, &y), (&x0, &y0));
            prop_assert_eq!(cx.check(&a), Ok(()));
            prop_assert_eq!(cy.check(&a), Ok(()));
            prop_assert!(is_insertion(cx.tokens(), x.tokens(), y.tokens()), "{:?} <- {:?} = {:?}", x, y, cx);
            prop_assert!(is_insertion(cy.tokens(), y.tokens(), x.tokens()), "{:?} <- {:?} = {:?}", y, x, cy);
            // Keep the trees small enough for the check above.
            (x, y) = if cx.length() < 40 { (cx, cy) } else { (x0, y0) };
        }
    }
}

#[test]
fn each_mutation_kind_does_what_it_says() {
    let a = alphabet(0);
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    // A parent without lone children, the root included (a mutation result with a
    // two-child root), so that nothing but the mutation itself changes the size: a
    // lone child is dissolved by any mutation, and wrapping a one-child root in a
    // control node of its child's kind merges the three.
    let mut parent = random_tree(10, &a, &mut rng).unwrap();
    let mut trimmed = 0;
    while trimmed < 5 {
        let child = mutate(&parent, &a, &MutationRates::default(), &mut rng).unwrap();
        let root_children = child.tokens().iter().scan(0i32, |depth, t| {
            let at_top = *depth == 1 && *t != Token::Close;
            *depth += i32::from(t.is_control()) - i32::from(*t == Token::Close);
            Some(at_top)
        });
        if child.length() >= 6 && root_children.filter(|&c| c).count() >= 2 {
            parent = child;
            trimmed += 1;
        }
    }
    let only = |add, delete, change| MutationRates { add, delete, change };
    let mut sizes = |rates: MutationRates| -> Vec<isize> {
        (0..300)
            .map(|_| {
                let child = mutate(&parent, &a, &rates, &mut rng).unwrap_or_else(|| panic!("{parent:?} {rates:?}"));
                child.length() as isize - parent.length() as isize
            })
            .collect()
    };
    assert!(sizes(only(0.0, 1.0, 0.0)).iter().all(|&d| d < 0));
    // Adding a leaf gives +1, a control node with its two children +3 (or +1 wrapping
    // the root).
    let added = sizes(only(1.0, 0.0, 0.0));
    assert!(added.iter().all(|&d| d == 1 || d == 3), "{added:?}");
    assert!(added.contains(&1) && added.contains(&3));
    // Changing keeps the size (same kind), adds two (leaf to control) or drops a
    // subtree (control to leaf).
    let changed = sizes(only(0.0, 0.0, 1.0));
    assert!(changed.iter().all(|&d| d <= 2), "{changed:?}");
    assert!(changed.contains(&0) && changed.contains(&2) && changed.iter().any(|&d| d < 0));
    // With Table I's rates all three happen.
    let mixed = sizes(MutationRates::default());
    assert!(mixed.iter().any(|&d| d < 0) && mixed.contains(&0) && mixed.iter().any(|&d| d > 0));
}

#[test]
fn a_single_leaf_mutates_into_a_tree() {
    let spec = Task::Tower.spec();
    let a = Alphabet::from_catalog(&spec).unwrap();
    let leaf = Genome::parse("pick 0!", &spec, &a).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let mut grown = 0;
    for _ in 0..200 {
        if let Some(child) = mutate(&leaf, &a, &MutationRates::default(), &mut rng) {
            assert_eq!(child.check(&a), Ok(()));
            grown += usize::from(child.length() > 1);
        }
    }
    assert!(grown > 50, "{grown}");
    // A single leaf cannot take part in crossover: every insertion makes two roots.
    let other = Genome::parse("s( picked 0? pick 0! )", &spec, &a).unwrap();
    assert_eq!(crossover(&leaf, &other, &a, &mut rng), None);
}

fn any_token() -> impl Strategy<Value = Token> {
    prop_oneof![
        Just(Token::Sequence),
        Just(Token::Fallback),
        Just(Token::Close),
        (0u16..30).prop_map(Token::Condition),
        (0u16..30).prop_map(Token::Action),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Any token sequence, however broken: no operator panics, and whatever they
    /// return is valid.
    #[test]
    fn operators_survive_any_tokens(
        x in proptest::collection::vec(any_token(), 0..30),
        y in proptest::collection::vec(any_token(), 0..30),
        seed: u64,
    ) {
        let a = alphabet(0);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let (gx, gy) = (Genome::from(x), Genome::from(y));
        if let Some(m) = mutate(&gx, &a, &MutationRates::default(), &mut rng) {
            prop_assert_eq!(m.check(&a), Ok(()));
        }
        if let Some((cx, cy)) = crossover(&gx, &gy, &a, &mut rng) {
            prop_assert!(cx.is_valid(&a) && cy.is_valid(&a));
        }
        if let Ok(nodes) = gx.to_nodes() {
            // A well-formed tree converts back, whatever GP thinks of its leaves.
            prop_assert_eq!(nodes.len(), gx.length());
        }
        if gx.is_valid(&a) {
            prop_assert_eq!(Genome::from_nodes(&gx.to_nodes().unwrap(), &a).unwrap(), gx);
        }
    }
}
