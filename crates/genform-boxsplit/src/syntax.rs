//! The `.bsg` syntax tree and its recursive-descent parser. The parser
//! reports every error it can find: after a mistake it skips to the end of
//! the alternative or declaration and carries on.

use crate::dialect::{DIALECT, KEYWORDS};
use crate::lex::{Tok, Token, block_at, string_value, token_at};
use crate::split::Round;
use genform_core::diag::{Diagnostic, Span};
use genform_core::expr::{self, Ast};

/// A name and where it is.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Ident {
    pub name: String,
    pub span: Span,
}

/// One entry of a `material` mix: `3 stone_bricks`.
#[derive(Clone, Debug)]
pub(crate) struct MixEntry {
    pub weight: f64,
    pub weight_span: Option<Span>,
    pub block: Ident,
}

/// A top-level declaration.
#[derive(Clone, Debug)]
pub(crate) enum Item {
    Grammar(String, Span),
    Axiom(Ident),
    Limits(Vec<(Ident, f64, Span)>),
    /// `box x0, y0, z0, x1, y1, z1;`: the corners as written (sign applied)
    /// and the whole declaration's span.
    Box(Vec<(f64, Span)>, Span),
    /// `world "…";`: the path and the string's span.
    World(String, Span),
    /// `allow_unknown_blocks;`: the statement's span.
    AllowUnknownBlocks(Span),
    Group(Ident, Vec<Ident>),
    Material(Ident, Vec<MixEntry>),
    /// `support above|below|beside|rooted members;`: the side and the members.
    Support(Ident, Vec<Ident>),
    /// `site foundation = B, yard = N;`: the settings and the keyword's span.
    Site(Vec<(Ident, SiteValue)>, Span),
    Let(Ident, Ast),
    Rule(RuleSyn),
}

/// A value in `site …;`: a block or material, or a number.
#[derive(Clone, Debug)]
pub(crate) enum SiteValue {
    Block(Ident),
    Number(f64, Span),
}

/// `Name { alternatives }`.
#[derive(Clone, Debug)]
pub(crate) struct RuleSyn {
    pub name: Ident,
    pub alts: Vec<AltSyn>,
}

/// When an alternative applies.
#[derive(Clone, Debug)]
pub(crate) enum Guard {
    Always,
    When(Ast),
    Else,
}

/// One alternative of a rule.
#[derive(Clone, Debug)]
pub(crate) struct AltSyn {
    pub guard: Guard,
    pub weight: Option<(f64, Span)>,
    pub op: OpSyn,
    /// The alternative's first token.
    pub span: Span,
}

/// An operation (or a split child).
#[derive(Clone, Debug)]
pub(crate) enum OpSyn {
    Split {
        axis: usize,
        sizes: Vec<Ast>,
        repeat: bool,
        round: Round,
        children: Vec<OpSyn>,
        /// The `split` keyword.
        span: Span,
        /// The `{ … }` of the children.
        children_span: Span,
    },
    Fill(Ident),
    Void,
    Skip,
    Reorient([usize; 3], Span, Box<OpSyn>),
    Call(Ident),
}

const DECLARATIONS: &[&str] = &[
    "grammar",
    "axiom",
    "limits",
    "box",
    "world",
    "allow_unknown_blocks",
    "group",
    "material",
    "support",
    "site",
    "let",
];

/// The sides a `support` declaration names.
pub(crate) const SUPPORT_SIDES: &[&str] = &["above", "below", "beside", "rooted"];

/// Deepest nesting of split children accepted (formulas have the core
/// parser's own limit).
const MAX_NESTING: usize = 100;

type PResult<T> = Result<T, Diagnostic>;

/// Reads a whole file into declarations, collecting every error.
pub(crate) fn parse(src: &str) -> (Vec<Item>, Vec<Diagnostic>) {
    let mut p = Parser { src, tok: token_at(src, 0), depth: 0, nesting: 0, errors: Vec::new() };
    let mut items = Vec::new();
    while p.tok.tok != Tok::Eof {
        match p.item() {
            Ok(Some(item)) => items.push(item),
            Ok(None) => {}
            Err(d) => {
                p.errors.push(d);
                p.recover_top();
            }
        }
    }
    (items, p.errors)
}

struct Parser<'a> {
    src: &'a str,
    tok: Token,
    /// Open `{` braces consumed so far.
    depth: usize,
    /// Current nesting of child lists (recursion guard).
    nesting: usize,
    errors: Vec<Diagnostic>,
}

fn describe(src: &str, t: Token) -> String {
    match t.tok {
        Tok::Eof => "the end of the file".into(),
        Tok::Str | Tok::BadStr => "a string".into(),
        _ => format!("`{}`", &src[t.span.start as usize..t.span.end as usize]),
    }
}

impl<'a> Parser<'a> {
    fn text(&self, span: Span) -> &'a str {
        &self.src[span.start as usize..span.end as usize]
    }

    fn bump(&mut self) -> Token {
        let t = self.tok;
        match t.tok {
            Tok::LBrace => self.depth += 1,
            Tok::RBrace => self.depth = self.depth.saturating_sub(1),
            _ => {}
        }
        self.tok = token_at(self.src, t.span.end as usize);
        t
    }

    fn is_kw(&self, kw: &str) -> bool {
        self.tok.tok == Tok::Ident && self.text(self.tok.span) == kw
    }

    fn eat_kw(&mut self, kw: &str) -> Option<Span> {
        if self.is_kw(kw) { Some(self.bump().span) } else { None }
    }

    fn found(&self) -> String {
        describe(self.src, self.tok)
    }

    fn error_here(&self, what: impl Into<String>) -> Diagnostic {
        Diagnostic::error(self.tok.span, format!("expected {}, found {}", what.into(), self.found()))
    }

    fn expect(&mut self, tok: Tok, what: &str) -> PResult<Span> {
        if self.tok.tok == tok { Ok(self.bump().span) } else { Err(self.error_here(what)) }
    }

    /// The keyword just seen, then `"…";`: the string's value and span
    /// (`grammar "castle";`, `world "r.0.0.mca";`). `what` names the string.
    fn quoted_declaration(&mut self, what: &str, hint: &str) -> PResult<(String, Span)> {
        self.bump();
        if self.tok.tok != Tok::Str {
            return Err(self.error_here(format!("{what} in quotes")).with_hint(hint));
        }
        let t = self.bump();
        self.end_declaration(what);
        Ok((string_value(self.src, t.span), t.span))
    }

    /// A `;` that ends a declaration; a missing one is reported without
    /// skipping anything (the declaration itself was complete).
    fn end_declaration(&mut self, what: &str) {
        if self.tok.tok == Tok::Semi {
            self.bump();
        } else {
            let d = self.error_here(format!("`;` after {what}")).with_hint("every declaration ends with `;`");
            self.errors.push(d);
        }
    }

    fn ident(&mut self, what: &str) -> PResult<Ident> {
        if self.tok.tok != Tok::Ident {
            return Err(self.error_here(what));
        }
        let t = self.bump();
        Ok(Ident { name: self.text(t.span).to_string(), span: t.span })
    }

    /// A name that must not be a keyword.
    fn name(&mut self, what: &str) -> PResult<Ident> {
        let id = self.ident(what)?;
        if KEYWORDS.contains(&id.name.as_str()) {
            return Err(Diagnostic::error(id.span, format!("expected {what}, found the keyword `{}`", id.name))
                .with_hint("keywords cannot be used as names"));
        }
        Ok(id)
    }

    /// A raw block reference (block id with properties, or a name).
    fn block(&mut self, what: &str) -> PResult<Ident> {
        let span = block_at(self.src, self.tok.span.start as usize);
        if span.start == span.end {
            return Err(self
                .error_here(what)
                .with_hint("a block is an id like `stone` or `minecraft:oak_log[axis=y]`"));
        }
        let end = span.end as usize;
        self.tok = token_at(self.src, end);
        Ok(Ident { name: self.text(span).to_string(), span })
    }

    fn item(&mut self) -> PResult<Option<Item>> {
        if self.tok.tok == Tok::Semi {
            self.bump();
            return Ok(None);
        }
        if self.tok.tok != Tok::Ident {
            return Err(self
                .error_here("a declaration or a rule")
                .with_hint("declarations start with `grammar`, `axiom`, `limits`, `box`, `world`, `allow_unknown_blocks`, `group`, `material`, `support`, `site` or `let`; a rule is `Name { … }`"));
        }
        let word = self.text(self.tok.span);
        Ok(Some(match word {
            "grammar" => {
                let (name, span) = self.quoted_declaration("the grammar's name", "write `grammar \"castle\";`")?;
                Item::Grammar(name, span)
            }
            "axiom" => {
                self.bump();
                let name = self.name("the start rule after `axiom`")?;
                self.end_declaration("the axiom");
                Item::Axiom(name)
            }
            "limits" => {
                self.bump();
                let mut limits = Vec::new();
                loop {
                    let key = self.ident("a limit (`applications`, `backtracks` or `depth`)")?;
                    self.expect(Tok::Assign, &format!("`=` after `{}`", key.name))?;
                    let Tok::Num(v) = self.tok.tok else {
                        return Err(self.error_here("a whole number"));
                    };
                    let vs = self.bump().span;
                    limits.push((key, v, vs));
                    if self.tok.tok != Tok::Comma {
                        break;
                    }
                    self.bump();
                }
                self.end_declaration("the limits");
                Item::Limits(limits)
            }
            "box" => {
                let start = self.bump().span;
                let mut corners = Vec::new();
                loop {
                    corners.push(self.signed_number("a whole number (a corner coordinate)")?);
                    if matches!(self.tok.tok, Tok::Num(_) | Tok::Minus) {
                        return Err(self
                            .error_here("`,` between the corner coordinates")
                            .with_hint("write `box x0, y0, z0, x1, y1, z1;` (two opposite corners, inclusive)"));
                    }
                    if self.tok.tok != Tok::Comma {
                        break;
                    }
                    self.bump();
                }
                let end = corners.last().map_or(start, |c| c.1);
                self.end_declaration("the box's corners");
                Item::Box(corners, start.to(end))
            }
            "world" => {
                let (path, span) = self.quoted_declaration(
                    "the world's path",
                    "write `world \"../terrain/r.0.0.mca\";` (relative to the grammar file)",
                )?;
                Item::World(path, span)
            }
            "allow_unknown_blocks" => {
                let span = self.bump().span;
                self.end_declaration("`allow_unknown_blocks`");
                Item::AllowUnknownBlocks(span)
            }
            "group" => {
                self.bump();
                let name = self.name("the group's name")?;
                self.expect(Tok::Assign, "`=` after the group's name")?;
                let mut members = vec![self.block("a block, a block type or a group")?];
                while self.tok.tok == Tok::Comma {
                    self.bump();
                    members.push(self.block("a block, a block type or a group")?);
                }
                self.end_declaration("the group's members");
                Item::Group(name, members)
            }
            "material" => {
                self.bump();
                let name = self.name("the material's name")?;
                self.expect(Tok::Assign, "`=` after the material's name")?;
                let mut entries = vec![self.mix_entry()?];
                while self.tok.tok == Tok::Comma {
                    self.bump();
                    entries.push(self.mix_entry()?);
                }
                self.end_declaration("the material's blocks");
                Item::Material(name, entries)
            }
            "support" => {
                self.bump();
                let side = self.ident("`above`, `below`, `beside` or `rooted` after `support`")?;
                if !SUPPORT_SIDES.contains(&side.name.as_str()) {
                    return Err(Diagnostic::error(side.span, format!("`support {}`: expected `above`, `below`, `beside` or `rooted`", side.name))
                        .with_hint("`support above lantern[hanging=true];` keeps a block only under a solid one, `below` only on one, `beside` only next to one; `rooted` keeps a tree only while it stands"));
                }
                let mut members = vec![self.block("a block, a block type, a group or a material")?];
                while self.tok.tok == Tok::Comma {
                    self.bump();
                    members.push(self.block("a block, a block type, a group or a material")?);
                }
                self.end_declaration("the supported blocks");
                Item::Support(side, members)
            }
            "site" => {
                let start = self.bump().span;
                let mut entries = Vec::new();
                loop {
                    let key = self.ident("`foundation` or `yard`")?;
                    self.expect(Tok::Assign, &format!("`=` after `{}`", key.name))?;
                    let value = if let Tok::Num(v) = self.tok.tok {
                        SiteValue::Number(v, self.bump().span)
                    } else {
                        SiteValue::Block(self.block("a block or a material")?)
                    };
                    entries.push((key, value));
                    if self.tok.tok != Tok::Comma {
                        break;
                    }
                    self.bump();
                }
                self.end_declaration("the site's settings");
                Item::Site(entries, start)
            }
            "let" => {
                self.bump();
                let name = self.name("a name after `let`")?;
                self.expect(Tok::Assign, "`=` after the name")?;
                let e = self.formula()?;
                self.end_declaration("the formula");
                Item::Let(name, e)
            }
            _ => Item::Rule(self.rule()?),
        }))
    }

    /// A number with an optional leading `-`, and its span (sign included).
    fn signed_number(&mut self, what: &str) -> PResult<(f64, Span)> {
        let start = self.tok.span;
        let sign = if self.tok.tok == Tok::Minus {
            self.bump();
            -1.0
        } else {
            1.0
        };
        match self.tok.tok {
            Tok::Num(v) => Ok((sign * v, start.to(self.bump().span))),
            _ => Err(self
                .error_here(what)
                .with_hint("write `box x0, y0, z0, x1, y1, z1;` (two opposite corners, inclusive)")),
        }
    }

    fn mix_entry(&mut self) -> PResult<MixEntry> {
        let (weight, weight_span) = match self.tok.tok {
            Tok::Num(v) => (v, Some(self.bump().span)),
            _ => (1.0, None),
        };
        let block = self.block("a block")?;
        Ok(MixEntry { weight, weight_span, block })
    }

    fn rule(&mut self) -> PResult<RuleSyn> {
        let name = self.name("a rule name")?;
        if self.tok.tok != Tok::LBrace {
            return Err(self
                .error_here(format!("`{{` to start the alternatives of `{}`", name.name))
                .with_hint("a rule is `Name { when … { operation } else { operation } }`"));
        }
        self.bump();
        let rule_depth = self.depth;
        let mut alts = Vec::new();
        while self.tok.tok != Tok::RBrace {
            if self.tok.tok == Tok::Eof {
                return Err(Diagnostic::error(self.tok.span, format!("rule `{}` is never closed", name.name))
                    .with_label(name.span, "opened here")
                    .with_hint("close it with `}`"));
            }
            match self.alternative() {
                Ok(a) => alts.push(a),
                Err(d) => {
                    let entered = self.depth > rule_depth;
                    self.errors.push(d);
                    self.recover_alternative(rule_depth, entered);
                }
            }
        }
        self.bump();
        Ok(RuleSyn { name, alts })
    }

    fn alternative(&mut self) -> PResult<AltSyn> {
        let span = self.tok.span;
        let guard = if self.eat_kw("when").is_some() {
            Guard::When(self.formula()?)
        } else if self.eat_kw("else").is_some() {
            Guard::Else
        } else {
            Guard::Always
        };
        let weight = if let Some(ws) = self.eat_kw("weight") {
            let sign = if self.tok.tok == Tok::Minus {
                self.bump();
                -1.0
            } else {
                1.0
            };
            match self.tok.tok {
                Tok::Num(v) => Some((sign * v, ws.to(self.bump().span))),
                _ => return Err(self.error_here("a number after `weight`")),
            }
        } else {
            None
        };
        let op = if self.tok.tok == Tok::LBrace {
            self.bump();
            let op = self.op("an operation")?;
            if self.tok.tok != Tok::RBrace {
                return Err(self
                    .error_here("`}` after the operation")
                    .with_hint("an alternative holds one operation; combine several with `split`"));
            }
            self.bump();
            op
        } else if matches!(guard, Guard::Always) && weight.is_none() {
            // A rule whose body is one operation: `House { split y … }`.
            let op = self.op("an alternative (`when …`, `else`, `{ … }`) or an operation")?;
            if self.tok.tok != Tok::RBrace {
                return Err(self.error_here("`}` after the rule's operation").with_hint(
                    "a rule written without alternatives holds one operation; give several alternatives each their own `{ … }`",
                ));
            }
            op
        } else {
            return Err(self.error_here("`{` before the operation").with_hint("write `when X > 4 { fill stone }`"));
        };
        Ok(AltSyn { guard, weight, op, span })
    }

    fn op(&mut self, what: &str) -> PResult<OpSyn> {
        self.nesting += 1;
        if self.nesting > MAX_NESTING {
            return Err(Diagnostic::error(self.tok.span, "operations are nested too deeply")
                .with_hint(format!("at most {MAX_NESTING} levels; move parts into rules")));
        }
        let r = self.op_inner(what);
        self.nesting -= 1;
        r
    }

    fn op_inner(&mut self, what: &str) -> PResult<OpSyn> {
        if self.tok.tok != Tok::Ident {
            return Err(self
                .error_here(what)
                .with_hint("operations are `split`, `fill`, `void`, `skip`, `reorient(…)` or a rule name"));
        }
        let word = self.text(self.tok.span);
        match word {
            "split" => self.split(),
            "fill" => {
                self.bump();
                Ok(OpSyn::Fill(self.block("a block or material after `fill`")?))
            }
            "void" => {
                self.bump();
                Ok(OpSyn::Void)
            }
            "skip" => {
                self.bump();
                Ok(OpSyn::Skip)
            }
            "reorient" => {
                let (perm, span) = self.reorient()?;
                let then = self.op("an operation or rule after `reorient(…)`")?;
                Ok(OpSyn::Reorient(perm, span, Box::new(then)))
            }
            _ => {
                let name = self.name(what)?;
                if self.is_kw("reorient") {
                    let (perm, span) = self.reorient()?;
                    return Ok(OpSyn::Reorient(perm, span, Box::new(OpSyn::Call(name))));
                }
                Ok(OpSyn::Call(name))
            }
        }
    }

    fn axis(&mut self) -> PResult<usize> {
        let t = self.tok;
        let axis = match (t.tok, self.text(t.span)) {
            (Tok::Ident, "x") => 0,
            (Tok::Ident, "y") => 1,
            (Tok::Ident, "z") => 2,
            _ => return Err(self.error_here("an axis (`x`, `y` or `z`)")),
        };
        self.bump();
        Ok(axis)
    }

    fn reorient(&mut self) -> PResult<([usize; 3], Span)> {
        let start = self.bump().span;
        self.expect(Tok::LParen, "`(` after `reorient`")?;
        let mut perm = [0; 3];
        for (i, p) in perm.iter_mut().enumerate() {
            if i > 0 {
                self.expect(Tok::Comma, "`,` between the axes")?;
            }
            *p = self.axis()?;
        }
        let end = self.expect(Tok::RParen, "`)` after the three axes")?;
        Ok((perm, start.to(end)))
    }

    fn split(&mut self) -> PResult<OpSyn> {
        let span = self.bump().span;
        let axis = self.axis()?;
        self.expect(Tok::LBrack, "`[` and the sizes")?;
        let mut sizes = Vec::new();
        if self.tok.tok != Tok::RBrack {
            loop {
                sizes.push(self.formula()?);
                if self.tok.tok != Tok::Comma {
                    break;
                }
                self.bump();
            }
        }
        self.expect(Tok::RBrack, "`,` or `]` after a size")?;
        let mut repeat = false;
        let mut round = Round::Truncate;
        loop {
            if self.eat_kw("repeat").is_some() {
                repeat = true;
            } else if self.eat_kw("round").is_some() {
                let t = self.tok;
                round = match (t.tok, self.text(t.span)) {
                    (Tok::Ident, "truncate") => Round::Truncate,
                    (Tok::Ident, "start") => Round::Start,
                    (Tok::Ident, "end") => Round::End,
                    (Tok::Ident, "middle") => Round::Middle,
                    _ => {
                        return Err(self
                            .error_here("a rounding mode")
                            .with_hint("rounding modes are `truncate`, `start`, `end` and `middle`"));
                    }
                };
                self.bump();
            } else {
                break;
            }
        }
        if self.tok.tok != Tok::LBrace {
            return Err(self.error_here("`{` and the children of the split").with_hint(
                "write `split x [2, -1] { Left, Right }`; after the sizes may come `repeat` and `round start|end|middle|truncate`",
            ));
        }
        let open = self.bump().span;
        let mut children = Vec::new();
        if self.tok.tok != Tok::RBrace {
            loop {
                children.push(self.op("a child (a rule name, `fill …`, `void`, `skip` or a nested operation)")?);
                if self.tok.tok != Tok::Comma {
                    break;
                }
                self.bump();
            }
        }
        if self.tok.tok != Tok::RBrace {
            return Err(self.error_here("`,` or `}` after a child").with_hint("separate the children with commas"));
        }
        let close = self.bump().span;
        Ok(OpSyn::Split { axis, sizes, repeat, round, children, span, children_span: open.to(close) })
    }

    // ---- formulas -------------------------------------------------------

    /// A formula, read by the core expression parser in the `.bsg`
    /// dialect ([`DIALECT`]).
    fn formula(&mut self) -> PResult<Ast> {
        match expr::parse_prefix_in(self.src, self.tok.span.start as usize, DIALECT) {
            Ok((ast, end)) => {
                self.tok = token_at(self.src, end);
                Ok(ast)
            }
            Err(d) => {
                // Recovery goes on from where the formula broke.
                if let Some(at) = d.span {
                    self.tok = token_at(self.src, at.start as usize);
                }
                Err(d)
            }
        }
    }

    // ---- recovery -------------------------------------------------------

    /// Skips the rest of a broken alternative: out of any block it opened,
    /// or, when the mistake came before its body, up to and over the body.
    fn recover_alternative(&mut self, rule_depth: usize, entered: bool) {
        self.nesting = 0;
        while self.depth > rule_depth && self.tok.tok != Tok::Eof {
            self.bump();
        }
        if entered {
            return;
        }
        loop {
            match self.tok.tok {
                Tok::Eof | Tok::RBrace => return,
                Tok::Ident if self.is_kw("when") || self.is_kw("else") => return,
                Tok::LBrace => {
                    self.bump();
                    while self.depth > rule_depth && self.tok.tok != Tok::Eof {
                        self.bump();
                    }
                    return;
                }
                _ => {
                    self.bump();
                }
            }
        }
    }

    /// Skips to the end of a broken declaration or rule.
    fn recover_top(&mut self) {
        self.nesting = 0;
        loop {
            if self.depth == 0 {
                match self.tok.tok {
                    Tok::Eof => return,
                    Tok::Semi => {
                        self.bump();
                        return;
                    }
                    Tok::Ident if DECLARATIONS.contains(&self.text(self.tok.span)) => return,
                    _ => {}
                }
            }
            if self.tok.tok == Tok::Eof {
                return;
            }
            let before = self.depth;
            self.bump();
            if before == 1 && self.depth == 0 {
                return;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_rules_alternatives_and_children() {
        let src = "axiom A;\nA {\n  when X >= 4 and not FULL(SOLID) weight 2 { split x [2, -1] repeat round middle { B reorient(z, y, x), fill stone } }\n  else { skip }\n}\nB { void }\n";
        let (items, errors) = parse(src);
        assert!(errors.is_empty(), "{errors:?}");
        assert_eq!(items.len(), 3);
        let Item::Rule(r) = &items[1] else { panic!() };
        assert_eq!(r.alts.len(), 2);
        assert!(matches!(r.alts[0].guard, Guard::When(_)));
        assert_eq!(r.alts[0].weight.map(|w| w.0), Some(2.0));
        let OpSyn::Split { axis, sizes, repeat, round, children, .. } = &r.alts[0].op else { panic!() };
        assert_eq!((*axis, sizes.len(), *repeat, *round), (0, 2, true, Round::Middle));
        assert!(matches!(&children[0], OpSyn::Reorient([2, 1, 0], _, c) if matches!(**c, OpSyn::Call(_))));
        assert!(matches!(&children[1], OpSyn::Fill(b) if b.name == "stone"));
        let Item::Rule(b) = &items[2] else { panic!() };
        assert!(matches!(b.alts[0].op, OpSyn::Void));
    }

    #[test]
    fn recovers_and_reports_every_broken_alternative() {
        let src = "A {\n when X > { fill stone }\n when Y > 1 { fill }\n else { skip }\n}\nB { split q [1] { C } }\nC { skip }\n";
        let (items, errors) = parse(src);
        assert_eq!(errors.len(), 3, "{errors:?}");
        // A keeps its good alternative, B its name, C parses.
        let names: Vec<_> = items
            .iter()
            .filter_map(|i| match i {
                Item::Rule(r) => Some((r.name.name.clone(), r.alts.len())),
                _ => None,
            })
            .collect();
        assert_eq!(names, vec![("A".to_string(), 1), ("B".to_string(), 0), ("C".to_string(), 1)]);
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_stack_overflow() {
        let src = format!("A {{ when {}1{} {{ skip }} }}", "(".repeat(5000), ")".repeat(5000));
        let (_, errors) = parse(&src);
        assert!(errors.iter().any(|e| e.message.contains("nested too deeply")), "{errors:?}");
        let src = format!("A {{ {} }}", "split x [1] { ".repeat(3000));
        let (_, errors) = parse(&src);
        assert!(errors.iter().any(|e| e.message.contains("nested too deeply")), "{errors:?}");
    }
}
