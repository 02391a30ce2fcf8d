//! The `.gr8` front end: Genr8's grammar-file language read into a
//! [`Hemls`], every problem of a file reported at once with its position.
//!
//! A file is, line by line (blank lines and `//` comments anywhere, also
//! after content):
//!
//! ```text
//! axiom         Edge0 + ~ Edge1 + Edge0 + ~ Edge1       (≥ 3 sides, single `+` between)
//! rules         pred -> succ [Weight w] [If i <|>|= c] { -> succ [Weight w] }
//! Angle d       0–360 degrees, required
//! Sync          optional, anywhere after the rules (also before `Angle`)
//! BranchAngle d optional, 0–90 degrees, after `Angle`
//! ```
//!
//! A predecessor is `E`, `L < E`, `E > R` or `L < E > R`, where the strict
//! edge `E` may be timed (`Edge3_i`). A successor is turns `+ - & ^ \ /`,
//! edges (`~` reverses the next one; `_i`, `_i+1`, `_i-1` set ages) and
//! branches `[ {branch} {turn} [~] EdgeN ]`; nested brackets flatten into
//! sibling branches, innermost first. Errors are recovered per line.

use crate::grammar::{
    Age, AxiomSide, Branch, Cmp, Condition, EdgeSym, Hemls, Item, Predecessor, Rule, Successor, Turn,
};
use crate::lex::{self, Line, Tok, Token};
use genform_core::{Diagnostic, Diagnostics, SourceFile, Span};

pub use crate::lex::MAX_EDGE_ID;

/// Deepest bracket nesting accepted (deeper input is certainly a mistake,
/// and the limit keeps the recursive branch parser's stack small).
const MAX_NESTING: usize = 64;

/// Compiles a `.gr8` file. Returns the system and its warnings, or every
/// error found. [`Hemls::name`] is the file stem of `file.name`.
pub fn compile(file: &SourceFile) -> Result<(Hemls, Diagnostics), Diagnostics> {
    let lines = lex::lines(&file.text);
    let mut p = Parser::default();
    for line in &lines {
        p.line(line);
    }
    let name = std::path::Path::new(&*file.name).file_stem().map(|s| s.to_string_lossy().into_owned());
    let hemls = p.finish(&lines, name.unwrap_or_default());
    let mut diags = Diagnostics::new(file.clone());
    diags.items = p.diags;
    match hemls {
        Some(h) if !diags.has_errors() => Ok((h, diags)),
        _ => Err(diags),
    }
}

/// Compiles `.gr8` text under the display name `name` (a path or file
/// name; its stem becomes [`Hemls::name`]), dropping warnings.
///
/// ```
/// let h = genform_hemls::parse_str("grammars/koch.gr8", "Edge0 + Edge0 + Edge0\nEdge0 -> Edge0 - Edge0 + + Edge0 - Edge0\nAngle 60\n").unwrap();
/// assert_eq!((h.name.as_str(), h.axiom.len(), h.angle), ("koch", 3, 60.0));
/// // Written back in canonical form.
/// assert_eq!(h.to_string(), "Edge0 + Edge0 + Edge0\nEdge0 -> Edge0 - Edge0 + + Edge0 - Edge0\nAngle 60\n");
/// ```
pub fn parse_str(name: &str, text: &str) -> Result<Hemls, Diagnostics> {
    compile(&SourceFile::new(name, text)).map(|(h, _)| h)
}

/// Parse state across the lines of one file.
#[derive(Default)]
struct Parser {
    diags: Vec<Diagnostic>,
    /// The axiom line, once one was seen (parsed or not).
    axiom_line: Option<Span>,
    axiom: Option<Vec<AxiomSide>>,
    /// "missing axiom" was reported already.
    told_no_axiom: bool,
    /// Rule lines seen (parsed or not).
    rule_lines: usize,
    rules: Vec<Rule>,
    /// Line number of each rule in `rules`.
    rule_numbers: Vec<usize>,
    /// The first parameter line: its keyword's span, text and line number.
    first_param: Option<(Span, &'static str, usize)>,
    angle_line: Option<Span>,
    angle: Option<f64>,
    sync_line: Option<Span>,
    branch_angle_line: Option<Span>,
    branch_angle: Option<f64>,
}

impl Parser {
    fn error(&mut self, span: Span, message: impl Into<String>, hint: impl Into<String>) {
        self.diags.push(Diagnostic::error(span, message).with_hint(hint));
    }

    fn line(&mut self, line: &Line) {
        let first = line.words[0].text;
        if line.words.iter().any(|w| w.text.contains("->")) {
            self.rule(line);
        } else if let Some(which) = lex::param_keyword(first) {
            self.param(line, which);
        } else if self.axiom_line.is_none() {
            self.axiom_line(line);
        } else {
            self.stray(line);
        }
    }

    /// Every word of a line as a token, or `None` after reporting the bad ones.
    fn tokens<'a>(&mut self, line: &Line<'a>) -> Option<Vec<Token<'a>>> {
        let mut out = Vec::with_capacity(line.words.len());
        let mut ok = true;
        for w in &line.words {
            match lex::lex(w) {
                Ok(t) => out.push(t),
                Err(d) => {
                    self.diags.push(d);
                    ok = false;
                }
            }
        }
        ok.then_some(out)
    }

    /// Reports a missing axiom once, at the first line that should follow it.
    fn need_axiom(&mut self, at: Span) {
        if self.axiom_line.is_none() && !self.told_no_axiom {
            self.told_no_axiom = true;
            self.error(
                at,
                "missing axiom: the first line must be the seed polygon",
                "start with the axiom, e.g. `Edge0 + Edge0 + Edge0`, then the rules",
            );
        }
    }

    // ---- axiom --------------------------------------------------------

    fn axiom_line(&mut self, line: &Line) {
        self.axiom_line = Some(line.span());
        let Some(toks) = self.tokens(line) else { return };
        self.axiom = self.axiom(&toks, line.span());
    }

    fn axiom(&mut self, toks: &[Token], span: Span) -> Option<Vec<AxiomSide>> {
        const ONLY: &str = "the axiom is a regular polygon written as edges separated by single `+`, each optionally \
                            preceded by `~`: `Edge0 + ~ Edge1 + Edge0`";
        let mut sides = Vec::new();
        let mut want_side = true;
        let mut reversed: Option<Span> = None;
        for (k, t) in toks.iter().enumerate() {
            match t.tok {
                Tok::Edge(kind, age) if want_side => {
                    if age != Age::Zero {
                        self.error(
                            t.span,
                            format!("the axiom's edges have no age: `{}`", t.text),
                            format!("write `Edge{kind}`"),
                        );
                        return None;
                    }
                    sides.push(AxiomSide { kind, reversed: reversed.take().is_some() });
                    want_side = false;
                }
                Tok::Edge(..) => {
                    self.error(t.span, "expected `+` between the axiom's sides", ONLY);
                    return None;
                }
                Tok::Tilde
                    if want_side
                        && reversed.is_none()
                        && matches!(toks.get(k + 1), Some(n) if matches!(n.tok, Tok::Edge(..))) =>
                {
                    reversed = Some(t.span);
                }
                Tok::Tilde => {
                    self.error(
                        t.span,
                        "`~` in the axiom must come directly before an edge",
                        "write `+ ~ Edge1`: `~` reverses the edge after it",
                    );
                    return None;
                }
                Tok::Turn(Turn::Right) if !want_side => want_side = true,
                Tok::Turn(Turn::Right) => {
                    let msg = if sides.is_empty() {
                        "the axiom must start with an edge"
                    } else {
                        "two `+` in a row in the axiom"
                    };
                    self.error(t.span, msg, ONLY);
                    return None;
                }
                _ => {
                    self.error(
                        t.span,
                        format!("the axiom may contain only `EdgeN`, `+` and `~`, not `{}`", t.text),
                        ONLY,
                    );
                    return None;
                }
            }
        }
        if want_side {
            let at = toks.last().map_or(span, |t| t.span);
            self.error(at, "the axiom ends with `+`", "end the axiom with an edge");
            return None;
        }
        if sides.len() < 3 {
            self.error(
                span,
                format!("the axiom needs at least 3 sides, found {}", sides.len()),
                "the seed is a regular polygon: `Edge0 + Edge0 + Edge0` is a triangle",
            );
            return None;
        }
        Some(sides)
    }

    // ---- lines out of place ---------------------------------------------

    fn stray(&mut self, line: &Line) {
        if self.tokens(line).is_none() {
            return;
        }
        let at = line.words[0].span;
        let looks_like_axiom = line
            .words
            .iter()
            .all(|w| lex::lex(w).is_ok_and(|t| matches!(t.tok, Tok::Edge(..) | Tok::Turn(Turn::Right) | Tok::Tilde)));
        let hint = if looks_like_axiom {
            "a file has one axiom (its first line); later lines are rules `EdgeN -> successor`".to_string()
        } else {
            "a rule is `EdgeN -> successor`; parameters are `Angle d`, `Sync` and `BranchAngle d`".to_string()
        };
        self.error(at, "expected a rule, but this line has no `->`", hint);
    }

    // ---- parameters -------------------------------------------------------

    fn param(&mut self, line: &Line, which: Tok) {
        let span = line.span();
        self.need_axiom(span);
        let Some(toks) = self.tokens(line) else {
            // Count a misspelt parameter line as present: no "missing `Angle`" on top.
            match which {
                Tok::Angle => self.angle_line.get_or_insert(span),
                Tok::Sync => self.sync_line.get_or_insert(span),
                _ => self.branch_angle_line.get_or_insert(span),
            };
            return;
        };
        let head = toks[0];
        if self.first_param.is_none() {
            let word = match which {
                Tok::Angle => "Angle",
                Tok::Sync => "Sync",
                _ => "BranchAngle",
            };
            self.first_param = Some((head.span, word, line.number));
        }
        match which {
            Tok::Angle => {
                if self.duplicate(head, self.angle_line) {
                    return;
                }
                self.angle_line = Some(span);
                self.angle = self.number(&toks, 0.0, 360.0);
            }
            Tok::Sync => {
                if self.duplicate(head, self.sync_line) {
                    return;
                }
                self.sync_line = Some(span);
                if let Some(t) = toks.get(1) {
                    self.error(
                        t.span,
                        format!("unexpected `{}` after `Sync`", t.text),
                        "`Sync` stands alone on its line",
                    );
                }
            }
            _ => {
                if self.duplicate(head, self.branch_angle_line) {
                    return;
                }
                self.branch_angle_line = Some(span);
                if self.angle_line.is_none() {
                    self.error(
                        head.span,
                        "`BranchAngle` must come after `Angle`",
                        "the file ends with `Angle d`, then `Sync` and `BranchAngle d` in either order",
                    );
                }
                self.branch_angle = self.number(&toks, 0.0, 90.0);
            }
        }
    }

    /// Reports a second `Angle`/`Sync`/`BranchAngle` line.
    fn duplicate(&mut self, head: Token, first: Option<Span>) -> bool {
        let Some(first) = first else { return false };
        self.diags.push(
            Diagnostic::error(head.span, format!("duplicate `{}` line", head.text))
                .with_label(first, "first given here")
                .with_hint(format!("a file gives `{}` once; remove one of the lines", head.text)),
        );
        true
    }

    /// The number after a parameter keyword, checked to lie in `lo..=hi`.
    fn number(&mut self, toks: &[Token], lo: f64, hi: f64) -> Option<f64> {
        let head = toks[0];
        let hint = format!("e.g. `{} {}` (degrees, {lo}–{hi})", head.text, hi.min(60.0));
        let value = match toks.get(1) {
            None => {
                self.error(head.span, format!("expected a number after `{}`", head.text), hint);
                return None;
            }
            Some(t) => match t.tok {
                Tok::Num(v) if !v.is_finite() => {
                    self.error(t.span, format!("`{}` is not a finite number", t.text), hint);
                    return None;
                }
                Tok::Num(v) if !(lo..=hi).contains(&v) => {
                    self.error(t.span, format!("`{}` must be between {lo} and {hi} degrees, not {v}", head.text), hint);
                    return None;
                }
                Tok::Num(v) => v,
                _ => {
                    self.error(t.span, format!("expected a number after `{}`, found `{}`", head.text, t.text), hint);
                    return None;
                }
            },
        };
        if let Some(t) = toks.get(2) {
            self.error(
                t.span,
                format!("unexpected `{}` after the angle", t.text),
                format!("`{} d` is the whole line", head.text),
            );
            return None;
        }
        Some(value)
    }

    // ---- rules ------------------------------------------------------------

    fn rule(&mut self, line: &Line) {
        let span = line.span();
        self.rule_lines += 1;
        self.need_axiom(span);
        if let Some((at, word, number)) = self.first_param {
            self.diags.push(
                Diagnostic::error(line.words[0].span, format!("rule after `{word}`: rules come before the parameters"))
                    .with_label(at, format!("`{word}` is here"))
                    .with_hint(format!(
                        "move this rule above line {number}; the file ends with `Angle d`, then `Sync` and `BranchAngle d`"
                    )),
            );
        }
        let Some(toks) = self.tokens(line) else { return };
        let arrows: Vec<usize> = toks.iter().enumerate().filter(|(_, t)| t.tok == Tok::Arrow).map(|(i, _)| i).collect();
        let Some(pred) = self.predecessor(&toks[..arrows[0]], toks[arrows[0]].span) else { return };
        let mut successors = Vec::new();
        let mut condition = None;
        let mut ok = true;
        for (j, &a) in arrows.iter().enumerate() {
            let end = arrows.get(j + 1).copied().unwrap_or(toks.len());
            match self.successor(&toks[a + 1..end], toks[a].span, j == 0, pred.timed) {
                Some((s, c)) => {
                    successors.push(s);
                    if c.is_some() {
                        condition = c;
                    }
                }
                None => ok = false,
            }
        }
        if ok {
            self.add_rule(Rule { pred, condition, successors, span }, line.number);
        }
    }

    /// Keeps a rule, warning when an earlier rule shadows it.
    fn add_rule(&mut self, rule: Rule, number: usize) {
        let same = |a: &Predecessor, b: &Predecessor| a.kind == b.kind && a.left == b.left && a.right == b.right;
        let earlier = self
            .rules
            .iter()
            .zip(&self.rule_numbers)
            .find(|(r, _)| same(&r.pred, &rule.pred) && (r.condition.is_none() || r.condition == rule.condition));
        if let Some((r, n)) = earlier {
            self.diags.push(
                Diagnostic::warning(
                    rule.span,
                    format!("this rule can never apply: the rule on line {n} matches first"),
                )
                .with_label(r.span, "this rule matches every edge the later one would")
                .with_hint(
                    "the first matching rule wins; for a random choice write one rule with several successors: \
                         `Edge0 -> Edge0 Edge0 Weight 2 -> Edge0 Weight 1`",
                ),
            );
        }
        self.rules.push(rule);
        self.rule_numbers.push(number);
    }

    fn predecessor(&mut self, toks: &[Token], arrow: Span) -> Option<Predecessor> {
        const FORMS: &str = "a predecessor is one edge with optional contexts: `E`, `L < E`, `E > R` or `L < E > R`";
        if toks.is_empty() {
            self.error(arrow, "expected an edge before `->`", "a rule is `EdgeN -> successor`");
            return None;
        }
        for t in toks {
            match t.tok {
                Tok::Edge(..) | Tok::Lt | Tok::Gt => {}
                Tok::Tilde => {
                    self.error(
                        t.span,
                        "a predecessor cannot hold `~`",
                        "`~` reverses edges in successors and the axiom",
                    );
                    return None;
                }
                Tok::Turn(_) | Tok::Open | Tok::Close => {
                    self.error(t.span, format!("`{}` cannot appear in a predecessor", t.text), FORMS);
                    return None;
                }
                _ => {
                    self.error(t.span, format!("unexpected `{}` in the predecessor", t.text), FORMS);
                    return None;
                }
            }
        }
        let find = |tok: Tok| toks.iter().enumerate().filter(move |(_, t)| t.tok == tok).map(|(i, _)| i);
        let lts: Vec<usize> = find(Tok::Lt).collect();
        let gts: Vec<usize> = find(Tok::Gt).collect();
        if let Some(&extra) = lts.get(1).or(gts.get(1)) {
            self.error(toks[extra].span, format!("a second `{}` in the predecessor", toks[extra].text), FORMS);
            return None;
        }
        let (lt, gt) = (lts.first().copied(), gts.first().copied());
        if let (Some(l), Some(g)) = (lt, gt)
            && g < l
        {
            self.error(toks[g].span, "`>` must come after `<`", FORMS);
            return None;
        }
        let strict_from = lt.map_or(0, |l| l + 1);
        let strict_to = gt.unwrap_or(toks.len());
        let strict = &toks[strict_from..strict_to];
        let (kind, age) = match strict {
            [] => {
                let at = gt.or(lt).map_or(arrow, |i| toks[i].span);
                self.error(at, "expected the strict edge of the predecessor", FORMS);
                return None;
            }
            [t] => match t.tok {
                Tok::Edge(k, a) => (k, a),
                _ => {
                    self.error(t.span, "expected the strict edge of the predecessor", FORMS);
                    return None;
                }
            },
            [_, second, ..] => {
                self.error(
                    second.span,
                    "multi-segment predecessors are not supported: a rule rewrites one edge",
                    "Genr8 never defined their meaning; write one rule per edge, and use `L < E > R` to depend \
                     on the neighbouring edges",
                );
                return None;
            }
        };
        let timed = match age {
            Age::Zero => false,
            Age::Same => true,
            _ => {
                self.error(
                    strict[0].span,
                    format!("`{}`: in a predecessor only `Edge{kind}_i` binds the age", strict[0].text),
                    "`_i+1` and `_i-1` set the ages of successor edges",
                );
                return None;
            }
        };
        let left = match lt {
            Some(l) => Some(self.context(&toks[..l], toks[l], "left")?),
            None => None,
        };
        let right = match gt {
            Some(g) => Some(self.context(&toks[g + 1..], toks[g], "right")?),
            None => None,
        };
        Some(Predecessor { kind, timed, left, right })
    }

    /// A context: exactly one plain edge beside `<` or `>`.
    fn context(&mut self, toks: &[Token], mark: Token, side: &str) -> Option<u32> {
        match toks {
            [t] => match t.tok {
                Tok::Edge(k, Age::Zero) => Some(k),
                _ => {
                    self.error(
                        t.span,
                        format!("a {side} context is a plain edge, not `{}`", t.text),
                        "only the strict edge may be timed",
                    );
                    None
                }
            },
            [] => {
                let where_ = if side == "left" { "before" } else { "after" };
                self.error(
                    mark.span,
                    format!("expected a {side} context edge {where_} `{}`", mark.text),
                    "e.g. `Edge1 < Edge0 > Edge2`",
                );
                None
            }
            [_, second, ..] => {
                self.error(second.span, format!("a {side} context is one edge"), "e.g. `Edge1 < Edge0 > Edge2`");
                None
            }
        }
    }

    /// One successor after `->` with its `Weight` and (first successor only)
    /// condition. `None` when it could not be read.
    fn successor(
        &mut self,
        toks: &[Token],
        arrow: Span,
        first: bool,
        timed: bool,
    ) -> Option<(Successor, Option<Condition>)> {
        let tail = toks.iter().position(|t| matches!(t.tok, Tok::Weight | Tok::If)).unwrap_or(toks.len());
        let (body, rest) = toks.split_at(tail);
        if body.is_empty() {
            self.error(
                arrow,
                "expected a successor after `->`",
                "a successor is edges, turns and branches, e.g. `Edge0 [ [ + Edge1 ] - Edge1 ] Edge0`",
            );
            return None;
        }
        let span = body[0].span.to(body[body.len() - 1].span);
        let items = self.items(body, timed)?;
        self.check_main_line(&items, span);
        let (weight, condition) = self.tail(rest, first, timed)?;
        Some((Successor { items, weight }, condition))
    }

    /// `Weight w` and `If i <op> c` after a successor's items.
    fn tail(&mut self, toks: &[Token], first: bool, timed: bool) -> Option<(f64, Option<Condition>)> {
        let mut i = 0;
        let mut weight = 1.0;
        let mut condition = None;
        if let Some(w) = toks.first().filter(|t| t.tok == Tok::Weight) {
            let hint = "a weight is a positive number, e.g. `Weight 2`; weights of a rule are normalised";
            match toks.get(1).map(|t| (t, t.tok)) {
                Some((t, Tok::Num(v))) if !v.is_finite() => {
                    self.error(t.span, format!("`{}` is not a finite number", t.text), hint);
                    return None;
                }
                Some((t, Tok::Num(v))) if v <= 0.0 => {
                    self.error(t.span, format!("a weight must be positive, not {v}"), hint);
                    return None;
                }
                Some((_, Tok::Num(v))) => weight = v,
                _ => {
                    self.error(w.span, "expected a number after `Weight`", hint);
                    return None;
                }
            }
            i = 2;
        }
        if let Some(t) = toks.get(i).filter(|t| t.tok == Tok::If) {
            if !first {
                self.error(
                    t.span,
                    "the condition goes after the first successor",
                    "the condition applies to the whole rule: `Edge0_i -> A Weight 1 If i < 3 -> B Weight 1`",
                );
                return None;
            }
            condition = Some(self.condition(&toks[i..], timed)?);
            i += 4;
        }
        if let Some(t) = toks.get(i) {
            let hint = match t.tok {
                Tok::Weight if condition.is_some() => "`Weight w` comes before `If`",
                Tok::Weight => "a successor has one `Weight`",
                _ => "a successor ends with an optional `Weight w` and, after the first successor, `If i < c`",
            };
            self.error(t.span, format!("unexpected `{}` after the successor", t.text), hint);
            return None;
        }
        Some((weight, condition))
    }

    /// `If i <op> c`, `toks[0]` being `If`.
    fn condition(&mut self, toks: &[Token], timed: bool) -> Option<Condition> {
        const HINT: &str = "a condition tests the edge's age: `If i < 3`, `If i > 0` or `If i = 2`";
        let at = |k: usize| toks.get(k).map_or(toks[0].span, |t| t.span);
        if toks.get(1).map(|t| t.tok) != Some(Tok::I) {
            self.error(at(1), "expected `i` after `If`", HINT);
            return None;
        }
        let cmp = match toks.get(2).map(|t| t.tok) {
            Some(Tok::Lt) => Cmp::Less,
            Some(Tok::Gt) => Cmp::Greater,
            Some(Tok::Eq) => Cmp::Equal,
            _ => {
                self.error(at(2), "expected `<`, `>` or `=` after `If i`", HINT);
                return None;
            }
        };
        let Some(value) = toks.get(3).filter(|t| matches!(t.tok, Tok::Num(_))).and_then(|t| t.text.parse::<i64>().ok())
        else {
            self.error(at(3), "expected a whole number in the condition", HINT);
            return None;
        };
        if !timed {
            self.error(
                toks[0].span,
                "a condition needs a timed predecessor",
                "write the predecessor as `EdgeN_i` so that `i` is the edge's age",
            );
        }
        Some(Condition { cmp, value })
    }

    /// The items of a successor's body (no `Weight`/`If`).
    fn items(&mut self, toks: &[Token], timed: bool) -> Option<Vec<Item>> {
        let mut items = Vec::new();
        let mut tilde: Option<Span> = None;
        let mut i = 0;
        while let Some(t) = toks.get(i) {
            match t.tok {
                Tok::Turn(turn) => items.push(Item::Turn(turn)),
                Tok::Tilde => self.tilde(&mut tilde, t.span),
                Tok::Edge(kind, age) => items.push(Item::Edge(self.edge(t, kind, age, tilde.take(), timed))),
                Tok::Open => {
                    self.dangling(&mut tilde);
                    self.branch(toks, &mut i, 1, timed, &mut items)?;
                    continue;
                }
                Tok::Close => {
                    self.error(t.span, "unmatched `]`", "this `]` has no `[` before it on the line");
                    return None;
                }
                _ => {
                    self.unexpected(t);
                    return None;
                }
            }
            i += 1;
        }
        self.dangling(&mut tilde);
        Some(items)
    }

    /// A `[ … ]` starting at `toks[*i]`: nested branches first (pushed to
    /// `out` before this one), then turns and one edge.
    fn branch(&mut self, toks: &[Token], i: &mut usize, depth: usize, timed: bool, out: &mut Vec<Item>) -> Option<()> {
        let open = toks[*i].span;
        if depth > MAX_NESTING {
            self.error(
                open,
                format!("brackets nested more than {MAX_NESTING} deep"),
                "write the branches as siblings: `[ + Edge1 ] [ - Edge1 ]`",
            );
            return None;
        }
        *i += 1;
        let mut turns = Vec::new();
        let mut edge: Option<EdgeSym> = None;
        let mut tilde: Option<Span> = None;
        loop {
            let Some(t) = toks.get(*i) else {
                self.error(open, "`[` is never closed", "every `[` needs a matching `]` on the same line");
                return None;
            };
            match t.tok {
                Tok::Close => {
                    *i += 1;
                    self.dangling(&mut tilde);
                    match edge {
                        Some(edge) => out.push(Item::Branch(Branch { turns, edge })),
                        None => self.error(
                            open,
                            "a branch needs an edge",
                            "a branch is turns and then one edge: `[ + Edge1 ]`",
                        ),
                    }
                    return Some(());
                }
                Tok::Open if edge.is_none() && turns.is_empty() && tilde.is_none() => {
                    self.branch(toks, i, depth + 1, timed, out)?;
                    continue;
                }
                _ if edge.is_some() => {
                    self.error(
                        t.span,
                        "a branch holds exactly one edge and ends after it",
                        "close it with `]`; for more edges write sibling branches: `[ + Edge1 ] [ - Edge2 ]`",
                    );
                    return None;
                }
                Tok::Open => {
                    self.error(
                        t.span,
                        "a nested branch must come first in its branch, before any turn",
                        "all branches start from the pushed state: write `[ [ + Edge1 ] - Edge1 ]` or the siblings \
                         `[ + Edge1 ] [ - Edge1 ]`",
                    );
                    return None;
                }
                Tok::Turn(turn) => turns.push(turn),
                Tok::Tilde => self.tilde(&mut tilde, t.span),
                Tok::Edge(kind, age) => edge = Some(self.edge(t, kind, age, tilde.take(), timed)),
                _ => {
                    self.unexpected(t);
                    return None;
                }
            }
            *i += 1;
        }
    }

    /// A `~`: it reverses the next edge of its line; a second one cancels it.
    fn tilde(&mut self, pending: &mut Option<Span>, at: Span) {
        if let Some(first) = pending.take() {
            self.diags.push(
                Diagnostic::warning(at, "two `~` before one edge cancel out")
                    .with_label(first, "first `~`")
                    .with_hint("remove both, or keep one to reverse the edge"),
            );
        } else {
            *pending = Some(at);
        }
    }

    /// Reports a `~` that found no edge before `[`, `]` or the end.
    fn dangling(&mut self, pending: &mut Option<Span>) {
        if let Some(at) = pending.take() {
            self.error(
                at,
                "`~` must be followed by an edge",
                "`~` reverses the next edge: write it directly before one, e.g. `~ Edge1`",
            );
        }
    }

    fn edge(&mut self, t: &Token, kind: u32, age: Age, tilde: Option<Span>, timed: bool) -> EdgeSym {
        if age != Age::Zero && !timed {
            self.error(
                t.span,
                format!("`{}` uses the age `i`, but the predecessor is not timed", t.text),
                "write the predecessor as `EdgeN_i` to bind `i`",
            );
        }
        EdgeSym { kind, reversed: tilde.is_some(), age }
    }

    fn unexpected(&mut self, t: &Token) {
        let (message, hint) = match t.tok {
            Tok::Lt | Tok::Gt => (
                format!("`{}` marks a context and belongs in the predecessor", t.text),
                "e.g. `Edge1 < Edge0 > Edge2 -> …`".to_string(),
            ),
            Tok::Angle | Tok::Sync | Tok::BranchAngle => (
                format!("`{}` goes on its own line after the rules", t.text),
                "the file ends with `Angle d`, then `Sync` and `BranchAngle d`, one per line".to_string(),
            ),
            Tok::Num(_) => (
                format!("unexpected number `{}`", t.text),
                "numbers follow `Angle`, `BranchAngle`, `Weight` or `If i <`".to_string(),
            ),
            _ => (
                format!("unexpected `{}` in a successor", t.text),
                "a successor holds edges, turns `+ - & ^ \\ /`, `~` and branches `[ … ]`".to_string(),
            ),
        };
        self.error(t.span, message, hint);
    }

    /// A successor's main line needs an edge and balanced turns.
    fn check_main_line(&mut self, items: &[Item], span: Span) {
        if !items.iter().any(|it| matches!(it, Item::Edge(_))) {
            self.error(
                span,
                "the successor's main line has no edge",
                "the main line replaces the old edge: it needs at least one edge outside brackets",
            );
            return;
        }
        let count = |turn: Turn| items.iter().filter(|it| **it == Item::Turn(turn)).count();
        let pairs = [
            (Turn::Right, Turn::Left, "+", "-"),
            (Turn::PitchDown, Turn::PitchUp, "&", "^"),
            (Turn::RollLeft, Turn::RollRight, "\\", "/"),
        ];
        let uneven: Vec<String> = pairs
            .iter()
            .filter(|(a, b, ..)| count(*a) != count(*b))
            .map(|(a, b, sa, sb)| format!("{} `{sa}` but {} `{sb}`", count(*a), count(*b)))
            .collect();
        if !uneven.is_empty() {
            self.error(
                span,
                format!("the successor's main line turns do not balance: {}", uneven.join(", ")),
                "the main line must end on the old edge's end vertex, so outside brackets every `+` needs a `-`, \
                 every `&` a `^` and every `\\` a `/` (branches may turn freely)",
            );
        }
    }

    // ---- end of file ------------------------------------------------------

    fn finish(&mut self, lines: &[Line], name: String) -> Option<Hemls> {
        let Some(last) = lines.last() else {
            self.error(
                Span::new(0, 0),
                "empty file: expected the axiom, the rules and `Angle`",
                "a minimal grammar is `Edge0 + Edge0 + Edge0`, `Edge0 -> Edge0 - Edge0 + + Edge0 - Edge0`, `Angle 60` \
                 on three lines",
            );
            return None;
        };
        let end = last.span().end as usize;
        if self.angle_line.is_none() {
            self.error(
                Span::new(end, end),
                "missing `Angle`",
                "add a line `Angle d` after the rules, the turn angle in degrees, e.g. `Angle 60`",
            );
        }
        if self.rule_lines == 0
            && let Some(at) = self.axiom_line
        {
            self.diags.push(
                Diagnostic::warning(at, "no rewrite rules: every edge keeps its type and only grows")
                    .with_hint("add rules after the axiom, e.g. `Edge0 -> Edge0 - Edge0 + + Edge0 - Edge0`"),
            );
        }
        Some(Hemls {
            name,
            axiom: self.axiom.take()?,
            rules: std::mem::take(&mut self.rules),
            angle: self.angle?,
            sync: self.sync_line.is_some(),
            branch_angle: self.branch_angle,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ok(text: &str) -> Hemls {
        match compile(&SourceFile::new("t.gr8", text)) {
            Ok((h, w)) => {
                assert!(w.items.is_empty(), "unexpected warnings:\n{}", w.short());
                h
            }
            Err(e) => panic!("{text}\n{}", e.short()),
        }
    }

    fn errors(text: &str) -> String {
        match compile(&SourceFile::new("t.gr8", text)) {
            Ok(_) => panic!("accepted:\n{text}"),
            Err(e) => e.short(),
        }
    }

    fn warnings(text: &str) -> String {
        match compile(&SourceFile::new("t.gr8", text)) {
            Ok((_, w)) => w.short(),
            Err(e) => panic!("{}", e.short()),
        }
    }

    /// The only rule's first successor of `axiom / rule / Angle 60`.
    fn succ(rule: &str) -> Vec<Item> {
        let h = ok(&format!("Edge0 + Edge0 + Edge0\n{rule}\nAngle 60\n"));
        h.rules[0].successors[0].items.clone()
    }

    fn e(kind: u32) -> EdgeSym {
        EdgeSym { kind, reversed: false, age: Age::Zero }
    }

    fn br(turns: &[Turn], kind: u32) -> Item {
        Item::Branch(Branch { turns: turns.to_vec(), edge: e(kind) })
    }

    use Turn::{Left as L, Right as R};

    #[test]
    fn koch_reads_axiom_rule_and_angle() {
        let h = ok("// Koch\nEdge0 + Edge0 + Edge0\nEdge0 -> Edge0 - Edge0 + + Edge0 - Edge0\nAngle 60\n");
        assert_eq!(h.name, "t");
        assert_eq!(h.axiom, vec![AxiomSide { kind: 0, reversed: false }; 3]);
        assert_eq!(h.angle, 60.0);
        assert!(!h.sync);
        assert_eq!(h.branch_angle, None);
        let r = &h.rules[0];
        assert_eq!(r.pred, Predecessor { kind: 0, timed: false, left: None, right: None });
        assert_eq!(r.condition, None);
        assert_eq!(r.successors.len(), 1);
        assert_eq!(r.successors[0].weight, 1.0);
        use Item::{Edge as E, Turn as T};
        assert_eq!(r.successors[0].items, vec![E(e(0)), T(L), E(e(0)), T(R), T(R), E(e(0)), T(L), E(e(0))]);
    }

    #[test]
    fn nested_brackets_equal_sibling_branches() {
        let nested = succ("Edge0 -> Edge0 [ [ [ [ + Edge2 ] + + Edge1 ] - Edge1 ] - - Edge2 ] Edge0");
        let siblings = succ("Edge0 -> Edge0 [ + Edge2 ] [ + + Edge1 ] [ - Edge1 ] [ - - Edge2 ] Edge0");
        assert_eq!(nested, siblings);
        assert_eq!(
            nested,
            vec![Item::Edge(e(0)), br(&[R], 2), br(&[R, R], 1), br(&[L], 1), br(&[L, L], 2), Item::Edge(e(0))]
        );
        // Two nested siblings inside one branch keep their order too.
        assert_eq!(succ("Edge0 -> Edge0 [ [ + Edge1 ] [ - Edge2 ] Edge3 ]"), {
            vec![Item::Edge(e(0)), br(&[R], 1), br(&[L], 2), br(&[], 3)]
        });
    }

    #[test]
    fn tilde_reverses_the_next_edge() {
        let h = ok("Edge0 + ~ Edge1 + Edge0 + ~ Edge1\nEdge0 -> ~ Edge0 [ + ~ Edge1 ] Edge2\nAngle 90\n");
        let rev: Vec<bool> = h.axiom.iter().map(|s| s.reversed).collect();
        assert_eq!(rev, vec![false, true, false, true]);
        let items = &h.rules[0].successors[0].items;
        assert_eq!(items[0], Item::Edge(EdgeSym { reversed: true, ..e(0) }));
        assert_eq!(items[1], Item::Branch(Branch { turns: vec![R], edge: EdgeSym { reversed: true, ..e(1) } }));
        assert_eq!(items[2], Item::Edge(e(2)));
        // The BNF's `~ <Modifier>`: `~` carries over turns to the next edge.
        assert_eq!(
            succ("Edge0 -> ~ + Edge1 - Edge0"),
            vec![Item::Turn(R), Item::Edge(EdgeSym { reversed: true, ..e(1) }), Item::Turn(L), Item::Edge(e(0))]
        );
        // `~ ~` cancel, with a warning.
        let w = warnings("Edge0 + Edge0 + Edge0\nEdge0 -> ~ ~ Edge1\nAngle 60\n");
        assert!(w.contains("2:12: warning: two `~` before one edge cancel out"), "{w}");
        // A `~` with no edge after it.
        let es = errors("Edge0 + Edge0 + Edge0\nEdge0 -> Edge0 ~ [ + Edge1 ] Edge0 ~\nAngle 60\n");
        assert!(es.contains("2:16: error: `~` must be followed by an edge"), "{es}");
        assert!(es.contains("2:36: error: `~` must be followed by an edge"), "{es}");
        // The EA's `Edge ~ + Edge` axiom form is rejected with a hint.
        let es = errors("Edge0 ~ + Edge1 + Edge0\nAngle 60\n");
        assert!(es.contains("1:7: error: `~` in the axiom must come directly before an edge"), "{es}");
        assert!(es.contains("`+ ~ Edge1`"), "{es}");
    }

    #[test]
    fn weights_make_stochastic_rules() {
        let h = ok("Edge0 + Edge0 + Edge0\nEdge0 -> Edge0 Edge0 Weight 3 -> Edge0 -> Edge1 Weight 0.5\nAngle 60\n");
        let w: Vec<f64> = h.rules[0].successors.iter().map(|s| s.weight).collect();
        assert_eq!(w, vec![3.0, 1.0, 0.5]);
        assert_eq!(h.rules[0].successors[2].items, vec![Item::Edge(e(1))]);
        for (bad, msg) in [
            ("Weight 0", "2:29: error: a weight must be positive, not 0"),
            ("Weight -2", "2:29: error: a weight must be positive, not -2"),
            ("Weight NaN", "2:29: error: `NaN` is not a finite number"),
            ("Weight inf", "2:29: error: `inf` is not a finite number"),
            ("Weight", "2:22: error: expected a number after `Weight`"),
            ("Weight 1 Weight 2", "2:31: error: unexpected `Weight` after the successor"),
        ] {
            let es = errors(&format!("Edge0 + Edge0 + Edge0\nEdge0 -> Edge0 Edge0 {bad}\nAngle 60\n"));
            assert!(es.contains(msg), "{bad}: {es}");
        }
    }

    #[test]
    fn timed_edges_and_conditions() {
        let h =
            ok("Edge0 + Edge0 + Edge0\nEdge0_i -> Edge0_i+1 Edge1_i Edge2_i-1 Edge3 Weight 2 If i < 3 -> Edge0_i\n\
                    Edge1_i -> Edge1_i+1 If i = -1\nEdge2_i -> Edge2 If i > 7\nAngle 60\n");
        let r = &h.rules[0];
        assert!(r.pred.timed);
        assert_eq!(r.condition, Some(Condition { cmp: Cmp::Less, value: 3 }));
        let ages: Vec<Age> = r.successors[0]
            .items
            .iter()
            .map(|it| match it {
                Item::Edge(s) => s.age,
                _ => panic!(),
            })
            .collect();
        assert_eq!(ages, vec![Age::Plus1, Age::Same, Age::Minus1, Age::Zero]);
        assert_eq!(r.successors[0].weight, 2.0);
        assert_eq!(h.rules[1].condition, Some(Condition { cmp: Cmp::Equal, value: -1 }));
        assert_eq!(h.rules[2].condition, Some(Condition { cmp: Cmp::Greater, value: 7 }));

        let es = errors(
            "Edge0 + Edge0 + Edge0\nEdge0 -> Edge0_i+1 If i < 3\nEdge1_i -> Edge1 -> Edge1 If i < 2\nAngle 60\n",
        );
        assert!(es.contains("2:10: error: `Edge0_i+1` uses the age `i`, but the predecessor is not timed"), "{es}");
        assert!(es.contains("2:20: error: a condition needs a timed predecessor"), "{es}");
        assert!(es.contains("3:27: error: the condition goes after the first successor"), "{es}");
        let es = errors("Edge0 + Edge0 + Edge0\nEdge0_i -> Edge0 If i < 2.5\nEdge0_i+1 -> Edge0\nAngle 60\n");
        assert!(es.contains("2:25: error: expected a whole number in the condition"), "{es}");
        assert!(es.contains("3:1: error: `Edge0_i+1`: in a predecessor only `Edge0_i` binds the age"), "{es}");
    }

    #[test]
    fn contexts_and_predecessor_forms() {
        let h = ok(
            "Edge0 + Edge1 + Edge2\nEdge1 < Edge0 -> Edge0\nEdge0 > Edge2 -> Edge0\nEdge1 < Edge0_i > Edge2 -> Edge0\n\
                    Angle 60\n",
        );
        let p: Vec<Predecessor> = h.rules.iter().map(|r| r.pred).collect();
        assert_eq!(p[0], Predecessor { kind: 0, timed: false, left: Some(1), right: None });
        assert_eq!(p[1], Predecessor { kind: 0, timed: false, left: None, right: Some(2) });
        assert_eq!(p[2], Predecessor { kind: 0, timed: true, left: Some(1), right: Some(2) });
        let es = errors(
            "Edge0 + Edge1 + Edge2\nEdge1 Edge2 -> Edge0\nEdge1_i < Edge0 -> Edge0\n< Edge0 -> Edge0\nEdge0 > -> Edge0\n\
             Edge0 > Edge1 < Edge2 -> Edge0\n-> Edge0\n~ Edge0 -> Edge0\nAngle 60\n",
        );
        for want in [
            "2:7: error: multi-segment predecessors are not supported",
            "3:1: error: a left context is a plain edge, not `Edge1_i`",
            "4:1: error: expected a left context edge before `<`",
            "5:7: error: expected a right context edge after `>`",
            "6:7: error: `>` must come after `<`",
            "7:1: error: expected an edge before `->`",
            "8:1: error: a predecessor cannot hold `~`",
        ] {
            assert!(es.contains(want), "{want}\n{es}");
        }
    }

    #[test]
    fn parameter_lines_in_either_order_after_angle() {
        let h = ok("Edge0 + Edge0 + Edge0\nEdge0 -> Edge0\nAngle 45\nBranchAngle 15\nSync\n");
        assert!(h.sync);
        assert_eq!(h.branch_angle, Some(15.0));
        // The EA's output puts `Sync` before `Angle`.
        let h = ok("Edge0 + Edge0 + Edge0\nEdge0 -> Edge0\nSync\nAngle 22.5\nBranchAngle 60\n");
        assert!(h.sync);
        assert_eq!(h.angle, 22.5);
        let es = errors("Edge0 + Edge0 + Edge0\nEdge0 -> Edge0\nBranchAngle 15\nAngle 45\n");
        assert!(es.contains("3:1: error: `BranchAngle` must come after `Angle`"), "{es}");
        let es = errors("Edge0 + Edge0 + Edge0\nAngle 60\nEdge0 -> Edge0\nSync\nEdge1 -> Edge1\n");
        assert!(es.contains("3:1: error: rule after `Angle`"), "{es}");
        assert!(es.contains("move this rule above line 2"), "{es}");
        assert!(es.contains("5:1: error: rule after `Angle`"), "{es}");
    }

    #[test]
    fn parameter_values_are_checked() {
        let es = errors(
            "Edge0 + Edge0 + Edge0\nEdge0 -> Edge0\nAngle 361\nAngle 60\nBranchAngle -1\nSync 1\nSync\nBranchAngle 5\n",
        );
        for want in [
            "3:7: error: `Angle` must be between 0 and 360 degrees, not 361",
            "4:1: error: duplicate `Angle` line",
            "5:13: error: `BranchAngle` must be between 0 and 90 degrees, not -1",
            "6:6: error: unexpected `1` after `Sync`",
            "7:1: error: duplicate `Sync` line",
            "8:1: error: duplicate `BranchAngle` line",
        ] {
            assert!(es.contains(want), "{want}\n{es}");
        }
        for (bad, want) in [
            ("Angle nan", "3:7: error: `nan` is not a finite number"),
            ("Angle 1e999", "3:7: error: `1e999` is not a finite number"),
            ("Angle", "3:1: error: expected a number after `Angle`"),
            ("Angle sixty", "3:7: error: unknown token `sixty`"),
            ("Angle 60 60", "3:10: error: unexpected `60` after the angle"),
        ] {
            let es = errors(&format!("Edge0 + Edge0 + Edge0\nEdge0 -> Edge0\n{bad}\n"));
            assert!(es.contains(want), "{bad}: {es}");
        }
        // Bounds are inclusive.
        let h = ok("Edge0 + Edge0 + Edge0\nEdge0 -> Edge0\nAngle 360\nBranchAngle 90\n");
        assert_eq!((h.angle, h.branch_angle), (360.0, Some(90.0)));
    }

    #[test]
    fn main_line_must_have_an_edge_and_balanced_turns() {
        let es = errors(
            "Edge0 + Edge0 + Edge0\nEdge0 -> [ + Edge1 ]\nEdge0 -> Edge0 + Edge0\nEdge0 -> & Edge0 \\ Edge0 ^\nAngle 60\n",
        );
        assert!(es.contains("2:10: error: the successor's main line has no edge"), "{es}");
        assert!(es.contains("3:10: error: the successor's main line turns do not balance: 1 `+` but 0 `-`"), "{es}");
        assert!(es.contains("4:10: error: the successor's main line turns do not balance: 1 `\\` but 0 `/`"), "{es}");
        assert!(es.contains("end vertex"), "{es}");
        // Branch turns do not count; pitch and roll pairs balance on their own.
        succ("Edge0 -> Edge0 [ + + & Edge1 ] & \\ Edge0 / ^");
    }

    #[test]
    fn brackets_must_balance_and_branches_hold_one_edge() {
        let es = errors(
            "Edge0 + Edge0 + Edge0\nEdge0 -> Edge0 ] Edge0\nEdge0 -> Edge0 [ + Edge1\nEdge0 -> Edge0 [ + Edge1 Edge2 ] Edge0\n\
             Edge0 -> Edge0 [ + ] Edge0\nEdge0 -> Edge0 [ + [ - Edge1 ] Edge2 ] Edge0\nAngle 60\n",
        );
        for want in [
            "2:16: error: unmatched `]`",
            "3:16: error: `[` is never closed",
            "4:26: error: a branch holds exactly one edge",
            "5:16: error: a branch needs an edge",
            "6:20: error: a nested branch must come first in its branch",
        ] {
            assert!(es.contains(want), "{want}\n{es}");
        }
        let deep = format!(
            "Edge0 + Edge0 + Edge0\nEdge0 -> Edge0 {} Edge1 {} Edge0\nAngle 60\n",
            "[ ".repeat(100),
            "] ".repeat(100)
        );
        assert!(errors(&deep).contains("nested more than 64 deep"));
    }

    #[test]
    fn tokens_and_edges_are_checked_with_hints() {
        let es = errors("Edge0 + Edge0 + Edge0\nedge0 -> Edge Edge1000001 EdgeX\nangle 60\n");
        for want in [
            "2:1: error: unknown token `edge0`\n  hint: did you mean `Edge0`?",
            "2:10: error: `Edge`: an edge needs its type number",
            "2:15: error: the edge type in `Edge1000001` is too large (at most 1000000)",
            "2:27: error: `EdgeX` is a placeholder",
            "3:1: error: unknown token `angle`\n  hint: did you mean `Angle`?",
        ] {
            assert!(es.contains(want), "{want}\n{es}");
        }
        // A misspelt `Angle` line does not also count as a missing `Angle`.
        assert!(!es.contains("missing `Angle`"), "{es}");
    }

    #[test]
    fn file_structure_errors() {
        assert!(errors("").contains("1:1: error: empty file"));
        assert!(errors("// only a comment\n\n").contains("1:1: error: empty file"));
        let es = errors("Edge0 + Edge0 + Edge0\nEdge0 -> Edge0\n");
        assert!(es.contains("2:15: error: missing `Angle`"), "{es}");
        let es = errors("Edge0 -> Edge0\nAngle 60\n");
        assert!(es.contains("1:1: error: missing axiom"), "{es}");
        assert_eq!(es.matches("missing axiom").count(), 1, "{es}");
        let es = errors("Edge0 + Edge0 + Edge0\nEdge0 + Edge0 + Edge0\nEdge0 Edge1\nAngle 60\n");
        assert!(
            es.contains("2:1: error: expected a rule, but this line has no `->`\n  hint: a file has one axiom"),
            "{es}"
        );
        assert!(es.contains("3:1: error: expected a rule"), "{es}");
        for (axiom, want) in [
            ("Edge0 + Edge0", "1:1: error: the axiom needs at least 3 sides, found 2"),
            ("Edge0 + Edge0 + + Edge0", "1:17: error: two `+` in a row"),
            ("Edge0 Edge0 + Edge0", "1:7: error: expected `+` between the axiom's sides"),
            ("Edge0 + Edge0 - Edge0", "1:15: error: the axiom may contain only"),
            ("Edge0 + Edge0 + Edge0 +", "1:23: error: the axiom ends with `+`"),
            ("+ Edge0 + Edge0 + Edge0", "1:1: error: the axiom must start with an edge"),
            ("Edge0_i + Edge0 + Edge0", "1:1: error: the axiom's edges have no age"),
        ] {
            let es = errors(&format!("{axiom}\nEdge0 -> Edge0\nAngle 60\n"));
            assert!(es.contains(want), "{axiom}: {es}");
        }
    }

    #[test]
    fn all_errors_of_a_file_are_reported() {
        let es = errors("Edge0 + Edge0\nEdge0 -> Edge0 +\nEdge1 -> [\nAngle 400\n");
        assert_eq!(es.matches(": error: ").count(), 4, "{es}");
    }

    #[test]
    fn shadowed_rules_warn() {
        let w = warnings(
            "Edge0 + Edge0 + Edge0\nEdge0 -> Edge0 Edge0\nEdge0 -> Edge0\nEdge0_i -> Edge0 If i < 2\n\
             Edge1_i -> Edge1 If i < 2\nEdge1_i -> Edge1 If i < 2\nEdge1_i -> Edge1 If i < 3\nEdge1 < Edge0 -> Edge0\nAngle 60\n",
        );
        assert!(w.contains("3:1: warning: this rule can never apply: the rule on line 2 matches first"), "{w}");
        assert!(w.contains("4:1: warning: this rule can never apply: the rule on line 2"), "{w}");
        assert!(w.contains("6:1: warning: this rule can never apply: the rule on line 5"), "{w}");
        assert_eq!(w.matches("warning").count(), 3, "{w}");
        let w = warnings("Edge0 + Edge0 + Edge0\nAngle 60\n");
        assert!(w.contains("1:1: warning: no rewrite rules"), "{w}");
    }

    #[test]
    fn comments_crlf_and_several_spaces() {
        let h = ok(
            "// header\r\n// more\r\nEdge0  +\tEdge0 + Edge0   // the seed\r\n\r\n// a rule:\r\nEdge0 -> Edge0 Edge0\r\n\
                    Angle 60 // degrees\r\nSync\r\n",
        );
        assert_eq!(h.axiom.len(), 3);
        assert_eq!(h.rules.len(), 1);
        assert!(h.sync);
        // Rule spans cover the rule's text, not its comment.
        let h = ok("Edge0 + Edge0 + Edge0\nEdge0 -> Edge0 Edge0 // doubled\nAngle 60\n");
        assert_eq!(h.rules[0].span, Span::new(22, 42));
    }

    #[test]
    fn name_is_the_file_stem() {
        let h = parse_str("some/dir/tiles3.gr8", "Edge0 + Edge0 + Edge0\nEdge0 -> Edge0\nAngle 60\n").unwrap();
        assert_eq!(h.name, "tiles3");
        let h = parse_str("koch", "Edge0 + Edge0 + Edge0\nEdge0 -> Edge0\nAngle 60\n").unwrap();
        assert_eq!(h.name, "koch");
    }
}
