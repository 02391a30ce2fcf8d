//! Tokens of the expression language.

use super::dialect::{Dialect, skip_hash_trivia};
use crate::diag::Span;

#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Tok<'a> {
    Num(f64),
    Ident(&'a str),
    LParen,
    RParen,
    Comma,
    Question,
    Colon,
    Plus,
    Minus,
    Star,
    Slash,
    Percent,
    Caret,
    Lt,
    Le,
    Gt,
    Ge,
    EqEq,
    Ne,
    AndAnd,
    OrOr,
    Bang,
    /// `//` in a [`Dialect::hash_comments`] dialect.
    SlashSlash,
    /// A single `=` in a [`Dialect::word_logic`] dialect (a mistaken `==`).
    Assign,
    /// Anything the expression language does not use; ends an expression.
    Other,
    Eof,
}

/// Skips whitespace, `//` line comments and `/* */` block comments from
/// byte `pos`. Returns the position of the next token and, for a block
/// comment that never ends, where it started. Shared by every front end that
/// embeds expressions, so comments mean the same everywhere.
pub fn skip_trivia(src: &str, mut pos: usize) -> (usize, Option<usize>) {
    let b = src.as_bytes();
    loop {
        while pos < b.len() && b[pos].is_ascii_whitespace() {
            pos += 1;
        }
        if b[pos..].starts_with(b"//") {
            while pos < b.len() && b[pos] != b'\n' {
                pos += 1;
            }
        } else if b[pos..].starts_with(b"/*") {
            match src[pos + 2..].find("*/") {
                Some(i) => pos += i + 4,
                None => return (b.len(), Some(pos)),
            }
        } else {
            return (pos, None);
        }
    }
}

pub(crate) struct Lexer<'a> {
    src: &'a str,
    pub(crate) pos: usize,
    dialect: Dialect<'a>,
}

impl<'a> Lexer<'a> {
    /// A lexer over `src` from byte `start`.
    pub(crate) fn new(src: &'a str, start: usize, dialect: Dialect<'a>) -> Self {
        Lexer { src, pos: start, dialect }
    }

    /// Where the next token after byte `pos` starts.
    pub(crate) fn trivia_end(&self, pos: usize) -> usize {
        if self.dialect.hash_comments { skip_hash_trivia(self.src, pos) } else { skip_trivia(self.src, pos).0 }
    }

    fn skip_trivia(&mut self) {
        self.pos = self.trivia_end(self.pos);
    }

    /// The next token and its span; does not consume `Other`/`Eof` past themselves.
    pub(crate) fn next(&mut self) -> (Tok<'a>, Span) {
        self.skip_trivia();
        let b = self.src.as_bytes();
        let start = self.pos;
        if start >= b.len() {
            return (Tok::Eof, Span::new(start, start));
        }
        let c = b[start];
        let two = |s: &[u8]| b[start..].starts_with(s);
        let (tok, len) = if c.is_ascii_digit() || (c == b'.' && b.get(start + 1).is_some_and(u8::is_ascii_digit)) {
            let sep = self.dialect.digit_separators;
            let mut end = start;
            while end < b.len() && (b[end].is_ascii_digit() || b[end] == b'.' || (sep && b[end] == b'_')) {
                end += 1;
            }
            if end < b.len() && (b[end] == b'e' || b[end] == b'E') {
                let mut e = end + 1;
                if e < b.len() && (b[e] == b'+' || b[e] == b'-') {
                    e += 1;
                }
                if e < b.len() && b[e].is_ascii_digit() {
                    while e < b.len() && b[e].is_ascii_digit() {
                        e += 1;
                    }
                    end = e;
                }
            }
            let text = &self.src[start..end];
            let parsed = if sep { text.replace('_', "").parse::<f64>() } else { text.parse::<f64>() };
            match parsed {
                Ok(v) => (Tok::Num(v), end - start),
                Err(_) => (Tok::Other, end - start),
            }
        } else if c.is_ascii_alphabetic() || c == b'_' {
            let mut end = start;
            loop {
                while end < b.len() && (b[end].is_ascii_alphanumeric() || b[end] == b'_') {
                    end += 1;
                }
                // Dotted names: `size.x`, `scope.sx`.
                if self.dialect.dotted_names
                    && end + 1 < b.len()
                    && b[end] == b'.'
                    && (b[end + 1].is_ascii_alphabetic() || b[end + 1] == b'_')
                {
                    end += 1;
                } else {
                    break;
                }
            }
            (Tok::Ident(&self.src[start..end]), end - start)
        } else if self.dialect.hash_comments && two(b"//") {
            (Tok::SlashSlash, 2)
        } else if two(b"&&") {
            (Tok::AndAnd, 2)
        } else if two(b"||") {
            (Tok::OrOr, 2)
        } else if two(b"<=") {
            (Tok::Le, 2)
        } else if two(b">=") {
            (Tok::Ge, 2)
        } else if two(b"==") {
            (Tok::EqEq, 2)
        } else if two(b"!=") {
            (Tok::Ne, 2)
        } else if two(b"**") {
            (Tok::Caret, 2)
        } else {
            let t = match c {
                b'(' => Tok::LParen,
                b')' => Tok::RParen,
                b',' => Tok::Comma,
                b'?' => Tok::Question,
                b':' => Tok::Colon,
                b'+' => Tok::Plus,
                b'-' => Tok::Minus,
                b'*' => Tok::Star,
                b'/' => Tok::Slash,
                b'%' => Tok::Percent,
                b'^' => Tok::Caret,
                b'<' => Tok::Lt,
                b'>' => Tok::Gt,
                b'!' => Tok::Bang,
                b'=' if self.dialect.word_logic => Tok::Assign,
                _ => Tok::Other,
            };
            let len = self.src[start..].chars().next().map_or(1, char::len_utf8);
            (t, len)
        };
        self.pos = start + len;
        (tok, Span::new(start, start + len))
    }
}
