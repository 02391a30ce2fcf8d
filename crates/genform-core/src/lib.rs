//! Core of genform: everything the formalisms, optimizers, scorers and
//! exporters share.
//!
//! - [`scene`]: the resolved geometry every generator produces and every
//!   exporter and scorer consumes.
//! - [`surface`]: polygon surfaces with typed edges, and preview guides.
//! - [`subdivide`]: Catmull–Clark subdivision of surfaces.
//! - [`camera`]: the orbit camera and its world → pixel projection, shared by
//!   the preview renderer and the image scorers.
//! - [`graph`]: the generator graph (symbols, parameter specs, child slots).
//! - [`genome`]: the packed derivation-tree genome and its JSON form.
//! - [`generator`]: the [`Generator`] trait, limits and prior sampling.
//! - [`rng`]: counter-derived random streams (splitmix64 → xoshiro256++).
//! - [`codons`]: codon genomes as a source of random choices (grammatical
//!   evolution).
//! - [`diag`]: the one diagnostics type, with file:line:col rendering.
//! - [`expr`]: the one compiler for user formulas, to an f64 bytecode.
//! - `fixtures` (tests only, feature `test-support`): the checker of
//!   grammar files annotated with their expected diagnostics.

pub mod blocks;
pub mod camera;
pub mod codons;
pub mod diag;
pub mod expr;
#[cfg(any(test, feature = "test-support"))]
pub mod fixtures;
pub mod generator;
pub mod genome;
pub mod graph;
pub mod rng;
pub mod scene;
pub mod subdivide;
pub mod surface;

pub use blocks::{BlockGrid, BlockKind, BlockState};
pub use codons::CodonSource;
pub use diag::{Diagnostic, Diagnostics, Severity, SourceFile, Span};
pub use generator::{ExpressError, Generator, LimitKind, Limits, Sampled};
pub use genome::{Genome, GenomeError};
pub use graph::{Distribution, GeneratorGraph, ParamSpec, SlotSpec, SymbolId, SymbolSpec};
pub use rng::{Draws, Rng};
pub use scene::{Instance, Mesh, MeshId, Primitive, Scene, TagId};
pub use subdivide::catmull_clark;
pub use surface::{Guide, GuideKind, Surface, SurfaceEdge};
