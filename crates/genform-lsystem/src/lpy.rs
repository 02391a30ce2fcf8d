//! Reading L-Py (`.lpy`) files: the subset of pure L-systems.
//!
//! An L-Py file is a Python module with an L-system section. genform reads
//! the files whose Python part is only declarations: the header words
//! (`Axiom:`, `derivation length:`, `maximum depth:`, `production:`,
//! `decomposition:`, `interpretation:`/`homomorphism:`, `endlsystem`,
//! `group N:`/`endgroup`, `ignore:`/`consider:`), `module` declarations,
//! productions with `-->` (or `->`), or with a body that is one `produce`,
//! module-level constants (`x = 3`), `from math import …`, and L-Py's
//! `context().turtle.setAngleIncrement(a)`. Everything else that is
//! Python (`def`, `if`, loops, `nproduce`, other imports, calls) is an
//! error at its `file:line:col` naming the construct.
//!
//! The file is translated into the `.ls` language and compiled by the
//! `.ls` compiler, so derivation, the turtle and every export work
//! unchanged; a source map takes every diagnostic back to the `.lpy` text.
//!
//! **Turtle.** PlantGL's turtle starts with heading H = (0, 0, 1), left
//! L = (0, −1, 0) and up U = (1, 0, 0) in L-Py's z-up world, turns by 60°
//! and steps by 1. genform's world is y-up; the axis change
//! (x, y, z) ↦ (y, z, x) (a rotation, [`to_genform_axes`]) takes L-Py's
//! up +z to genform's +y and its frame to H = +y, L = −x, U = +z, which is
//! genform's `heading: +y` frame, and L-Py's default camera (from +x, with
//! +y to the right) to the SVG's xy plane. PlantGL's widths are radii:
//! `width_unit: 2` turns them into genform's diameters (initial radius
//! 0.1). Long predefined names (`SetColor`, `SetWidth`, `Sphere`, `Left`,
//! …) are one module each and draw as their one-character aliases.

use crate::alphabet::Command;
use crate::compile::LSystem;
use crate::surface::SurfaceAssets;
use genform_core::{Diagnostic, Diagnostics, SourceFile, Span};
use glam::DVec3;

/// L-Py's predefined long module names that genform draws, with the
/// one-character (or `@`) alias whose turtle command they share. PlantGL
/// calls `/` RollL and `\` RollR.
const ALIASES: &[(&str, &str)] = &[
    ("Left", "+"),
    ("Right", "-"),
    ("Up", "^"),
    ("Down", "&"),
    ("RollL", "/"),
    ("RollR", "\\"),
    ("TurnAround", "|"),
    ("IncWidth", "_"),
    ("DecWidth", "!"),
    ("SetWidth", "!"),
    ("IncColor", ";"),
    ("DecColor", ","),
    ("SetColor", ","),
    ("SetHead", "@R"),
    ("Sphere", "@O"),
    ("StartGC", "@Gc"),
    ("EndGC", "@Ge"),
    ("BP", "{"),
    ("EP", "}"),
    ("PP", "."),
    ("SetScale", "@D"),
    ("MultScale", "@Di"),
    ("DivScale", "@Dd"),
];

/// L-Py's other predefined long names: one module each, not drawn by
/// genform (plain symbols).
const OTHER_NAMES: &[&str] = &[
    "nF",
    "MoveTo",
    "MoveRel",
    "LineTo",
    "OLineTo",
    "Pinpoint",
    "LineRel",
    "OLineRel",
    "PinpointRel",
    "EulerAngles",
    "iRollL",
    "iRollR",
    "RollToVert",
    "RollToHorizontal",
    "Box",
    "Quad",
    "Circle",
    "Label",
    "InterpolateColors",
    "TextureBaseColor",
    "InterpolateTextureBaseColors",
    "PglShape",
    "Frame",
    "Arrow",
    "Elasticity",
    "Tropism",
    "SetContour",
    "SectionResolution",
    "SetGuide",
    "EndGuide",
    "Sweep",
    "PositionOnGuide",
    "TextureScale",
    "TextureUScale",
    "TextureVScale",
    "TextureVCoeff",
    "TextureTranslation",
    "TextureRotation",
    "TextureTransformation",
    "LeftReflection",
    "UpReflection",
    "HeadingReflection",
    "GetPos",
    "GetHead",
    "GetUp",
    "GetLeft",
    "GetRight",
    "GetFrame",
    "StartScreenProjection",
    "EndScreenProjection",
];

/// The settings every translated file starts with: PlantGL's defaults.
const PRELUDE: &str = "angle: 60\nstep: 1\nheading: +y\nview: 3d\nwidth: 0.1\nwidth_unit: 2\n";

/// An L-Py vector (x, y, z) in genform's axes: (y, z, x). L-Py's up +z
/// becomes genform's up +y.
pub fn to_genform_axes(v: DVec3) -> DVec3 {
    DVec3::new(v.y, v.z, v.x)
}

/// A genform vector in L-Py's axes (the inverse of [`to_genform_axes`]).
pub fn to_lpy_axes(v: DVec3) -> DVec3 {
    DVec3::new(v.z, v.x, v.y)
}

/// A `.lpy` file translated to `.ls` text, with the way back.
#[derive(Clone, Debug)]
pub struct Translation {
    /// The `.ls` text.
    pub text: String,
    /// (offset in `text`, offset in the `.lpy` text), by the first.
    map: Vec<(usize, usize)>,
    /// Warnings of the translation, in `.lpy` offsets.
    pub warnings: Vec<Diagnostic>,
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

/// The `.ls` text being written, with its source map.
struct Out {
    text: String,
    map: Vec<(usize, usize)>,
}

impl Out {
    /// Appends `s`, which stands for the `.lpy` text at `at`.
    fn push(&mut self, s: &str, at: usize) {
        if s.is_empty() {
            return;
        }
        self.map.push((self.text.len(), at));
        self.text.push_str(s);
    }

    fn newline(&mut self) {
        self.text.push('\n');
    }
}

/// Why a construct is outside the subset, as an error.
fn outside(at: usize, len: usize, what: &str) -> Diagnostic {
    Diagnostic::error(
        Span::new(at, at + len.max(1)),
        format!("{what}: Python outside the pure L-system subset genform reads from .lpy files"),
    )
    .with_hint(
        "L-Py (the Python package) runs it; running Python bodies is a later increment \
         (docs/lsystem.md, Reading L-Py files). Rewrite it as a `.ls` file to use it now",
    )
}

/// What the Python statement `code` is, for messages.
fn construct(code: &str) -> String {
    let word: String = code.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
    match word.as_str() {
        "if" | "elif" | "else" => "a Python `if`".into(),
        "for" | "while" => format!("a Python `{word}` loop"),
        "def" => {
            let name: String =
                code[3..].trim_start().chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
            format!("a Python function `def {name}`")
        }
        "class" => "a Python class".into(),
        "nproduce" => "`nproduce`".into(),
        "import" | "from" => format!("the Python import `{}`", code.trim()),
        "return" | "pass" | "global" | "try" | "with" | "print" | "lambda" => format!("the Python `{word}`"),
        _ if is_assignment(code).is_some() => "a Python assignment".into(),
        _ if !word.is_empty() && code[word.len()..].trim_start().starts_with('(') => {
            format!("the Python call `{word}(…)`")
        }
        _ => "a Python statement".into(),
    }
}

/// `name = value` (not `==`): the name's length and the offset of the value.
fn is_assignment(code: &str) -> Option<(usize, usize)> {
    let name_len = code.chars().take_while(|c| c.is_alphanumeric() || *c == '_').count();
    if name_len == 0 || code.as_bytes()[0].is_ascii_digit() {
        return None;
    }
    let rest = &code[name_len..];
    let trimmed = rest.trim_start();
    if trimmed.starts_with('=') && !trimmed.starts_with("==") {
        let eq = name_len + (rest.len() - trimmed.len());
        Some((name_len, eq + 1))
    } else {
        None
    }
}

/// The end of the code of `line` (before a `#` comment outside quotes).
fn code_end(line: &str) -> usize {
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

/// Translates a module string at `at`: the parameters in parentheses are
/// formulas ([`push_formula`]), the rest is copied.
fn push_modules(out: &mut Out, s: &str, at: usize) {
    let b = s.as_bytes();
    let (mut depth, mut start) = (0i32, 0);
    for i in 0..b.len() {
        match b[i] {
            b'(' => {
                if depth == 0 {
                    out.push(&s[start..=i], at + start);
                    start = i + 1;
                }
                depth += 1;
            }
            b')' => {
                depth -= 1;
                if depth == 0 {
                    push_formula(out, &s[start..i], at + start);
                    start = i;
                }
            }
            _ => {}
        }
    }
    out.push(&s[start..], at + start);
}

/// A Python formula as a `.ls` formula: `**` becomes `^`,
/// `getIterationNb()` `iteration`, `True`/`False` 1/0.
fn push_formula(out: &mut Out, s: &str, at: usize) {
    let mut start = 0;
    loop {
        let next = [("**", " ^"), ("getIterationNb()", "iteration")]
            .iter()
            .filter_map(|(p, r)| s[start..].find(p).map(|k| (k, p.len(), *r)))
            .min();
        let Some((k, len, r)) = next else { break };
        out.push(&s[start..start + k], at + start);
        out.push(r, at + start + k);
        start += k + len;
    }
    let rest = &s[start..];
    // Whole words True / False.
    let mut last = 0;
    let mut words = Vec::new();
    for (i, _) in rest.char_indices() {
        for (w, v) in [("True", "1"), ("False", "0")] {
            let before = rest[..i].chars().next_back().is_none_or(|c| !(c.is_alphanumeric() || c == '_'));
            let after =
                rest[i..].strip_prefix(w).map(|r| r.chars().next().is_none_or(|c| !(c.is_alphanumeric() || c == '_')));
            if before && after == Some(true) {
                words.push((i, w.len(), v));
            }
        }
    }
    for (i, len, v) in words {
        out.push(&rest[last..i], at + start + last);
        out.push(v, at + start + i);
        last = i + len;
    }
    out.push(&rest[last..], at + start + last);
}

/// Whether `name` occurs in `text` as a run of name characters of its own.
fn mentions(text: &str, name: &str) -> bool {
    text.match_indices(name).any(|(i, _)| {
        let before = text[..i].chars().next_back().is_none_or(|c| !c.is_alphanumeric() && c != '_');
        let after = text[i + name.len()..].chars().next().is_none_or(|c| !c.is_alphanumeric() && c != '_');
        before && after
    })
}

/// Where a header word starts a line: the text after it.
fn header<'a>(code: &'a str, words: &[&str]) -> Option<(usize, &'a str)> {
    for w in words {
        if let Some(rest) = code.strip_prefix(w) {
            return Some((w.len(), rest));
        }
    }
    None
}

/// Translates an L-Py file into `.ls` text, or says why it cannot.
pub fn translate(src: &str) -> Result<Translation, Vec<Diagnostic>> {
    let mut out = Out { text: String::new(), map: Vec::new() };
    let mut errors: Vec<Diagnostic> = Vec::new();
    let mut warnings = Vec::new();
    out.push(PRELUDE, 0);

    // Lines with their offsets.
    let mut lines = Vec::new();
    let mut off = 0;
    for raw in src.split_inclusive('\n') {
        let line = raw.trim_end_matches(['\n', '\r']);
        lines.push((off, line));
        off += raw.len();
    }

    // Module names: declared ones (`module A, B`) and the predefined long
    // names the file mentions, declared first so the whole file reads them.
    let mut names: Vec<(String, usize)> = Vec::new();
    for &(at, line) in &lines {
        let code = &line[..code_end(line)];
        if let Some(rest) = code.strip_prefix("module").filter(|r| r.starts_with([' ', '\t'])) {
            let base = at + "module".len();
            // `: scale = n` (multiscale) and `: base = M` are not read.
            let rest = &rest[..rest.find(':').unwrap_or(rest.len())];
            let mut pos = 0;
            for item in rest.split(',') {
                let lead = item.len() - item.trim_start().len();
                let name: String = item.trim_start().chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
                let nat = base + pos + lead;
                if let Some(k) = item.find('=') {
                    errors.push(
                        Diagnostic::error(
                            Span::new(base + pos + k, base + pos + k + 1),
                            "module aliases (`module A = F`) are not read yet",
                        )
                        .with_hint("write the aliased module's name instead"),
                    );
                } else if !name.is_empty() {
                    names.push((name, nat));
                }
                pos += item.len() + 1;
            }
        }
    }
    for name in ALIASES.iter().map(|(n, _)| *n).chain(OTHER_NAMES.iter().copied()) {
        if name.len() > 1 && mentions(src, name) && !names.iter().any(|(n, _)| n == name) {
            names.push((name.to_string(), 0));
        }
    }
    let long: Vec<&(String, usize)> = names.iter().filter(|(n, _)| n.chars().count() > 1).collect();
    if !long.is_empty() {
        out.push("module:", 0);
        for (n, at) in long {
            out.push(" ", *at);
            out.push(n, *at);
        }
        out.newline();
    }

    let mut in_rules = false;
    let mut after_end = false;
    let mut skip_group = false;
    let mut skip_indented = false;
    let mut in_triple: Option<&str> = None;
    let mut i = 0;
    while i < lines.len() {
        let (at, line) = lines[i];
        i += 1;
        // Inside a triple-quoted string (docstrings, `__description__`).
        if let Some(q) = in_triple {
            if line.contains(q) {
                in_triple = None;
            }
            out.newline();
            continue;
        }
        let code = line[..code_end(line)].trim_end();
        let indent = code.len() - code.trim_start().len();
        let body = code.trim_start();
        let bat = at + indent;
        if body.is_empty() {
            out.newline();
            continue;
        }
        // Python string statements and `__meta__ = """…"""`.
        let meta = body.starts_with("__") && is_assignment(body).is_some();
        if meta || body.starts_with("\"\"\"") || body.starts_with("'''") {
            for q in ["\"\"\"", "'''"] {
                if body.matches(q).count() % 2 == 1 {
                    in_triple = Some(q);
                }
            }
            out.newline();
            continue;
        }
        if indent > 0 && skip_indented {
            out.newline();
            continue;
        }
        skip_indented = false;
        if skip_group {
            if body == "endgroup" {
                skip_group = false;
            } else if body.starts_with("group ") {
                errors.push(Diagnostic::error(Span::new(bat, bat + body.len()), "`group` inside a group"));
            }
            out.newline();
            continue;
        }
        if indent > 0 {
            errors.push(outside(bat, body.len(), &construct(body)));
            out.newline();
            continue;
        }
        if body == "endlsystem" {
            after_end = true;
            in_rules = false;
            out.newline();
            continue;
        }
        if body.starts_with("def __initialiseContext__") {
            warnings.push(
                Diagnostic::warning(Span::new(bat, bat + body.len()), "L-Py's `__initialiseContext__` is not read")
                    .with_hint(
                        "its materials, options and animation settings are ignored; colours come from genform's table",
                    ),
            );
            skip_indented = true;
            out.newline();
            continue;
        }
        if let Some((w, rest)) = header(body, &["Axiom:", "axiom:"]) {
            out.push("axiom:", bat);
            push_modules(&mut out, rest, bat + w);
        } else if let Some((w, rest)) = header(body, &["derivation length:"]) {
            out.push("derivation:", bat);
            push_formula(&mut out, rest, bat + w);
        } else if let Some((w, rest)) = header(body, &["maximum depth:"]) {
            out.push("maxdepth:", bat);
            out.push(rest, bat + w);
        } else if let Some((w, rest)) = header(body, &["ignore:", "consider:"]) {
            out.push(&body[..w], bat);
            push_modules(&mut out, rest, bat + w);
        } else if let Some(kind) = ["production:", "decomposition:", "interpretation:", "homomorphism:"]
            .iter()
            .find(|h| body.starts_with(**h) && body[h.len()..].trim().is_empty())
        {
            out.push(kind, bat);
            in_rules = true;
        } else if let Some(rest) = body.strip_prefix("group ") {
            let n = rest.trim_end_matches(':').trim();
            if n.parse::<u32>().is_ok_and(|n| n != 0) {
                warnings.push(
                    Diagnostic::warning(
                        Span::new(bat, bat + body.len()),
                        format!("the rules of group {n} are left out"),
                    )
                    .with_hint("only group 0 is active unless Python calls `useGroup`"),
                );
                skip_group = true;
            }
        } else if body == "endgroup" {
        } else if body.starts_with("module ") || body.starts_with("module\t") {
            // Declared above.
        } else if body.starts_with("from math import") {
        } else if let Some(a) =
            header(body, &["context().turtle.setAngleIncrement(", "execContext().turtle.setAngleIncrement("])
                .map(|(w, r)| (w, r.strip_suffix(')')))
                .and_then(|(w, r)| r.map(|r| (w, r)))
        {
            out.push("angle:", bat);
            push_formula(&mut out, a.1, bat + a.0);
        } else if !after_end && in_rules && arrow(body).is_some() {
            let (k, len) = arrow(body).unwrap_or_default();
            rule(&mut out, &mut errors, body, bat, k, len);
        } else if !after_end && in_rules && body.ends_with(':') && !is_python_head(body) {
            // A production with a Python body: one `produce` is a successor.
            let pred = body[..body.len() - 1].trim_end();
            let mut succ = None;
            let mut bad = false;
            while i < lines.len() {
                let (lat, l) = lines[i];
                let c = l[..code_end(l)].trim_end();
                let ind = c.len() - c.trim_start().len();
                if c.trim().is_empty() {
                    i += 1;
                    out.newline();
                    continue;
                }
                if ind == 0 {
                    break;
                }
                i += 1;
                let st = c.trim_start();
                let sat = lat + ind;
                let produce = st.strip_prefix("produce").filter(|r| r.is_empty() || r.starts_with([' ', '\t', '(']));
                match produce {
                    Some(r) if succ.is_none() && !bad => succ = Some((r, sat + "produce".len())),
                    _ if bad => {}
                    _ => {
                        errors.push(outside(sat, st.len(), &format!("{} in a production body", construct(st))));
                        bad = true;
                    }
                }
                out.newline();
            }
            match succ {
                Some((r, rat)) if !bad => {
                    push_pred(&mut out, &mut errors, pred, bat);
                    out.push(" ->", bat + pred.len());
                    push_succ(&mut out, r, rat);
                }
                None if !bad => errors.push(
                    Diagnostic::error(Span::new(bat, bat + body.len()), "a production body without `produce`")
                        .with_hint("give the successor with `-->` or a `produce` line"),
                ),
                _ => {}
            }
        } else if let Some((name_len, value)) = is_assignment(body) {
            out.push("define ", bat);
            out.push(&body[..name_len], bat);
            out.push(" =", bat + value - 1);
            push_formula(&mut out, &body[value..], bat + value);
        } else {
            errors.push(outside(bat, body.len(), &construct(body)));
        }
        out.newline();
    }
    if errors.is_empty() { Ok(Translation { text: out.text, map: out.map, warnings }) } else { Err(errors) }
}

/// Whether a line ending with `:` is a Python block head rather than a
/// production.
fn is_python_head(body: &str) -> bool {
    let word: String = body.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
    matches!(word.as_str(), "if" | "elif" | "else" | "for" | "while" | "def" | "class" | "with" | "try" | "except")
}

/// A predecessor (contexts and condition included).
fn push_pred(out: &mut Out, errors: &mut Vec<Diagnostic>, pred: &str, at: usize) {
    for op in ["<<", ">>"] {
        if let Some(k) = pred.find(op) {
            errors.push(outside(at + k, 2, &format!("L-Py's new-context operator `{op}`")));
        }
    }
    if let Some(k) = pred
        .find('*')
        .filter(|&k| !pred[..k].contains('(') || pred[..k].matches('(').count() == pred[..k].matches(')').count())
    {
        errors.push(outside(at + k, 1, "the pattern `*` (any module)"));
    }
    push_modules(out, pred, at);
}

/// A successor: `*` or nothing erases the module.
fn push_succ(out: &mut Out, succ: &str, at: usize) {
    if succ.trim() == "*" {
        return;
    }
    push_modules(out, succ, at);
}

/// A production `pred --> succ` with its arrow at `k`.
fn rule(out: &mut Out, errors: &mut Vec<Diagnostic>, body: &str, at: usize, k: usize, len: usize) {
    push_pred(out, errors, body[..k].trim_end(), at);
    out.push(" ->", at + k);
    push_succ(out, &body[k + len..], at + k + len);
}

/// Compiles an L-Py file (the subset above) into an [`LSystem`].
pub fn compile_lpy(file: &SourceFile) -> Result<(LSystem, Diagnostics), Diagnostics> {
    compile_lpy_with_assets(file, &crate::surface::NoSurfaceAssets)
}

/// [`compile_lpy`], loading surface meshes through `assets`.
pub fn compile_lpy_with_assets(
    file: &SourceFile,
    assets: &dyn SurfaceAssets,
) -> Result<(LSystem, Diagnostics), Diagnostics> {
    let mut diags = Diagnostics::new(file.clone());
    let t = match translate(&file.text) {
        Ok(t) => t,
        Err(errors) => {
            for e in errors {
                diags.push(e);
            }
            return Err(diags);
        }
    };
    let ls = SourceFile::new(format!("{} (as .ls)", file.name), t.text.clone());
    let map = |d: Diagnostics, diags: &mut Diagnostics| {
        for item in d.items {
            diags.push(t.map_diagnostic(item));
        }
    };
    match crate::entry::compile_with_assets(&ls, assets) {
        Ok((mut system, warnings)) => {
            for w in t.warnings.iter().cloned() {
                diags.push(w);
            }
            map(warnings, &mut diags);
            let stem = std::path::Path::new(&*file.name).file_stem().map(|s| s.to_string_lossy().into_owned());
            system.settings.name = stem.unwrap_or_default();
            for sym in &mut system.alphabet.symbols {
                if let Some((_, alias)) = ALIASES.iter().find(|(n, _)| *n == sym.name) {
                    sym.command = Command::of(alias);
                }
            }
            Ok((system, diags))
        }
        Err(errors) => {
            map(errors, &mut diags);
            Err(diags)
        }
    }
}
