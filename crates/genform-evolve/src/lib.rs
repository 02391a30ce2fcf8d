//! Optimizers over genform genomes.
//!
//! Optimizers know genomes and the generator graph, never a formalism:
//! they call an [`Objective`] for fitness and reshape derivation trees with
//! the [`operators`].
//!
//! - [`objective`]: the fitness interface (per-worker scratch, invalid =
//!   non-finite).
//! - [`operators`]: grow, cut, alter, crossover, initial individuals.
//! - [`selection`]: roulette, tournament, uniform.
//! - [`ga`]: the ShapeGenetics genetic algorithm.
//! - [`random`]: the random-search baseline.
//! - [`run`](mod@run): the driver with generation, time, evaluation and cancel stops.
//! - [`config`], [`stats`], [`optimizer`]: settings, per-generation
//!   statistics, the shared [`Optimizer`] trait.
//! - [`fixtures`]: toy graphs and objectives for tests and benchmarks.
#![warn(missing_docs)]

pub mod config;
mod evaluate;
pub mod fixtures;
pub mod ga;
pub mod objective;
pub mod operators;
pub mod optimizer;
pub mod random;
pub mod run;
pub mod selection;
pub mod stats;

pub use config::{ConfigError, GaConfig, RandomConfig, SelectionPair};
pub use ga::Ga;
pub use objective::{FnObjective, Objective};
pub use operators::{LengthBounds, MutationKind, MutationMix};
pub use optimizer::{Individual, Optimizer};
pub use random::RandomSearch;
pub use run::{RunSummary, Stop, StopReason, Unbounded, run};
pub use selection::Selection;
pub use stats::GenerationStats;
