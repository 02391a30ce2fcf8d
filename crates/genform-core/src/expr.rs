//! The one compiler for user formulas (placeholder API; being implemented).

use crate::diag::{Diagnostic, Span};
use crate::rng::Rng;

/// A parsed expression.
#[derive(Clone, Debug, PartialEq)]
pub struct Ast {
    _private: (),
}

/// Names visible to an expression, mapped to indices of the `env` slice
/// passed to [`Program::eval`].
pub trait Scope {
    /// The env index of variable `name` (names may contain dots, e.g.
    /// `size.x`; a call `f(x)` of a non-builtin function `f` with one bare
    /// identifier argument is looked up as the variable `"f(x)"`).
    fn variable(&self, name: &str) -> Option<u32>;
    /// Known names, for "did you mean" hints.
    fn names(&self) -> Vec<String> {
        Vec::new()
    }
}

/// A compiled expression.
#[derive(Clone, Debug, PartialEq)]
pub struct Program {
    _private: (),
}

/// Parses one expression at the start of `text`; returns it and the number of bytes consumed.
pub fn parse_prefix(_text: &str) -> Result<(Ast, usize), Diagnostic> {
    Err(Diagnostic::error(Span::new(0, 0), "expressions are not implemented yet"))
}

/// Parses `text`, which must be exactly one expression.
pub fn parse(text: &str) -> Result<Ast, Diagnostic> {
    parse_prefix(text).map(|(a, _)| a)
}

/// Compiles an expression against the names of `scope`.
pub fn compile(_ast: &Ast, _scope: &dyn Scope) -> Result<Program, Vec<Diagnostic>> {
    Ok(Program { _private: () })
}

impl Program {
    /// Evaluates without random draws.
    pub fn eval(&self, _env: &[f64]) -> f64 {
        0.0
    }
    /// Evaluates, drawing random values from `rng`.
    pub fn eval_rng(&self, _env: &[f64], _rng: &mut Rng) -> f64 {
        0.0
    }
    /// The value if the expression is constant.
    pub fn constant(&self) -> Option<f64> {
        None
    }
}
