//! Genr8's Hemberg Extended Map L-systems (HEMLS): surfaces grown from a
//! seed polygon by edge rewriting, branch joining and an environment.
//!
//! - [`grammar`]: the compiled rewrite system (plain data, writes back as `.gr8`).
//! - [`settings`]: growth settings (Genr8's flags) and element limits.
//! - [`env`](mod@env): attractors, repellers, gravity and boundaries.
//! - [`syntax`]: the `.gr8` front end, [`compile`] and [`parse_str`].
//! - [`envfile`]: the TOML environment file (settings and environment).
//! - [`map`], [`grow`](mod@grow): the half-edge surface and the growth engine ([`grow()`], [`grow_with`]).

pub mod env;
pub mod envfile;
mod error;
pub mod grammar;
pub mod grow;
mod join;
mod lex;
pub mod map;
pub mod settings;
pub mod syntax;
#[cfg(test)]
mod testkit;
mod turtle;
mod write;

pub use env::{Axis, Behaviour, Boundary, Charge, ChargeKind, Environment, Gravity, Keep, MeshBoundary, Shape};
pub use envfile::{BoundarySpec, EnvSpec, ShapeSpec, parse_env};
pub use grammar::{Age, AxiomSide, Branch, Cmp, Condition, EdgeSym, Hemls, Item, Predecessor, Rule, Successor, Turn};
pub use grow::{GrowError, Growth, StepStats, grow, grow_with};
pub use map::Map;
pub use settings::{GrowthLimits, JoinTest, Settings};
pub use syntax::{compile, parse_str};
