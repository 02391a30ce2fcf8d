//! Genr8's Hemberg Extended Map L-systems (HEMLS): surfaces grown from a
//! seed polygon by edge rewriting, branch joining and an environment.
//!
//! - [`grammar`]: the compiled rewrite system (plain data, writes back as `.gr8`).
//! - [`settings`]: growth settings (Genr8's flags) and element limits.
//! - [`env`]: attractors, repellers, gravity and boundaries.

pub mod env;
pub mod grammar;
pub mod settings;

pub use env::Environment;
pub use grammar::{Age, AxiomSide, Branch, Cmp, Condition, EdgeSym, Hemls, Item, Predecessor, Rule, Successor, Turn};
pub use settings::{GrowthLimits, Settings};
