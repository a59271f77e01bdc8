//! PDDL's surface syntax: symbols and parenthesised lists, with `;` comments. Read
//! without recursion; nesting is bounded so that hostile input cannot exhaust the
//! stack of the recursive interpretation that follows.

use super::{ErrorKind, Pos};

/// Deepest nesting accepted. Real domains stay under 10.
pub const MAX_DEPTH: usize = 64;

/// A symbol or a list, with where it starts.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Sexp {
    /// A symbol (name, variable, keyword, ...).
    Symbol(String, Pos),
    /// A parenthesised list.
    List(Vec<Sexp>, Pos),
}

impl Sexp {
    /// Where it starts.
    pub fn pos(&self) -> Pos {
        match self {
            Self::Symbol(_, p) | Self::List(_, p) => *p,
        }
    }

    /// The symbol's text, lower-cased by the reader.
    pub fn symbol(&self) -> Option<&str> {
        match self {
            Self::Symbol(s, _) => Some(s),
            Self::List(..) => None,
        }
    }

    /// The list's items.
    pub fn list(&self) -> Option<&[Sexp]> {
        match self {
            Self::List(items, _) => Some(items),
            Self::Symbol(..) => None,
        }
    }

    /// How a message names it: the symbol in backquotes, or "a list".
    pub fn describe(&self) -> String {
        match self {
            Self::Symbol(s, _) => format!("`{s}`"),
            Self::List(items, _) => match items.first().and_then(Sexp::symbol) {
                Some(head) => format!("a list `({head} ...)`"),
                None => "a list".into(),
            },
        }
    }
}

/// Reads exactly one top-level list from `text`.
pub fn read(text: &str) -> Result<Sexp, (Pos, ErrorKind)> {
    let mut stack: Vec<(Vec<Sexp>, Pos)> = Vec::new();
    let mut done: Option<Sexp> = None;
    let mut line = 1usize;
    let mut column = 1usize;
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        let here = Pos { line, column };
        let mut advance = |c: char| {
            if c == '\n' {
                line += 1;
                column = 1;
            } else {
                column += 1;
            }
        };
        advance(c);
        match c {
            ';' => {
                while let Some(&n) = chars.peek() {
                    if n == '\n' {
                        break;
                    }
                    advance(n);
                    chars.next();
                }
            }
            c if c.is_whitespace() => {}
            '(' => {
                if done.is_some() {
                    return Err((here, ErrorKind::Trailing));
                }
                if stack.len() >= MAX_DEPTH {
                    return Err((here, ErrorKind::TooDeep { limit: MAX_DEPTH }));
                }
                stack.push((Vec::new(), here));
            }
            ')' => {
                let Some((items, at)) = stack.pop() else {
                    return Err((here, ErrorKind::UnexpectedClose));
                };
                let list = Sexp::List(items, at);
                match stack.last_mut() {
                    Some((parent, _)) => parent.push(list),
                    None => done = Some(list),
                }
            }
            c => {
                let mut s = String::new();
                s.push(c.to_ascii_lowercase());
                while let Some(&n) = chars.peek() {
                    if n.is_whitespace() || n == '(' || n == ')' || n == ';' {
                        break;
                    }
                    advance(n);
                    s.push(n.to_ascii_lowercase());
                    chars.next();
                }
                if c.is_control() {
                    return Err((here, ErrorKind::BadCharacter(c)));
                }
                match stack.last_mut() {
                    Some((parent, _)) => parent.push(Sexp::Symbol(s, here)),
                    None => {
                        return Err((
                            here,
                            ErrorKind::Expected { expected: "`(define ...)`".into(), found: format!("`{s}`") },
                        ));
                    }
                }
            }
        }
    }
    if let Some((_, at)) = stack.first() {
        // Report the innermost unclosed list: that is where the parenthesis is missing.
        let at = stack.last().map_or(*at, |l| l.1);
        return Err((at, ErrorKind::Unclosed));
    }
    done.ok_or((
        Pos { line, column },
        ErrorKind::Expected { expected: "`(define ...)`".into(), found: "end of file".into() },
    ))
}
