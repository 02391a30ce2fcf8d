//! Tokens of the `.sg` language outside expressions.
//!
//! Expressions are not tokenized here: the parser hands the text at the
//! current position to [`genform_core::expr::parse_prefix`] (the project's
//! one expression parser) and resumes lexing where the expression ended. The
//! lexer is therefore restartable at any byte offset ([`Lexer::seek`]).

use genform_core::Span;

/// Kind of a token.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Tok {
    /// A name: letters, digits and `_`, not starting with a digit.
    Ident(String),
    /// A decimal number (only template ranges read numbers directly).
    Num(f64),
    /// A double-quoted string without escapes except `\"` and `\\`.
    Str(String),
    /// A string that reaches the end of the line or file.
    BadStr,
    LBrace,
    RBrace,
    LParen,
    RParen,
    LBracket,
    RBracket,
    Lt,
    Gt,
    Comma,
    Semi,
    Colon,
    Pipe,
    Eq,
    DotDot,
    Minus,
    /// Any other character.
    Other(char),
    Eof,
}

impl Tok {
    /// How the token reads in messages ("found …").
    pub(crate) fn describe(&self) -> String {
        match self {
            Tok::Ident(s) => format!("`{s}`"),
            Tok::Num(v) => format!("number `{v}`"),
            Tok::Str(s) => format!("string \"{s}\""),
            Tok::BadStr => "an unterminated string".into(),
            Tok::Other(c) => format!("`{c}`"),
            Tok::Eof => "the end of the file".into(),
            t => format!("`{}`", t.text()),
        }
    }

    /// The source text of a punctuation token.
    pub(crate) fn text(&self) -> &'static str {
        match self {
            Tok::LBrace => "{",
            Tok::RBrace => "}",
            Tok::LParen => "(",
            Tok::RParen => ")",
            Tok::LBracket => "[",
            Tok::RBracket => "]",
            Tok::Lt => "<",
            Tok::Gt => ">",
            Tok::Comma => ",",
            Tok::Semi => ";",
            Tok::Colon => ":",
            Tok::Pipe => "|",
            Tok::Eq => "=",
            Tok::DotDot => "..",
            Tok::Minus => "-",
            _ => "?",
        }
    }
}

/// A token and where it is.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Token {
    pub kind: Tok,
    pub span: Span,
}

/// On-demand lexer over the whole file.
pub(crate) struct Lexer<'a> {
    src: &'a str,
    pos: usize,
    /// Set when a block comment is not closed; reported once by the parser.
    pub unterminated_comment: Option<Span>,
}

impl<'a> Lexer<'a> {
    pub(crate) fn new(src: &'a str) -> Self {
        Lexer { src, pos: 0, unterminated_comment: None }
    }

    /// Continues lexing at byte `pos` (after an embedded expression).
    pub(crate) fn seek(&mut self, pos: usize) {
        self.pos = pos.min(self.src.len());
    }

    fn skip_trivia(&mut self) {
        let (pos, unterminated) = genform_core::expr::skip_trivia(self.src, self.pos);
        if let Some(start) = unterminated {
            self.unterminated_comment.get_or_insert(Span::new(start, start + 2));
        }
        self.pos = pos;
    }

    /// The next token.
    pub(crate) fn next_token(&mut self) -> Token {
        self.skip_trivia();
        let b = self.src.as_bytes();
        let start = self.pos;
        if start >= b.len() {
            return Token { kind: Tok::Eof, span: Span::new(start, start) };
        }
        let c = b[start];
        let (kind, len) = if c.is_ascii_alphabetic() || c == b'_' {
            let mut end = start;
            while end < b.len() && (b[end].is_ascii_alphanumeric() || b[end] == b'_') {
                end += 1;
            }
            (Tok::Ident(self.src[start..end].to_string()), end - start)
        } else if c.is_ascii_digit() {
            let mut end = start;
            while end < b.len() && b[end].is_ascii_digit() {
                end += 1;
            }
            // A fraction needs a digit after the dot, so `0..8` stays a range.
            if end + 1 < b.len() && b[end] == b'.' && b[end + 1].is_ascii_digit() {
                end += 1;
                while end < b.len() && b[end].is_ascii_digit() {
                    end += 1;
                }
            }
            (Tok::Num(self.src[start..end].parse().unwrap_or(f64::NAN)), end - start)
        } else if c == b'"' {
            let mut end = start + 1;
            let mut text = String::new();
            let mut closed = false;
            while end < b.len() && b[end] != b'\n' {
                if b[end] == b'"' {
                    closed = true;
                    end += 1;
                    break;
                }
                if b[end] == b'\\' && end + 1 < b.len() && (b[end + 1] == b'"' || b[end + 1] == b'\\') {
                    text.push(b[end + 1] as char);
                    end += 2;
                    continue;
                }
                let ch = self.src[end..].chars().next().unwrap_or('?');
                text.push(ch);
                end += ch.len_utf8();
            }
            (if closed { Tok::Str(text) } else { Tok::BadStr }, end - start)
        } else if b[start..].starts_with(b"..") {
            (Tok::DotDot, 2)
        } else {
            let ch = self.src[start..].chars().next().unwrap_or('?');
            let kind = match ch {
                '{' => Tok::LBrace,
                '}' => Tok::RBrace,
                '(' => Tok::LParen,
                ')' => Tok::RParen,
                '[' => Tok::LBracket,
                ']' => Tok::RBracket,
                '<' => Tok::Lt,
                '>' => Tok::Gt,
                ',' => Tok::Comma,
                ';' => Tok::Semi,
                ':' => Tok::Colon,
                '|' => Tok::Pipe,
                '=' => Tok::Eq,
                '-' => Tok::Minus,
                other => Tok::Other(other),
            };
            (kind, ch.len_utf8())
        };
        self.pos = start + len;
        Token { kind, span: Span::new(start, start + len) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(src: &str) -> Vec<Tok> {
        let mut l = Lexer::new(src);
        let mut out = Vec::new();
        loop {
            let t = l.next_token();
            if t.kind == Tok::Eof {
                return out;
            }
            out.push(t.kind);
        }
    }

    #[test]
    fn ranges_numbers_strings_and_comments() {
        assert_eq!(
            kinds("Body<i: 0..8> // c\n /* x */ \"a\\\"b\" 1.5"),
            vec![
                Tok::Ident("Body".into()),
                Tok::Lt,
                Tok::Ident("i".into()),
                Tok::Colon,
                Tok::Num(0.0),
                Tok::DotDot,
                Tok::Num(8.0),
                Tok::Gt,
                Tok::Str("a\"b".into()),
                Tok::Num(1.5),
            ]
        );
        assert_eq!(kinds("\"abc\nx"), vec![Tok::BadStr, Tok::Ident("x".into())]);
        let mut l = Lexer::new("a /* never closed");
        l.next_token();
        assert_eq!(l.next_token().kind, Tok::Eof);
        assert!(l.unterminated_comment.is_some());
        assert_eq!(kinds("é"), vec![Tok::Other('é')]);
    }
}
