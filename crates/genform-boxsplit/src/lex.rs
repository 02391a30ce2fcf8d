//! Tokens of the `.bsg` language, read on demand so the parser can switch
//! to raw block-id scanning (`minecraft:oak_stairs[facing=east]`) where a
//! block is expected.

use genform_core::diag::Span;

/// A token kind. Identifier and number text is read back from the span.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Tok {
    Ident,
    Num(f64),
    /// A `"…"` string (text between the quotes read back from the span).
    Str,
    /// A `"` that is never closed on its line.
    BadStr,
    LBrace,
    RBrace,
    LBrack,
    RBrack,
    LParen,
    RParen,
    Comma,
    Semi,
    Assign,
    Minus,
    /// Any other operator of formulas (`//`, `<=`, `&&`, `*`, …): formulas
    /// themselves are read by the core expression parser.
    Operator,
    /// A character the language does not use.
    Other,
    Eof,
}

/// A token and where it is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Token {
    pub tok: Tok,
    pub span: Span,
}

/// Skips whitespace and `#` comments from `pos` (the trivia of the
/// `.bsg` dialect of formulas too).
pub(crate) use genform_core::expr::skip_hash_trivia as skip_trivia;

/// The token starting at the first non-trivia byte from `pos`.
pub(crate) fn token_at(src: &str, pos: usize) -> Token {
    let start = skip_trivia(src, pos);
    let b = src.as_bytes();
    if start >= b.len() {
        return Token { tok: Tok::Eof, span: Span::new(b.len(), b.len()) };
    }
    let c = b[start];
    let at = |s: &[u8]| b[start..].starts_with(s);
    let (tok, len) = if c.is_ascii_digit() || (c == b'.' && b.get(start + 1).is_some_and(u8::is_ascii_digit)) {
        let mut end = start;
        while end < b.len() && (b[end].is_ascii_digit() || b[end] == b'.' || b[end] == b'_') {
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
        let text: String = src[start..end].chars().filter(|&c| c != '_').collect();
        match text.parse::<f64>() {
            Ok(v) => (Tok::Num(v), end - start),
            Err(_) => (Tok::Other, end - start),
        }
    } else if c.is_ascii_alphabetic() || c == b'_' {
        let mut end = start;
        while end < b.len() && (b[end].is_ascii_alphanumeric() || b[end] == b'_') {
            end += 1;
        }
        (Tok::Ident, end - start)
    } else if c == b'"' {
        let mut end = start + 1;
        while end < b.len() && b[end] != b'"' && b[end] != b'\n' {
            end += if b[end] == b'\\' && end + 1 < b.len() && b[end + 1] != b'\n' { 2 } else { 1 };
        }
        if end < b.len() && b[end] == b'"' { (Tok::Str, end + 1 - start) } else { (Tok::BadStr, end - start) }
    } else if [&b"//"[..], b"==", b"!=", b"<=", b">=", b"&&", b"||", b"**"].iter().any(|op| at(op)) {
        (Tok::Operator, 2)
    } else {
        let t = match c {
            b'{' => Tok::LBrace,
            b'}' => Tok::RBrace,
            b'[' => Tok::LBrack,
            b']' => Tok::RBrack,
            b'(' => Tok::LParen,
            b')' => Tok::RParen,
            b',' => Tok::Comma,
            b';' => Tok::Semi,
            b'=' => Tok::Assign,
            b'-' => Tok::Minus,
            b'<' | b'>' | b'+' | b'*' | b'/' | b'%' | b'^' | b'!' => Tok::Operator,
            _ => Tok::Other,
        };
        (t, src[start..].chars().next().map_or(1, char::len_utf8))
    };
    Token { tok, span: Span::new(start, start + len) }
}

/// Characters of a block id or group name (`minecraft:oak_log`, `SOLID`).
fn block_char(c: u8) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, b'_' | b'-' | b'.' | b'/' | b':')
}

/// The raw text of a block reference starting at the first non-trivia byte
/// from `pos`: id characters, then a `[…]` property list when one follows
/// directly. Empty span when no id character is there.
pub(crate) fn block_at(src: &str, pos: usize) -> Span {
    let start = skip_trivia(src, pos);
    let b = src.as_bytes();
    let mut end = start;
    while end < b.len() && block_char(b[end]) {
        end += 1;
    }
    if end > start && end < b.len() && b[end] == b'[' {
        match src[end..].find([']', '\n', ')', '{', '}', ';']) {
            Some(k) if b[end + k] == b']' => end += k + 1,
            // Unclosed: stop where the reference clearly ends, so the
            // message points at it.
            Some(k) => end += k,
            None => end = b.len(),
        }
    }
    Span::new(start, end)
}

/// Text of a string token without its quotes, escapes resolved.
pub(crate) fn string_value(src: &str, span: Span) -> String {
    let inner = &src[span.start as usize + 1..span.end as usize - 1];
    let mut out = String::new();
    let mut chars = inner.chars();
    while let Some(c) = chars.next() {
        if c == '\\' {
            match chars.next() {
                Some('n') => out.push('\n'),
                Some('t') => out.push('\t'),
                Some(o) => out.push(o),
                None => {}
            }
        } else {
            out.push(c);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn toks(src: &str) -> Vec<Tok> {
        let mut pos = 0;
        let mut out = Vec::new();
        loop {
            let t = token_at(src, pos);
            out.push(t.tok);
            if t.tok == Tok::Eof {
                return out;
            }
            pos = t.span.end as usize;
        }
    }

    #[test]
    fn integer_division_is_an_operator_and_hash_a_comment() {
        assert_eq!(toks("X // 2 # half\n"), vec![Tok::Ident, Tok::Operator, Tok::Num(2.0), Tok::Eof]);
        let src = "a<=b!=c-d";
        assert_eq!(
            toks(src),
            [Tok::Ident, Tok::Operator, Tok::Ident, Tok::Operator, Tok::Ident, Tok::Minus, Tok::Ident, Tok::Eof]
        );
        assert_eq!(token_at(src, 1).span, Span::new(1, 3), "two-character operators are one token");
        assert_eq!(toks("\"ab\\\"c\" \"open"), vec![Tok::Str, Tok::BadStr, Tok::Eof]);
        assert_eq!(toks("1_000 2.5e1"), vec![Tok::Num(1000.0), Tok::Num(25.0), Tok::Eof]);
    }

    #[test]
    fn block_references_take_namespace_and_properties() {
        let src = "  minecraft:oak_stairs[facing=east, half=top], stone";
        let s = block_at(src, 0);
        assert_eq!(&src[s.start as usize..s.end as usize], "minecraft:oak_stairs[facing=east, half=top]");
        let s = block_at(src, s.end as usize + 1);
        assert_eq!(&src[s.start as usize..s.end as usize], "stone");
        let s = block_at("oak_log [axis=y]", 0);
        assert_eq!(s, Span::new(0, 7), "properties must follow the id directly");
        assert_eq!(string_value("\"a\\\"b\"", Span::new(0, 6)), "a\"b");
    }
}
