//! Indented Python blocks of `.lpy` files — production bodies, hooks
//! (`def StartEach():` …) and small functions — read into statements and
//! written as `.ls` statement lines.
//!
//! The `.ls` statement language takes one statement after `if cond:`, so
//! a Python `if`/`elif`/`else` whose branches hold several statements is
//! written with a hidden variable that records which branch holds
//! (`lpy_k1 = c1 ? 1 : (c2 ? 2 : 3)`), evaluated once and in Python's
//! order, and every statement of a branch guarded by it (`if lpy_k1 == 2:
//! …`). In a hook the hidden variable is a global.

use super::pyexpr::{self, Names, Py};
use super::text::{Line, Out, assignment, construct, find_top, is_name, leading_name, outside};
use genform_core::{Diagnostic, Span};

/// Where a block stands: its statements may differ.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    /// A production body (`produce`, `nproduce`, locals).
    Production,
    /// A hook: assignments to globals, `useGroup`.
    Hook,
    /// A small function: assignments, `if`, `return`.
    Function,
}

/// One statement.
#[derive(Clone, Debug)]
pub(super) enum Stmt {
    /// `produce` (`end`) or `nproduce`: the modules are `code[start..]` of
    /// logical line `line`.
    Produce { end: bool, line: usize, start: usize },
    /// `name = value` (`op` for `name op= value`).
    Assign { name: String, at: usize, op: Option<char>, value: Py },
    /// `if`/`elif`/`else` arms; the `else` arm has no condition.
    If(Vec<(Option<Py>, Vec<Stmt>)>),
    /// `useGroup(n)`.
    UseGroup(Py, usize),
    /// `return value` (functions).
    Return(Option<Py>, usize),
    /// `global a, b`.
    Global(Vec<String>),
    /// Statements of one line (`a, b = 1, 2`).
    Seq(Vec<Stmt>),
}

/// A piece of a line's code and its offset there.
pub(super) type Piece<'a> = (&'a str, usize);

/// Writes the module string of a line from an offset of its code.
pub(super) type WriteModules<'a> = dyn Fn(&mut Out, &Line, usize, &mut Vec<Diagnostic>) + 'a;

/// `a, b = x, y` as its names and values, (name, offset in `code`) and
/// (value, offset), when both sides have as many items and no value
/// names an assigned name (then assigning one after the other is what
/// Python does).
pub(super) fn tuple_assignment(code: &str) -> Option<Vec<(Piece<'_>, Piece<'_>)>> {
    let eq = find_top(code, b'=')?;
    let (left, right) = (&code[..eq], &code[eq + 1..]);
    if right.starts_with('=') || !left.contains(',') || left.ends_with(['<', '>', '!', '=']) {
        return None;
    }
    let split = |s: &str, base: usize| -> Vec<(usize, usize)> {
        let mut parts = Vec::new();
        let (mut depth, mut from) = (0i32, 0);
        for (i, c) in s.bytes().enumerate() {
            match c {
                b'(' | b'[' => depth += 1,
                b')' | b']' => depth -= 1,
                b',' if depth == 0 => {
                    parts.push((base + from, base + i));
                    from = i + 1;
                }
                _ => {}
            }
        }
        parts.push((base + from, base + s.len()));
        parts
    };
    let names = split(left, 0);
    let values = split(right, eq + 1);
    if names.len() != values.len() {
        return None;
    }
    let trim = |(a, b): (usize, usize)| {
        let t = &code[a..b];
        (t.trim(), a + (t.len() - t.trim_start().len()))
    };
    let pairs: Vec<_> = names.into_iter().map(trim).zip(values.into_iter().map(trim)).collect();
    let ok = pairs.iter().all(|((n, _), _)| is_name(n))
        && pairs.iter().all(|(_, (v, _))| pairs.iter().all(|((n, _), _)| !mentions_name(v, n)));
    ok.then_some(pairs)
}

/// Whether `name` occurs in `text` as a name of its own.
fn mentions_name(text: &str, name: &str) -> bool {
    text.match_indices(name).any(|(i, _)| {
        let before = text[..i].chars().next_back().is_none_or(|c| !c.is_alphanumeric() && c != '_');
        let after = text[i + name.len()..].chars().next().is_none_or(|c| !c.is_alphanumeric() && c != '_');
        before && after
    })
}

/// Reads blocks of one file.
pub(super) struct Reader<'l> {
    pub lines: &'l [Line],
    pub errors: Vec<Diagnostic>,
    pub warnings: Vec<Diagnostic>,
    /// How deep blocks nest here (bounded, so no input exhausts the stack).
    pub depth: usize,
}

/// Deepest nesting of blocks read.
const MAX_NESTING: usize = 32;

/// The index after the block of lines indented more than `indent` that
/// starts at `i`.
pub(super) fn block_end(lines: &[Line], mut i: usize, indent: usize) -> usize {
    while i < lines.len() && lines[i].indent > indent {
        i += 1;
    }
    i
}

impl Reader<'_> {
    /// The statements of lines `lo..hi`, all indented as `lines[lo]`.
    pub fn block(&mut self, lo: usize, hi: usize, kind: Kind) -> Vec<Stmt> {
        let out: Vec<Stmt> = Vec::new();
        let Some(first) = self.lines.get(lo) else { return out };
        if self.depth >= MAX_NESTING {
            self.errors.push(Diagnostic::error(Span::new(first.at, first.at + 1), "blocks nested too deeply"));
            return out;
        }
        self.depth += 1;
        let out = self.block_lines(lo, hi, kind, first.indent, out);
        self.depth -= 1;
        out
    }

    fn block_lines(&mut self, lo: usize, hi: usize, kind: Kind, indent: usize, mut out: Vec<Stmt>) -> Vec<Stmt> {
        let mut i = lo;
        while i < hi {
            let line = &self.lines[i];
            let end = block_end(self.lines, i + 1, line.indent).min(hi);
            if line.indent != indent {
                self.errors.push(Diagnostic::error(Span::new(line.at, line.at + 1), "unexpected indentation"));
                i = end;
                continue;
            }
            let code = line.code.as_str();
            let word = leading_name(code);
            if matches!(word, "if" | "elif" | "else") {
                let arm = self.arm(i, 0, word, end, kind);
                match (word, arm) {
                    ("if", Some(a)) => out.push(Stmt::If(vec![a])),
                    (_, Some(a)) => match out.last_mut() {
                        Some(Stmt::If(arms)) if arms.last().is_some_and(|(c, _)| c.is_some()) => arms.push(a),
                        _ => self.errors.push(Diagnostic::error(
                            Span::new(line.at, line.at + word.len()),
                            format!("this `{word}` follows no `if`"),
                        )),
                    },
                    _ => {}
                }
            } else {
                if end > i + 1 {
                    self.errors.push(outside(line.at, code.len(), &construct(code)));
                    i = end;
                    continue;
                }
                if let Some(s) = self.simple(i, 0, kind) {
                    out.push(s);
                }
            }
            i = end;
        }
        out
    }

    /// An `if cond:`/`elif cond:`/`else:` line at offset `k` of line `i`
    /// with its block (the rest of the line, or lines `i + 1..end`).
    fn arm(&mut self, i: usize, k: usize, word: &str, end: usize, kind: Kind) -> Option<(Option<Py>, Vec<Stmt>)> {
        let line = &self.lines[i];
        let code = &line.code[k..];
        let after = &code[word.len()..];
        let Some(colon) = find_top(after, b':') else {
            self.errors.push(Diagnostic::error(
                Span::new(line.offset(k), line.offset(k) + code.len()),
                format!("expected `:` after `{word}`"),
            ));
            return None;
        };
        let cond = if word == "else" {
            if !after[..colon].trim().is_empty() {
                self.errors.push(Diagnostic::error(
                    Span::new(line.offset(k), line.offset(k + code.len())),
                    "expected `else:`",
                ));
                return None;
            }
            None
        } else {
            let ck = k + word.len();
            match pyexpr::parse(&after[..colon], line.offset(ck)) {
                Ok(c) => Some(c),
                Err(d) => {
                    self.errors.push(d);
                    return None;
                }
            }
        };
        let rest_k = k + word.len() + colon + 1;
        let rest = line.code[rest_k..].trim();
        let stmts = if rest.is_empty() {
            if end == i + 1 {
                self.errors.push(Diagnostic::error(
                    Span::new(line.offset(k), line.offset(k) + word.len()),
                    format!("`{word}:` without a block"),
                ));
                return None;
            }
            self.block(i + 1, end, kind)
        } else {
            if end > i + 1 {
                self.errors.push(Diagnostic::error(
                    Span::new(line.offset(rest_k), line.offset(rest_k) + rest.len()),
                    "unexpected indentation after a one-line `if`",
                ));
            }
            let lead = line.code[rest_k..].len() - line.code[rest_k..].trim_start().len();
            let w = leading_name(rest);
            if matches!(w, "if" | "elif" | "else") {
                self.errors.push(outside(
                    line.offset(rest_k + lead),
                    rest.len(),
                    "a Python `if` after `:` on one line",
                ));
                return None;
            }
            self.simple(i, rest_k + lead, kind).into_iter().collect()
        };
        Some((cond, stmts))
    }

    /// A one-line statement at offset `k` of line `i`.
    pub fn simple(&mut self, i: usize, k: usize, kind: Kind) -> Option<Stmt> {
        let line = &self.lines[i];
        let code = line.code[k..].trim_end();
        let at = line.offset(k);
        let word = leading_name(code);
        let after = &code[word.len()..];
        let bad = |this: &mut Self, what: String| {
            this.errors.push(outside(at, code.len(), &what));
            None
        };
        match word {
            "produce" | "nproduce" if after.is_empty() || after.starts_with([' ', '\t', '(', '[']) => {
                if kind != Kind::Production {
                    let where_ = if kind == Kind::Hook { "a hook" } else { "a function" };
                    return bad(self, format!("`{word}` in {where_}"));
                }
                Some(Stmt::Produce { end: word == "produce", line: i, start: k + word.len() })
            }
            "pass" if after.trim().is_empty() => None,
            "return" if kind == Kind::Function => {
                let v = after.trim();
                if v.is_empty() {
                    return Some(Stmt::Return(None, at));
                }
                let vk = k + word.len() + (after.len() - after.trim_start().len());
                match pyexpr::parse(v, line.offset(vk)) {
                    Ok(e) => Some(Stmt::Return(Some(e), at)),
                    Err(d) => {
                        self.errors.push(d);
                        None
                    }
                }
            }
            "global" if after.starts_with([' ', '\t']) => {
                if kind == Kind::Production {
                    return bad(
                        self,
                        "the Python `global` in a production body (L-Py runs productions one after another; \
                         genform rewrites in parallel and changes globals only in hooks)"
                            .into(),
                    );
                }
                Some(Stmt::Global(after.split(',').map(|n| n.trim().to_string()).filter(|n| !n.is_empty()).collect()))
            }
            "print" if after.trim_start().starts_with('(') || after.starts_with(' ') => {
                self.warnings.push(
                    Diagnostic::warning(Span::new(at, at + code.len()), "`print` is not run")
                        .with_hint("genform reads the model, not its console output"),
                );
                None
            }
            _ => {
                // The called (dotted) name, as in `rd.seed(0)`.
                let callee = find_top(code, b'(').map_or("", |k| code[..k].trim());
                let call = !callee.is_empty()
                    && callee.split('.').all(|p| !p.is_empty() && leading_name(p) == p)
                    && code.ends_with(')');
                if call && (callee == "seed" || callee.ends_with(".seed")) {
                    self.warnings.push(
                        Diagnostic::warning(Span::new(at, at + code.len()), "`seed(…)` is not followed")
                            .with_hint("genform's random draws come from the run's seed (`--seed`)"),
                    );
                    return None;
                }
                if call && callee == "useGroup" {
                    let open = code.find('(').unwrap_or(0);
                    let inner = code[open + 1..].trim_end().strip_suffix(')').unwrap_or("");
                    return match pyexpr::parse(inner, line.offset(k + open + 1)) {
                        Ok(e) => Some(Stmt::UseGroup(e, at)),
                        Err(d) => {
                            self.errors.push(d);
                            None
                        }
                    };
                }
                if let Some(pairs) = tuple_assignment(code) {
                    let mut seq = Vec::new();
                    for ((name, _), (v, vk)) in pairs {
                        match pyexpr::parse(v, line.offset(k + vk)) {
                            Ok(value) => seq.push(Stmt::Assign { name: name.to_string(), at, op: None, value }),
                            Err(d) => self.errors.push(d),
                        }
                    }
                    return Some(Stmt::Seq(seq));
                }
                if let Some((name_len, op, vk)) = assignment(code) {
                    let v = &code[vk..];
                    let lead = v.len() - v.trim_start().len();
                    return match pyexpr::parse(v.trim(), line.offset(k + vk + lead)) {
                        Ok(value) => Some(Stmt::Assign { name: code[..name_len].to_string(), at, op, value }),
                        Err(d) => {
                            self.errors.push(d);
                            None
                        }
                    };
                }
                let what = match kind {
                    Kind::Production => format!("{} in a production body", construct(code)),
                    Kind::Hook => format!("{} in a hook", construct(code)),
                    Kind::Function => format!("{} in a function", construct(code)),
                };
                bad(self, what)
            }
        }
    }
}

/// A function body as one expression: assignments are substituted,
/// `if`/`else` with `return` become conditional expressions.
pub(super) fn reduce(stmts: &[Stmt], env: &mut Vec<(String, Py)>, at: usize) -> Result<Py, Diagnostic> {
    for (k, s) in stmts.iter().enumerate() {
        match s {
            Stmt::Assign { name, op, value, at } => {
                let value = match op {
                    None => value.clone(),
                    Some(op) => {
                        let op = match op {
                            '+' => "+",
                            '-' => "-",
                            '*' => "*",
                            _ => "/",
                        };
                        Py::Bin(op, *at, Box::new(Py::Name(name.clone(), *at)), Box::new(value.clone()))
                    }
                };
                let v = subst_env(&value, env);
                match env.iter_mut().find(|(n, _)| n == name) {
                    Some(slot) => slot.1 = v,
                    None => env.push((name.clone(), v)),
                }
            }
            Stmt::Return(Some(e), _) => return Ok(subst_env(e, env)),
            Stmt::Return(None, at) => {
                return Err(Diagnostic::error(Span::new(*at, at + 6), "a function that returns nothing"));
            }
            Stmt::If(arms) => {
                let rest = &stmts[k + 1..];
                let mut result: Option<Py> = None;
                let has_else = arms.last().is_some_and(|(c, _)| c.is_none());
                let mut tail = if has_else { None } else { Some(reduce(rest, &mut env.clone(), at)?) };
                for (cond, body) in arms.iter().rev() {
                    let mut joined = body.clone();
                    joined.extend_from_slice(rest);
                    let value = reduce(&joined, &mut env.clone(), at)?;
                    result = Some(match cond {
                        None => value,
                        Some(c) => {
                            let other = result.take().or_else(|| tail.take());
                            match other {
                                Some(o) => Py::Cond(Box::new(subst_env(c, env)), Box::new(value), Box::new(o)),
                                None => value,
                            }
                        }
                    });
                }
                return result.ok_or_else(|| Diagnostic::error(Span::new(at, at + 3), "an empty `if`"));
            }
            Stmt::Global(_) => {}
            Stmt::Seq(inner) => {
                let mut joined = inner.clone();
                joined.extend_from_slice(&stmts[k + 1..]);
                return reduce(&joined, env, at);
            }
            Stmt::Produce { .. } | Stmt::UseGroup(..) => {
                return Err(Diagnostic::error(Span::new(at, at + 3), "a function with effects"));
            }
        }
    }
    Err(Diagnostic::error(Span::new(at, at + 3), "a function that returns nothing"))
}

fn subst_env(e: &Py, env: &[(String, Py)]) -> Py {
    let (names, values): (Vec<String>, Vec<Py>) = env.iter().cloned().unzip();
    pyexpr::substitute(e, &names, &values)
}

/// Writes statements as `.ls` statement lines, each after `guard` (`if
/// lpy_k1 == 2: `), numbering hidden variables from `temps`.
pub(super) struct Writer<'a> {
    pub names: &'a Names,
    pub lines: &'a [Line],
    pub kind: Kind,
    /// Hidden variables used so far (hooks declare them as globals).
    pub temps: &'a mut Vec<String>,
    pub errors: &'a mut Vec<Diagnostic>,
    /// Writes a module string: (out, line, start offset in its code).
    pub modules: &'a WriteModules<'a>,
}

impl Writer<'_> {
    /// Writes `stmts`, one per line, each after `guard`.
    pub fn write(&mut self, stmts: &[Stmt], guard: &str, at: usize, out: &mut Out) {
        for s in stmts {
            match s {
                Stmt::Produce { end, line, start } => {
                    out.push(guard, at);
                    let l = &self.lines[*line];
                    out.push(if *end { "produce" } else { "nproduce" }, l.offset(start.saturating_sub(7)));
                    (self.modules)(out, l, *start, self.errors);
                    out.newline();
                }
                Stmt::Assign { name, at, op, value } => {
                    out.push(guard, *at);
                    let to = self.names.renamed.iter().find(|(p, _)| p == name).map_or(name.as_str(), |(_, t)| t);
                    out.push(to, *at);
                    out.push(" = ", *at);
                    if let Some(op) = op {
                        out.push(to, *at);
                        out.push(&format!(" {op} ("), *at);
                        self.names.emit(value, out, self.errors);
                        out.push(")", *at);
                    } else {
                        self.names.emit(value, out, self.errors);
                    }
                    out.newline();
                }
                Stmt::UseGroup(e, at) => {
                    if self.kind == Kind::Production {
                        self.errors.push(outside(*at, 8, "`useGroup` in a production body"));
                        continue;
                    }
                    out.push(guard, *at);
                    out.push(super::names::GROUP, *at);
                    out.push(" = ", *at);
                    self.names.emit(e, out, self.errors);
                    out.newline();
                }
                Stmt::If(arms) => self.conditional(arms, guard, out),
                Stmt::Seq(inner) => self.write(inner, guard, at, out),
                Stmt::Return(_, at) => self.errors.push(outside(*at, 6, "the Python `return` in a production body")),
                Stmt::Global(_) => {}
            }
        }
    }

    fn conditional(&mut self, arms: &[(Option<Py>, Vec<Stmt>)], guard: &str, out: &mut Out) {
        let at = arms.first().and_then(|(c, _)| c.as_ref()).map_or(0, pyexpr::at_of);
        let one_liners = arms.iter().all(|(_, b)| {
            b.len() == 1 && matches!(b[0], Stmt::Produce { .. } | Stmt::Assign { .. } | Stmt::UseGroup(..))
        });
        if guard.is_empty() && one_liners {
            for (k, (cond, body)) in arms.iter().enumerate() {
                match cond {
                    Some(c) => {
                        out.push(if k == 0 { "if " } else { "elif " }, pyexpr::at_of(c));
                        self.names.emit(c, out, self.errors);
                        out.push(": ", pyexpr::at_of(c));
                    }
                    None => out.push("else: ", at),
                }
                // The statement writes its own line end.
                self.write(body, "", at, out);
                // `write` ended the line; the next arm starts a new one.
            }
            return;
        }
        let name = format!("lpy_k{}", self.temps.len() + 1);
        self.temps.push(name.clone());
        out.push(guard, at);
        out.push(&name, at);
        out.push(" = ", at);
        let mut closes: i32 = 0;
        for (k, (cond, _)) in arms.iter().enumerate() {
            match cond {
                Some(c) => {
                    out.push("(", pyexpr::at_of(c));
                    self.names.emit(c, out, self.errors);
                    out.push(&format!(" ? {} : ", k + 1), pyexpr::at_of(c));
                    closes += 1;
                }
                None => {
                    out.push(&(k + 1).to_string(), at);
                    closes = -closes;
                }
            }
        }
        if closes >= 0 {
            out.push("0", at);
        }
        out.push(&")".repeat(closes.unsigned_abs() as usize), at);
        out.newline();
        for (k, (_, body)) in arms.iter().enumerate() {
            let g = format!("{guard}if {name} == {}: ", k + 1);
            self.write(body, &g, at, out);
        }
    }
}
