//! The `.lpy` text as logical lines, and the `.ls` text written from it
//! with its source map.

use genform_core::{Diagnostic, Span};

/// One logical line of the `.lpy` file: physical lines joined while a
/// bracket is open or a line ends with `\`, comments removed.
#[derive(Clone, Debug)]
pub(super) struct Line {
    /// Offset of the first character of the code (after the indent).
    pub at: usize,
    /// Columns of indentation (a tab counts as 8, as Python reads it).
    pub indent: usize,
    /// The code without its indent and comment; continuation lines are
    /// joined with one space per removed line break, so offsets inside
    /// `code` map back with [`Line::offset`].
    pub code: String,
    /// (offset in `code`, offset in the file) where each physical piece
    /// starts.
    pieces: Vec<(usize, usize)>,
}

impl Line {
    /// The file offset of offset `k` in [`Line::code`].
    pub fn offset(&self, k: usize) -> usize {
        let i = self.pieces.partition_point(|&(c, _)| c <= k);
        match i.checked_sub(1).and_then(|i| self.pieces.get(i)) {
            Some(&(c, f)) => f + (k - c),
            None => self.at + k,
        }
    }
}

/// The end of the code of `line` (before a `#` comment outside quotes).
pub(super) fn code_end(line: &str) -> usize {
    let mut quote: Option<char> = None;
    for (i, c) in line.char_indices() {
        match quote {
            Some(q) if c == q => quote = None,
            Some(_) => {}
            None if c == '\'' || c == '"' => quote = Some(c),
            None if c == '#' => return i,
            None => {}
        }
    }
    line.len()
}

/// How far `code` leaves brackets open (never below 0).
fn depth_after(code: &str, mut depth: i32) -> i32 {
    let mut quote: Option<char> = None;
    for c in code.chars() {
        match quote {
            Some(q) if c == q => quote = None,
            Some(_) => {}
            None => match c {
                '\'' | '"' => quote = Some(c),
                '(' | '[' | '{' => depth += 1,
                ')' | ']' | '}' => depth = (depth - 1).max(0),
                _ => {}
            },
        }
    }
    depth
}

/// The logical lines of `src`. Triple-quoted strings (docstrings,
/// `__description__ = """…"""`) are left out, as are blank lines. In the
/// L-system part, only parentheses join lines (L-Py's module strings hold
/// unbalanced `[` and `]`).
pub(super) fn logical_lines(src: &str) -> Vec<Line> {
    let mut physical = Vec::new();
    let mut off = 0;
    for raw in src.split_inclusive('\n') {
        physical.push((off, raw.trim_end_matches(['\n', '\r'])));
        off += raw.len();
    }
    let mut out: Vec<Line> = Vec::new();
    let mut triple: Option<&str> = None;
    let mut i = 0;
    while i < physical.len() {
        let (at, raw) = physical[i];
        i += 1;
        if let Some(q) = triple {
            if raw.matches(q).count() % 2 == 1 {
                triple = None;
            }
            continue;
        }
        let code = raw[..code_end(raw)].trim_end();
        let body = code.trim_start();
        if body.is_empty() {
            continue;
        }
        let lead = code.len() - body.len();
        let indent = code[..lead].chars().map(|c| if c == '\t' { 8 } else { 1 }).sum();
        // A string statement or `__meta__ = """…"""` opening a triple quote.
        let opens = ["\"\"\"", "'''"].into_iter().find(|q| body.matches(q).count() % 2 == 1);
        let string_statement = body.starts_with("\"\"\"") || body.starts_with("'''") || body.starts_with("__");
        if let Some(q) = opens.filter(|_| string_statement || body.contains('=')) {
            triple = Some(q);
            continue;
        }
        let mut line = Line { at: at + lead, indent, code: body.to_string(), pieces: vec![(0, at + lead)] };
        // Round brackets and a final backslash continue the line.
        let mut depth = paren_depth(body, 0);
        while (depth > 0 || line.code.ends_with('\\')) && i < physical.len() {
            if line.code.ends_with('\\') {
                line.code.pop();
            }
            let (nat, nraw) = physical[i];
            i += 1;
            let ncode = nraw[..code_end(nraw)].trim_end();
            let nbody = ncode.trim_start();
            line.code.push(' ');
            line.pieces.push((line.code.len(), nat + (ncode.len() - nbody.len())));
            line.code.push_str(nbody);
            depth = paren_depth(nbody, depth);
        }
        out.push(line);
    }
    out
}

/// [`depth_after`] counting only round brackets.
fn paren_depth(code: &str, depth: i32) -> i32 {
    let only: String = code.chars().map(|c| if matches!(c, '[' | ']' | '{' | '}') { ' ' } else { c }).collect();
    depth_after(&only, depth)
}

/// The `.ls` text being written, with its source map.
pub(super) struct Out {
    pub text: String,
    pub map: Vec<(usize, usize)>,
}

impl Out {
    /// Appends `s`, which stands for the `.lpy` text at `at`.
    pub fn push(&mut self, s: &str, at: usize) {
        if s.is_empty() {
            return;
        }
        self.map.push((self.text.len(), at));
        self.text.push_str(s);
    }

    /// Ends the `.ls` line.
    pub fn newline(&mut self) {
        self.text.push('\n');
    }
}

/// Why a construct is outside the subset, as an error.
pub(super) fn outside(at: usize, len: usize, what: &str) -> Diagnostic {
    Diagnostic::error(
        Span::new(at, at + len.max(1)),
        format!("{what}: Python outside the subset genform reads from .lpy files"),
    )
    .with_hint(
        "L-Py (the Python package) runs it; genform reads L-systems with constants, `if` bodies, \
         small functions and hooks that assign globals (docs/lsystem.md, Reading L-Py files)",
    )
}

/// The leading Python name of `code` (letters, digits, `_`).
pub(super) fn leading_name(code: &str) -> &str {
    let end = code.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(code.len());
    &code[..end]
}

/// Whether `s` is a Python name (`x`, `_a1`; not `1a`, not `a.b`).
pub(super) fn is_name(s: &str) -> bool {
    !s.is_empty() && leading_name(s) == s && !s.as_bytes()[0].is_ascii_digit()
}

/// What the Python statement `code` is, for messages.
pub(super) fn construct(code: &str) -> String {
    let word = leading_name(code);
    match word {
        "if" | "elif" | "else" => "a Python `if`".into(),
        "for" | "while" => format!("a Python `{word}` loop"),
        "def" => format!("a Python function `def {}`", leading_name(code[3..].trim_start())),
        "class" => "a Python class".into(),
        "nproduce" => "`nproduce`".into(),
        "import" | "from" => format!("the Python import `{}`", code.trim()),
        "return" | "pass" | "global" | "try" | "with" | "print" | "lambda" | "assert" | "del" | "yield" | "raise" => {
            format!("the Python `{word}`")
        }
        _ if assignment(code).is_some() => "a Python assignment".into(),
        _ if !word.is_empty() && code[word.len()..].trim_start().starts_with('(') => {
            format!("the Python call `{word}(…)`")
        }
        _ => "a Python statement".into(),
    }
}

/// `name = value` or `name op= value` (not `==`): the name's length, the
/// operator (`None` for `=`) and the offset of the value.
pub(super) fn assignment(code: &str) -> Option<(usize, Option<char>, usize)> {
    let name_len = leading_name(code).len();
    if name_len == 0 || code.as_bytes()[0].is_ascii_digit() {
        return None;
    }
    let rest = &code[name_len..];
    let trimmed = rest.trim_start();
    let eq = name_len + (rest.len() - trimmed.len());
    if trimmed.starts_with('=') && !trimmed.starts_with("==") {
        return Some((name_len, None, eq + 1));
    }
    for op in ['+', '-', '*', '/'] {
        if trimmed.strip_prefix(op).is_some_and(|r| r.starts_with('=')) {
            return Some((name_len, Some(op), eq + 2));
        }
    }
    None
}

/// The offset of `c` in `s` outside brackets and quotes.
pub(super) fn find_top(s: &str, c: u8) -> Option<usize> {
    let b = s.as_bytes();
    let (mut depth, mut quote) = (0i32, None);
    for (i, &x) in b.iter().enumerate() {
        match quote {
            Some(q) if x == q => quote = None,
            Some(_) => {}
            None => match x {
                _ if x == c && depth == 0 => return Some(i),
                b'\'' | b'"' => quote = Some(x),
                b'(' => depth += 1,
                b')' => depth -= 1,
                _ => {}
            },
        }
    }
    None
}

/// A `.lpy` file translated to `.ls` text, with the way back.
#[derive(Clone, Debug)]
pub struct Translation {
    /// The `.ls` text.
    pub text: String,
    /// (offset in `text`, offset in the `.lpy` text), by the first.
    pub(super) map: Vec<(usize, usize)>,
    /// Warnings of the translation, in `.lpy` offsets.
    pub warnings: Vec<Diagnostic>,
    /// The axiom is empty (the `.ls` text holds a stand-in module).
    pub(super) empty_axiom: bool,
    /// `module A = F`: (A, F); A draws as F.
    pub(super) aliases: Vec<(String, String)>,
    /// (module name, arity, which parameters are Python floats or
    /// booleans) for every module written with parameters.
    pub(super) params: Vec<(String, usize, crate::alphabet::PyParams)>,
}

impl Translation {
    /// The `.lpy` offset of `.ls` offset `at`.
    pub fn source_offset(&self, at: usize) -> usize {
        let i = self.map.partition_point(|&(g, _)| g <= at);
        if i == 0 {
            return 0;
        }
        let (g, s) = self.map[i - 1];
        s + (at - g)
    }

    fn span(&self, span: Span) -> Span {
        let start = self.source_offset(span.start as usize);
        let end = if span.end > span.start { self.source_offset(span.end as usize - 1) + 1 } else { start };
        Span::new(start, end)
    }

    /// `d` (about the `.ls` text) about the `.lpy` text.
    pub fn map_diagnostic(&self, mut d: Diagnostic) -> Diagnostic {
        d.span = d.span.map(|s| self.span(s));
        for (s, _) in &mut d.labels {
            *s = self.span(*s);
        }
        d
    }
}
