//! Pratt parser for expressions.

use super::dialect::Dialect;
use super::lex::{Lexer, Tok};
use crate::diag::{Diagnostic, Span};

/// Deepest nesting accepted, so hostile input cannot overflow the stack.
const MAX_DEPTH: usize = 128;

/// A parsed expression. Hosts may read and rewrite it (box-split replaces
/// its observer calls and inlines its `let`s) before [`super::compile`].
#[derive(Clone, Debug, PartialEq)]
pub struct Ast {
    /// What the expression is.
    pub kind: Node,
    /// Where the expression (or sub-expression) is, relative to the parsed text.
    pub span: Span,
}

/// The kinds of expression.
#[derive(Clone, Debug, PartialEq)]
pub enum Node {
    /// A number literal.
    Num(f64),
    /// A name: a variable or constant of the scope.
    Var(String),
    /// A prefix operator.
    Unary(UnOp, Box<Ast>),
    /// An infix operator.
    Binary(BinOp, Box<Ast>, Box<Ast>),
    /// `test ? then : else`.
    Cond(Box<Ast>, Box<Ast>, Box<Ast>),
    /// A call: the function's name, the name's span, the arguments.
    Call(String, Span, Vec<Ast>),
}

/// Prefix operators.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnOp {
    /// `-a`.
    Neg,
    /// `!a`, `not a`.
    Not,
}

/// Infix operators (`&&`/`and`, `||`/`or` short-circuit).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinOp {
    /// `||`, `or`.
    Or,
    /// `&&`, `and`.
    And,
    /// `==`.
    Eq,
    /// `!=`.
    Ne,
    /// `<`.
    Lt,
    /// `<=`.
    Le,
    /// `>`.
    Gt,
    /// `>=`.
    Ge,
    /// `+`.
    Add,
    /// `-`.
    Sub,
    /// `*`.
    Mul,
    /// `/`.
    Div,
    /// `%`, the truncated remainder.
    Rem,
    /// `^`, `**`.
    Pow,
}

fn binop(t: Tok<'_>) -> Option<(BinOp, u8, bool)> {
    // (op, precedence, right-associative)
    Some(match t {
        Tok::OrOr | Tok::Ident("or") => (BinOp::Or, 1, false),
        Tok::AndAnd | Tok::Ident("and") => (BinOp::And, 2, false),
        Tok::EqEq => (BinOp::Eq, 3, false),
        Tok::Ne => (BinOp::Ne, 3, false),
        Tok::Lt => (BinOp::Lt, 4, false),
        Tok::Le => (BinOp::Le, 4, false),
        Tok::Gt => (BinOp::Gt, 4, false),
        Tok::Ge => (BinOp::Ge, 4, false),
        Tok::Plus => (BinOp::Add, 5, false),
        Tok::Minus => (BinOp::Sub, 5, false),
        Tok::Star => (BinOp::Mul, 6, false),
        Tok::Slash => (BinOp::Div, 6, false),
        Tok::Percent => (BinOp::Rem, 6, false),
        Tok::Caret => (BinOp::Pow, 8, true),
        _ => return None,
    })
}

/// Precedence of the comparisons.
const COMPARISON: u8 = 3;
/// Precedence of `+` and `-`.
const SUM: u8 = 5;

struct Parser<'a> {
    src: &'a str,
    dialect: Dialect<'a>,
    lex: Lexer<'a>,
    tok: Tok<'a>,
    span: Span,
    /// End of the last consumed token.
    last_end: usize,
    depth: usize,
}

type PResult<T> = Result<T, Diagnostic>;

fn tok_text(t: Tok<'_>) -> &'static str {
    match t {
        Tok::LParen => "(",
        Tok::RParen => ")",
        Tok::Comma => ",",
        Tok::Question => "?",
        Tok::Colon => ":",
        Tok::Plus => "+",
        Tok::Minus => "-",
        Tok::Star => "*",
        Tok::Slash => "/",
        Tok::SlashSlash => "//",
        Tok::Percent => "%",
        Tok::Caret => "^",
        Tok::Lt => "<",
        Tok::Le => "<=",
        Tok::Gt => ">",
        Tok::Ge => ">=",
        Tok::EqEq => "==",
        Tok::Ne => "!=",
        Tok::AndAnd => "&&",
        Tok::OrOr => "||",
        Tok::Bang => "!",
        Tok::Assign => "=",
        _ => "?",
    }
}

fn is_comparison(t: Tok<'_>) -> bool {
    matches!(t, Tok::EqEq | Tok::Ne | Tok::Lt | Tok::Le | Tok::Gt | Tok::Ge)
}

fn is_not(t: Tok<'_>) -> bool {
    matches!(t, Tok::Bang | Tok::Ident("not"))
}

impl<'a> Parser<'a> {
    fn new(src: &'a str, start: usize, dialect: Dialect<'a>) -> Self {
        let mut lex = Lexer::new(src, start, dialect);
        let (tok, span) = lex.next();
        Parser { src, dialect, lex, tok, span, last_end: start, depth: 0 }
    }

    /// The current token, for messages.
    fn describe(&self) -> String {
        let w = self.dialect.wording;
        match self.tok {
            Tok::Eof => w.end.into(),
            Tok::Other if w.quote_source && self.src[self.span.start as usize..].starts_with('"') => "a string".into(),
            _ if w.quote_source => format!("`{}`", &self.src[self.span.start as usize..self.span.end as usize]),
            Tok::Num(v) => format!("number `{v}`"),
            Tok::Ident(s) => format!("`{s}`"),
            Tok::Other => "an unexpected character".into(),
            t => format!("`{}`", tok_text(t)),
        }
    }

    fn bump(&mut self) -> (Tok<'a>, Span) {
        let cur = (self.tok, self.span);
        self.last_end = self.span.end as usize;
        let (t, s) = self.lex.next();
        self.tok = t;
        self.span = s;
        cur
    }

    /// Continues lexing at byte `pos`.
    fn seek(&mut self, pos: usize) {
        self.lex.pos = pos;
        let (t, s) = self.lex.next();
        self.tok = t;
        self.span = s;
    }

    fn expect(&mut self, want: Tok<'a>, context: &str) -> PResult<Span> {
        if self.tok == want {
            Ok(self.bump().1)
        } else {
            Err(Diagnostic::error(
                self.span,
                format!("expected `{}` {context}, found {}", tok_text(want), self.describe()),
            ))
        }
    }

    fn enter(&mut self, at: Span) -> PResult<()> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            let name = self.dialect.wording.expression.split_once(' ').map_or("expression", |(_, n)| n);
            return Err(Diagnostic::error(at, format!("{name} is nested too deeply"))
                .with_hint(format!("at most {MAX_DEPTH} levels of nesting are allowed")));
        }
        Ok(())
    }

    fn expr(&mut self, min_prec: u8) -> PResult<Ast> {
        self.enter(self.span)?;
        let word_logic = self.dialect.word_logic;
        let mut lhs = if word_logic && min_prec <= COMPARISON && is_not(self.tok) {
            // `not` applies to a whole comparison (or another `not`).
            let (_, start) = self.bump();
            let inner = self.expr(COMPARISON)?;
            let span = start.to(inner.span);
            Ast { kind: Node::Unary(UnOp::Not, Box::new(inner)), span }
        } else {
            self.unary()?
        };
        loop {
            if self.tok == Tok::Question && min_prec == 0 && !word_logic {
                self.bump();
                let then = self.expr(0)?;
                self.expect(Tok::Colon, "between the branches of `?:`")?;
                let els = self.expr(0)?;
                let span = lhs.span.to(els.span);
                lhs = Ast { kind: Node::Cond(Box::new(lhs), Box::new(then), Box::new(els)), span };
                continue;
            }
            if self.tok == Tok::Assign && min_prec <= COMPARISON {
                return Err(Diagnostic::error(self.span, "`=` is not a comparison").with_hint("write `==`"));
            }
            let Some((op, prec, right)) = self.binop() else {
                break;
            };
            let (prec, next) = if word_logic && is_comparison(self.tok) {
                // One comparison between two sums: `a < b < c` is a mistake.
                (COMPARISON, SUM)
            } else {
                (prec, if right { prec } else { prec + 1 })
            };
            if prec < min_prec.max(1) {
                break;
            }
            self.bump();
            let rhs = self.expr(next)?;
            let span = lhs.span.to(rhs.span);
            lhs = match op {
                Op::Plain(op) => Ast { kind: Node::Binary(op, Box::new(lhs), Box::new(rhs)), span },
                Op::Call(name) => Ast { kind: Node::Call(name.into(), span, vec![lhs, rhs]), span },
                Op::FloorDiv => {
                    let quotient = Ast { kind: Node::Binary(BinOp::Div, Box::new(lhs), Box::new(rhs)), span };
                    Ast { kind: Node::Call("floor".into(), span, vec![quotient]), span }
                }
            };
            if word_logic && prec == COMPARISON && is_comparison(self.tok) {
                return Err(
                    Diagnostic::error(self.span, "comparisons do not chain").with_hint("write `a < b and b < c`")
                );
            }
        }
        self.depth -= 1;
        Ok(lhs)
    }

    /// The infix operator at the current token in this dialect.
    fn binop(&self) -> Option<(Op, u8, bool)> {
        let floored = self.dialect.hash_comments;
        match self.tok {
            Tok::SlashSlash => Some((Op::FloorDiv, 6, false)),
            Tok::Percent if floored => Some((Op::Call("mod"), 6, false)),
            t => binop(t).map(|(op, p, r)| (Op::Plain(op), p, r)),
        }
    }

    fn unary(&mut self) -> PResult<Ast> {
        let (op, span) = match self.tok {
            Tok::Minus => (UnOp::Neg, self.span),
            Tok::Plus => {
                let (_, at) = self.bump();
                self.enter(at)?;
                let inner = self.unary();
                self.depth -= 1;
                return inner;
            }
            Tok::Bang | Tok::Ident("not") if !self.dialect.word_logic => (UnOp::Not, self.span),
            _ => return self.power(),
        };
        self.bump();
        self.enter(span)?;
        // Unary minus binds looser than `^`: -2^2 = -4.
        let inner = self.unary()?;
        self.depth -= 1;
        let span = span.to(inner.span);
        Ok(Ast { kind: Node::Unary(op, Box::new(inner)), span })
    }

    fn power(&mut self) -> PResult<Ast> {
        let base = self.atom()?;
        if self.tok == Tok::Caret {
            let (_, at) = self.bump();
            self.enter(at)?;
            let exp = self.unary()?;
            self.depth -= 1;
            let span = base.span.to(exp.span);
            return Ok(Ast { kind: Node::Binary(BinOp::Pow, Box::new(base), Box::new(exp)), span });
        }
        Ok(base)
    }

    fn is_name(&self, name: &str) -> bool {
        !matches!(name, "and" | "or" | "not") && !self.dialect.reserved.contains(&name)
    }

    fn atom(&mut self) -> PResult<Ast> {
        match self.tok {
            Tok::Num(v) => {
                let (_, span) = self.bump();
                Ok(Ast { kind: Node::Num(v), span })
            }
            Tok::Ident(name) if self.is_name(name) => {
                let (_, span) = self.bump();
                if self.tok != Tok::LParen {
                    return Ok(Ast { kind: Node::Var(name.to_string()), span });
                }
                let (_, open) = self.bump();
                if let Some(raw) = self.dialect.raw_argument.filter(|r| r.calls.contains(&name)) {
                    return self.raw_call(name, span, open, raw);
                }
                let mut args = Vec::new();
                if self.tok != Tok::RParen {
                    loop {
                        args.push(self.expr(0)?);
                        if self.tok == Tok::Comma {
                            self.bump();
                        } else {
                            break;
                        }
                    }
                }
                if self.tok != Tok::RParen {
                    return Err(Diagnostic::error(
                        self.span,
                        format!("expected `,` or `)` in the arguments of `{name}`, found {}", self.describe()),
                    ));
                }
                let (_, end) = self.bump();
                Ok(Ast { kind: Node::Call(name.to_string(), span, args), span: span.to(end) })
            }
            Tok::LParen => {
                let (_, open) = self.bump();
                let inner = self.expr(0)?;
                let close = self.expect(Tok::RParen, "to close `(`")?;
                Ok(Ast { kind: inner.kind, span: open.to(close) })
            }
            _ => {
                let w = self.dialect.wording;
                Err(Diagnostic::error(self.span, format!("expected {}, found {}", w.expression, self.describe()))
                    .with_hint(w.hint))
            }
        }
    }

    /// `name(` raw text `)`: the text as one [`Node::Var`] argument.
    fn raw_call(&mut self, name: &str, span: Span, open: Span, raw: super::dialect::RawArgument<'a>) -> PResult<Ast> {
        let start = self.lex.trivia_end(open.end as usize);
        let mut end = (raw.scan)(self.src, start).clamp(start, self.src.len());
        // A host's scanner is trusted with positions, not with UTF-8.
        while !self.src.is_char_boundary(end) {
            end -= 1;
        }
        if end == start {
            return Err(Diagnostic::error(Span::new(start, start), format!("expected a {} in `{name}(…)`", raw.noun))
                .with_hint(raw.hint));
        }
        let arg = Ast { kind: Node::Var(self.src[start..end].to_string()), span: Span::new(start, end) };
        self.seek(end);
        self.last_end = end;
        let close = self.expect(Tok::RParen, &format!("after the {} of `{name}`", raw.noun))?;
        Ok(Ast { kind: Node::Call(name.to_string(), span, vec![arg]), span: span.to(close) })
    }
}

/// An infix operator as the parser builds it.
enum Op {
    Plain(BinOp),
    /// `a % b` in a floored dialect: `mod(a, b)`.
    Call(&'static str),
    /// `a // b`: `floor(a / b)`.
    FloorDiv,
}

/// Parses one expression at the start of `text`. Returns it and the number
/// of bytes consumed (up to the end of its last token); the expression ends
/// at the first token that cannot continue it (`;`, `]`, `{`, an identifier
/// after a complete operand, …). Spans are relative to `text`.
pub fn parse_prefix(text: &str) -> Result<(Ast, usize), Diagnostic> {
    parse_prefix_in(text, 0, Dialect::STANDARD)
}

/// Parses one expression of `dialect` starting at byte `start` of `text`
/// (a host's whole file, so spans are positions in it). Returns it and the
/// end of its last token; the expression ends as for [`parse_prefix`].
pub fn parse_prefix_in<'a>(text: &'a str, start: usize, dialect: Dialect<'a>) -> Result<(Ast, usize), Diagnostic> {
    let mut p = Parser::new(text, start, dialect);
    let ast = p.expr(0)?;
    Ok((ast, p.last_end))
}

/// Parses `text`, which must be exactly one expression (surrounding
/// whitespace and comments allowed).
pub fn parse(text: &str) -> Result<Ast, Diagnostic> {
    let mut p = Parser::new(text, 0, Dialect::STANDARD);
    let ast = p.expr(0)?;
    if p.tok != Tok::Eof {
        return Err(Diagnostic::error(
            p.span,
            format!("expected an operator or the end of the expression, found {}", p.describe()),
        ));
    }
    Ok(ast)
}
