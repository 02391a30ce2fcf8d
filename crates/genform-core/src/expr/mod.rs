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
mod scope;
mod suggest;
pub mod vec2;

pub use compile::{Arith, Operand, Program, Trivial, compile, smootherstep};
pub use dialect::{Dialect, RawArgument, Wording, skip_hash_trivia};
pub use lex::skip_trivia;
pub use parse::{Ast, BinOp, Node, UnOp, parse, parse_prefix, parse_prefix_in};
pub use scope::{Names, Scope};
pub use suggest::did_you_mean;

#[cfg(test)]
mod tests;
