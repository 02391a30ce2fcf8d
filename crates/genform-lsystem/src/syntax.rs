//! The `.ls` text format, read into a syntax tree with spans.
//!
//! The format is line-oriented: `key: value` settings, `define name = expr`
//! constants, section headers (`production:`, `decomposition:`,
//! `interpretation:`) and, inside sections, one production per line. `#`
//! starts a comment (except in a `#rrggbb` colour). Every problem is reported,
//! with its position, before anything is compiled.

use genform_core::diag::{Diagnostic, Span};
use genform_core::expr::{self, Ast};

/// A formula and where its text starts in the file (its [`Ast`] spans are
/// relative to that).
#[derive(Clone, Debug)]
pub struct Expr {
    /// The parsed formula.
    pub ast: Ast,
    /// Byte offset of the formula's text in the file.
    pub at: usize,
}

/// A module in an axiom or successor: a name and actual parameters.
#[derive(Clone, Debug)]
pub struct Call {
    /// The module name.
    pub name: String,
    /// Where the name is.
    pub span: Span,
    /// Actual parameters (none without parentheses).
    pub args: Vec<Expr>,
}

/// A module in a predecessor or context: a name and formal parameter names.
#[derive(Clone, Debug)]
pub struct Pattern {
    /// The module name.
    pub name: String,
    /// Where the name (and its parameter list) is.
    pub span: Span,
    /// Formal parameter names with their spans.
    pub formals: Vec<(String, Span)>,
    /// L-Py's `or(P1, P2, …)` (name `or`): the alternative module
    /// sequences, the first that matches counts; empty for a module.
    pub alts: Vec<Vec<Pattern>>,
}

/// One production line.
#[derive(Clone, Debug)]
pub struct Production {
    /// Left context, in string order.
    pub left: Vec<Pattern>,
    /// The strict predecessor: one module, or several that match
    /// consecutive modules of the string (L-Py's `A B --> …`).
    pub strict: Vec<Pattern>,
    /// Right context, in string order.
    pub right: Vec<Pattern>,
    /// Condition after `:`.
    pub cond: Option<Expr>,
    /// Weight of a stochastic production (`-(w)->`).
    pub weight: Option<Expr>,
    /// The successor (empty: the module is deleted).
    pub successor: Vec<Call>,
    /// A body `-> { … }` of statements with `produce` (instead of a
    /// successor).
    pub body: Option<Vec<Stmt>>,
    /// The whole line.
    pub span: Span,
}

/// A statement of a production body or a hook.
#[derive(Clone, Debug)]
pub enum Stmt {
    /// `name = formula`.
    Assign {
        /// The assigned name.
        name: String,
        /// Where the name is.
        span: Span,
        /// The formula.
        value: Expr,
    },
    /// `if cond: statement`, with an optional `else:` (or `elif`) branch.
    If {
        /// The condition.
        cond: Expr,
        /// Runs when it holds.
        then: Box<Stmt>,
        /// Runs otherwise.
        els: Option<Box<Stmt>>,
    },
    /// `produce modules` (ends the body) or `nproduce modules` (appends and
    /// goes on).
    Produce {
        /// The modules.
        calls: Vec<Call>,
        /// `produce` (true) or `nproduce` (false).
        end: bool,
    },
}

/// An L-Py hook: statements run around the derivation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Hook {
    /// Once, before the first step (`Start:`).
    Start,
    /// Before every step (`StartEach:`).
    StartEach,
    /// After every step (`EndEach:`).
    EndEach,
    /// Once, after the last step (`End:`).
    End,
}

/// Which table a production belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Section {
    /// Rewriting productions (`production:`).
    Production,
    /// Decomposition rules, applied after each step (`decomposition:`).
    Decomposition,
    /// Interpretation rules, applied when drawing (`interpretation:` or
    /// `homomorphism:`).
    Interpretation,
}

/// A `key: value` setting.
#[derive(Clone, Debug)]
pub struct Setting {
    /// The key.
    pub key: String,
    /// Where the key is.
    pub key_span: Span,
    /// The value text (comment stripped, trimmed).
    pub value: String,
    /// Byte offset of the value text.
    pub at: usize,
}

/// A constant: `define name = formula`, and with a range (`in [min, max]`
/// or `in min..max`) a gene of the generator.
#[derive(Clone, Debug)]
pub struct Define {
    /// The constant's name.
    pub name: String,
    /// Where the name is.
    pub span: Span,
    /// The written value.
    pub expr: Expr,
    /// The range that makes it a gene, if any.
    pub range: Option<Range>,
}

/// The range of a ranged constant: real (`[min, max]`) or whole numbers
/// (`min..max`), bounds included.
#[derive(Clone, Debug)]
pub struct Range {
    /// Whole numbers only (`min..max`).
    pub integer: bool,
    /// The lower bound.
    pub min: Expr,
    /// The upper bound.
    pub max: Expr,
    /// Where the range is written (after `in`).
    pub span: Span,
}

/// A whole `.ls` file.
#[derive(Clone, Debug, Default)]
pub struct File {
    /// Settings in file order (`axiom`, `define` and sections excluded).
    pub settings: Vec<Setting>,
    /// `define name = expr` (optionally `in` a range), in file order.
    pub defines: Vec<Define>,
    /// Declared multi-character module names.
    pub modules: Vec<(String, Span)>,
    /// The axiom.
    pub axiom: Option<(Vec<Call>, Span)>,
    /// Productions per section, in file order.
    pub productions: Vec<(Section, Production)>,
    /// `maxdepth:` of the decomposition and interpretation sections.
    pub max_depth: [Option<(u32, Span)>; 2],
    /// `ignore:` (false) or `consider:` (true) lists: module names.
    pub context_sets: Vec<(bool, Vec<String>, Span)>,
    /// `global name = formula`, in file order.
    pub globals: Vec<(String, Span, Expr)>,
    /// Statements of the hook sections, indexed by [`Hook`], in file order.
    pub hooks: [Vec<Stmt>; 4],
    /// `surface name = "file.obj"` declarations: name, its span, the path
    /// and the path's span.
    pub surfaces: Vec<(String, Span, String, Span)>,
}

/// Setting keys, for "did you mean" hints.
pub const KEYS: &[&str] = &[
    "name",
    "derivation",
    "angle",
    "step",
    "width",
    "width_factor",
    "width_unit",
    "heading",
    "view",
    "tropism",
    "elasticity",
    "growth",
    "colors",
    "max_modules",
    "ignore",
    "consider",
    "module",
    "axiom",
    "maxdepth",
];

/// What the lines below a section header are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Block {
    /// Productions of a table.
    Rules(Section),
    /// Statements of a hook.
    Hook(Hook),
}

const SECTIONS: &[(&str, Block)] = &[
    ("production", Block::Rules(Section::Production)),
    ("productions", Block::Rules(Section::Production)),
    ("decomposition", Block::Rules(Section::Decomposition)),
    ("interpretation", Block::Rules(Section::Interpretation)),
    ("homomorphism", Block::Rules(Section::Interpretation)),
    ("Start", Block::Hook(Hook::Start)),
    ("StartEach", Block::Hook(Hook::StartEach)),
    ("EndEach", Block::Hook(Hook::EndEach)),
    ("End", Block::Hook(Hook::End)),
    ("start", Block::Hook(Hook::Start)),
    ("start_each", Block::Hook(Hook::StartEach)),
    ("end_each", Block::Hook(Hook::EndEach)),
    ("end", Block::Hook(Hook::End)),
];

/// The deepest decomposition or interpretation recursion (`maxdepth:`).
pub const MAX_RULE_DEPTH: u32 = 1000;

/// Characters that are syntax, never module names.
/// (`,` is L-Py's DecColor module outside parentheses.)
const RESERVED: &[char] = &['(', ')', '<', '>', ':', '=', '#'];

/// L-Py/cpfg command names of three characters, read as one module (before
/// the two-character `@X` rule).
const LONG_COMMANDS: &[&str] = &["@Gc", "@Ge", "@Dd", "@Di", "@Ts", "@Tp", "@2D", "@3D"];

/// The length of the module name `text` starts with (not empty, not
/// starting with white space or a reserved character): the longest of the
/// `declared` names, an L-Py command such as `@Gc`, `@O` or `?P`, a
/// surface `~name`, or one character.
pub(crate) fn module_name_len<'d>(text: &str, declared: impl Iterator<Item = &'d str>) -> usize {
    let declared = declared.filter(|n| text.starts_with(n)).map(str::len).max();
    // `@O`-style names (L-Py's sphere) and `?P`-style queries are
    // one module; so are L-Py's three-character `@` commands.
    let long = LONG_COMMANDS.iter().find(|n| text.starts_with(**n)).map(|n| n.len());
    let c = text.chars().next().unwrap_or(' ');
    let at_name = c == '@' && text[1..].starts_with(|n: char| n.is_ascii_alphabetic());
    let query = c == '?' && text[1..].starts_with(|n: char| n.is_ascii_uppercase());
    // `~name` is a predefined surface (cpfg/L-Py), one module.
    let surface = (c == '~')
        .then(|| text[1..].find(|n: char| !(n.is_ascii_alphanumeric() || n == '_')).unwrap_or(text.len() - 1))
        .filter(|&n| n > 0)
        .map(|n| n + 1);
    declared.or(long).or(surface).unwrap_or(if at_name || query { 2 } else { c.len_utf8() })
}

/// Reads `text` into a [`File`], collecting every error.
pub fn parse(text: &str) -> (File, Vec<Diagnostic>) {
    let mut p = Parser { file: File::default(), errors: Vec::new(), section: None, open_body: None };
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let body = strip_comment(line.trim_end_matches(['\n', '\r']));
        p.line(body, offset);
        offset += line.len();
    }
    if let Some(k) = p.open_body {
        let span = p.file.productions[k].1.span;
        p.errors.push(
            Diagnostic::error(span, "this production's body is never closed").with_hint("end the body with a line `}`"),
        );
    }
    (p.file, p.errors)
}

/// The line without its `#` comment; `#` followed by six hex digits is a
/// colour, not a comment.
fn strip_comment(line: &str) -> &str {
    let b = line.as_bytes();
    let mut i = 0;
    while let Some(k) = line[i..].find('#') {
        let at = i + k;
        let hex = b.len() >= at + 7
            && b[at + 1..at + 7].iter().all(u8::is_ascii_hexdigit)
            && b.get(at + 7).is_none_or(|c| !c.is_ascii_alphanumeric());
        if !hex {
            return &line[..at];
        }
        i = at + 7;
    }
    line
}

struct Parser {
    file: File,
    errors: Vec<Diagnostic>,
    section: Option<Block>,
    /// The production whose body `{ … }` is being read, by index into
    /// `file.productions`.
    open_body: Option<usize>,
}

/// Trims `s` (at byte `at`), returning the trimmed text and its offset.
fn trimmed(s: &str, at: usize) -> (&str, usize) {
    let start = s.len() - s.trim_start().len();
    (s.trim(), at + start)
}

fn span(at: usize, len: usize) -> Span {
    Span::new(at, at + len)
}

/// A leading identifier and the rest after it.
fn leading_word(s: &str) -> Option<(&str, &str)> {
    let end = s.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(s.len());
    if end == 0 || !s.as_bytes()[0].is_ascii_alphabetic() {
        return None;
    }
    Some((&s[..end], &s[end..]))
}

impl Parser {
    fn line(&mut self, raw: &str, offset: usize) {
        let (line, at) = trimmed(raw, offset);
        if line.is_empty() {
            return;
        }
        if let Some(k) = self.open_body {
            if line == "}" {
                self.open_body = None;
            } else if let Some(stmt) = self.statement(line, at, true) {
                self.push_statement(stmt, |f| f.productions[k].1.body.get_or_insert_with(Vec::new));
            }
            return;
        }
        if let Some(rest) = line.strip_prefix("global").filter(|r| r.starts_with(char::is_whitespace)) {
            let skip = line.len() - rest.len();
            if let Some((name, span, e)) = self.named_formula(rest, at + skip, span(at, line.len()), "global") {
                self.file.globals.push((name, span, e));
            }
            return;
        }
        if let Some(rest) = line.strip_prefix("surface").filter(|r| r.starts_with(char::is_whitespace)) {
            let skip = line.len() - rest.len();
            self.surface(rest, at + skip, span(at, line.len()));
            return;
        }
        if let Some(rest) = line.strip_prefix("define").filter(|r| r.starts_with(char::is_whitespace)) {
            let skip = line.len() - rest.len();
            self.define(rest, at + skip, span(at, line.len()));
            return;
        }
        if let Some((word, rest)) = leading_word(line) {
            let after = rest.trim_start();
            if let Some(value) = after.strip_prefix(':')
                && !value.starts_with('=')
            {
                if let Some(&(_, s)) = SECTIONS.iter().find(|(n, _)| *n == word) {
                    if !value.trim().is_empty() {
                        self.errors.push(
                            Diagnostic::error(
                                span(at, line.len()),
                                format!("`{word}:` starts a section; put the productions on the lines below it"),
                            )
                            .with_hint("write one production per line after the section header"),
                        );
                    }
                    self.section = Some(s);
                    return;
                }
                if KEYS.contains(&word) {
                    let vstart = line.len() - value.len();
                    let (v, vat) = trimmed(value, at + vstart);
                    self.setting(word, span(at, word.len()), v, vat);
                    return;
                }
                if self.section.is_none() {
                    let mut d = Diagnostic::error(span(at, word.len()), format!("unknown setting `{word}`"));
                    let all = KEYS.iter().chain(SECTIONS.iter().map(|(n, _)| n)).copied();
                    d = match expr::did_you_mean(word, all) {
                        Some(s) => d.with_hint(format!("did you mean `{s}`?")),
                        None => d.with_hint(format!("settings are: {}", KEYS.join(", "))),
                    };
                    self.errors.push(d);
                    return;
                }
            }
        }
        match self.section {
            Some(Block::Rules(section)) => {
                if let Some(p) = self.production(line, at) {
                    let opens = p.body.is_some();
                    self.file.productions.push((section, p));
                    if opens {
                        self.open_body = Some(self.file.productions.len() - 1);
                    }
                }
            }
            Some(Block::Hook(hook)) => {
                if let Some(stmt) = self.statement(line, at, false) {
                    self.push_statement(stmt, |f| &mut f.hooks[hook as usize]);
                }
            }
            None => self.errors.push(
                Diagnostic::error(
                    span(at, line.len()),
                    "expected a setting (`key: value`), `define`, or a section header",
                )
                .with_hint("productions go below a `production:` line"),
            ),
        }
    }

    fn setting(&mut self, key: &str, key_span: Span, value: &str, at: usize) {
        match key {
            "axiom" => {
                let calls = self.calls(value, at);
                if self.file.axiom.is_some() {
                    self.errors.push(Diagnostic::error(key_span, "the axiom is given twice"));
                }
                self.file.axiom = Some((calls, span(at, value.len())));
            }
            "ignore" | "consider" => {
                let names = self.modules(value, at).iter().map(|m| m.name.to_string()).collect();
                self.file.context_sets.push((key == "consider", names, key_span));
            }
            "module" => {
                for (w, wat) in words(value, at) {
                    if leading_word(w).is_none_or(|(n, rest)| !rest.is_empty() || n.len() != w.len()) {
                        self.errors.push(
                            Diagnostic::error(span(wat, w.len()), format!("`{w}` is not a module name"))
                                .with_hint("declared names are letters, digits and `_`, starting with a letter"),
                        );
                    } else {
                        self.file.modules.push((w.to_string(), span(wat, w.len())));
                    }
                }
            }
            "maxdepth" => {
                let idx = match self.section {
                    Some(Block::Rules(Section::Decomposition)) => 0,
                    Some(Block::Rules(Section::Interpretation)) => 1,
                    _ => {
                        self.errors.push(
                            Diagnostic::error(
                                key_span,
                                "`maxdepth:` belongs in a decomposition or interpretation section",
                            )
                            .with_hint("it bounds how often those rules re-apply to their own output"),
                        );
                        return;
                    }
                };
                match value.parse::<u32>() {
                    Ok(n) if n <= MAX_RULE_DEPTH => self.file.max_depth[idx] = Some((n, key_span)),
                    _ => self.errors.push(
                        Diagnostic::error(
                            span(at, value.len().max(1)),
                            format!("`maxdepth` needs a whole number up to {MAX_RULE_DEPTH}"),
                        )
                        .with_hint("for example `maxdepth: 5`"),
                    ),
                }
            }
            _ => self.file.settings.push(Setting { key: key.to_string(), key_span, value: value.to_string(), at }),
        }
    }

    fn define(&mut self, rest: &str, at: usize, whole: Span) {
        // `define name = formula in RANGE`: the formula is what comes
        // before a free-standing `in`.
        let (formula, range) = match find_in(rest) {
            Some(k) => (&rest[..k], Some((&rest[k + 2..], at + k + 2))),
            None => (rest, None),
        };
        let Some((name, span, expr)) = self.named_formula(formula, at, whole, "define") else { return };
        let range = match range {
            Some((text, rat)) => {
                let Some(r) = self.range(text, rat, whole) else { return };
                Some(r)
            }
            None => None,
        };
        self.file.defines.push(Define { name, span, expr, range });
    }

    /// The range after `in`: `[min, max]` (real) or `min..max` (whole
    /// numbers).
    fn range(&mut self, text: &str, at: usize, whole: Span) -> Option<Range> {
        let (t, tat) = trimmed(text, at);
        let here = if t.is_empty() { whole } else { span(tat, t.len()) };
        let hint = "write `in [0, 90]` for a real range or `in 0..9` for whole numbers (bounds included)";
        let bounds: Vec<(&str, usize)>;
        let integer;
        if let Some(inner) = t.strip_prefix('[') {
            let Some(inner) = inner.strip_suffix(']') else {
                self.errors.push(Diagnostic::error(here, "expected `]` closing the range").with_hint(hint));
                return None;
            };
            bounds = split_top(inner, tat + 1, ',');
            integer = false;
        } else if let Some(k) = t.find("..") {
            bounds = vec![(&t[..k], tat), (&t[k + 2..], tat + k + 2)];
            integer = true;
        } else {
            self.errors.push(Diagnostic::error(here, "expected a range after `in`").with_hint(hint));
            return None;
        }
        if bounds.len() != 2 {
            self.errors.push(Diagnostic::error(here, "a range has two bounds, min and max").with_hint(hint));
            return None;
        }
        let (a, aat) = trimmed(bounds[0].0, bounds[0].1);
        let (b, bat) = trimmed(bounds[1].0, bounds[1].1);
        let min = self.expr(a, aat, here);
        let max = self.expr(b, bat, here);
        Some(Range { integer, min: min?, max: max?, span: here })
    }

    /// `name = formula` after the keyword `what` (`define`, `global`).
    fn named_formula(&mut self, rest: &str, at: usize, whole: Span, what: &str) -> Option<(String, Span, Expr)> {
        let (rest, at) = trimmed(rest, at);
        let example = format!("write `{what} p = 0.3`");
        let Some((name, after)) = leading_word(rest) else {
            self.errors.push(Diagnostic::error(whole, format!("expected a name after `{what}`")).with_hint(example));
            return None;
        };
        let Some(value) = after.trim_start().strip_prefix('=') else {
            self.errors.push(
                Diagnostic::error(span(at, name.len()), format!("expected `=` after `{what} {name}`"))
                    .with_hint(example),
            );
            return None;
        };
        let vstart = rest.len() - value.len();
        let (v, vat) = trimmed(value, at + vstart);
        let e = self.expr(v, vat, whole)?;
        Some((name.to_string(), span(at, name.len()), e))
    }

    /// `surface name = "file.obj"`.
    fn surface(&mut self, rest: &str, at: usize, whole: Span) {
        let (rest, at) = trimmed(rest, at);
        let example = "write `surface petal = \"petal.obj\"` and draw it with `~petal(size)`";
        let parsed = leading_word(rest).and_then(|(name, after)| {
            let value = after.trim_start().strip_prefix('=')?;
            let vstart = rest.len() - value.len();
            let (v, vat) = trimmed(value, at + vstart);
            let path = v.strip_prefix('"')?.strip_suffix('"')?;
            (!path.is_empty() && !path.contains('"')).then(|| (name, path, span(vat, v.len())))
        });
        match parsed {
            Some((name, path, path_span)) => {
                self.file.surfaces.push((name.to_string(), span(at, name.len()), path.to_string(), path_span))
            }
            None => {
                self.errors.push(Diagnostic::error(whole, "expected `surface name = \"file.obj\"`").with_hint(example))
            }
        }
    }

    /// One statement line of a body (`in_body`) or a hook.
    fn statement(&mut self, line: &str, at: usize, in_body: bool) -> Option<StmtLine> {
        let whole = span(at, line.len());
        match leading_word(line) {
            Some(("if", rest)) | Some(("elif", rest)) if rest.starts_with(char::is_whitespace) => {
                let is_elif = line.starts_with("elif");
                let off = line.len() - rest.len();
                let stmt = self.conditional(rest, at + off, whole, in_body)?;
                Some(if is_elif { StmtLine::Else(stmt, whole) } else { StmtLine::New(stmt) })
            }
            Some(("else", rest)) => {
                let Some(after) = rest.trim_start().strip_prefix(':') else {
                    self.errors.push(
                        Diagnostic::error(whole, "expected `else: statement`")
                            .with_hint("an `else:` line follows an `if cond: statement` line"),
                    );
                    return None;
                };
                let off = line.len() - after.len();
                let (t, tat) = trimmed(after, at + off);
                let then = self.statement(t, tat, in_body)?;
                match then {
                    StmtLine::New(stmt) => Some(StmtLine::Else(stmt, whole)),
                    StmtLine::Else(..) => {
                        self.errors.push(Diagnostic::error(whole, "`else:` cannot be followed by `else`"));
                        None
                    }
                }
            }
            Some((kw @ ("produce" | "nproduce"), rest)) if rest.is_empty() || rest.starts_with(char::is_whitespace) => {
                if !in_body {
                    self.errors.push(
                        Diagnostic::error(span(at, kw.len()), format!("`{kw}` belongs in a production body"))
                            .with_hint("hooks (Start, StartEach, EndEach, End) only assign global variables"),
                    );
                    return None;
                }
                let off = line.len() - rest.len();
                let calls = self.calls(rest, at + off);
                Some(StmtLine::New(Stmt::Produce { calls, end: kw == "produce" }))
            }
            Some((name, rest)) if rest.trim_start().starts_with('=') && !rest.trim_start().starts_with("==") => {
                let value = &rest.trim_start()[1..];
                let off = line.len() - value.len();
                let (v, vat) = trimmed(value, at + off);
                let value = self.expr(v, vat, whole)?;
                Some(StmtLine::New(Stmt::Assign { name: name.to_string(), span: span(at, name.len()), value }))
            }
            _ => {
                let hint = if in_body {
                    "a body holds `name = formula`, `if cond: …`, `else: …`, `produce modules`, `nproduce modules`; end it with `}`"
                } else {
                    "a hook holds `name = formula`, `if cond: …` and `else: …` lines"
                };
                self.errors.push(Diagnostic::error(whole, "expected a statement").with_hint(hint));
                None
            }
        }
    }

    /// `cond: statement` after `if` or `elif`.
    fn conditional(&mut self, rest: &str, at: usize, whole: Span, in_body: bool) -> Option<Stmt> {
        let (text, tat) = trimmed(rest, at);
        let (ast, used) = match expr::parse_prefix(text) {
            Ok(r) => r,
            Err(d) => {
                self.errors.push(d.shifted(tat));
                return None;
            }
        };
        let rest = text[used..].trim_start();
        let Some(after) = rest.strip_prefix(':') else {
            let next = tat + text.len() - rest.len();
            self.errors.push(
                Diagnostic::error(span(next, 1), "expected `:` after the condition")
                    .with_hint("write `if x > 1: produce A(x)`"),
            );
            return None;
        };
        let off = text.len() - after.len();
        let (t, sat) = trimmed(after, tat + off);
        if t.is_empty() {
            self.errors.push(Diagnostic::error(whole, "expected a statement after `:`"));
            return None;
        }
        let then = match self.statement(t, sat, in_body)? {
            StmtLine::New(s) => s,
            StmtLine::Else(..) => {
                self.errors.push(Diagnostic::error(span(sat, t.len()), "`else` cannot follow `if …:` on one line"));
                return None;
            }
        };
        Some(Stmt::If { cond: Expr { ast, at: tat }, then: Box::new(then), els: None })
    }

    /// Appends a statement line to the list `list` selects; `else:` and
    /// `elif` attach to the `if` chain just before them.
    fn push_statement(&mut self, line: StmtLine, list: impl FnOnce(&mut File) -> &mut Vec<Stmt>) {
        let list = list(&mut self.file);
        match line {
            StmtLine::New(s) => list.push(s),
            StmtLine::Else(s, whole) => {
                let attached = match list.last_mut() {
                    Some(last) => attach_else(last, s),
                    None => false,
                };
                if !attached {
                    self.errors.push(
                        Diagnostic::error(whole, "this `else`/`elif` follows no `if`")
                            .with_hint("write `if cond: …` on the line before; an `if` takes one `else`"),
                    );
                }
            }
        }
    }

    fn expr(&mut self, text: &str, at: usize, ctx: Span) -> Option<Expr> {
        if text.trim().is_empty() {
            self.errors.push(Diagnostic::error(ctx, "expected a formula here"));
            return None;
        }
        match expr::parse(text) {
            Ok(ast) => Some(Expr { ast, at }),
            Err(d) => {
                self.errors.push(d.shifted(at));
                None
            }
        }
    }

    /// Splits a module sequence into names and raw parameter lists.
    fn modules<'t>(&mut self, text: &'t str, at: usize) -> Vec<RawModule<'t>> {
        let mut out = Vec::new();
        let mut i = 0;
        while i < text.len() {
            let c = text[i..].chars().next().unwrap_or(' ');
            if c.is_whitespace() {
                i += c.len_utf8();
                continue;
            }
            if RESERVED.contains(&c) {
                let hint = match c {
                    '(' => "parameters follow a module name directly, as in `F(x)`",
                    '<' | '>' => "`<` and `>` mark contexts and only appear before the arrow",
                    ':' => "a condition follows the predecessor: `A(x) : x > 1 -> …`",
                    _ => "module names are letters, digits and turtle symbols",
                };
                self.errors.push(
                    Diagnostic::error(span(at + i, c.len_utf8()), format!("`{c}` cannot be a module here"))
                        .with_hint(hint),
                );
                i += c.len_utf8();
                continue;
            }
            let len = module_name_len(&text[i..], self.file.modules.iter().map(|(n, _)| n.as_str()));
            let name = &text[i..i + len];
            let start = i;
            i += len;
            let mut args = None;
            if text[i..].starts_with('(') {
                match matching_paren(&text[i..]) {
                    Some(close) => {
                        args = Some((&text[i + 1..i + close], at + i + 1));
                        i += close + 1;
                    }
                    None => {
                        self.errors.push(
                            Diagnostic::error(span(at + i, 1), "this `(` is never closed")
                                .with_hint("close the parameter list with `)`"),
                        );
                        i = text.len();
                    }
                }
            }
            out.push(RawModule { name, span: Span::new(at + start, at + i), args });
        }
        out
    }

    fn calls(&mut self, text: &str, at: usize) -> Vec<Call> {
        let raw = self.modules(text, at);
        raw.into_iter()
            .map(|m| {
                let mut args = Vec::new();
                if let Some((inner, iat)) = m.args {
                    for (piece, pat) in split_top(inner, iat, ',') {
                        let (t, tat) = trimmed(piece, pat);
                        if let Some(e) = self.expr(t, tat, m.span) {
                            args.push(e);
                        }
                    }
                }
                Call { name: m.name.to_string(), span: m.span, args }
            })
            .collect()
    }

    /// The patterns of `text`; `or(P1, P2, …)` holds alternatives (as in
    /// L-Py, where `or` is a module name of its own, so an undeclared
    /// `For(…)` is `F` and `or(…)`).
    fn patterns(&mut self, text: &str, at: usize) -> Vec<Pattern> {
        let raw = self.modules(text, at);
        let mut out = Vec::with_capacity(raw.len());
        let mut k = 0;
        while k < raw.len() {
            let m = &raw[k];
            let or = (m.name == "o" && m.args.is_none())
                .then(|| raw.get(k + 1))
                .flatten()
                .filter(|r| r.name == "r" && r.span.start == m.span.end)
                .and_then(|r| r.args.map(|a| (r.span, a)));
            if let Some((r_span, (inner, iat))) = or {
                let mut alts = Vec::new();
                for (piece, pat) in split_top(inner, iat, ',') {
                    let alt = self.patterns(piece, pat);
                    if alt.is_empty() {
                        let (t, tat) = trimmed(piece, pat);
                        self.errors.push(
                            Diagnostic::error(span(tat, t.len().max(1)), "an alternative of `or(…)` has no module")
                                .with_hint("write the module sequences it may match: `A > or(B C, D) -> …`"),
                        );
                    }
                    alts.push(alt);
                }
                let whole = Span::new(m.span.start as usize, r_span.end as usize);
                out.push(Pattern { name: "or".to_string(), span: whole, formals: Vec::new(), alts });
                k += 2;
                continue;
            }
            // L-Py's repetition `all(…)` (or `x(…)`): matches of varying length.
            let all = k + 2 < raw.len()
                && m.name == "a"
                && raw[k + 1].name == "l"
                && raw[k + 2].name == "l"
                && raw[k + 2].args.is_some()
                && raw[k + 1].span.start == m.span.end
                && raw[k + 2].span.start == raw[k + 1].span.end;
            if all {
                self.errors.push(
                    Diagnostic::error(
                        Span::new(m.span.start as usize, raw[k + 2].span.end as usize),
                        "L-Py's repetition pattern `all(…)` is not read by genform",
                    )
                    .with_hint(
                        "a predecessor or context matches a fixed number of modules; `or(…)` chooses among sequences",
                    ),
                );
                k += 3;
                continue;
            }
            let mut formals = Vec::new();
            if let Some((inner, iat)) = m.args {
                for (piece, pat) in split_top(inner, iat, ',') {
                    let (t, tat) = trimmed(piece, pat);
                    match leading_word(t) {
                        Some((w, "")) => formals.push((w.to_string(), span(tat, w.len()))),
                        _ => self.errors.push(
                            Diagnostic::error(span(tat, t.len().max(1)), "a predecessor's parameters are names")
                                .with_hint("write `A(x, y) : x > y -> …`; put tests in the condition"),
                        ),
                    }
                }
            }
            out.push(Pattern { name: m.name.to_string(), span: m.span, formals, alts: Vec::new() });
            k += 1;
        }
        out
    }

    fn production(&mut self, line: &str, at: usize) -> Option<Production> {
        let whole = span(at, line.len());
        let Some(arrow) = find_arrow(line) else {
            self.errors.push(
                Diagnostic::error(whole, "expected a production `predecessor -> successor`")
                    .with_hint("stochastic productions are written `A -(0.3)-> B`; conditions `A(x) : x > 1 -> B`"),
            );
            return None;
        };
        let lhs = &line[..arrow.start];
        let succ_text = &line[arrow.end..];
        let weight = match arrow.weight {
            Some((s, e)) => {
                let (t, tat) = trimmed(&line[s..e], at + s);
                Some(self.expr(t, tat, whole)?)
            }
            None => None,
        };
        let (pattern_text, cond) = match find_top(lhs, ':') {
            Some(c) => {
                let (t, tat) = trimmed(&lhs[c + 1..], at + c + 1);
                (&lhs[..c], Some(self.expr(t, tat, whole)?))
            }
            None => (lhs, None),
        };
        let lt = find_top(pattern_text, '<');
        let gt = find_top(pattern_text, '>');
        let (l_end, s_start) = match lt {
            Some(i) => (i, i + 1),
            None => (0, 0),
        };
        let (s_end, r_start) = match gt {
            Some(i) if i >= s_start => (i, i + 1),
            Some(i) => {
                self.errors
                    .push(Diagnostic::error(span(at + i, 1), "the right context `>` must follow the left context `<`"));
                return None;
            }
            None => (pattern_text.len(), pattern_text.len()),
        };
        let left = self.patterns(&pattern_text[..l_end], at);
        let strict = self.patterns(&pattern_text[s_start..s_end], at + s_start);
        let right = self.patterns(&pattern_text[r_start..], at + r_start);
        if strict.is_empty() {
            let (t, tat) = trimmed(&pattern_text[s_start..s_end], at + s_start);
            self.errors.push(
                Diagnostic::error(span(tat, t.len().max(1)), "the strict predecessor has no module")
                    .with_hint("name the module(s) to rewrite between the contexts: `A < B > C -> …` rewrites B"),
            );
            return None;
        }
        // `-> {` alone opens a body of statements on the lines below.
        let body = (succ_text.trim() == "{").then(Vec::new);
        let successor = if body.is_some() { Vec::new() } else { self.calls(succ_text, at + arrow.end) };
        Some(Production { left, strict, right, cond, weight, successor, body, span: whole })
    }
}

/// Makes `s` the `else` branch at the end of the `if` chain `stmt`; false
/// when `stmt` is no `if` or its chain already ends in an `else`.
fn attach_else(stmt: &mut Stmt, s: Stmt) -> bool {
    match stmt {
        Stmt::If { els: Some(next), .. } => matches!(**next, Stmt::If { .. }) && attach_else(next, s),
        Stmt::If { els, .. } => {
            *els = Some(Box::new(s));
            true
        }
        _ => false,
    }
}

/// A statement line: a new statement, or an `else:`/`elif` branch of the
/// `if` before it.
enum StmtLine {
    New(Stmt),
    Else(Stmt, Span),
}

struct RawModule<'t> {
    name: &'t str,
    span: Span,
    args: Option<(&'t str, usize)>,
}

/// Whitespace-separated words with their offsets.
fn words(s: &str, at: usize) -> Vec<(&str, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    for w in s.split_whitespace() {
        let k = s[i..].find(w).map_or(i, |k| i + k);
        out.push((w, at + k));
        i = k + w.len();
    }
    out
}

/// Index of the `)` closing the `(` at `s[0]`.
fn matching_paren(s: &str) -> Option<usize> {
    let mut depth = 0usize;
    for (i, c) in s.char_indices() {
        match c {
            '(' => depth += 1,
            ')' => {
                depth -= 1;
                if depth == 0 {
                    return Some(i);
                }
            }
            _ => {}
        }
    }
    None
}

/// First `c` outside parentheses.
fn find_top(s: &str, c: char) -> Option<usize> {
    let mut depth = 0i32;
    for (i, ch) in s.char_indices() {
        match ch {
            '(' => depth += 1,
            ')' => depth -= 1,
            _ if ch == c && depth == 0 => return Some(i),
            _ => {}
        }
    }
    None
}

/// Byte index of the keyword `in` standing alone (spaces before it, no
/// name character after it) after the first `=` (so a constant may still
/// be named `in`), outside parentheses and brackets.
fn find_in(s: &str) -> Option<usize> {
    let b = s.as_bytes();
    let mut depth = 0i32;
    let start = s.find('=')? + 1;
    for (i, &c) in b.iter().enumerate().skip(start) {
        match c {
            b'(' | b'[' => depth += 1,
            b')' | b']' => depth -= 1,
            b'i' if depth == 0 && i > 0 && b[i - 1].is_ascii_whitespace() && b[i..].starts_with(b"in") => {
                let after = b.get(i + 2).copied();
                if !after.is_some_and(|a| a.is_ascii_alphanumeric() || a == b'_' || a == b'.') {
                    return Some(i);
                }
            }
            _ => {}
        }
    }
    None
}

/// `s` split at top-level `c`, each piece with its offset.
fn split_top(s: &str, at: usize, c: char) -> Vec<(&str, usize)> {
    let mut out = Vec::new();
    let mut start = 0;
    let mut depth = 0i32;
    for (i, ch) in s.char_indices() {
        match ch {
            '(' => depth += 1,
            ')' => depth -= 1,
            _ if ch == c && depth == 0 => {
                out.push((&s[start..i], at + start));
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push((&s[start..], at + start));
    out
}

struct Arrow {
    start: usize,
    end: usize,
    weight: Option<(usize, usize)>,
}

/// The production arrow: `->`, or `-(w)->` with a weight. `-(a)` right at
/// the start of a line is the parametric turn module, not a weight.
fn find_arrow(line: &str) -> Option<Arrow> {
    let b = line.as_bytes();
    let mut depth = 0i32;
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'(' => depth += 1,
            b')' => depth -= 1,
            b'-' if depth == 0 => {
                if b.get(i + 1) == Some(&b'>') {
                    return Some(Arrow { start: i, end: i + 2, weight: None });
                }
                if b.get(i + 1) == Some(&b'(') && !line[..i].trim().is_empty() {
                    let close = i + 1 + matching_paren(&line[i + 1..])?;
                    if line[close + 1..].starts_with("->") {
                        return Some(Arrow { start: i, end: close + 3, weight: Some((i + 2, close)) });
                    }
                }
            }
            _ => {}
        }
        i += 1;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ok(text: &str) -> File {
        let (f, errors) = parse(text);
        assert!(errors.is_empty(), "{errors:?}");
        f
    }

    #[test]
    fn settings_sections_and_productions() {
        let f = ok("# Koch\nangle: 60 # degrees\naxiom: F++F++F\nproduction:\nF -> F-F++F-F\n");
        assert_eq!(f.settings.len(), 1);
        assert_eq!(f.settings[0].value, "60");
        let (axiom, _) = f.axiom.unwrap();
        assert_eq!(axiom.iter().map(|c| c.name.as_str()).collect::<String>(), "F++F++F");
        assert_eq!(f.productions.len(), 1);
        assert_eq!(f.productions[0].1.successor.len(), 8);
    }

    #[test]
    fn contexts_conditions_weights_and_parameters() {
        let f = ok("production:\nA B(y) < C(x) > D : x > y && x < 3 -(0.25)-> C(x+1) [ +(45) ]\n-(a) -> +(a)\n");
        let p = &f.productions[0].1;
        assert_eq!(p.left.len(), 2);
        assert_eq!(p.left[1].formals[0].0, "y");
        assert_eq!(p.strict[0].name, "C");
        assert_eq!(p.right.len(), 1);
        assert!(p.cond.is_some() && p.weight.is_some());
        assert_eq!(p.successor.len(), 4);
        assert_eq!(p.successor[2].args.len(), 1);
        let q = &f.productions[1].1;
        assert_eq!(q.strict[0].name, "-");
        assert!(q.weight.is_none());
    }

    #[test]
    fn declared_names_match_longest_first() {
        let f = ok("module: Apex Ap\naxiom: ApexApB\n");
        let (axiom, _) = f.axiom.unwrap();
        let names: Vec<&str> = axiom.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["Apex", "Ap", "B"]);
    }

    #[test]
    fn colours_are_not_comments() {
        let f = ok("colors: #6b4423 #3a7d23 # brown, green\n");
        assert_eq!(f.settings[0].value, "#6b4423 #3a7d23");
    }

    #[test]
    fn empty_successor_deletes() {
        let f = ok("production:\nA ->\n");
        assert!(f.productions[0].1.successor.is_empty());
    }

    #[test]
    fn every_error_is_reported_with_its_position() {
        let text = "angel: 60\nproduction:\nF => FF\nA(x+1) -> B\nA -> B(\n";
        let (_, errors) = parse(text);
        assert_eq!(errors.len(), 4, "{errors:?}");
        assert!(errors[0].message.contains("unknown setting"));
        assert!(errors[0].hints[0].contains("angle"));
        assert_eq!(errors[1].span.unwrap().start as usize, text.find("F =>").unwrap());
    }
}
