//! Recursive-descent parser for `.sg` files.
//!
//! Every syntax error is collected; after one the parser skips to the end
//! of the statement (or item) and goes on, so one run reports them all.
//! Nesting is bounded by [`MAX_NESTING`] so hostile input cannot overflow
//! the stack. Expressions are parsed by `genform_core::expr::parse_prefix`.

use crate::ast::*;
use crate::lexer::{Lexer, Tok, Token};
use crate::program::selector;
use genform_core::expr::parse_prefix;
use genform_core::{Diagnostic, Span};

/// Deepest nesting of blocks accepted.
pub(crate) const MAX_NESTING: usize = 256;

/// Words with a fixed meaning at the start of a top-level item.
/// The operations that build a solid on a polygon and may be followed by
/// the arms of its faces.
const SOLIDS: &[&str] = &["roof_gable", "roof_hip", "roof_pyramid", "roof_shed", "roof_ridge", "taper"];

const HEADER_WORDS: &[&str] = &["grammar", "axiom", "limits", "const", "mesh", "footprints", "context"];

/// Marker for "an error was recorded; recover".
struct Fail;
type PResult<T> = Result<T, Fail>;

pub(crate) struct Parser<'a> {
    src: &'a str,
    lex: Lexer<'a>,
    tok: Token,
    /// End of the last consumed token (where a missing `;` belongs).
    prev_end: usize,
    errors: Vec<Diagnostic>,
    depth: usize,
    /// Set after the nesting limit was hit: the rest of the file is skipped.
    aborted: bool,
}

/// Parses a whole file into items and the syntax errors found.
pub(crate) fn parse_file(src: &str) -> (Vec<Item>, Vec<Diagnostic>) {
    let mut p = Parser::new(src);
    let mut items = Vec::new();
    while p.tok.kind != Tok::Eof && !p.aborted {
        match p.item() {
            Ok(it) => items.push(it),
            Err(Fail) => p.recover(true),
        }
    }
    if let Some(span) = p.lex.unterminated_comment {
        p.errors.push(Diagnostic::error(span, "this block comment is never closed").with_hint("close it with `*/`"));
    }
    (items, p.errors)
}

fn is_ident(s: &str) -> bool {
    let mut c = s.chars();
    c.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_') && c.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

impl<'a> Parser<'a> {
    fn new(src: &'a str) -> Self {
        let mut lex = Lexer::new(src);
        let tok = lex.next_token();
        Parser { src, lex, tok, prev_end: 0, errors: Vec::new(), depth: 0, aborted: false }
    }

    fn bump(&mut self) -> Token {
        let next = self.lex.next_token();
        self.prev_end = self.tok.span.end as usize;
        std::mem::replace(&mut self.tok, next)
    }

    fn seek(&mut self, pos: usize) {
        self.prev_end = pos;
        self.lex.seek(pos);
        self.tok = self.lex.next_token();
    }

    fn is(&self, t: &Tok) -> bool {
        &self.tok.kind == t
    }

    fn is_word(&self, w: &str) -> bool {
        matches!(&self.tok.kind, Tok::Ident(s) if s == w)
    }

    fn eat(&mut self, t: &Tok) -> bool {
        if self.is(t) {
            self.bump();
            true
        } else {
            false
        }
    }

    fn error(&mut self, d: Diagnostic) -> Fail {
        self.errors.push(d);
        Fail
    }

    fn expected(&mut self, what: &str, context: &str) -> Fail {
        // A missing `;` at the end of a line belongs to that line.
        let newline = self.src.get(self.prev_end..self.tok.span.start as usize).is_some_and(|gap| gap.contains('\n'));
        let span = if what == "`;`" && newline { Span::new(self.prev_end, self.prev_end) } else { self.tok.span };
        let d = Diagnostic::error(span, format!("expected {what} {context}, found {}", self.tok.kind.describe()));
        let d = match (&self.tok.kind, what) {
            (Tok::RBrace | Tok::Ident(_) | Tok::Eof, "`;`") => d.with_hint("every statement ends with `;`"),
            _ => d,
        };
        self.error(d)
    }

    fn expect(&mut self, t: Tok, context: &str) -> PResult<Span> {
        if self.is(&t) {
            return Ok(self.bump().span);
        }
        Err(self.expected(&format!("`{}`", t.text()), context))
    }

    fn ident(&mut self, what: &str, context: &str) -> PResult<(String, Span)> {
        if let Tok::Ident(s) = &self.tok.kind {
            let s = s.clone();
            let span = self.bump().span;
            return Ok((s, span));
        }
        Err(self.expected(what, context))
    }

    /// Skips to the end of the broken statement: past the next `;` or the
    /// next complete `{ ... }` at this nesting level, or up to (not past) the
    /// `}`/`]` that closes the enclosing block (past it at the top level).
    fn recover(&mut self, top: bool) {
        let mut depth = 0usize;
        loop {
            match self.tok.kind {
                Tok::Eof => return,
                Tok::Semi if depth == 0 => {
                    self.bump();
                    return;
                }
                Tok::LBrace | Tok::LBracket => depth += 1,
                Tok::RBrace | Tok::RBracket => {
                    if depth == 0 {
                        if top {
                            self.bump();
                        }
                        return;
                    }
                    depth -= 1;
                    // A broken block statement ends with its block.
                    if depth == 0 {
                        self.bump();
                        return;
                    }
                }
                _ => {}
            }
            self.bump();
        }
    }

    /// Parses one embedded expression at the current token.
    fn expr(&mut self) -> PResult<ExprSrc> {
        let start = self.tok.span.start as usize;
        match parse_prefix(&self.src[start..]) {
            Ok((ast, n)) => {
                let text = self.src[start..start + n].trim();
                let bare = is_ident(text).then(|| text.to_string());
                self.seek(start + n);
                Ok(ExprSrc { ast, offset: start, bare })
            }
            Err(d) => Err(self.error(d.shifted(start))),
        }
    }

    /// `[a, b, c]` or one expression.
    fn value(&mut self) -> PResult<Value> {
        if self.is(&Tok::LBracket) {
            let open = self.bump().span;
            let mut items = Vec::new();
            loop {
                items.push(self.expr()?);
                if !self.eat(&Tok::Comma) {
                    break;
                }
            }
            let close = self.expect(Tok::RBracket, "to close the vector")?;
            return Ok(Value::Vector(items, open.to(close)));
        }
        Ok(Value::Scalar(self.expr()?))
    }

    fn item(&mut self) -> PResult<Item> {
        let Tok::Ident(word) = self.tok.kind.clone() else {
            return Err(self.error(
                Diagnostic::error(
                    self.tok.span,
                    format!("expected a rule or a header item, found {}", self.tok.kind.describe()),
                )
                .with_hint(
                    "a file holds `grammar`, `axiom`, `limits`, `const`, `mesh`, `footprints` and `context` items and rules `Name { ... }`",
                ),
            ));
        };
        match word.as_str() {
            "grammar" => {
                self.bump();
                let (name, span) = self.quoted("a quoted name", "after `grammar`")?;
                self.expect(Tok::Semi, "after the grammar name")?;
                Ok(Item::Grammar(name, span))
            }
            "axiom" => {
                self.bump();
                let r = self.symref("after `axiom`")?;
                self.expect(Tok::Semi, "after the axiom")?;
                Ok(Item::Axiom(r))
            }
            "limits" => {
                self.bump();
                let mut out = Vec::new();
                loop {
                    let (k, span) = self.ident("a limit name (`genes`, `depth` or `primitives`)", "in `limits`")?;
                    self.expect(Tok::Eq, &format!("after `{k}`"))?;
                    let v = self.expr()?;
                    out.push((k, span, v));
                    if !self.eat(&Tok::Comma) {
                        break;
                    }
                }
                self.expect(Tok::Semi, "after the limits")?;
                Ok(Item::Limits(out))
            }
            "const" => {
                self.bump();
                let (name, span) = self.ident("a name", "after `const`")?;
                self.expect(Tok::Eq, &format!("after `const {name}`"))?;
                let v = self.expr()?;
                self.expect(Tok::Semi, "after the constant")?;
                Ok(Item::Const(name, span, v))
            }
            "mesh" => {
                self.bump();
                let (name, span) = self.ident("a name", "after `mesh`")?;
                self.expect(Tok::Eq, &format!("after `mesh {name}`"))?;
                let (path, pspan) = self.quoted("a quoted file path", &format!("for mesh `{name}`"))?;
                self.expect(Tok::Semi, "after the mesh path")?;
                Ok(Item::Mesh(name, span, path, pspan))
            }
            "footprints" => {
                self.bump();
                let (path, pspan) = self.quoted("a quoted file path", "after `footprints`")?;
                self.expect(Tok::Semi, "after the footprint file")?;
                Ok(Item::Footprints(path, pspan))
            }
            "context" => {
                self.bump();
                let (path, pspan) = self.quoted("a quoted file path", "after `context`")?;
                self.expect(Tok::Semi, "after the context mesh file")?;
                Ok(Item::Context(path, pspan))
            }
            _ => self.rule().map(Item::Rule),
        }
    }

    /// A string token: its text and span (`what` is expected `context`).
    fn quoted(&mut self, what: &str, context: &str) -> PResult<(String, Span)> {
        let text = match &self.tok.kind {
            Tok::Str(s) => s.clone(),
            _ => return Err(self.expected(what, context)),
        };
        Ok((text, self.bump().span))
    }

    fn rule(&mut self) -> PResult<Rule> {
        let (name, span) = self.ident("a rule name", "")?;
        let mut template = None;
        if self.eat(&Tok::Lt) {
            let (var, var_span) = self.ident("an index name", "in the template parameters, as in `Body<i: 0..8>`")?;
            self.expect(Tok::Colon, "after the template index name")?;
            let lo = self.bound()?;
            self.expect(Tok::DotDot, "between the bounds of the template range")?;
            let hi = self.bound()?;
            self.expect(Tok::Gt, "to close the template parameters")?;
            template = Some(Template { var, var_span, lo, hi });
        }
        let mut args = Vec::new();
        if self.eat(&Tok::LParen) {
            if !self.is(&Tok::RParen) {
                loop {
                    args.push(self.ident("an argument name", &format!("in the arguments of `{name}`"))?);
                    if !self.eat(&Tok::Comma) {
                        break;
                    }
                }
            }
            self.expect(Tok::RParen, "to close the argument names")?;
        }
        if !self.is(&Tok::LBrace) {
            let f = self.expected("`{`", &format!("to start the body of rule `{name}`"));
            if name == "rule"
                && let Some(d) = self.errors.last_mut()
            {
                d.hints.push("rules are written `Name { ... }`, without a keyword".into());
            }
            return Err(f);
        }
        let open = self.tok.span;
        // A body that does not parse ends the file (statements recover up to
        // its end), so the rule is still declared, with an empty body: the
        // syntax error is the one to fix, and references to the rule must
        // not add "unknown rule" errors to it.
        let body = match self.block() {
            Ok(body) => body,
            Err(Fail) => {
                if !self.aborted
                    && let Some(d) = self.errors.last_mut()
                {
                    d.labels.push((open, format!("the body of rule `{name}` starts here")));
                }
                Vec::new()
            }
        };
        Ok(Rule { name, span, template, args, body })
    }

    fn bound(&mut self) -> PResult<Bound> {
        let neg = self.is(&Tok::Minus).then(|| self.bump().span);
        match self.tok.kind.clone() {
            Tok::Num(v) => {
                let s = self.bump().span;
                Ok(Bound::Int(if neg.is_some() { -v } else { v }, neg.unwrap_or(s).to(s)))
            }
            Tok::Ident(c) if neg.is_none() => {
                let s = self.bump().span;
                Ok(Bound::Const(c, s))
            }
            _ => Err(self.expected("an integer or a `const` name", "as a template bound")),
        }
    }

    /// `Name` or `Name<index>`. The index is an expression up to the first
    /// `>` outside parentheses (so comparisons inside it need parentheses).
    fn symref(&mut self, context: &str) -> PResult<SymRef> {
        let (name, span) = self.ident("a rule name", context)?;
        if !self.is(&Tok::Lt) {
            return Ok(SymRef { name, span, index: None });
        }
        let open = self.tok.span;
        let start = open.end as usize;
        let bytes = self.src.as_bytes();
        let mut depth = 0i32;
        let mut end = None;
        for (i, &b) in bytes.iter().enumerate().skip(start) {
            match b {
                b'(' => depth += 1,
                b')' => depth -= 1,
                b'>' if depth <= 0 => {
                    end = Some(i);
                    break;
                }
                b';' | b'{' | b'}' | b'\n' => break,
                _ => {}
            }
        }
        let Some(end) = end else {
            return Err(self.error(
                Diagnostic::error(open, format!("expected `>` to close the template index of `{name}`"))
                    .with_hint("write the index on one line, like `Body<i + 1>`; put comparisons in parentheses"),
            ));
        };
        let (ast, n) = match parse_prefix(&self.src[start..end]) {
            Ok(r) => r,
            Err(d) => return Err(self.error(d.shifted(start))),
        };
        if !self.src[start + n..end].trim().is_empty() {
            let at = start + n + (self.src[start + n..end].len() - self.src[start + n..end].trim_start().len());
            return Err(self.error(Diagnostic::error(
                Span::new(at, end),
                format!("unexpected text in the template index of `{name}`"),
            )));
        }
        let index = ExprSrc { ast, offset: start, bare: None };
        self.seek(end + 1);
        Ok(SymRef { name, span: span.to(Span::new(end, end + 1)), index: Some(index) })
    }

    /// `{ stmt* }`
    fn block(&mut self) -> PResult<Vec<Stmt>> {
        self.expect(Tok::LBrace, "to start a block")?;
        let body = self.stmts(Tok::RBrace)?;
        self.expect(Tok::RBrace, "to close the block")?;
        Ok(body)
    }

    /// Statements up to (not including) `close`.
    fn stmts(&mut self, close: Tok) -> PResult<Vec<Stmt>> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            let d = Diagnostic::error(self.tok.span, "blocks are nested too deeply")
                .with_hint(format!("at most {MAX_NESTING} levels of nesting are allowed"));
            self.errors.push(d);
            self.aborted = true;
            let end = self.src.len();
            self.seek(end);
            return Err(Fail);
        }
        let mut out = Vec::new();
        while !self.is(&close) && !self.is(&Tok::Eof) && !self.aborted {
            match self.stmt() {
                Ok(s) => out.push(s),
                Err(Fail) => {
                    if self.aborted {
                        break;
                    }
                    self.recover(false);
                    // A stray closer of the other kind would stop recovery forever.
                    if (self.is(&Tok::RBrace) || self.is(&Tok::RBracket)) && !self.is(&close) {
                        self.bump();
                    }
                }
            }
        }
        self.depth -= 1;
        if self.aborted {
            return Err(Fail);
        }
        Ok(out)
    }

    fn axis(&mut self, context: &str) -> PResult<Axis> {
        let a = match &self.tok.kind {
            Tok::Ident(s) if s == "x" => Axis::X,
            Tok::Ident(s) if s == "y" => Axis::Y,
            Tok::Ident(s) if s == "z" => Axis::Z,
            _ => return Err(self.expected("an axis `x`, `y` or `z`", context)),
        };
        self.bump();
        Ok(a)
    }

    fn stmt(&mut self) -> PResult<Stmt> {
        let word = match &self.tok.kind {
            Tok::Ident(s) => s.clone(),
            Tok::LBracket => {
                self.bump();
                let body = self.stmts(Tok::RBracket)?;
                self.expect(Tok::RBracket, "to close the `[` scope")?;
                return Ok(Stmt::Scoped(body));
            }
            _ => {
                return Err(self.error(
                    Diagnostic::error(
                        self.tok.span,
                        format!("expected a statement, found {}", self.tok.kind.describe()),
                    )
                    .with_hint(
                        "statements are operations like `box;`, invocations like `Wing;`, declarations and blocks",
                    ),
                ));
            }
        };
        match word.as_str() {
            "param" => self.param().map(Stmt::Param),
            "slot" => self.slot().map(Stmt::Slot),
            "let" => {
                self.bump();
                let (name, span) = self.ident("a name", "after `let`")?;
                self.expect(Tok::Eq, &format!("after `let {name}`"))?;
                let value = self.expr()?;
                self.expect(Tok::Semi, "after the `let` value")?;
                Ok(Stmt::Let { name, span, value })
            }
            "if" => self.if_stmt(),
            "alt" => {
                let span = self.bump().span;
                self.expect(Tok::LBrace, "after `alt`")?;
                let mut arms = Vec::new();
                while !self.is(&Tok::RBrace) && !self.is(&Tok::Eof) {
                    let w = self.expr()?;
                    self.expect(Tok::Colon, "after the weight of an alternative")?;
                    let body = self.nested_block()?;
                    arms.push((w, body));
                }
                self.expect(Tok::RBrace, "to close `alt`")?;
                if arms.is_empty() {
                    return Err(self.error(
                        Diagnostic::error(span, "`alt` needs at least one alternative")
                            .with_hint("write `alt { 2: { ... } 1: { ... } }`"),
                    ));
                }
                Ok(Stmt::Alt { span, arms })
            }
            "mirror" => {
                self.bump();
                self.expect(Tok::LParen, "after `mirror`")?;
                let axis = self.axis("in `mirror`")?;
                self.expect(Tok::RParen, "after the mirror axis")?;
                let body = self.nested_block()?;
                Ok(Stmt::Mirror { axis, body })
            }
            "repeat" => {
                self.bump();
                self.expect(Tok::LParen, "after `repeat`")?;
                let axis = self.axis("in `repeat`")?;
                self.expect(Tok::Comma, "after the repeat axis")?;
                // `~2` reads as CGA's floating tile; repeat tiles always float.
                self.eat(&Tok::Other('~'));
                let tile = self.expr()?;
                self.expect(Tok::RParen, "after the tile size")?;
                let body = self.nested_block()?;
                Ok(Stmt::Repeat { axis, tile, body })
            }
            "split" | "splitArea" => self.split(),
            "comp" => self.comp(),
            _ => {
                let (target, args) = self.call("as a statement")?;
                // `offset(d) { … }`: a component split, told from a call by
                // its arms, so these names stay free for rules and values.
                if let Some(kind) = CompKind::of_name(&target.name).filter(|_| self.is(&Tok::LBrace)) {
                    return self.comp_call(kind, target, args);
                }
                // `roof_hip(30) { top: A | side: B }`: the roof's faces.
                if SOLIDS.contains(&target.name.as_str()) && self.is(&Tok::LBrace) {
                    let mut stmt = self.comp_block(target.span, CompKind::Solid, Vec::new())?;
                    if let Stmt::Comp { solid, .. } = &mut stmt {
                        *solid = Some(Box::new((target, args.unwrap_or_default())));
                    }
                    return Ok(stmt);
                }
                self.expect(Tok::Semi, "after the statement")?;
                Ok(Stmt::Call { target, args })
            }
        }
    }

    /// A block that counts towards the nesting limit.
    fn nested_block(&mut self) -> PResult<Vec<Stmt>> {
        self.expect(Tok::LBrace, "to start a block")?;
        let body = self.stmts(Tok::RBrace)?;
        self.expect(Tok::RBrace, "to close the block")?;
        Ok(body)
    }

    fn if_stmt(&mut self) -> PResult<Stmt> {
        self.bump();
        let cond = self.expr()?;
        let then = self.nested_block()?;
        let els = if self.is_word("else") {
            self.bump();
            if self.is_word("if") {
                self.depth += 1;
                let r = if self.depth > MAX_NESTING {
                    Err(self.expected("a block", "(too many `else if`)"))
                } else {
                    self.if_stmt()
                };
                self.depth -= 1;
                vec![r?]
            } else {
                self.nested_block()?
            }
        } else {
            Vec::new()
        };
        Ok(Stmt::If { cond, then, els })
    }

    fn call(&mut self, context: &str) -> PResult<(SymRef, Option<Vec<Arg>>)> {
        let target = self.symref(context)?;
        let args = if self.is(&Tok::LParen) {
            self.bump();
            let mut args = Vec::new();
            if !self.is(&Tok::RParen) {
                loop {
                    if let Some(name) = self.named_arg() {
                        let span = self.bump().span;
                        self.expect(Tok::Eq, "after the name of a named argument")?;
                        let list = self.eat(&Tok::LBracket);
                        let mut value = Vec::new();
                        loop {
                            value.push(self.plain_arg()?);
                            if !list || !self.eat(&Tok::Comma) {
                                break;
                            }
                        }
                        if list {
                            self.expect(Tok::RBracket, "to close the list")?;
                        }
                        args.push(Arg::Named { name, span, value, list });
                    } else {
                        args.push(self.plain_arg()?);
                    }
                    if !self.eat(&Tok::Comma) {
                        break;
                    }
                }
            }
            self.expect(Tok::RParen, &format!("to close the arguments of `{}`", target.name))?;
            Some(args)
        } else {
            None
        };
        Ok((target, args))
    }

    /// The name of a named argument `name = value` starting here (one `=`,
    /// not `==`).
    fn named_arg(&self) -> Option<String> {
        let Tok::Ident(name) = &self.tok.kind else { return None };
        let rest = self.src[self.tok.span.end as usize..].trim_start();
        (rest.starts_with('=') && !rest.starts_with("==")).then(|| name.clone())
    }

    /// A string or an expression argument.
    fn plain_arg(&mut self) -> PResult<Arg> {
        if let Tok::Str(s) = &self.tok.kind {
            let s = s.clone();
            return Ok(Arg::Str(s, self.bump().span));
        }
        Ok(Arg::Expr(self.expr()?))
    }

    fn split(&mut self) -> PResult<Stmt> {
        let area = self.is_word("splitArea");
        let span = self.bump().span;
        self.expect(Tok::LParen, "after `split`")?;
        let axis = self.axis("in `split`")?;
        self.expect(Tok::RParen, "after the split axis")?;
        self.expect(Tok::LBrace, "to start the pieces of `split`")?;
        let mut pieces = Vec::new();
        loop {
            let floating = self.eat(&Tok::Other('~'));
            let size = self.expr()?;
            let relative = !floating && self.is_word("r");
            if relative {
                self.bump();
            }
            self.expect(Tok::Colon, "after the size of a split piece (`2: A`, `1r: A` or `~2: A`)")?;
            let body = if self.is(&Tok::LBrace) {
                self.nested_block()?
            } else {
                let (target, args) = self.call("as a split piece")?;
                // `1r: A;` reads naturally too.
                self.eat(&Tok::Semi);
                vec![Stmt::Call { target, args }]
            };
            pieces.push(Piece { size, relative, floating, body });
            if !self.eat(&Tok::Pipe) {
                break;
            }
        }
        self.expect(Tok::RBrace, "to close `split` (pieces are separated by `|`)")?;
        Ok(Stmt::Split { axis, pieces, area, span })
    }

    /// `comp(f) { front: A | side | top: { ... } | ... }`, `comp(e) { … }` and
    /// `comp(v) { … }`.
    fn comp(&mut self) -> PResult<Stmt> {
        let span = self.bump().span;
        self.expect(Tok::LParen, "after `comp`")?;
        let kind = match &self.tok.kind {
            Tok::Ident(s) if s == "f" => CompKind::Faces,
            Tok::Ident(s) if s == "e" => CompKind::Edges,
            Tok::Ident(s) if s == "v" => CompKind::Vertices,
            _ => {
                let d = Diagnostic::error(
                    self.tok.span,
                    format!(
                        "expected `f` (faces), `e` (edges) or `v` (vertices) in `comp`, found {}",
                        self.tok.kind.describe()
                    ),
                )
                .with_hint(
                    "`comp(f)` takes the faces of a mass, `comp(e)` the edges of a polygon, `comp(v)` its corners",
                );
                return Err(self.error(d));
            }
        };
        self.bump();
        self.expect(Tok::RParen, &format!("after `{}`", &kind.name().0[..kind.name().0.len() - 1]))?;
        self.comp_block(span, kind, Vec::new())
    }

    /// The arms of a component split from its `{`, after its name and
    /// arguments.
    fn comp_block(&mut self, span: Span, kind: CompKind, args: Vec<ExprSrc>) -> PResult<Stmt> {
        let name = kind.name().0;
        self.expect(Tok::LBrace, &format!("to start the arms of `{name}`"))?;
        let mut arms = Vec::new();
        if self.comp_arms(kind, &mut arms).is_err() {
            // The error is recorded: skip the rest of the arms, up to and
            // including the `}` that closes them, and go on after them.
            let mut depth = 0usize;
            loop {
                match self.tok.kind {
                    Tok::Eof => break,
                    Tok::LBrace => depth += 1,
                    Tok::RBrace if depth == 0 => {
                        self.bump();
                        break;
                    }
                    Tok::RBrace => depth -= 1,
                    _ => {}
                }
                self.bump();
            }
            return Ok(Stmt::Comp { span, kind, args, arms, solid: None });
        }
        self.expect(Tok::RBrace, &format!("to close `{name}` (arms are separated by `|`)"))?;
        Ok(Stmt::Comp { span, kind, args, arms, solid: None })
    }

    /// `offset(d) { … }` and the other splits written like a call: the
    /// arguments must be numbers.
    fn comp_call(&mut self, kind: CompKind, target: SymRef, args: Option<Vec<Arg>>) -> PResult<Stmt> {
        let mut exprs = Vec::new();
        // `setback(d, front = …, back = …, left = …, right = …)`: the
        // distance of each side's edges, `d` where not given.
        let mut sides: [Option<ExprSrc>; 4] = [None, None, None, None];
        // `setback(d, edges = [d0, d1, …])`: a distance per edge (CGA's
        // `setbackPerEdge`).
        let mut per_edge: Option<(Vec<ExprSrc>, Span)> = None;
        for a in args.unwrap_or_default() {
            match a {
                Arg::Expr(e) => exprs.push(e),
                Arg::Str(_, span) => {
                    let d = Diagnostic::error(span, format!("`{}` takes numbers, not a string", target.name));
                    return Err(self.error(d));
                }
                Arg::Named { name, span, value, list } if kind == CompKind::Setback && name == "edges" => {
                    let all: Option<Vec<ExprSrc>> = value
                        .into_iter()
                        .map(|v| match v {
                            Arg::Expr(e) => Some(e),
                            _ => None,
                        })
                        .collect();
                    match all {
                        Some(v) if list && !v.is_empty() && per_edge.is_none() => per_edge = Some((v, span)),
                        _ => {
                            let d = Diagnostic::error(span, "`edges` takes a list of distances, one per edge")
                                .with_hint("write `setback(0, edges = [3, 0, 1, 0]) { … }` (edge i runs from corner i to i + 1)");
                            return Err(self.error(d));
                        }
                    }
                }
                Arg::Named { name, span, mut value, list } if kind == CompKind::Setback => {
                    let Some(k) = ["front", "back", "left", "right"].iter().position(|s| *s == name) else {
                        let d = Diagnostic::error(span, format!("`setback` has no argument `{name}`")).with_hint(
                            "its named arguments are the sides' distances `front`, `back`, `left`, `right`, \
                             and `edges = [d0, d1, …]`, one per edge",
                        );
                        return Err(self.error(d));
                    };
                    let one = if list || value.len() != 1 { None } else { value.pop() };
                    let Some(Arg::Expr(e)) = one else {
                        let d =
                            Diagnostic::error(span, format!("`{name}` takes one number: the distance of those edges"));
                        return Err(self.error(d));
                    };
                    if sides[k].replace(e).is_some() {
                        let d = Diagnostic::error(span, format!("`{name}` is given twice"));
                        return Err(self.error(d));
                    }
                }
                Arg::Named { span, .. } => {
                    let d = Diagnostic::error(span, format!("`{}` takes no named arguments", target.name));
                    return Err(self.error(d));
                }
            }
        }
        if kind == CompKind::Setback {
            if exprs.len() != 1 {
                let d = Diagnostic::error(
                    target.span,
                    format!("wrong number of arguments for `setback`: found {}", exprs.len()),
                )
                .with_hint(
                    "write `setback(distance)` or `setback(distance, front = …, back = …, left = …, right = …)`",
                );
                return Err(self.error(d));
            }
            let d = exprs[0].clone();
            exprs.extend(sides.into_iter().map(|s| s.unwrap_or_else(|| d.clone())));
            // The list's length, then the list.
            let (list, at) = per_edge.unwrap_or((Vec::new(), target.span));
            let (ast, _) = parse_prefix(&list.len().to_string()).map_err(|d| self.error(d))?;
            exprs.push(ExprSrc { ast, offset: at.start as usize, bare: None });
            exprs.extend(list);
        }
        self.comp_block(target.span, kind, exprs)
    }

    /// The arms of a component split, up to (not including) the closing `}`.
    fn comp_arms(&mut self, kind: CompKind, arms: &mut Vec<CompArm>) -> PResult<()> {
        let name = kind.name().0;
        let what = if kind == CompKind::Faces { "a face selector" } else { "a selector" };
        loop {
            let (mut mask, mut indices) = (0u8, 0u64);
            loop {
                // `0: A`: the piece of that index (CGA's index selector).
                if let Tok::Num(v) = self.tok.kind {
                    let at = self.bump().span;
                    if v.fract() != 0.0 || !(0.0..64.0).contains(&v) {
                        let d = Diagnostic::error(
                            at,
                            format!("an index selector is a whole number from 0 to 63, found {v}"),
                        )
                        .with_hint(
                            "index selectors name the pieces in the order the split lists them: `0: A | 1: B | all: C`",
                        );
                        return Err(self.error(d));
                    }
                    indices |= 1u64 << v as u32;
                    if !self.eat(&Tok::Comma) {
                        break;
                    }
                    continue;
                }
                let (sel, sspan) = self.ident(what, &format!("in `{name}`"))?;
                match selector(kind, &sel) {
                    Ok(m) => mask |= m,
                    Err(known) => {
                        let d = Diagnostic::error(sspan, format!("unknown selector `{sel}` in `{name}`"))
                            .with_hint(format!("selectors of `{name}` are {known}"));
                        return Err(self.error(d));
                    }
                }
                // `side | top: A` would be ambiguous with the arm separator,
                // so several selectors are joined with `,`.
                if !self.eat(&Tok::Comma) {
                    break;
                }
            }
            self.expect(Tok::Colon, &format!("after the selector of a `{name}` arm (`{sel}: A`)", sel = "front"))?;
            let body = if self.is(&Tok::LBrace) {
                self.nested_block()?
            } else {
                let (target, args) = self.call(&format!("as a `{name}` arm"))?;
                self.eat(&Tok::Semi);
                vec![Stmt::Call { target, args }]
            };
            arms.push(CompArm { mask, indices, body });
            if !self.eat(&Tok::Pipe) {
                return Ok(());
            }
        }
    }

    fn param(&mut self) -> PResult<ParamDecl> {
        self.bump();
        let (name, span) = self.ident("a parameter name", "after `param`")?;
        self.expect(Tok::Colon, &format!("after `param {name}`"))?;
        let mut dim = None;
        if let Tok::Ident(t) = &self.tok.kind {
            dim = match t.as_str() {
                "vec2" => Some(2),
                "vec3" => Some(3),
                "scalar" | "float" => Some(1),
                _ => None,
            };
            if dim.is_some() {
                self.bump();
            }
        }
        let (dist, dist_span) = self.ident("a distribution (`uniform`, `normal`, `int` or `choice`)", "")?;
        let open = self.expect(Tok::LParen, &format!("after `{dist}`"))?;
        let mut args = Vec::new();
        if !self.is(&Tok::RParen) {
            loop {
                let value = self.value()?;
                let weight = if self.eat(&Tok::Colon) { Some(self.expr()?) } else { None };
                args.push(DistArg { value, weight });
                if !self.eat(&Tok::Comma) {
                    break;
                }
            }
        }
        let close = self.expect(Tok::RParen, &format!("to close the arguments of `{dist}`"))?;
        let mut bounds = None;
        if self.is_word("in") {
            self.bump();
            self.expect(Tok::LBracket, "after `in`")?;
            let lo = self.value()?;
            self.expect(Tok::Comma, "between the bounds")?;
            let hi = self.value()?;
            self.expect(Tok::RBracket, "to close the bounds")?;
            bounds = Some((lo, hi));
        }
        self.expect(Tok::Semi, "after the parameter")?;
        Ok(ParamDecl { name, span, dim, dist, dist_span, args, args_span: dist_span.to(open).to(close), bounds })
    }

    fn slot(&mut self) -> PResult<SlotDecl> {
        self.bump();
        let (name, span) = self.ident("a slot name", "after `slot`")?;
        self.expect(Tok::Colon, &format!("after `slot {name}`"))?;
        let target = self.symref("as the slot's target")?;
        let mut prob = None;
        let mut count = None;
        if self.is_word("p") {
            self.bump();
            prob = Some(self.expr()?);
        }
        if self.is_word("x") {
            self.bump();
            count = Some(self.expr()?);
        }
        if !self.is(&Tok::Semi) {
            return Err(self.expected("`p <probability>`, `x <count>` or `;`", "after the slot target"));
        }
        self.bump();
        Ok(SlotDecl { name, span, target, prob, count })
    }
}

/// Whether `name` starts a header item (such names cannot name rules).
pub(crate) fn is_header_word(name: &str) -> bool {
    HEADER_WORDS.contains(&name)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ok(src: &str) -> Vec<Item> {
        let (items, errs) = parse_file(src);
        assert!(errs.is_empty(), "{src}: {errs:?}");
        items
    }

    fn errs(src: &str) -> Vec<String> {
        parse_file(src).1.into_iter().map(|d| d.message).collect()
    }

    #[test]
    fn parses_every_statement_kind() {
        let items = ok(r#"
            grammar "g"; axiom S; limits genes = 10, depth = 3; const k = 2; mesh leaf = "a.obj";
            S { Body<0>(1, 2); }
            Body<i: 0..k>(a, b) {
                param size: vec3 uniform([0.3, 0.1, 0.3], [0.8, 0.2, 0.8]);
                param n: normal(0, 1) in [-1, 1];
                param c: choice(1: 2, 3: 1);
                slot next: Body<i + 1> p exp(-0.4 * i) x 2;
                let v = size.x * a;
                if (has(next) && v > 1) { box; } else if v < 0 { cone; } else { sphere; }
                alt { 2: { cylinder; } 1: { frustum(0.5); } }
                mirror(x) { translate(sx / 2, 0, 0); next(a, b); }
                split(z) { 2: box | 1r: next(1, 2) | 1r: { tag("x"); box; } }
                repeat(x, 2.2) { [ rotate(y, 90); scale(0.5); box; ] }
                mesh(leaf);
            }
        "#);
        assert_eq!(items.len(), 7);
        let Item::Rule(r) = &items[6] else { panic!() };
        assert_eq!(r.body.len(), 11);
        assert!(r.template.is_some());
        assert_eq!(r.args.len(), 2);
    }

    #[test]
    fn collects_every_syntax_error() {
        let e = errs("A { box box; translate(1, 2; }\nB { cone }\nC { sphere; }");
        assert_eq!(e.len(), 3, "{e:?}");
        assert!(e[0].contains("expected `;`"), "{e:?}");
        assert!(e[1].contains("expected `)`"), "{e:?}");
    }

    #[test]
    fn an_unterminated_body_still_declares_its_rule() {
        let (items, errs) = parse_file("axiom S;\nS {\n  box;\n");
        assert_eq!(errs.len(), 1, "{errs:?}");
        assert!(errs[0].message.contains("expected `}`"), "{errs:?}");
        assert_eq!(errs[0].labels, vec![(Span::new(11, 12), "the body of rule `S` starts here".to_string())]);
        assert!(items.iter().any(|i| matches!(i, Item::Rule(r) if r.name == "S" && r.body.is_empty())));
    }

    #[test]
    fn nesting_is_bounded() {
        let src = format!("A {{ {} }}", "[".repeat(10_000));
        let e = errs(&src);
        assert!(e.iter().any(|m| m.contains("nested too deeply")), "{e:?}");
        let src = format!("A {{ {} }}", "if 1 { ".repeat(10_000));
        assert!(errs(&src).iter().any(|m| m.contains("nested too deeply")));
    }

    #[test]
    fn template_index_stops_at_the_closing_angle() {
        let items = ok("A { B<(1 > 0) + 2>; }");
        let Item::Rule(r) = &items[0] else { panic!() };
        let Stmt::Call { target, .. } = &r.body[0] else { panic!() };
        assert!(target.index.is_some());
        assert!(errs("A { B<1; }")[0].contains("expected `>`"));
    }
}
