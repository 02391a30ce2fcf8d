//! Reading `.bnf` text into raw rules (names not yet resolved), collecting
//! every syntax error instead of stopping at the first.
//!
//! The format is the one of the GE golden traces (`<name> ::= alt | alt`,
//! one rule per line, double-quoted terminals) plus these extensions:
//! `{ … }` repetition, `[ … ]` and `[? … ]` options, `#` and `//` comments
//! (outside quotes, to the end of the line), continuation lines that start
//! with `|`, and the escapes `\n`, `\t`, `\\`, `\"` inside quotes.

use genform_core::{Diagnostic, Span};

/// An item before name resolution.
#[derive(Clone, Debug)]
pub(crate) enum RawItem {
    Terminal(String),
    NonTerminal(String, Span),
    Repeat(Vec<RawItem>),
    Optional(Vec<RawItem>, bool),
}

/// An alternative before name resolution.
#[derive(Clone, Debug)]
pub(crate) struct RawAlt {
    pub items: Vec<RawItem>,
    pub span: Span,
}

/// A rule before name resolution.
#[derive(Clone, Debug)]
pub(crate) struct RawRule {
    pub name: String,
    pub span: Span,
    pub alts: Vec<RawAlt>,
}

/// Parses the whole text; returns the rules that could be read and every
/// syntax error.
pub(crate) fn parse(text: &str) -> (Vec<RawRule>, Vec<Diagnostic>) {
    let mut rules: Vec<RawRule> = Vec::new();
    let mut errors = Vec::new();
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let base = offset;
        offset += line.len();
        let body = line.trim_end_matches(['\n', '\r']);
        let mut p = LineParser { src: body.as_bytes(), text: body, base, pos: 0, errors: &mut errors };
        p.skip_ws();
        if p.at_end() || p.at_comment() {
            continue;
        }
        if p.peek() == Some(b'|') {
            match rules.last_mut() {
                Some(rule) => {
                    let continuation = p.pos;
                    p.pos += 1;
                    p.alternatives(&mut rule.alts, Some(continuation));
                }
                None => {
                    let at = p.span_at(p.pos, 1);
                    p.errors.push(Diagnostic::error(at, "a continuation line `| …` needs a rule before it"));
                }
            }
            continue;
        }
        if let Some(rule) = p.rule() {
            rules.push(rule);
        }
    }
    (rules, errors)
}

struct LineParser<'a, 'e> {
    src: &'a [u8],
    text: &'a str,
    /// Byte offset of the line in the file.
    base: usize,
    pos: usize,
    errors: &'e mut Vec<Diagnostic>,
}

/// Characters that end an unquoted word.
fn is_delimiter(c: u8) -> bool {
    c.is_ascii_whitespace() || matches!(c, b'<' | b'"' | b'{' | b'}' | b'[' | b']' | b'|')
}

impl LineParser<'_, '_> {
    fn peek(&self) -> Option<u8> {
        self.src.get(self.pos).copied()
    }

    fn at_end(&self) -> bool {
        self.pos >= self.src.len()
    }

    fn at_comment(&self) -> bool {
        self.src[self.pos..].starts_with(b"#") || self.src[self.pos..].starts_with(b"//")
    }

    fn skip_ws(&mut self) {
        while self.peek().is_some_and(|c| c.is_ascii_whitespace()) {
            self.pos += 1;
        }
    }

    /// Span of `len` bytes at line position `at`.
    fn span_at(&self, at: usize, len: usize) -> Span {
        Span::new(self.base + at, self.base + at + len)
    }

    fn error(&mut self, at: usize, len: usize, message: impl Into<String>) -> &mut Diagnostic {
        let d = Diagnostic::error(self.span_at(at, len), message);
        self.errors.push(d);
        self.errors.last_mut().expect("just pushed")
    }

    /// `<name> ::= alternatives`.
    fn rule(&mut self) -> Option<RawRule> {
        let start = self.pos;
        if self.peek() != Some(b'<') {
            let word = self.word_len();
            self.error(start, word, "expected a rule `<name> ::= …`")
                .hints
                .push("rules look like `<expr> ::= <expr> \"+\" <expr> | \"x\"`".into());
            return None;
        }
        let (name, span) = self.nonterminal()?;
        self.skip_ws();
        if !self.src[self.pos..].starts_with(b"::=") {
            let word = self.word_len().max(1);
            self.error(self.pos, word, format!("expected `::=` after `{name}`"));
            return None;
        }
        let arrow = self.pos;
        self.pos += 3;
        let mut alts = Vec::new();
        self.skip_ws();
        if self.at_end() || self.at_comment() {
            self.error(arrow, 3, format!("`{name}` has no alternatives after `::=`"));
            return Some(RawRule { name, span, alts });
        }
        self.alternatives(&mut alts, None);
        Some(RawRule { name, span, alts })
    }

    /// Length of the unquoted word at the cursor (for error spans).
    fn word_len(&self) -> usize {
        self.src[self.pos..].iter().take_while(|c| !c.is_ascii_whitespace()).count()
    }

    /// `<name>` at the cursor, brackets included in the name.
    fn nonterminal(&mut self) -> Option<(String, Span)> {
        let start = self.pos;
        let rest = &self.src[start + 1..];
        let len = rest.iter().take_while(|&&c| !is_delimiter(c) && c != b'>').count();
        if rest.get(len) != Some(&b'>') {
            self.pos = start + 1 + len;
            self.error(start, 1 + len, "expected `>` to close the non-terminal name")
                .hints
                .push("non-terminal names have no spaces, quotes or brackets: `<name>`".into());
            return None;
        }
        self.pos = start + len + 2;
        if len == 0 {
            self.error(start, 2, "empty non-terminal name `<>`");
            return None;
        }
        Some((self.text[start..self.pos].to_string(), self.span_at(start, self.pos - start)))
    }

    /// Alternatives separated by `|` up to the end of the line, appended to
    /// `alts`. `lead` is the position of a continuation line's leading `|`.
    fn alternatives(&mut self, alts: &mut Vec<RawAlt>, lead: Option<usize>) {
        // Position of the `|` before the current alternative, if any.
        let mut bar = lead;
        loop {
            self.skip_ws();
            let start = self.pos;
            let errors_before = self.errors.len();
            let items = self.sequence(None);
            let end = self.pos;
            let at_bar = self.peek() == Some(b'|');
            // An alternative left empty by an error already reported is not
            // reported again.
            if items.is_empty() && self.errors.len() == errors_before {
                match (at_bar, bar) {
                    (true, _) => {
                        self.error(self.pos, 1, "empty alternative before `|`");
                    }
                    (false, Some(b)) => {
                        self.error(b, 1, "empty alternative after `|`");
                    }
                    (false, None) => {
                        self.error(start, 1, "empty alternative");
                    }
                }
            } else if !items.is_empty() {
                let trimmed = self.text[start..end].trim_end().len();
                alts.push(RawAlt { items, span: self.span_at(start, trimmed) });
            }
            if at_bar {
                bar = Some(self.pos);
                self.pos += 1;
            } else {
                return;
            }
        }
    }

    /// Items up to the end of the line, a top-level `|`, or the closing
    /// bracket of `group` (`(closer, open position)`), which it consumes.
    fn sequence(&mut self, group: Option<(u8, usize)>) -> Vec<RawItem> {
        let mut items = Vec::new();
        loop {
            self.skip_ws();
            if self.at_comment() {
                self.pos = self.src.len();
            }
            let Some(c) = self.peek() else {
                if let Some((closer, open)) = group {
                    let opener = if closer == b'}' { "{" } else { "[" };
                    self.error(
                        open,
                        1,
                        format!("unclosed `{opener}`: expected `{}` before the end of the line", closer as char),
                    );
                }
                return items;
            };
            match c {
                b'|' => match group {
                    None => return items,
                    Some(_) => {
                        self.error(self.pos, 1, "`|` inside a group; put the alternatives in a rule of their own");
                        self.pos += 1;
                    }
                },
                b'"' => {
                    if let Some(t) = self.terminal() {
                        items.push(RawItem::Terminal(t));
                    }
                }
                b'<' => {
                    if let Some((name, span)) = self.nonterminal() {
                        items.push(RawItem::NonTerminal(name, span));
                    }
                }
                b'{' | b'[' => {
                    let open = self.pos;
                    let evolved = !(c == b'[' && self.src.get(open + 1) == Some(&b'?'));
                    self.pos += if evolved { 1 } else { 2 };
                    let closer = if c == b'{' { b'}' } else { b']' };
                    let inner = self.sequence(Some((closer, open)));
                    let len = if evolved { 1 } else { 2 };
                    if inner.is_empty() {
                        let shown = if c == b'{' { "{ }" } else { "[ ]" };
                        self.error(open, len, format!("empty group `{shown}`"));
                    } else if c == b'{' {
                        items.push(RawItem::Repeat(inner));
                    } else {
                        items.push(RawItem::Optional(inner, evolved));
                    }
                }
                b'}' | b']' => {
                    match group {
                        Some((closer, _)) if closer == c => {}
                        Some((closer, open)) => {
                            let col = self.text[..open].chars().count() + 1;
                            self.error(
                                self.pos,
                                1,
                                format!(
                                    "`{}` does not match the group opened at column {col}: expected `{}`",
                                    c as char, closer as char
                                ),
                            );
                        }
                        None => {
                            self.error(self.pos, 1, format!("unmatched `{}`", c as char));
                            self.pos += 1;
                            continue;
                        }
                    }
                    self.pos += 1;
                    return items;
                }
                _ => {
                    let start = self.pos;
                    let len = self.src[start..].iter().take_while(|&&c| !is_delimiter(c)).count().max(1);
                    let len = self.char_len(start, len);
                    let word = self.text[start..start + len].to_string();
                    self.pos = start + len;
                    self.error(start, len, format!("unquoted terminal `{word}`"))
                        .hints
                        .push(format!("terminals are written in double quotes: \"{word}\""));
                }
            }
        }
    }

    /// `len` widened to the next character boundary (unquoted words may
    /// hold non-ASCII text).
    fn char_len(&self, start: usize, mut len: usize) -> usize {
        while !self.text.is_char_boundary(start + len) {
            len += 1;
        }
        len
    }

    /// A double-quoted terminal at the cursor, escapes resolved.
    fn terminal(&mut self) -> Option<String> {
        let open = self.pos;
        self.pos += 1;
        let mut out = String::new();
        let mut seg = self.pos;
        let mut ok = true;
        loop {
            let Some(c) = self.peek() else {
                self.error(open, 1, "unterminated string: expected a closing `\"` on this line");
                return None;
            };
            match c {
                b'"' => {
                    out.push_str(&self.text[seg..self.pos]);
                    self.pos += 1;
                    return ok.then_some(out);
                }
                b'\\' => {
                    out.push_str(&self.text[seg..self.pos]);
                    let esc = self.src.get(self.pos + 1).copied();
                    match esc {
                        Some(b'n') => out.push('\n'),
                        Some(b't') => out.push('\t'),
                        Some(b'\\') => out.push('\\'),
                        Some(b'"') => out.push('"'),
                        _ => {
                            let len = if esc.is_some() { self.char_len(self.pos, 2) } else { 1 };
                            let shown = self.text[self.pos..self.pos + len].to_string();
                            self.error(self.pos, len, format!("unknown escape `{shown}`"))
                                .hints
                                .push("the escapes are \\n, \\t, \\\\ and \\\"; write a backslash as \"\\\\\"".into());
                            ok = false;
                            self.pos += len;
                            seg = self.pos;
                            continue;
                        }
                    }
                    self.pos += 2;
                    seg = self.pos;
                }
                _ => self.pos += 1,
            }
        }
    }
}
