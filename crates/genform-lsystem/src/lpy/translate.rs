//! A whole `.lpy` file translated into `.ls` text.
//!
//! Two passes over the logical lines: the first collects imports, small
//! functions and hooks (a name a hook assigns is a `global`, every other
//! module-level constant a `define`); the second writes the L-system
//! part, module-level constants and production bodies in file order, then
//! the hooks.

use super::block::{self, Kind, Reader, Stmt, Writer};
use super::names::{EMPTY, GROUP, PRELUDE, canonical, long_names};
use super::pyexpr::{self, Func, Names, Py};
use super::pytypes::{Facts, Scope, Slot};
use super::text::{
    Line, Out, Translation, assignment, construct, find_top, is_name, leading_name, logical_lines, outside,
};
use crate::syntax::module_name_len;
use genform_core::{Diagnostic, Span};

/// L-Py's hooks that the `.ls` language has, with its section name.
const HOOKS: &[(&str, &str)] =
    &[("Start", "Start"), ("StartEach", "StartEach"), ("EndEach", "EndEach"), ("End", "End")];

/// An L-Py rewriting feature the `.ls` language lacks, as an error.
fn feature(at: usize, len: usize, what: &str) -> Diagnostic {
    Diagnostic::error(Span::new(at, at + len.max(1)), format!("{what} is not read by genform"))
        .with_hint("L-Py (the Python package) runs it; genform's `.ls` rules have no such construct yet")
}

/// Whether `name` occurs in `text` as a run of name characters of its own.
fn mentions(text: &str, name: &str) -> bool {
    text.match_indices(name).any(|(i, _)| {
        let before = text[..i].chars().next_back().is_none_or(|c| !c.is_alphanumeric() && c != '_');
        let after = text[i + name.len()..].chars().next().is_none_or(|c| !c.is_alphanumeric() && c != '_');
        before && after
    })
}

/// The offset of the rule arrow (`-->` or `->`) outside parentheses, and
/// its length.
fn arrow(code: &str) -> Option<(usize, usize)> {
    let b = code.as_bytes();
    let mut depth = 0i32;
    for i in 0..b.len() {
        match b[i] {
            b'(' => depth += 1,
            b')' => depth -= 1,
            b'-' if depth == 0 => {
                if b[i..].starts_with(b"-->") {
                    return Some((i, 3));
                }
                if b[i..].starts_with(b"->") {
                    return Some((i, 2));
                }
            }
            _ => {}
        }
    }
    None
}

/// A `def` of the file.
struct Def {
    name: String,
    params: Vec<String>,
    /// Its line and the lines of its block (`lo..hi`; empty for a
    /// one-line `def f(x): return x`).
    line: usize,
    lo: usize,
    hi: usize,
}

/// Reads `def name(a, b):` at line `i`.
fn def_head(line: &Line) -> Option<(String, Vec<String>, usize)> {
    let code = line.code.strip_prefix("def")?.strip_prefix([' ', '\t'])?;
    let name = leading_name(code.trim_start()).to_string();
    let open = code.find('(')?;
    let close = code.find(')')?;
    let params =
        code.get(open + 1..close)?.split(',').map(|p| p.trim().to_string()).filter(|p| !p.is_empty()).collect();
    let colon = close + code[close..].find(':')?;
    let body_k = line.code.len() - code.len() + colon + 1;
    Some((name, params, body_k))
}

/// The translation state of the second pass.
struct Tr<'a> {
    lines: &'a [Line],
    names: Names,
    out: Out,
    errors: Vec<Diagnostic>,
    warnings: Vec<Diagnostic>,
    /// Names hooks assign: module-level globals.
    globals: Vec<String>,
    /// Whether `useGroup` is called: groups are conditions on a global.
    groups: bool,
    /// Hidden variables of production bodies (numbered with the hooks').
    temps: Vec<String>,
    /// The axiom is empty.
    empty_axiom: bool,
    /// `module A = F`: (A, F).
    aliases: Vec<(String, String)>,
    /// What types the modules' parameters (floats print as `6.0`).
    facts: Facts,
}

/// Translates an L-Py file into `.ls` text, or says why it cannot.
pub(super) fn translate(src: &str) -> Result<Translation, Vec<Diagnostic>> {
    let lines = logical_lines(src);
    let mut tr = Tr {
        lines: &lines,
        names: Names::default(),
        out: Out { text: String::new(), map: Vec::new() },
        errors: Vec::new(),
        warnings: Vec::new(),
        globals: Vec::new(),
        groups: mentions(src, "useGroup"),
        temps: Vec::new(),
        empty_axiom: false,
        aliases: Vec::new(),
        facts: Facts::default(),
    };
    tr.out.push(PRELUDE, 0);
    tr.declare_modules(src);

    // First pass: imports and defs.
    let mut defs = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let line = &lines[i];
        let end = block::block_end(&lines, i + 1, line.indent);
        if line.indent == 0 {
            if let Some((name, params, body_k)) = def_head(line) {
                let (lo, hi) = if line.code[body_k..].trim().is_empty() { (i + 1, end) } else { (i, i) };
                defs.push(Def { name, params, line: i, lo, hi });
            } else {
                tr.import(line, false);
            }
        }
        i = end.max(i + 1);
    }
    // The editor's scalars (`scalars = [('N', 'Integer', 5, 0, 9)]` in
    // `__initialiseContext__`) are constants; with their slider's range
    // they are ranged constants, genes of the generator.
    let mut scalars: Vec<(String, f64)> = Vec::new();
    for d in defs.iter().filter(|d| d.name == "__initialiseContext__") {
        for l in &lines[d.lo..d.hi] {
            if let Some(list) = l.code.strip_prefix("scalars").map(str::trim_start).and_then(|r| r.strip_prefix('=')) {
                for sc in editor_scalars(list) {
                    let at = l.at;
                    let range = sc.range_text();
                    if sc.range.is_some() && range.is_none() {
                        tr.warnings.push(
                            Diagnostic::warning(
                                Span::new(at, at + l.code.len()),
                                format!("the editor's range of the scalar `{}` is not used", sc.name),
                            )
                            .with_hint(format!(
                                "its value must lie inside a finite range (whole numbers for an Integer); \
                                 `{}` is read as a plain constant, not a gene",
                                sc.name
                            )),
                        );
                    }
                    tr.out.push(&format!("define {} = {}{}\n", sc.name, sc.value, range.unwrap_or_default()), at);
                    tr.facts.consts.push((sc.name.clone(), sc.python_value()));
                    scalars.push((sc.name, sc.value));
                }
            }
        }
    }
    // Hooks: their statements, and the globals they assign.
    let mut hooks: Vec<(&str, Vec<Stmt>)> = Vec::new();
    let mut funcs = Vec::new();
    for d in &defs {
        if d.name == "__initialiseContext__" {
            let l = &lines[d.line];
            // Only the scalars (read above), with the loop L-Py's editor
            // writes to set each one (the old editor's or the new's):
            // nothing is left out.
            let scalars_only = lines[d.lo..d.hi].iter().all(|b| {
                let c = b.code.replace([' ', '\''], "").replace('"', "");
                c.starts_with("scalars=")
                    || [
                        "context[__scalars__]=scalars",
                        "forsinscalars:",
                        "ifnots[1]==Category:context[s[0]]=s[2]",
                        "forn,v,mnv,mxvinscalars:",
                        "context[n]=v",
                    ]
                    .contains(&c.as_str())
            });
            if scalars_only && d.lo < d.hi {
                continue;
            }
            tr.warnings.push(
                Diagnostic::warning(Span::new(l.at, l.at + l.code.len()), "L-Py's `__initialiseContext__` is not read")
                    .with_hint(
                        "its materials, options and animation settings are ignored; colours come from genform's table",
                    ),
            );
            continue;
        }
        let mut reader = Reader { lines: &lines, errors: Vec::new(), warnings: Vec::new(), depth: 0 };
        let hook = HOOKS.iter().find(|(n, _)| *n == d.name).map(|(_, s)| *s);
        let kind = if hook.is_some() { Kind::Hook } else { Kind::Function };
        let stmts = if d.lo == d.hi {
            let (_, _, k) = def_head(&lines[d.line]).unwrap_or_default();
            let lead = lines[d.line].code[k..].len() - lines[d.line].code[k..].trim_start().len();
            reader.simple(d.line, k + lead, kind).into_iter().collect()
        } else {
            reader.block(d.lo, d.hi, kind)
        };
        let l = &lines[d.line];
        match hook {
            Some(section) => {
                // A hook's parameter (`EndEach(lstring)`) is the derived string.
                // Lines that only print it do not count (printing is not run).
                let body_text: String = lines[d.lo..d.hi]
                    .iter()
                    .map(|l| l.code.as_str())
                    .filter(|c| leading_name(c) != "print")
                    .collect::<Vec<_>>()
                    .join("\n");
                if let Some(p) = d.params.iter().find(|p| mentions(&body_text, p)) {
                    tr.errors.push(outside(
                        l.at,
                        l.code.len(),
                        &format!("the hook `{}({p})` reads the derived string", d.name),
                    ));
                }
                tr.errors.extend(reader.errors);
                tr.warnings.extend(reader.warnings);
                collect_globals(&stmts, &mut tr.globals);
                collect_assignments(&stmts, &mut tr.facts.consts);
                hooks.push((section, stmts));
            }
            None => {
                let body = match reader.errors.into_iter().next() {
                    Some(e) => Err(e),
                    None => block::reduce(&stmts, &mut Vec::new(), l.at),
                };
                funcs.push(Func { name: d.name.clone(), params: d.params.clone(), body });
            }
        }
    }
    tr.names.funcs = funcs;
    if tr.groups {
        tr.out.push(&format!("global {GROUP} = 0\n"), 0);
    }

    // Second pass: everything else, in file order.
    let mut section: Option<&str> = None;
    let mut after_end = false;
    let mut group = 0u32;
    let mut assigned: Vec<String> = Vec::new();
    let mut values: Vec<(String, f64)> = scalars.clone();
    let last_axiom = lines.iter().rposition(|l| l.indent == 0 && header(&l.code, &["Axiom:", "axiom:"]).is_some());
    let mut i = 0;
    while i < lines.len() {
        let line = &lines[i];
        let end = block::block_end(&lines, i + 1, line.indent);
        let next = end.max(i + 1);
        let code = line.code.as_str();
        let at = line.at;
        if line.indent > 0 {
            tr.errors.push(outside(at, code.len(), &construct(code)));
            i = next;
            continue;
        }
        if def_head(line).is_some() || code.starts_with("import ") || code.starts_with("from ") {
            if code.starts_with("import ") || code.starts_with("from ") {
                tr.import(line, true);
            }
            i = next;
            continue;
        }
        if code == "endlsystem" {
            after_end = true;
            section = None;
        } else if let Some((w, _)) = header(code, &["Axiom:", "axiom:"]) {
            if Some(i) != last_axiom {
                tr.warnings.push(
                    Diagnostic::warning(Span::new(at, at + code.len()), "a later `Axiom:` replaces this one")
                        .with_hint("L-Py reads the last axiom of the file"),
                );
            } else if end > i + 1 {
                tr.errors.push(outside(at, code.len(), "an axiom computed by Python code"));
            }
            if Some(i) == last_axiom {
                tr.out.push("axiom:", at);
                if code[w..].trim().is_empty() {
                    // L-Py derives an empty axiom; `.ls` needs a module,
                    // which `compile_lpy` takes out again.
                    tr.out.push(" ", at);
                    tr.out.push(EMPTY, at);
                    tr.empty_axiom = true;
                } else {
                    for (m, args) in write_modules(&tr.names, &mut tr.out, line, w, false, &mut tr.errors) {
                        tr.facts.write(&m, args, None);
                    }
                }
            }
        } else if let Some((w, rest)) = header(code, &["derivation length:"]) {
            tr.out.push("derivation: ", at);
            tr.formula(rest, line.offset(w));
        } else if let Some((w, rest)) = header(code, &["maximum depth:"]) {
            tr.out.push("maxdepth: ", at);
            // `.ls` takes a whole number: a formula of module constants is
            // computed here.
            let value = pyexpr::parse(rest.trim(), line.offset(w))
                .ok()
                .and_then(|e| pyexpr::constant(&e, &values))
                .filter(|v| v.fract() == 0.0 && (0.0..=1e6).contains(v));
            match value {
                Some(v) => tr.out.push(&format!("{v}"), line.offset(w)),
                None => tr.out.push(rest.trim(), line.offset(w)),
            }
        } else if let Some((w, _)) = header(code, &["ignore:", "consider:"]) {
            tr.out.push(if code.starts_with("ignore") { "ignore:" } else { "consider:" }, at);
            tr.modules(line, w, false);
        } else if let Some(kind) = ["production:", "decomposition:", "interpretation:", "homomorphism:"]
            .into_iter()
            .find(|h| header(code, &[h]).is_some_and(|(_, r)| r.trim().is_empty()))
        {
            tr.out.push(kind, at);
            section = Some(kind);
            group = 0;
        } else if let Some(rest) = code.strip_prefix("group ") {
            let n = rest.trim_end_matches(':').trim();
            match n.parse::<u32>() {
                Ok(n) => group = n,
                Err(_) => tr.errors.push(Diagnostic::error(Span::new(at, at + code.len()), "expected `group N:`")),
            }
            if group != 0 && !tr.groups {
                tr.warnings.push(
                    Diagnostic::warning(Span::new(at, at + code.len()), format!("the rules of group {n} are left out"))
                        .with_hint("only group 0 is active unless the file calls `useGroup`"),
                );
            }
        } else if code == "endgroup" {
            group = 0;
        } else if code.starts_with("module ") || code.starts_with("module\t") {
            // Declared before.
        } else if let Some(a) =
            header(code, &["context().turtle.setAngleIncrement(", "execContext().turtle.setAngleIncrement("])
                .and_then(|(w, r)| r.strip_suffix(')').map(|r| (w, r)))
        {
            tr.out.push("angle: ", at);
            tr.formula(a.1, line.offset(a.0));
        } else if section.is_some() && !after_end && (arrow(code).is_some() || is_rule_head(code)) {
            if group != 0 && !tr.groups {
                // Left out (warned at `group N:`).
            } else {
                tr.rule(i, end, group, section);
            }
        } else if let Some(pairs) = block::tuple_assignment(code).filter(|_| !code.starts_with("__")) {
            // `a, b = 1, 2`: one constant after the other.
            for ((name, _), (v, vk)) in pairs {
                let global = tr.globals.iter().any(|n| n == name);
                assigned.push(name.to_string());
                tr.out.push(if global { "global " } else { "define " }, at);
                tr.out.push(name, at);
                tr.out.push(" = ", at);
                match pyexpr::parse(v, line.offset(vk)) {
                    Ok(e) => {
                        tr.facts.consts.push((name.to_string(), e.clone()));
                        if let Some(x) = pyexpr::constant(&e, &values) {
                            values.push((name.to_string(), x));
                        }
                        tr.names.emit(&e, &mut tr.out, &mut tr.errors);
                    }
                    Err(d) => tr.errors.push(d),
                }
                tr.out.newline();
            }
        } else if let Some((name_len, op, vk)) = assignment(code) {
            let name = &code[..name_len];
            if name.starts_with("__") {
                // Metadata (`__copyright__ = …`).
            } else if assigned.iter().any(|n| n == name) && tr.globals.iter().any(|n| n == name) {
                tr.errors.push(outside(at, code.len(), &format!("a second assignment to the global `{name}`")));
            } else {
                // A constant assigned again (`R *= R`) is defined again:
                // `.ls` constants are read in file order, as Python runs.
                let global = tr.globals.iter().any(|n| n == name);
                assigned.push(name.to_string());
                tr.out.push(if global { "global " } else { "define " }, at);
                tr.out.push(name, at);
                tr.out.push(" = ", at + vk - 1);
                let v = &code[vk..];
                let lead = v.len() - v.trim_start().len();
                let vat = line.offset(vk + lead);
                match pyexpr::parse(v.trim(), vat) {
                    Ok(e) => {
                        let e = pyexpr::compound(name, at, op, e);
                        tr.facts.consts.push((name.to_string(), e.clone()));
                        if let Some(x) = pyexpr::constant(&e, &values) {
                            values.push((name.to_string(), x));
                        }
                        tr.names.emit(&e, &mut tr.out, &mut tr.errors);
                    }
                    Err(d) => tr.errors.push(d),
                }
            }
        } else if let Some(rest) = code.strip_prefix("assert ") {
            // A module-level check of constants holds or stops the file.
            let k = code.len() - rest.len();
            let rest = rest.split(',').next().unwrap_or(rest);
            match pyexpr::parse(rest.trim(), line.offset(k)).map(|e| pyexpr::constant(&e, &values)) {
                Ok(Some(v)) if v != 0.0 && !v.is_nan() => {}
                Ok(Some(_)) => {
                    tr.errors.push(Diagnostic::error(Span::new(at, at + code.len()), "this assertion fails"))
                }
                _ => tr.errors.push(outside(at, code.len(), "the Python `assert`")),
            }
        } else if (code.starts_with('\'') || code.starts_with('"'))
            && (code.ends_with('\'') || code.ends_with('"'))
            && code.len() > 1
        {
            // A string statement (a comment in Python).
        } else if code.starts_with("print ") {
            // Python 2's `print x`.
            tr.warnings.push(
                Diagnostic::warning(Span::new(at, at + code.len()), "`print` is not run")
                    .with_hint("genform reads the model, not its console output"),
            );
        } else if let Some(stmt) = module_call(code) {
            match stmt {
                "seed" => tr.warnings.push(
                    Diagnostic::warning(Span::new(at, at + code.len()), "`seed(…)` is not followed")
                        .with_hint("genform's random draws come from the run's seed (`--seed`)"),
                ),
                _ => tr.warnings.push(
                    Diagnostic::warning(Span::new(at, at + code.len()), "`print` is not run")
                        .with_hint("genform reads the model, not its console output"),
                ),
            }
        } else {
            tr.errors.push(outside(at, code.len(), &construct(code)));
        }
        tr.out.newline();
        i = next;
    }

    if last_axiom.is_none() {
        // L-Py runs a file without `Axiom:` (a part composed into another
        // L-system) from an empty axiom.
        tr.warnings.push(
            Diagnostic::warning(Span::new(0, 0), "the file has no `Axiom:`; it derives from an empty axiom")
                .with_hint("L-Py composes such files into other L-systems from Python"),
        );
        tr.out.push(&format!("axiom: {EMPTY}\n"), 0);
        tr.empty_axiom = true;
    }
    // Globals the hooks assign but the module does not define.
    for g in tr.globals.clone() {
        if !assigned.contains(&g) && g != GROUP {
            tr.out.push(&format!("global {g} = 0\n"), 0);
        }
    }
    // The hooks, after everything else (sections switch in `.ls`).
    let body_temps = tr.temps.len();
    for (section, stmts) in &hooks {
        tr.out.push(&format!("{section}:\n"), 0);
        let names = std::mem::take(&mut tr.names);
        let modules = |_: &mut Out, _: &Line, _: usize, _: &mut Vec<Diagnostic>| {};
        let mut w = Writer {
            names: &names,
            lines: &lines,
            kind: Kind::Hook,
            temps: &mut tr.temps,
            errors: &mut tr.errors,
            modules: &modules,
        };
        w.write(stmts, "", 0, &mut tr.out);
        tr.names = names;
    }
    for t in &tr.temps[body_temps..] {
        tr.out.push(&format!("global {t} = 0\n"), 0);
    }
    if tr.errors.is_empty() {
        Ok(Translation {
            params: tr.facts.solve(&tr.names),
            text: tr.out.text,
            map: tr.out.map,
            warnings: tr.warnings,
            empty_axiom: tr.empty_axiom,
            aliases: tr.aliases,
        })
    } else {
        Err(tr.errors)
    }
}

/// One of the editor's scalars: its name, value and, for a slider, its
/// range and whether it is whole numbers.
struct Scalar {
    name: String,
    value: f64,
    /// `(min, max, integer)`.
    range: Option<(f64, f64, bool)>,
    /// `Integer`, `Float` or `Bool`.
    kind: String,
}

impl Scalar {
    /// The scalar as the Python value L-Py gives it (for typing).
    fn python_value(&self) -> Py {
        match self.kind.as_str() {
            "Bool" => Py::Name("True".into(), 0),
            "Float" => Py::Num("0.0".into(), 0),
            _ => Py::Num("0".into(), 0),
        }
    }

    /// ` in min..max` or ` in [min, max]` when the range is usable (finite,
    /// holding the value, whole for an Integer); `None` otherwise.
    fn range_text(&self) -> Option<String> {
        let (min, max, integer) = self.range?;
        let v = self.value;
        let finite = v.is_finite() && min.is_finite() && max.is_finite();
        let whole = !integer || (v.fract() == 0.0 && min.fract() == 0.0 && max.fract() == 0.0);
        if !(finite && whole && min <= v && v <= max) {
            return None;
        }
        Some(format!(" in {}", crate::ranged::range_text(integer, min, max)))
    }
}

/// The editor's scalar list `[('N', 'Integer', 5, 0, 9), ('B', 'Bool',
/// True), ('X', 18, -100, 100), ('A', 'Float', 30.0, 0.0, 90.0, 2), ('C',
/// 'Category')]`: an untyped scalar is an Integer, a Bool ranges over 0..1,
/// a Float's number of decimals (the slider's precision) is not read.
fn editor_scalars(list: &str) -> Vec<Scalar> {
    let mut out = Vec::new();
    for item in list.split('(').skip(1) {
        let fields: Vec<&str> = item.split(')').next().unwrap_or("").split(',').map(str::trim).collect();
        let quoted = |f: &str| f.strip_prefix('\'').and_then(|f| f.strip_suffix('\'')).map(str::to_string);
        let Some(name) = fields.first().and_then(|f| quoted(f)) else { continue };
        let (kind, rest) = match fields.get(1).and_then(|f| quoted(f)) {
            Some(kind) => (kind, &fields[2.min(fields.len())..]),
            None => ("Integer".to_string(), &fields[1.min(fields.len())..]),
        };
        let number = |f: Option<&&str>| match f.copied() {
            Some("True") => Some(1.0),
            Some("False") => Some(0.0),
            Some(v) => v.parse::<f64>().ok(),
            None => None,
        };
        let Some(value) = number(rest.first()) else { continue };
        let range = match kind.as_str() {
            "Bool" => Some((0.0, 1.0, true)),
            "Integer" | "Float" => match (number(rest.get(1)), number(rest.get(2))) {
                (Some(min), Some(max)) => Some((min, max, kind == "Integer")),
                _ => None,
            },
            _ => None,
        };
        if leading_name(&name) == name && !name.is_empty() {
            out.push(Scalar { name, value, range, kind });
        }
    }
    out
}

/// Every assignment of `stmts`, in any branch (`x += 1` as `x + 1`).
fn collect_assignments(stmts: &[Stmt], out: &mut Vec<(String, Py)>) {
    for s in stmts {
        match s {
            Stmt::Assign { name, at, op, value } => {
                out.push((name.clone(), pyexpr::compound(name, *at, *op, value.clone())))
            }
            Stmt::If(arms) => {
                for (_, b) in arms {
                    collect_assignments(b, out);
                }
            }
            Stmt::Seq(inner) => collect_assignments(inner, out),
            _ => {}
        }
    }
}

/// Every name a hook assigns or declares `global`.
fn collect_globals(stmts: &[Stmt], out: &mut Vec<String>) {
    for s in stmts {
        match s {
            Stmt::Assign { name, .. } if !out.contains(name) => out.push(name.clone()),
            Stmt::Global(names) => {
                for n in names {
                    if !out.contains(n) {
                        out.push(n.clone());
                    }
                }
            }
            Stmt::If(arms) => {
                for (_, b) in arms {
                    collect_globals(b, out);
                }
            }
            Stmt::Seq(inner) => collect_globals(inner, out),
            _ => {}
        }
    }
}

/// A module-level statement genform passes over: `seed(…)` or `print(…)`.
fn module_call(code: &str) -> Option<&'static str> {
    let open = find_top(code, b'(')?;
    let callee = code[..open].trim();
    if !code.trim_end().ends_with(')') {
        return None;
    }
    if callee == "seed" || callee.ends_with(".seed") {
        Some("seed")
    } else if callee == "print" {
        Some("print")
    } else {
        None
    }
}

/// Whether a line is a production with a Python body (`A(x) :` or `A :
/// produce B`) rather than a Python block head.
fn is_rule_head(code: &str) -> bool {
    let word = leading_name(code);
    if matches!(word, "if" | "elif" | "else" | "for" | "while" | "def" | "class" | "with" | "try" | "except") {
        return false;
    }
    find_top(code, b':').is_some_and(|k| !code[k + 1..].starts_with('='))
}

/// Where a header word starts a line: its length and the text after it.
/// L-Py also reads a space before the colon (`Axiom : F`).
fn header<'a>(code: &'a str, words: &[&str]) -> Option<(usize, &'a str)> {
    words.iter().find_map(|w| {
        let word = w.strip_suffix(':').unwrap_or(w);
        let rest = code.strip_prefix(word)?;
        let spaced = rest.trim_start_matches([' ', '\t']);
        let rest = if w.ends_with(':') { spaced.strip_prefix(':')? } else { rest };
        Some((code.len() - rest.len(), rest))
    })
}

/// The items of a comma-separated list, not split inside parentheses:
/// `Apex(age), Internode(length, radius)` is two items.
fn top_level_items(list: &str) -> Vec<&str> {
    let (mut out, mut depth, mut start) = (Vec::new(), 0i32, 0);
    for (i, c) in list.char_indices() {
        match c {
            '(' | '[' => depth += 1,
            ')' | ']' => depth -= 1,
            ',' if depth <= 0 => {
                out.push(&list[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(&list[start..]);
    out
}

impl Tr<'_> {
    /// `module A, B` declarations and the predefined long names the file
    /// mentions, declared first so the whole file reads them.
    fn declare_modules(&mut self, src: &str) {
        let mut names: Vec<(String, usize)> = Vec::new();
        for line in self.lines {
            let Some(rest) = line.code.strip_prefix("module").filter(|r| r.starts_with([' ', '\t'])) else {
                continue;
            };
            if line.indent > 0 {
                continue;
            }
            let base = "module".len();
            // `: scale = n` (multiscale) and `: base = M` are not read.
            let rest = &rest[..rest.find(':').unwrap_or(rest.len())];
            let mut pos = 0;
            for item in top_level_items(rest) {
                let lead = item.len() - item.trim_start().len();
                let name = leading_name(item.trim_start());
                let nat = line.offset(base + pos + lead);
                if let Some(k) = item.find('=') {
                    // `module A = F`: A draws as F.
                    let target = item[k + 1..].trim();
                    if !name.is_empty() && !target.is_empty() {
                        names.push((name.to_string(), nat));
                        self.aliases.push((name.to_string(), target.to_string()));
                    } else {
                        let eq = line.offset(base + pos + k);
                        self.errors.push(Diagnostic::error(Span::new(eq, eq + 1), "expected `module A = B`"));
                    }
                } else if !name.is_empty() && !name.as_bytes()[0].is_ascii_digit() {
                    names.push((name.to_string(), nat));
                }
                pos += item.len() + 1;
            }
        }
        for name in long_names() {
            if name.len() > 1 && mentions(src, name) && !names.iter().any(|(n, _)| n == name) {
                names.push((name.to_string(), 0));
            }
        }
        let last_axiom =
            self.lines.iter().rev().find_map(|l| header(&l.code, &["Axiom:", "axiom:"]).filter(|_| l.indent == 0));
        if last_axiom.is_none_or(|(_, rest)| rest.trim().is_empty()) {
            names.push((EMPTY.to_string(), 0));
        }
        let long: Vec<&(String, usize)> = names.iter().filter(|(n, _)| n.chars().count() > 1).collect();
        self.names.modules = long.iter().map(|(n, _)| n.clone()).collect();
        if !long.is_empty() {
            self.out.push("module:", 0);
            for (n, at) in long {
                self.out.push(" ", *at);
                self.out.push(n, *at);
            }
            self.out.newline();
        }
    }

    /// An import: `math` and `random` are read (`report` in the second
    /// pass, where anything else is an error).
    fn import(&mut self, line: &Line, report: bool) {
        let code = line.code.as_str();
        let refuse = |this: &mut Self| {
            if report {
                this.errors.push(outside(line.at, code.len(), &construct(code)));
            }
        };
        if let Some(rest) = code.strip_prefix("import ") {
            for item in rest.split(',') {
                let mut words = item.split_whitespace();
                let module = words.next().unwrap_or("");
                let alias = match (words.next(), words.next()) {
                    (Some("as"), Some(a)) => a,
                    _ => module,
                };
                match module {
                    "math" => self.names.math.push(alias.to_string()),
                    "random" => self.names.random.push(alias.to_string()),
                    _ => refuse(self),
                }
            }
        } else if let Some(rest) = code.strip_prefix("from ") {
            let module = rest.split_whitespace().next().unwrap_or("");
            // PlantGL's names are Python objects: a file that uses one
            // stops at that use; importing them changes nothing here.
            if !matches!(module, "math" | "random" | "openalea.plantgl.all" | "openalea.plantgl.math") {
                refuse(self);
            }
        }
    }

    /// Writes a Python formula.
    fn formula(&mut self, text: &str, at: usize) {
        match pyexpr::parse(text.trim(), at + (text.len() - text.trim_start().len())) {
            Ok(e) => self.names.emit(&e, &mut self.out, &mut self.errors),
            Err(d) => self.errors.push(d),
        }
    }

    /// Writes the module string `line.code[start..]` (not written into the
    /// derived string).
    fn modules(&mut self, line: &Line, start: usize, erase_star: bool) {
        write_modules(&self.names, &mut self.out, line, start, erase_star, &mut self.errors);
    }

    /// A production at line `i` (its block ends before `end`).
    fn rule(&mut self, i: usize, end: usize, group: u32, section: Option<&str>) {
        // Interpretation rules write nothing into the derived string.
        let writes = matches!(section, Some("production:" | "decomposition:"));
        let line = &self.lines[i];
        let code = line.code.as_str();
        let cond = if group != 0 { format!(" : {GROUP} == {group}") } else { String::new() };
        if let Some((k, len)) = arrow(code) {
            if end > i + 1 {
                self.errors.push(Diagnostic::error(
                    Span::new(self.lines[i + 1].at, self.lines[i + 1].at + 1),
                    "unexpected indentation after a production",
                ));
            }
            self.pred(line, &code[..k], &cond);
            self.out.push(" ->", line.offset(k));
            let mut s = k + len;
            s += code[s..].len() - code[s..].trim_start().len();
            let uses = write_modules(&self.names, &mut self.out, line, s, true, &mut self.errors);
            if writes {
                self.record(&code[..k], section, Vec::new(), uses);
            }
            self.always_applies(&code[..k], group, section);
            return;
        }
        let Some(colon) = find_top(code, b':') else { return };
        let mut reader = Reader { lines: self.lines, errors: Vec::new(), warnings: Vec::new(), depth: 0 };
        let rest = code[colon + 1..].trim();
        let stmts = if rest.is_empty() {
            if end == i + 1 {
                self.errors.push(
                    Diagnostic::error(Span::new(line.at, line.at + code.len()), "a production body without `produce`")
                        .with_hint("give the successor with `-->` or a `produce` line"),
                );
                return;
            }
            reader.block(i + 1, end, Kind::Production)
        } else {
            let k = colon + 1 + (code[colon + 1..].len() - code[colon + 1..].trim_start().len());
            match leading_name(rest) {
                w @ ("if" | "elif" | "else") => {
                    reader.errors.push(outside(line.offset(k), w.len(), "a Python `if` on the production's line"));
                    Vec::new()
                }
                _ => reader.simple(i, k, Kind::Production).into_iter().collect(),
            }
        };
        self.errors.extend(reader.errors);
        self.warnings.extend(reader.warnings);
        let pred = code[..colon].trim_end();
        if stmts.is_empty() {
            // A body that produces nothing never applies (L-Py's production
            // returning None): the rule is left out.
            return;
        }
        self.pred(line, pred, &cond);
        let mut locals = Vec::new();
        if writes {
            collect_assignments(&stmts, &mut locals);
            // A body's assignment to a global (`global n`) is one of its values.
            let globals = locals.iter().filter(|(n, _)| self.globals.contains(n));
            self.facts.consts.extend(globals.cloned());
        }
        // One `produce` is a plain successor.
        if let [Stmt::Produce { end: true, line: l, start }] = stmts.as_slice() {
            self.out.push(" ->", line.offset(colon));
            let l = &self.lines[*l];
            let uses = write_modules(&self.names, &mut self.out, l, *start, true, &mut self.errors);
            if writes {
                self.record(pred, section, locals, uses);
            }
            self.always_applies(pred, group, section);
            return;
        }
        self.out.push(" -> {", line.offset(colon));
        self.out.newline();
        let names = std::mem::take(&mut self.names);
        let uses = std::cell::RefCell::new(Vec::new());
        let write = |out: &mut Out, l: &Line, s: usize, errors: &mut Vec<Diagnostic>| {
            uses.borrow_mut().extend(write_modules(&names, out, l, s, true, errors));
        };
        let mut temps = std::mem::take(&mut self.temps);
        let mut w = Writer {
            names: &names,
            lines: self.lines,
            kind: Kind::Production,
            temps: &mut temps,
            errors: &mut self.errors,
            modules: &write,
        };
        w.write(&stmts, "", line.at, &mut self.out);
        self.temps = temps;
        self.names = names;
        self.out.push("}", line.at);
        if writes {
            self.record(pred, section, locals, uses.into_inner());
        }
    }

    /// Notes a production that always applies: one that always produces
    /// (an arrow or one `produce`) in group 0, whose predecessor is one
    /// module alone, rewrites that module wherever it stands.
    fn always_applies(&mut self, pred: &str, group: u32, section: Option<&str>) {
        if section == Some("production:")
            && group == 0
            && let Some((m, arity)) = lone_module(pred, &self.names)
        {
            self.facts.always_rewritten(&m, arity);
        }
    }

    /// Records the modules a production with predecessor `pred` writes,
    /// for typing their parameters.
    fn record(&mut self, pred: &str, section: Option<&str>, locals: Vec<(String, Py)>, uses: Vec<(String, Vec<Py>)>) {
        let decomposition = section == Some("decomposition:");
        let scope = self.facts.scope(Scope { params: pred_params(pred, &self.names), locals, decomposition });
        for (m, args) in uses {
            self.facts.write(&m, args, Some(scope));
        }
    }

    /// A predecessor (contexts included), with the group's condition
    /// `cond` (` : lpy_group == 2` or empty). A number where a parameter
    /// name stands (`D(20, k)`) matches that value: it becomes a name and
    /// a condition.
    fn pred(&mut self, line: &Line, pred: &str, cond: &str) {
        for op in ["<<", ">>"] {
            if let Some(k) = pred.find(op) {
                self.errors.push(feature(line.offset(k), 2, &format!("L-Py's new-context operator `{op}`")));
            }
        }
        if let Some(k) = pred
            .find('*')
            .filter(|&k| !pred[..k].contains('(') || pred[..k].matches('(').count() == pred[..k].matches(')').count())
        {
            self.errors.push(feature(line.offset(k), 1, "L-Py's pattern `*` (any module)"));
        }
        let mut conds: Vec<String> = cond.strip_prefix(" : ").map(str::to_string).into_iter().collect();
        let b = pred.as_bytes();
        let (mut depth, mut from, mut item) = (0i32, 0, 0);
        for k in 0..b.len() {
            let end_item = match b[k] {
                b'(' => {
                    depth += 1;
                    if depth == 1 {
                        self.out.push(&spelled(&pred[from..k], &self.names), line.offset(from));
                        self.out.push("(", line.offset(k));
                        from = k + 1;
                    }
                    false
                }
                b')' => {
                    depth -= 1;
                    depth == 0
                }
                b',' => depth == 1,
                _ => false,
            };
            if end_item {
                let p = &pred[from..k];
                if p.trim().parse::<f64>().is_ok() {
                    item += 1;
                    let name = format!("lpy_v{item}");
                    conds.push(format!("{name} == {}", p.trim()));
                    self.out.push(&name, line.offset(from));
                } else {
                    self.out.push(p, line.offset(from));
                }
                self.out.push(&pred[k..=k], line.offset(k));
                from = k + 1;
            }
        }
        self.out.push(&spelled(pred[from..].trim_end(), &self.names), line.offset(from));
        if !conds.is_empty() {
            self.out.push(&format!(" : {}", conds.join(" and ")), line.offset(pred.len()));
        }
    }
}

/// The module names of a module string without parameters (`F+A`: `F`,
/// `+`, `A`) with their offsets, read as the `.ls` lexer reads names.
fn module_names<'s>(chunk: &'s str, names: &Names) -> Vec<(usize, &'s str)> {
    let (mut i, mut out) = (0, Vec::new());
    while let Some(c) = chunk[i..].chars().next() {
        if c.is_whitespace() || "()<>:=#".contains(c) {
            i += c.len_utf8();
            continue;
        }
        let len = module_name_len(&chunk[i..], names.modules.iter().map(String::as_str));
        out.push((i, &chunk[i..i + len]));
        i += len;
    }
    out
}

/// The last module name of a module string without parameters.
fn last_module<'s>(chunk: &'s str, names: &Names) -> Option<&'s str> {
    module_names(chunk, names).pop().map(|(_, n)| canonical(n))
}

/// A module string without parameters with L-Py's long spellings written
/// as the names L-Py keeps (`Left` as `+`).
fn spelled(chunk: &str, names: &Names) -> String {
    let mut out = String::with_capacity(chunk.len());
    let mut done = 0;
    for (i, n) in module_names(chunk, names) {
        out.push_str(&chunk[done..i]);
        out.push_str(canonical(n));
        done = i + n.len();
    }
    out.push_str(&chunk[done..]);
    out
}

/// The module of a predecessor that is one module with distinct parameter
/// names (`A(x, y)`, no context, no value to match), and its arity.
fn lone_module(pred: &str, names: &Names) -> Option<(String, usize)> {
    let pred = pred.trim();
    let (head, args) = match find_top(pred, b'(') {
        Some(open) => {
            let inner = pred[open + 1..].strip_suffix(')')?;
            (&pred[..open], top_level_items(inner).into_iter().map(str::trim).collect::<Vec<_>>())
        }
        None => (pred, Vec::new()),
    };
    let head = head.trim();
    let distinct = args.iter().enumerate().all(|(i, a)| is_name(a) && !args[..i].contains(a));
    let one = !head.is_empty() && module_name_len(head, names.modules.iter().map(String::as_str)) == head.len();
    (one && distinct).then(|| (canonical(head).to_string(), args.len()))
}

/// The parameter names of a predecessor (contexts included) with their
/// slots: `A(x) < B(y, z)` binds x to (A, 1, 0), y to (B, 2, 0), z to
/// (B, 2, 1).
fn pred_params(pred: &str, names: &Names) -> Vec<(String, Slot)> {
    let mut out = Vec::new();
    let mut rest = pred;
    while let Some(open) = find_top(rest, b'(') {
        let Some(close) = find_top(&rest[open + 1..], b')').map(|c| open + 1 + c) else { break };
        if let Some(m) = last_module(&rest[..open], names) {
            let args: Vec<&str> = top_level_items(&rest[open + 1..close]).into_iter().map(str::trim).collect();
            for (i, a) in args.iter().enumerate() {
                if is_name(a) {
                    out.push((a.to_string(), (m.to_string(), args.len(), i)));
                }
            }
        }
        rest = &rest[close + 1..];
    }
    out
}

/// Writes the L-Py module string `line.code[start..]` as `.ls` modules:
/// parameters are Python formulas; with `erase_star`, `*` alone (L-Py's
/// empty successor) writes nothing. Returns the modules written with
/// parameters, with their arguments.
pub(super) fn write_modules(
    names: &Names,
    out: &mut Out,
    line: &Line,
    start: usize,
    erase_star: bool,
    errors: &mut Vec<Diagnostic>,
) -> Vec<(String, Vec<Py>)> {
    let mut uses = Vec::new();
    let s = line.code.get(start..).unwrap_or("");
    if erase_star && s.trim() == "*" {
        return uses;
    }
    if !s.is_empty() {
        out.push(" ", line.offset(start));
    }
    let b = s.as_bytes();
    let (mut depth, mut from) = (0i32, 0);
    let mut quote = None;
    let mut module = None;
    for i in 0..b.len() {
        match (quote, b[i]) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), _) => {}
            (None, c @ (b'\'' | b'"')) if depth > 0 => quote = Some(c),
            (None, b'(') => {
                if depth == 0 {
                    // `A()` has no parameters: `A`.
                    let empty = s[i + 1..].trim_start().starts_with(')');
                    module = last_module(&s[from..i], names);
                    out.push(&spelled(&s[from..i], names), line.offset(start + from));
                    if !empty {
                        out.push("(", line.offset(start + i));
                    }
                    from = i + 1;
                }
                depth += 1;
            }
            (None, b')') => {
                depth -= 1;
                if depth == 0 && s[from..i].trim().is_empty() {
                    from = i + 1;
                } else if depth == 0 {
                    let at = line.offset(start + from);
                    match pyexpr::parse_list(&s[from..i], at) {
                        Ok(args) => {
                            for (k, a) in args.iter().enumerate() {
                                if k > 0 {
                                    out.push(", ", at);
                                }
                                names.emit(a, out, errors);
                            }
                            if let Some(m) = module.take() {
                                uses.push((m.to_string(), args));
                            }
                        }
                        Err(d) => errors.push(d),
                    }
                    from = i;
                }
            }
            _ => {}
        }
    }
    out.push(&spelled(&s[from..], names), line.offset(start + from));
    uses
}
