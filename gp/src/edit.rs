//! Token-level edits shared by the operators: finding subtrees, parents and children,
//! balancing, and dissolving control nodes with fewer than two children.
//!
//! All of them tolerate any token sequence (they never panic); on the sequences the
//! operators build — balanced by construction — they do what their names say.

use crate::genome::Token;

/// End (exclusive) of the subtree starting at `at`: `at + 1` for a leaf, one past the
/// matching `)` for a control node, `at` for a `)`. Runs to the end if unbalanced.
pub(crate) fn subtree_end(tokens: &[Token], at: usize) -> usize {
    match tokens.get(at) {
        Some(t) if t.is_leaf() => at + 1,
        Some(t) if t.is_control() => {
            let mut level = 0usize;
            for (i, &t) in tokens.iter().enumerate().skip(at) {
                if t.is_control() {
                    level += 1;
                } else if t == Token::Close {
                    level -= 1;
                    if level == 0 {
                        return i + 1;
                    }
                }
            }
            tokens.len()
        }
        _ => at,
    }
}

/// Removes the node at `at` with its subtree (nothing for a `)`).
pub(crate) fn delete(tokens: &mut Vec<Token>, at: usize) {
    let end = subtree_end(tokens, at);
    if end > at {
        tokens.drain(at..end);
    }
}

/// Children of the control node at `at`: how many, and the index of its `)`.
fn children(tokens: &[Token], at: usize) -> Option<(usize, usize)> {
    let mut level = 0usize;
    let mut count = 0usize;
    for (i, &t) in tokens.iter().enumerate().skip(at + 1) {
        if t == Token::Close {
            if level == 0 {
                return Some((count, i));
            }
            level -= 1;
        } else {
            if level == 0 {
                count += 1;
            }
            if t.is_control() {
                level += 1;
            }
        }
    }
    None
}

/// The control node that is the parent of the node at `at`.
fn parent(tokens: &[Token], at: usize) -> Option<usize> {
    let mut siblings = 0usize;
    for p in (0..at.min(tokens.len())).rev() {
        let t = tokens[p];
        if t.is_control() {
            if siblings == 0 {
                return Some(p);
            }
            siblings -= 1;
        } else if t == Token::Close {
            siblings += 1;
        }
    }
    None
}

/// Balances the closing tokens, as the reference does: a tree whose first token is a
/// control node ends with `)`; missing `)` are appended; surplus ones are removed from
/// the right, never the last token.
pub(crate) fn balance(tokens: &mut Vec<Token>) {
    let Some(&first) = tokens.first() else { return };
    if first.is_control() && tokens.last() != Some(&Token::Close) {
        tokens.push(Token::Close);
    }
    let mut open = 0isize;
    for &t in tokens.iter() {
        if t.is_control() {
            open += 1;
        } else if t == Token::Close {
            open -= 1;
        }
    }
    for _ in 0..open.max(0) {
        tokens.push(Token::Close);
    }
    for _ in 0..(-open).max(0) {
        let last = tokens.len().saturating_sub(1);
        match (1..last).rev().find(|&j| tokens[j] == Token::Close) {
            Some(j) => {
                tokens.remove(j);
            }
            None => break,
        }
    }
}

/// Dissolves every control node below the root that has 0 or 1 child, deepest and
/// rightmost first: with no child it disappears; with one child the child takes its
/// place, and if that child is a control node of the same kind as the new parent, the
/// child's children move up into the parent too (so no `s(` lands under `s(`).
pub(crate) fn dissolve(tokens: &mut Vec<Token>) {
    let mut at = tokens.len().saturating_sub(1);
    while at >= 1 {
        if tokens.get(at).is_some_and(|t| t.is_control())
            && let Some((count, close)) = children(tokens, at)
            && count <= 1
        {
            let child = at + 1;
            let merge = count == 1
                && tokens[child].is_control()
                && parent(tokens, at).is_some_and(|p| tokens[p] == tokens[child]);
            tokens.remove(close);
            if merge {
                let child_end = subtree_end(tokens, child);
                tokens.remove(child_end - 1);
                tokens.remove(child);
            }
            tokens.remove(at);
        }
        at -= 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use Token::{Close as C, Fallback as F, Sequence as S};

    const A: Token = Token::Action(12);
    const B: Token = Token::Action(13);
    const X: Token = Token::Condition(0);

    #[test]
    fn subtrees() {
        let t = [S, F, X, A, C, B, C];
        assert_eq!(subtree_end(&t, 0), 7);
        assert_eq!(subtree_end(&t, 1), 5);
        assert_eq!(subtree_end(&t, 2), 3);
        assert_eq!(subtree_end(&t, 4), 4);
        assert_eq!(parent(&t, 5), Some(0));
        assert_eq!(parent(&t, 3), Some(1));
        assert_eq!(parent(&t, 0), None);
        assert_eq!(children(&t, 0), Some((2, 6)));
        let mut d = t.to_vec();
        delete(&mut d, 1);
        assert_eq!(d, [S, B, C]);
    }

    #[test]
    fn balance_like_the_reference() {
        let mut t = vec![S, A, C, B, C, X];
        balance(&mut t);
        assert_eq!(t, [S, A, B, X, C]);
        let mut t = vec![S, F, A];
        balance(&mut t);
        assert_eq!(t, [S, F, A, C, C]);
        let mut t = vec![A];
        balance(&mut t);
        assert_eq!(t, [A]);
    }

    #[test]
    fn dissolve_single_and_empty_children() {
        let mut t = vec![S, F, A, C, B, C];
        dissolve(&mut t);
        assert_eq!(t, [S, A, B, C]);
        let mut t = vec![S, F, C, B, C];
        dissolve(&mut t);
        assert_eq!(t, [S, B, C]);
        // f( s( a b ) ) under s(: the lone s( merges into the root s(.
        let mut t = vec![S, X, F, S, A, B, C, C, C];
        dissolve(&mut t);
        assert_eq!(t, [S, X, A, B, C]);
        // Nested single children collapse bottom-up; the root stays.
        let mut t = vec![S, F, S, A, C, C, C];
        dissolve(&mut t);
        assert_eq!(t, [S, A, C]);
    }
}
