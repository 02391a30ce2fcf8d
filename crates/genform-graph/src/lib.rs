//! Attributed 2D graph grammars (`.gg.yaml`), after "A Graph Grammar for
//! Procedural Generation of 2D Models" (the paper in `shared/papers`),
//! with single-pushout rewriting done in place.
//!
//! - [`compile`] reads a grammar (every error at once, with `file:line:col`
//!   and hints).
//! - [`GraphGrammar::derive`] rewrites the host graph step by step: priority
//!   groups, random production order, planned random matching (or the
//!   oldest match), weighted daughter options, automatic placement of new
//!   vertices. Every random decision comes from one
//!   [`genform_core::rng::Draws`] source.
//! - [`Graph::to_scene`] draws the result ([`genform_core::Scene::shapes2d`])
//!   and [`Graph::to_yaml`] writes it back in the host format.
//!
//! The format is documented in `docs/graph-grammar.md`.
//!
//! ```
//! use genform_core::{Rng, SourceFile};
//! let src = "
//! host:
//!   vertices: {a: {x: 0, y: 0}, b: {x: 9, y: 0}}
//!   edges: [{from: a, to: b, directed: true, label: seg}]
//! productions:
//!   - name: split
//!     mother:
//!       vertices: {A: {}, B: {}}
//!       edges: [{from: A, to: B, directed: true, label: seg}]
//!     daughter:
//!       vertices: {A: {}, B: {}, M: {pos: \"(A + B) / 2\"}}
//!       edges: [{from: A, to: M, directed: true, label: seg}, {from: M, to: B, directed: true, label: seg}]
//! ";
//! let (grammar, _warnings) = genform_graph::compile(&SourceFile::new("split.gg.yaml", src)).unwrap();
//! let d = grammar.derive(&mut Rng::from_seed(1), Some(3), 1000).unwrap();
//! assert_eq!((d.graph.vertex_count(), d.graph.edge_count()), (5, 4));
//! ```

mod choices;
mod compile;
mod derive;
mod draw;
mod element;
mod grammar;
mod graph;
mod index;
mod mother;
mod names;
mod placement;
mod plan;
mod rewrite;
mod search;
mod table;
mod template;
mod write;
mod yaml;

#[cfg(test)]
mod tests;

pub use compile::compile;
pub use derive::{DEFAULT_MAX_ELEMENTS, Derivation, DeriveError, Match, SEARCH_LIMIT, Stats, Stop, UNLIMITED_STEPS};
pub use draw::{DEFAULT_STROKE_WIDTH, DEFAULT_VERTEX_RADIUS};
pub use grammar::GraphGrammar;
pub use graph::{EdgeRef, Graph, Value, VertexRef};
