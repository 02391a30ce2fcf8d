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
/// to be a plausible typo (at most a third of the longer name's characters,
/// at least one); ties go to the first candidate.
pub fn did_you_mean<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let name: Vec<char> = name.chars().collect();
    let mut rows = Rows::default();
    let mut best: Option<(usize, &str)> = None;
    for c in candidates {
        let len = c.chars().count();
        let limit = (name.len().max(len) / 3).max(1);
        // Only a strictly closer candidate replaces the best so far; the
        // length difference alone bounds the distance from below, so most
        // of a long list (every block id) is never aligned at all.
        let bound = best.map_or(limit, |(d, _)| limit.min(d.saturating_sub(1)));
        if best.is_some_and(|(d, _)| d == 0) || len.abs_diff(name.len()) > bound {
            continue;
        }
        if let Some(d) = distance_within(&name, c, bound, &mut rows) {
            best = Some((d, c));
        }
    }
    best.map(|(_, c)| c)
}

/// Edit distance counting a swap of two neighbouring characters as one
/// edit (optimal string alignment): `stpes` is one typo from `steps`.
#[cfg(test)]
fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    distance_within(&a, b, usize::MAX, &mut Rows::default()).expect("no bound")
}

/// The three rows of the alignment table an optimal-string-alignment
/// distance needs, reused across candidates.
#[derive(Default)]
struct Rows {
    b: Vec<char>,
    before: Vec<usize>,
    last: Vec<usize>,
    this: Vec<usize>,
}

/// The optimal-string-alignment distance of `a` and `b` if it is at most
/// `max`, else `None` (given up as soon as a whole row exceeds `max`).
fn distance_within(a: &[char], b: &str, max: usize, rows: &mut Rows) -> Option<usize> {
    let Rows { b: bc, before, last, this } = rows;
    bc.clear();
    bc.extend(b.chars());
    let n = bc.len();
    for row in [&mut *before, &mut *last, &mut *this] {
        row.clear();
        row.resize(n + 1, 0);
    }
    last.iter_mut().enumerate().for_each(|(j, cell)| *cell = j);
    for i in 1..=a.len() {
        this[0] = i;
        let mut row_min = i;
        for j in 1..=n {
            let cost = usize::from(a[i - 1] != bc[j - 1]);
            let mut d = (last[j - 1] + cost).min(last[j] + 1).min(this[j - 1] + 1);
            if i > 1 && j > 1 && a[i - 1] == bc[j - 2] && a[i - 2] == bc[j - 1] {
                d = d.min(before[j - 2] + 1);
            }
            this[j] = d;
            row_min = row_min.min(d);
        }
        if row_min > max {
            return None;
        }
        std::mem::swap(before, last);
        std::mem::swap(last, this);
    }
    Some(last[n]).filter(|&d| d <= max)
}

#[cfg(test)]
mod tests;
