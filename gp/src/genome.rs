//! The token view of a tree (Styrud et al.): a genome is the pre-order list of tokens `s(`,
//! `f(`, leaves, and the closing `)` of every control node.
//!
//! GP's operators work on tokens because the reference's do: a mutation position is
//! drawn among all tokens, closing ones included. A genome converts exactly to and from
//! the flat pre-order [`Node`] array of bt-core, which is what fitness functions, the
//! executor and the image format see.

use std::hash::{Hash, Hasher};
use std::sync::Arc;

use bt_core::{BehaviorId, Catalog, Leaf, Node, NodeKind};

use crate::alphabet::Alphabet;

/// One token of a genome.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Token {
    /// `s(`: opens a reactive Sequence.
    Sequence,
    /// `f(`: opens a reactive Fallback.
    Fallback,
    /// `)`: closes the innermost open control node.
    Close,
    /// A condition leaf, by behavior id.
    Condition(BehaviorId),
    /// An action leaf, by behavior id.
    Action(BehaviorId),
}

impl Token {
    /// `s(` or `f(`.
    #[inline(always)]
    #[must_use]
    pub const fn is_control(self) -> bool {
        matches!(self, Self::Sequence | Self::Fallback)
    }

    /// A condition or an action.
    #[inline(always)]
    #[must_use]
    pub const fn is_leaf(self) -> bool {
        matches!(self, Self::Condition(_) | Self::Action(_))
    }

    /// One 32-bit word per token, for hashing.
    #[inline(always)]
    const fn code(self) -> u32 {
        match self {
            Self::Sequence => 0,
            Self::Fallback => 1,
            Self::Close => 2,
            Self::Condition(id) => 0x1_0000 | id as u32,
            Self::Action(id) => 0x2_0000 | id as u32,
        }
    }
}

impl Hash for Token {
    #[inline]
    fn hash<H: Hasher>(&self, state: &mut H) {
        state.write_u32(self.code());
    }
}

/// Which validity rule of Styrud et al. a genome breaks (the first one found).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum Invalid {
    /// No tokens.
    #[error("empty")]
    Empty,
    /// More than one token but the first is not a control node (a single leaf is a
    /// tree only on its own).
    #[error("starts with a leaf but has more tokens")]
    LeafRoot,
    /// A control node closed with no children.
    #[error("token {at}: control node without children")]
    EmptyControl {
        /// Token index of the control node.
        at: usize,
    },
    /// Two identical conditions next to each other.
    #[error("token {at}: the same condition twice in a row")]
    RepeatedCondition {
        /// Token index of the second one.
        at: usize,
    },
    /// A leaf the alphabet does not have (or of the other kind).
    #[error("token {at}: unknown behavior")]
    Unknown {
        /// Token index.
        at: usize,
    },
    /// A `)` with nothing open, the root closed before the last token, or control
    /// nodes left open at the end.
    #[error("token {at}: unbalanced")]
    Unbalanced {
        /// Token index where it shows.
        at: usize,
    },
    /// `f(` directly under `f(`, or `s(` directly under `s(`.
    #[error("token {at}: control node directly under one of the same kind")]
    SameKindNested {
        /// Token index of the inner control node.
        at: usize,
    },
}

/// `n` and the noun, singular for 1: `1 node`, `2 nodes`.
pub(crate) fn count<N: std::fmt::Display + PartialEq + From<u8>>(n: N, noun: &str) -> String {
    if n == N::from(1) { format!("1 {noun}") } else { format!("{n} {noun}s") }
}

/// `a` or `an` before a word: `an Inverter`, `an action`, `a condition`.
fn article(word: &str) -> String {
    let vowel = word.chars().next().is_some_and(|c| "aeiouAEIOU".contains(c));
    format!("{} {word}", if vowel { "an" } else { "a" })
}

/// Why a genome and a node array could not be converted.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum GenomeError {
    /// The tokens are not one balanced tree.
    #[error("the tokens are not one balanced tree ({0})")]
    NotATree(Invalid),
    /// A node kind GP does not use (only reactive Sequence, Fallback and leaves).
    #[error("node {node} is {}; GP trees have only reactive Sequence, Fallback and leaves", article(kind))]
    Kind {
        /// Node index.
        node: usize,
        /// Its kind's name.
        kind: &'static str,
    },
    /// A leaf with arguments.
    #[error("node {node}: leaf with arguments; GP leaves take none")]
    Arguments {
        /// Node index.
        node: usize,
    },
    /// A leaf the alphabet does not have, or declared with the other kind.
    #[error("node {node}: behavior {behavior} is not {} of this task", article(kind))]
    UnknownLeaf {
        /// Node index.
        node: usize,
        /// Its behavior id.
        behavior: BehaviorId,
        /// `condition` or `action`, as the node says.
        kind: &'static str,
    },
    /// Subtree sizes that do not nest.
    #[error("node {node}: subtree size {size} does not fit inside its parent")]
    Malformed {
        /// Node index.
        node: usize,
        /// Its size.
        size: u16,
    },
    /// More nodes than a bt-core tree can hold.
    #[error("{0} nodes; a tree holds at most 65535")]
    TooLong(usize),
    /// The token notation could not be read or written.
    #[error(transparent)]
    Tokens(#[from] bt_formats::tokens::TokenError),
}

/// A tree as GP sees it: pre-order tokens with closing tokens.
///
/// Equality and hashing are by tokens, which is the same as by tree: the conversion to
/// [`Node`]s is one to one. The hash is computed once, when the genome is made, so
/// cache lookups and duplicate checks cost a comparison of two words in the common
/// case. Validity is a separate question ([`Genome::check`]): the operators build
/// candidates that may break the rules, then keep only valid ones.
#[derive(Clone, Default)]
pub struct Genome {
    // Shared: the population, the offspring lists and the cache hold the same tree
    // without copying it.
    tokens: Arc<[Token]>,
    hash: u64,
}

impl PartialEq for Genome {
    #[inline]
    fn eq(&self, other: &Self) -> bool {
        self.hash == other.hash && (Arc::ptr_eq(&self.tokens, &other.tokens) || self.tokens == other.tokens)
    }
}

impl Eq for Genome {}

impl Hash for Genome {
    #[inline]
    fn hash<H: Hasher>(&self, state: &mut H) {
        state.write_u64(self.hash);
    }
}

impl std::fmt::Debug for Genome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("Genome").field(&self.tokens).finish()
    }
}

impl From<Vec<Token>> for Genome {
    fn from(tokens: Vec<Token>) -> Self {
        Self::from_slice(&tokens)
    }
}

impl From<&[Token]> for Genome {
    fn from(tokens: &[Token]) -> Self {
        Self::from_slice(tokens)
    }
}

/// The 64-bit hash of a token sequence: a multiply-rotate pass over the tokens (as
/// FxHash does), then a MurmurHash3 finalizer so that every bit depends on every
/// token. Not stable across versions; only used in memory.
#[inline]
#[must_use]
pub fn hash_tokens(tokens: &[Token]) -> u64 {
    const K: u64 = 0xf135_7aea_2e62_a9c5;
    let mut h = tokens.len() as u64;
    for t in tokens {
        h = (h.rotate_left(26) ^ u64::from(t.code())).wrapping_mul(K);
    }
    h ^= h >> 33;
    h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
    h ^= h >> 33;
    h = h.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    h ^ (h >> 33)
}

impl Genome {
    fn from_slice(tokens: &[Token]) -> Self {
        Self::with_hash(tokens, hash_tokens(tokens))
    }

    /// A genome whose hash is already known (`hash_tokens(tokens)`).
    pub(crate) fn with_hash(tokens: &[Token], hash: u64) -> Self {
        debug_assert_eq!(hash, hash_tokens(tokens));
        Self { tokens: Arc::from(tokens), hash }
    }

    /// The tokens, in order.
    #[inline(always)]
    #[must_use]
    pub fn tokens(&self) -> &[Token] {
        &self.tokens
    }

    /// The hash computed when the genome was made ([`hash_tokens`]).
    #[inline(always)]
    pub(crate) fn hash_value(&self) -> u64 {
        self.hash
    }

    /// The tree's length as Styrud et al. counts it: every node except the closing tokens
    /// (equal to the number of bt-core nodes).
    #[must_use]
    pub fn length(&self) -> usize {
        length(&self.tokens)
    }

    /// Whether the genome is a valid tree of `alphabet` ([`check`]).
    #[must_use]
    pub fn is_valid(&self, alphabet: &Alphabet) -> bool {
        check(&self.tokens, alphabet).is_ok()
    }

    /// The first validity rule the genome breaks, if any ([`check`]).
    ///
    /// # Errors
    /// The [`Invalid`] rule.
    pub fn check(&self, alphabet: &Alphabet) -> Result<(), Invalid> {
        check(&self.tokens, alphabet)
    }

    /// The genome of a bt-core node array.
    ///
    /// # Errors
    /// [`GenomeError`] for node kinds other than reactive Sequence, Fallback and
    /// argument-less leaves of `alphabet`, or sizes that do not nest.
    pub fn from_nodes(nodes: &[Node], alphabet: &Alphabet) -> Result<Self, GenomeError> {
        match nodes.first() {
            None => return Err(GenomeError::NotATree(Invalid::Empty)),
            Some(root) if usize::from(root.size()) != nodes.len() => {
                return Err(GenomeError::Malformed { node: 0, size: root.size() });
            }
            Some(_) => {}
        }
        let mut tokens = Vec::with_capacity(nodes.len() * 3 / 2 + 1);
        let mut ends: Vec<usize> = Vec::new();
        for (i, node) in nodes.iter().enumerate() {
            while ends.last().is_some_and(|&e| e <= i) {
                ends.pop();
                tokens.push(Token::Close);
            }
            let end = i + usize::from(node.size());
            if node.size() == 0 || ends.last().is_some_and(|&e| end > e) || end > nodes.len() {
                return Err(GenomeError::Malformed { node: i, size: node.size() });
            }
            let leaf = |leaf: &Leaf, kind: &'static str, token: Token| {
                if leaf.argc() != 0 {
                    Err(GenomeError::Arguments { node: i })
                } else if !alphabet.knows(token) {
                    Err(GenomeError::UnknownLeaf { node: i, behavior: leaf.behavior(), kind })
                } else {
                    Ok(token)
                }
            };
            let token = match node.kind() {
                NodeKind::Sequence => Token::Sequence,
                NodeKind::Fallback => Token::Fallback,
                NodeKind::Condition(l) => leaf(l, "condition", Token::Condition(l.behavior()))?,
                NodeKind::Action(l) => leaf(l, "action", Token::Action(l.behavior()))?,
                other => return Err(GenomeError::Kind { node: i, kind: other.name() }),
            };
            if token.is_control() {
                if node.size() == 1 {
                    return Err(GenomeError::NotATree(Invalid::EmptyControl { at: tokens.len() }));
                }
                ends.push(end);
            } else if node.size() != 1 {
                return Err(GenomeError::Malformed { node: i, size: node.size() });
            }
            tokens.push(token);
        }
        tokens.extend(ends.iter().map(|_| Token::Close));
        Ok(Self::from(tokens))
    }

    /// The bt-core node array of this genome.
    ///
    /// # Errors
    /// [`GenomeError::NotATree`] unless the tokens are one balanced tree whose control
    /// nodes all have children; [`GenomeError::TooLong`] past 65535 nodes.
    pub fn to_nodes(&self) -> Result<Vec<Node>, GenomeError> {
        let mut nodes = Vec::with_capacity(self.tokens.len());
        self.write_nodes(&mut nodes)?;
        Ok(nodes)
    }

    /// [`Genome::to_nodes`] into a buffer the caller reuses (cleared first).
    ///
    /// # Errors
    /// As [`Genome::to_nodes`].
    pub fn write_nodes(&self, nodes: &mut Vec<Node>) -> Result<(), GenomeError> {
        write_nodes(&self.tokens, nodes)
    }

    /// The genome in the token notation of Styrud et al. (`s( f( 0 on 1? ... ) )`), leaves
    /// named by `catalog` (see [`bt_formats::tokens`]).
    ///
    /// # Errors
    /// As [`Genome::to_nodes`].
    pub fn to_text<C: Catalog + ?Sized>(&self, catalog: &C) -> Result<String, GenomeError> {
        Ok(bt_formats::tokens::to_string(&self.to_nodes()?, catalog)?)
    }

    /// Reads the token notation, names resolved by `catalog`, leaves checked against
    /// `alphabet` (normally `Alphabet::from_catalog(catalog)`).
    ///
    /// # Errors
    /// A [`GenomeError`] naming the first fault.
    pub fn parse<C: Catalog + ?Sized>(text: &str, catalog: &C, alphabet: &Alphabet) -> Result<Self, GenomeError> {
        Self::from_nodes(&bt_formats::tokens::parse(text, catalog)?, alphabet)
    }
}

/// The bt-core nodes of a token list, into a buffer the caller reuses (cleared first):
/// [`Genome::write_nodes`] for tokens not (yet) made into a genome.
///
/// # Errors
/// As [`Genome::to_nodes`].
pub fn write_nodes(tokens: &[Token], nodes: &mut Vec<Node>) -> Result<(), GenomeError> {
    nodes.clear();
    if tokens.len() > 2 * usize::from(u16::MAX) {
        return Err(GenomeError::TooLong(length(tokens)));
    }
    // The open control nodes form a stack threaded through the nodes themselves:
    // while a control node is open, its size field holds 1 + the index of the
    // control node that was innermost before it (0 for none). No allocation.
    let mut innermost: Option<usize> = None;
    for (at, &token) in tokens.iter().enumerate() {
        if !nodes.is_empty() && innermost.is_none() {
            return Err(GenomeError::NotATree(Invalid::Unbalanced { at }));
        }
        let kind = match token {
            Token::Sequence => NodeKind::Sequence,
            Token::Fallback => NodeKind::Fallback,
            Token::Condition(id) => NodeKind::Condition(Leaf::new(id)),
            Token::Action(id) => NodeKind::Action(Leaf::new(id)),
            Token::Close => {
                let start = innermost.ok_or(GenomeError::NotATree(Invalid::Unbalanced { at }))?;
                let size = nodes.len() - start;
                if size < 2 {
                    return Err(GenomeError::NotATree(Invalid::EmptyControl { at }));
                }
                let size = u16::try_from(size).map_err(|_| GenomeError::TooLong(nodes.len()))?;
                if let Some(node) = nodes.get_mut(start) {
                    innermost = usize::from(node.size()).checked_sub(1);
                    *node = Node::new(*node.kind(), size);
                }
                continue;
            }
        };
        let link = if token.is_control() {
            let link = innermost.map_or(0, |i| i + 1);
            innermost = Some(nodes.len());
            u16::try_from(link).map_err(|_| GenomeError::TooLong(nodes.len()))?
        } else {
            1
        };
        nodes.push(Node::new(kind, link));
    }
    if nodes.is_empty() {
        return Err(GenomeError::NotATree(Invalid::Empty));
    }
    if innermost.is_some() {
        return Err(GenomeError::NotATree(Invalid::Unbalanced { at: tokens.len() }));
    }
    Ok(())
}

/// Number of tokens that are not `)`.
#[must_use]
pub fn length(tokens: &[Token]) -> usize {
    tokens.iter().filter(|t| **t != Token::Close).count()
}

/// The validity rules of Styrud et al., in one pass: non-empty; a leaf as the first token
/// only if it is the only one; no control node directly followed by `)`; no two
/// identical conditions in a row; every leaf known to `alphabet`; balanced, with the
/// root's `)` last; no `f(` directly under `f(` and no `s(` directly under `s(`.
///
/// # Errors
/// The first rule broken.
pub fn check(tokens: &[Token], alphabet: &Alphabet) -> Result<(), Invalid> {
    let Some(&root) = tokens.first() else {
        return Err(Invalid::Empty);
    };
    if !root.is_control() {
        return match tokens.len() {
            _ if root == Token::Close => Err(Invalid::Unbalanced { at: 0 }),
            1 if alphabet.knows(root) => Ok(()),
            1 => Err(Invalid::Unknown { at: 0 }),
            _ => Err(Invalid::LeafRoot),
        };
    }
    // Control kinds must alternate along every path (no `s(` under `s(`, no `f(` under
    // `f(`), so the kind at each depth is fixed by the root's: `root` at even depths.
    let other = if root == Token::Sequence { Token::Fallback } else { Token::Sequence };
    let last = tokens.len() - 1;
    let mut depth = 0usize;
    for (at, &token) in tokens.iter().enumerate() {
        let next = tokens.get(at + 1).copied();
        match token {
            Token::Sequence | Token::Fallback => {
                if next == Some(Token::Close) {
                    return Err(Invalid::EmptyControl { at });
                }
                if token != if depth.is_multiple_of(2) { root } else { other } {
                    return Err(Invalid::SameKindNested { at });
                }
                depth += 1;
            }
            Token::Close => {
                if depth == 0 || (depth == 1 && at != last) {
                    return Err(Invalid::Unbalanced { at });
                }
                depth -= 1;
            }
            Token::Condition(_) | Token::Action(_) => {
                if !alphabet.knows(token) {
                    return Err(Invalid::Unknown { at });
                }
                if matches!(token, Token::Condition(_)) && next == Some(token) {
                    return Err(Invalid::RepeatedCondition { at: at + 1 });
                }
            }
        }
    }
    if depth != 0 {
        return Err(Invalid::Unbalanced { at: tokens.len() });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner::duplo::Task;

    fn tower() -> (planner::duplo::Spec, Alphabet) {
        let spec = Task::Tower.spec();
        let alphabet = Alphabet::from_catalog(&spec).unwrap();
        (spec, alphabet)
    }

    fn genome(text: &str) -> Genome {
        let (spec, alphabet) = tower();
        Genome::parse(text, &spec, &alphabet).unwrap()
    }

    #[test]
    fn tokens_round_trip_through_nodes_and_text() {
        let (spec, alphabet) = tower();
        let text = "s( f( 0 on 1? s( pick 0! place on 1! ) ) apply force 0! )";
        let g = genome(text);
        assert_eq!(g.tokens().len(), 10);
        assert_eq!(g.length(), 7);
        let nodes = g.to_nodes().unwrap();
        assert_eq!(nodes.iter().map(Node::size).collect::<Vec<_>>(), [7, 5, 1, 3, 1, 1, 1]);
        assert_eq!(Genome::from_nodes(&nodes, &alphabet).unwrap(), g);
        assert_eq!(g.to_text(&spec).unwrap(), text);
        let leaf = genome("pick 2!");
        assert_eq!(leaf.tokens(), [Token::Action(14)]);
        assert_eq!(leaf.to_nodes().unwrap().len(), 1);
    }

    #[test]
    fn each_validity_rule() {
        let (_, a) = tower();
        let c = Token::Condition(0);
        let d = Token::Condition(1);
        let x = Token::Action(12);
        let (s, f, cl) = (Token::Sequence, Token::Fallback, Token::Close);
        assert_eq!(check(&[s, c, x, cl], &a), Ok(()));
        assert_eq!(check(&[x], &a), Ok(()));
        assert_eq!(check(&[c], &a), Ok(()));
        assert_eq!(check(&[], &a), Err(Invalid::Empty));
        assert_eq!(check(&[cl], &a), Err(Invalid::Unbalanced { at: 0 }));
        assert_eq!(check(&[cl, x], &a), Err(Invalid::Unbalanced { at: 0 }));
        assert_eq!(check(&[x, s, c, cl], &a), Err(Invalid::LeafRoot));
        assert_eq!(check(&[s, f, cl, x, cl], &a), Err(Invalid::EmptyControl { at: 1 }));
        assert_eq!(check(&[s, c, c, x, cl], &a), Err(Invalid::RepeatedCondition { at: 2 }));
        // Identical conditions not in a row are fine; identical actions in a row too.
        assert_eq!(check(&[s, c, d, c, x, x, cl], &a), Ok(()));
        assert_eq!(check(&[s, f, c, cl, c, cl], &a), Ok(()));
        assert_eq!(check(&[s, Token::Action(0), cl], &a), Err(Invalid::Unknown { at: 1 }));
        assert_eq!(check(&[s, Token::Condition(40), cl], &a), Err(Invalid::Unknown { at: 1 }));
        assert_eq!(check(&[s, c, cl, cl], &a), Err(Invalid::Unbalanced { at: 2 }));
        assert_eq!(check(&[s, c, cl, s, x, cl], &a), Err(Invalid::Unbalanced { at: 2 }));
        assert_eq!(check(&[s, f, c, cl], &a), Err(Invalid::Unbalanced { at: 4 }));
        assert_eq!(check(&[s, s, c, cl, x, cl], &a), Err(Invalid::SameKindNested { at: 1 }));
        assert_eq!(check(&[f, s, f, c, cl, x, cl, cl], &a), Ok(()));
        assert_eq!(check(&[f, s, s, c, cl, x, cl, cl], &a), Err(Invalid::SameKindNested { at: 2 }));
        assert_eq!(check(&[f, s, x, cl, f, c, cl, cl], &a), Err(Invalid::SameKindNested { at: 4 }));
    }

    #[test]
    fn conversion_errors_name_the_node() {
        let (_, a) = tower();
        let inv = [Node::new(NodeKind::Inverter, 2), Node::new(NodeKind::Action(Leaf::new(12)), 1)];
        assert_eq!(Genome::from_nodes(&inv, &a), Err(GenomeError::Kind { node: 0, kind: "Inverter" }));
        let args = [Node::new(NodeKind::Action(Leaf::with_args(12, &[1]).unwrap()), 1)];
        assert_eq!(Genome::from_nodes(&args, &a), Err(GenomeError::Arguments { node: 0 }));
        let wrong = [Node::new(NodeKind::Action(Leaf::new(0)), 1)];
        assert!(matches!(Genome::from_nodes(&wrong, &a), Err(GenomeError::UnknownLeaf { node: 0, behavior: 0, .. })));
        let short = [Node::new(NodeKind::Sequence, 3), Node::new(NodeKind::Action(Leaf::new(12)), 1)];
        assert_eq!(Genome::from_nodes(&short, &a), Err(GenomeError::Malformed { node: 0, size: 3 }));
        let two = [Node::new(NodeKind::Action(Leaf::new(12)), 1), Node::new(NodeKind::Action(Leaf::new(12)), 1)];
        assert_eq!(Genome::from_nodes(&two, &a), Err(GenomeError::Malformed { node: 0, size: 1 }));
        assert!(Genome::from_nodes(&[], &a).is_err());
        let g = Genome::from(vec![Token::Sequence, Token::Close]);
        assert_eq!(g.to_nodes(), Err(GenomeError::NotATree(Invalid::EmptyControl { at: 1 })));
        let g = Genome::from(vec![Token::Action(12), Token::Action(12)]);
        assert_eq!(g.to_nodes(), Err(GenomeError::NotATree(Invalid::Unbalanced { at: 1 })));
    }
}
