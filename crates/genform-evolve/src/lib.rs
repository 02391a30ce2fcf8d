//! Optimizers over genform genomes.
//!
//! Optimizers know genomes and the generator graph, never a formalism:
//! they call an [`Objective`] for fitness and reshape derivation trees with
//! the [`operators`]. The framework ([`Individual`], [`Objective`],
//! [`Optimizer`], [`run()`]) is generic over the genome type, which defaults to
//! the derivation-tree [`Genome`](genform_core::Genome); grammatical
//! evolution ([`ge`]) uses codon strings ([`Codons`]).
//!
//! - [`objective`]: the fitness interface (per-worker scratch, invalid =
//!   non-finite).
//! - [`operators`]: grow, cut, alter, crossover, initial individuals.
//! - [`selection`]: roulette, tournament, uniform.
//! - [`ga`]: the ShapeGenetics genetic algorithm.
//! - [`ge`]: grammatical evolution over codon strings (the Genr8 EA) and
//!   its random-search baseline.
//! - [`random`]: the random-search baseline.
//! - [`smc`]: SMC and SOSMC (fixed and stochastic growth order).
//! - [`hybrid`]: SOSMC seeding, GA, then MH polishing.
//! - [`map_elites`]: MAP-Elites, the best individual per cell of a grid
//!   over two behaviour descriptors (quality-diversity).
//! - [`mcmc`]: RJMCMC with parallel tempering, delayed rejection and annealing.
//! - [`run`](mod@run): the driver with generation, time, evaluation and cancel stops.
//! - [`algorithm`]: every optimizer behind one run-time choice.
//! - [`ask_tell`]: any optimizer driven by ask/tell (scores computed elsewhere:
//!   Python workers, a person picking favourites).
//! - [`rescore`]: re-scoring what an optimizer stores when the objective
//!   changes mid-run (steering).
//! - [`config`], [`stats`], [`optimizer`]: settings, per-generation
//!   statistics, the shared [`Optimizer`] trait.
//! - `fixtures` (tests only, feature `test-support`): toy graphs and
//!   objectives for tests and benchmarks.

pub mod algorithm;
pub mod ask_tell;
#[cfg(test)]
mod chi2;
pub mod config;
mod evaluate;
#[cfg(any(test, feature = "test-support"))]
pub mod fixtures;
pub mod ga;
pub mod ge;
pub mod hybrid;
mod individual;
pub mod map_elites;
pub mod mcmc;
pub mod objective;
pub mod operators;
pub mod optimizer;
mod population;
pub mod random;
pub mod rescore;
pub mod run;
pub mod selection;
pub mod smc;
pub mod stats;

pub use algorithm::{Algorithm, AnyOptimizer, Settings};
pub use config::{
    ConfigError, GaConfig, GaPreset, GeneChoice, HybridConfig, Initialization, MhConfig, RandomConfig, SelectionPair,
    SmcConfig, Weighting,
};
pub use ga::Ga;
pub use ge::{AnyCodonOptimizer, CodonAlgorithm, CodonRandom, CodonRandomConfig, Codons, Ge, GeConfig, Init, NovelKey};
pub use hybrid::{Horizon, Hybrid};
pub use map_elites::{DescriptorAxis, Elite, MapElites, MapElitesConfig};
pub use mcmc::Mh;
pub use objective::{CodonSpan, FnObjective, Objective, SensiblePlan};
pub use operators::{LengthBounds, MutationKind, MutationMix};
pub use optimizer::{Genotype, Individual, Optimizer};
pub use random::RandomSearch;
pub use rescore::Rescore;
pub use run::{RunSummary, Stop, StopReason, Unbounded, run};
pub use selection::Selection;
pub use smc::{Order, Smc};
pub use stats::{GenerationStats, MoveCounts};
