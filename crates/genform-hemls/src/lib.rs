//! Genr8's Hemberg Extended Map L-systems (HEMLS): surfaces grown from a
//! seed polygon by edge rewriting, branch joining and an environment.
//!
//! - [`grammar`]: the compiled rewrite system (plain data, writes back as `.gr8`).

pub mod grammar;

pub use grammar::{Age, AxiomSide, Branch, Cmp, Condition, EdgeSym, Hemls, Item, Predecessor, Rule, Successor, Turn};
