//! Grammatical evolution: the Genr8 EA over codon strings.
//!
//! The optimizer never sees a grammar. Its genomes are [`Codons`], and an
//! [`Objective<Codons>`](crate::Objective) (typically a GE mapper followed by a
//! fitness) scores them; a non-finite score marks the individual invalid
//! (e.g. the mapping ran out of codons), and it then loses every tournament
//! and sorts last.
//!
//! Generation loop of [`Ge`]: sort best first; copy the `elitism` best with
//! their cached fitness; fill the rest pair by pair, each pair from its own
//! random stream `(seed, GE_PAIR_STREAM, generation, pair)`: select two
//! parents; with probability `crossover_rate` cross them over
//! ([`crossover`](operators::crossover)), else copy them; mutate every codon
//! of each child with probability `mutation_rate`
//! ([`mutate`](operators::mutate)). A child equal to one of its parents
//! reuses that parent's fitness (objectives are deterministic); the others
//! are evaluated in parallel. Pairs and evaluations are collected in index
//! order, so a seed gives the same populations and statistics at any
//! thread count.
//!
//! - [`config`]: [`GeConfig`], [`CodonRandomConfig`].
//! - [`operators`]: random genomes, crossover, mutation.
//! - [`random`]: [`CodonRandom`], the random-search baseline.
//! - [`algorithm`]: [`CodonAlgorithm`], [`AnyCodonOptimizer`].

pub mod algorithm;
pub mod config;
pub mod operators;
pub mod random;
mod reproduce;
#[cfg(test)]
mod tests;

pub use algorithm::{AnyCodonOptimizer, CodonAlgorithm};
pub use config::{CodonRandomConfig, GeConfig};
pub use random::CodonRandom;

use crate::config::ConfigError;
use crate::objective::Objective;
use crate::optimizer::{Individual, Optimizer};
use crate::population::{Population, breed};
use crate::selection::Selector;
use crate::stats::GenerationStats;
use genform_core::Rng;
use reproduce::{Context, reproduce_pair};
use std::time::Instant;

/// A codon string: the genome of grammatical evolution. Codons lie in
/// `0..codon_range` of the optimizer's configuration.
pub type Codons = Vec<u32>;

/// Stream id of GE's initial genomes: `(seed, GE_INIT_STREAM, index)`.
pub const GE_INIT_STREAM: u64 = 0x4745_494e_4954; // "GEINIT"
/// Stream id of GE's reproduction: `(seed, GE_PAIR_STREAM, generation, pair)`.
pub const GE_PAIR_STREAM: u64 = 0x4745_5041_4952; // "GEPAIR"

/// The grammatical-evolution EA (Genr8's loop with the recommended GE
/// operators; see the [module](self) documentation).
#[derive(Clone, Debug)]
pub struct Ge {
    config: GeConfig,
    seed: u64,
    state: Population<Codons>,
}

impl Ge {
    /// A GE run with no population yet (see [`Ge::initialize`]).
    pub fn new(config: GeConfig, seed: u64) -> Result<Self, ConfigError> {
        config.validate()?;
        Ok(Ge { config, seed, state: Population::default() })
    }

    /// The configuration.
    pub fn config(&self) -> &GeConfig {
        &self.config
    }

    /// The current population, best first.
    pub fn population(&self) -> &[Individual<Codons>] {
        self.state.members()
    }

    /// The best valid individual seen so far (with elitism, the population's first).
    pub fn best(&self) -> Option<&Individual<Codons>> {
        self.state.best()
    }

    /// Index of the current generation (0 = the initial one).
    pub fn generation(&self) -> usize {
        self.state.generation()
    }

    /// Objective evaluations so far.
    pub fn evaluations(&self) -> u64 {
        self.state.evaluations()
    }

    /// Builds and evaluates generation 0 (discarding any population):
    /// individual `i` is [`random_codons`](operators::random_codons) from
    /// stream `(seed, GE_INIT_STREAM, i)`.
    pub fn initialize<O: Objective<Codons>>(&mut self, objective: &O) -> GenerationStats {
        let (length, range, seed) = (self.config.initial_length, self.config.codon_range, self.seed);
        self.state.initialize(objective, self.config.population, |i| {
            operators::random_codons(length, range, &mut Rng::stream(seed, &[GE_INIT_STREAM, i as u64]))
        })
    }

    /// Makes the next generation; initializes first if there is no population.
    pub fn step<O: Objective<Codons>>(&mut self, objective: &O) -> GenerationStats {
        if self.state.is_empty() {
            return self.initialize(objective);
        }
        let started = Instant::now();
        let generation = self.state.generation() + 1;
        let fitness = self.state.fitness();
        let ctx = Context {
            config: &self.config,
            population: self.state.members(),
            selector: Selector::new(self.config.selection, &fitness),
        };
        let seed = self.seed;
        let (children, counts) = breed(self.config.population - self.config.elitism, |pair, need| {
            reproduce_pair(&ctx, need, &mut Rng::stream(seed, &[GE_PAIR_STREAM, generation as u64, pair as u64]))
        });
        self.state.advance(objective, self.config.elitism, children, counts, started)
    }
}

impl Optimizer<Codons> for Ge {
    fn step<O: Objective<Codons>>(&mut self, objective: &O) -> GenerationStats {
        Ge::step(self, objective)
    }

    fn population(&self) -> &[Individual<Codons>] {
        Ge::population(self)
    }

    fn best(&self) -> Option<&Individual<Codons>> {
        Ge::best(self)
    }

    fn generation(&self) -> usize {
        Ge::generation(self)
    }

    fn evaluations(&self) -> u64 {
        Ge::evaluations(self)
    }
}

impl crate::rescore::Rescore<Codons> for Ge {
    /// Re-scores the population and the best.
    fn rescore<O: Objective<Codons>>(&mut self, objective: &O) -> u64 {
        self.state.rescore(objective)
    }
}
