//! Pratt parser for expressions.

use super::lex::{Lexer, Tok};
use crate::diag::{Diagnostic, Span};

/// Deepest nesting accepted, so hostile input cannot overflow the stack.
const MAX_DEPTH: usize = 128;

/// A parsed expression.
#[derive(Clone, Debug, PartialEq)]
pub struct Ast {
    pub(crate) kind: Node,
    /// Where the expression (or sub-expression) is, relative to the parsed text.
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Node {
    Num(f64),
    Var(String),
    Unary(UnOp, Box<Ast>),
    Binary(BinOp, Box<Ast>, Box<Ast>),
    Cond(Box<Ast>, Box<Ast>, Box<Ast>),
    Call(String, Span, Vec<Ast>),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum UnOp {
    Neg,
    Not,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum BinOp {
    Or,
    And,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    Add,
    Sub,
    Mul,
    Div,
    Rem,
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

struct Parser<'a> {
    lex: Lexer<'a>,
    tok: Tok<'a>,
    span: Span,
    /// End of the last consumed token.
    last_end: usize,
    depth: usize,
}

type PResult<T> = Result<T, Diagnostic>;

fn describe(t: Tok<'_>) -> String {
    match t {
        Tok::Eof => "end of input".into(),
        Tok::Num(v) => format!("number `{v}`"),
        Tok::Ident(s) => format!("`{s}`"),
        Tok::Other => "an unexpected character".into(),
        t => format!("`{}`", tok_text(t)),
    }
}

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
        _ => "?",
    }
}

impl<'a> Parser<'a> {
    fn new(src: &'a str) -> Self {
        let mut lex = Lexer::new(src);
        let (tok, span) = lex.next();
        Parser { lex, tok, span, last_end: 0, depth: 0 }
    }

    fn bump(&mut self) -> (Tok<'a>, Span) {
        let cur = (self.tok, self.span);
        self.last_end = self.span.end as usize;
        let (t, s) = self.lex.next();
        self.tok = t;
        self.span = s;
        cur
    }

    fn expect(&mut self, want: Tok<'a>, context: &str) -> PResult<Span> {
        if self.tok == want {
            Ok(self.bump().1)
        } else {
            Err(Diagnostic::error(
                self.span,
                format!("expected `{}` {context}, found {}", tok_text(want), describe(self.tok)),
            ))
        }
    }

    fn expr(&mut self, min_prec: u8) -> PResult<Ast> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(Diagnostic::error(self.span, "expression is nested too deeply")
                .with_hint(format!("at most {MAX_DEPTH} levels of nesting are allowed")));
        }
        let mut lhs = self.unary()?;
        loop {
            if self.tok == Tok::Question && min_prec == 0 {
                self.bump();
                let then = self.expr(0)?;
                self.expect(Tok::Colon, "between the branches of `?:`")?;
                let els = self.expr(0)?;
                let span = lhs.span.to(els.span);
                lhs = Ast { kind: Node::Cond(Box::new(lhs), Box::new(then), Box::new(els)), span };
                continue;
            }
            let Some((op, prec, right)) = binop(self.tok) else {
                break;
            };
            if prec < min_prec.max(1) {
                break;
            }
            self.bump();
            let rhs = self.expr(if right { prec } else { prec + 1 })?;
            let span = lhs.span.to(rhs.span);
            lhs = Ast { kind: Node::Binary(op, Box::new(lhs), Box::new(rhs)), span };
        }
        self.depth -= 1;
        Ok(lhs)
    }

    fn unary(&mut self) -> PResult<Ast> {
        let (op, span) = match self.tok {
            Tok::Minus => (UnOp::Neg, self.span),
            Tok::Plus => {
                self.bump();
                return self.unary();
            }
            Tok::Bang | Tok::Ident("not") => (UnOp::Not, self.span),
            _ => return self.power(),
        };
        self.bump();
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(Diagnostic::error(span, "expression is nested too deeply"));
        }
        // Unary minus binds looser than `^`: -2^2 = -4.
        let inner = self.unary()?;
        self.depth -= 1;
        let span = span.to(inner.span);
        Ok(Ast { kind: Node::Unary(op, Box::new(inner)), span })
    }

    fn power(&mut self) -> PResult<Ast> {
        let base = self.atom()?;
        if self.tok == Tok::Caret {
            self.bump();
            let exp = self.unary()?;
            let span = base.span.to(exp.span);
            return Ok(Ast { kind: Node::Binary(BinOp::Pow, Box::new(base), Box::new(exp)), span });
        }
        Ok(base)
    }

    fn atom(&mut self) -> PResult<Ast> {
        match self.tok {
            Tok::Num(v) => {
                let (_, span) = self.bump();
                Ok(Ast { kind: Node::Num(v), span })
            }
            Tok::Ident(name) if !matches!(name, "and" | "or" | "not") => {
                let (_, span) = self.bump();
                if self.tok != Tok::LParen {
                    return Ok(Ast { kind: Node::Var(name.to_string()), span });
                }
                self.bump();
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
                let end = self.expect(Tok::RParen, &format!("to close the arguments of `{name}`"))?;
                Ok(Ast { kind: Node::Call(name.to_string(), span, args), span: span.to(end) })
            }
            Tok::LParen => {
                let (_, open) = self.bump();
                let inner = self.expr(0)?;
                let close = self.expect(Tok::RParen, "to close `(`")?;
                Ok(Ast { kind: inner.kind, span: open.to(close) })
            }
            t => Err(Diagnostic::error(self.span, format!("expected an expression, found {}", describe(t))).with_hint(
                "an expression is a number, a name, a function call like `min(a, b)`, or a parenthesized formula",
            )),
        }
    }
}

/// Parses one expression at the start of `text`. Returns it and the number
/// of bytes consumed (up to the end of its last token); the expression ends
/// at the first token that cannot continue it (`;`, `]`, `{`, an identifier
/// after a complete operand, …). Spans are relative to `text`.
pub fn parse_prefix(text: &str) -> Result<(Ast, usize), Diagnostic> {
    let mut p = Parser::new(text);
    let ast = p.expr(0)?;
    Ok((ast, p.last_end))
}

/// Parses `text`, which must be exactly one expression (surrounding
/// whitespace and comments allowed).
pub fn parse(text: &str) -> Result<Ast, Diagnostic> {
    let mut p = Parser::new(text);
    let ast = p.expr(0)?;
    if p.tok != Tok::Eof {
        return Err(Diagnostic::error(
            p.span,
            format!("expected an operator or the end of the expression, found {}", describe(p.tok)),
        ));
    }
    Ok(ast)
}
