//! The one compiler for user formulas.
//!
//! Every formalism's formulas (shape-grammar sizes and conditions, L-system
//! parameters, box-split constraints, graph-grammar attributes) go through
//! here: [`parse_prefix`] reads one expression from the start of a text (so a
//! host language can embed expressions and continue after them),
//! [`compile`] resolves names against a [`Scope`] to indices, folds
//! constants and emits a small stack bytecode, and [`Program::eval`] runs it
//! on an `&[f64]` environment without allocating.
//!
//! Values are `f64`; comparisons and logic yield 1 or 0, and any non-zero,
//! non-NaN value is true. `&&`/`and`, `||`/`or` short-circuit.

mod compile;
mod dialect;
mod lex;
mod parse;
pub mod vec2;

pub use compile::{Arith, Operand, Program, Trivial, compile, smootherstep};
pub use dialect::{Dialect, RawArgument, Wording, skip_hash_trivia};
pub use lex::skip_trivia;
pub use parse::{Ast, BinOp, Node, UnOp, parse, parse_prefix, parse_prefix_in};

/// Names visible to an expression, mapped to indices of the `env` slice
/// passed to [`Program::eval`].
pub trait Scope {
    /// The env index of variable `name` (names may contain dots, e.g.
    /// `size.x`; a call `f(x)` of a non-builtin function `f` with one bare
    /// identifier argument is looked up as the variable `"f(x)"`, and a call
    /// `f()` without arguments as `"f()"`).
    fn variable(&self, name: &str) -> Option<u32>;
    /// The value of a named constant (folded at compile time); variables
    /// shadow constants, constants shadow the built-in `pi`, `e`, ….
    fn constant(&self, _name: &str) -> Option<f64> {
        None
    }
    /// Known names, for "did you mean" hints.
    fn names(&self) -> Vec<String> {
        Vec::new()
    }
}

/// A scope from a list of names: name `i` is env index `i`.
#[derive(Clone, Copy, Debug)]
pub struct Names<'a>(pub &'a [&'a str]);

impl Scope for Names<'_> {
    fn variable(&self, name: &str) -> Option<u32> {
        self.0.iter().position(|n| *n == name).map(|i| i as u32)
    }
    fn names(&self) -> Vec<String> {
        self.0.iter().map(|s| s.to_string()).collect()
    }
}

/// The closest of `candidates` to `name` by edit distance, if close enough
/// to be a plausible typo.
pub fn did_you_mean<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let mut best: Option<(usize, &str)> = None;
    for c in candidates {
        let d = edit_distance(name, c);
        let limit = (name.chars().count().max(c.chars().count()) / 3).max(1);
        if d <= limit && best.is_none_or(|(bd, _)| d < bd) {
            best = Some((d, c));
        }
    }
    best.map(|(_, c)| c)
}

/// Edit distance counting a swap of two neighbouring characters as one
/// edit (optimal string alignment): `stpes` is one typo from `steps`.
fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let mut rows = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in rows.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, cell) in rows[0].iter_mut().enumerate() {
        *cell = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut d = (rows[i - 1][j - 1] + cost).min(rows[i - 1][j] + 1).min(rows[i][j - 1] + 1);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                d = d.min(rows[i - 2][j - 2] + 1);
            }
            rows[i][j] = d;
        }
    }
    rows[a.len()][b.len()]
}

#[cfg(test)]
mod tests;
