//! The codon optimizers behind one name, for drivers that pick the
//! algorithm at run time. Kept apart from [`Algorithm`](crate::Algorithm):
//! codon optimizers need an `Objective<Codons>`, tree optimizers an
//! `Objective<Genome>`, and neither enum forces the other's objective.

use super::codons::Codons;
use super::config::{CodonRandomConfig, GeConfig};
use super::ea::Ge;
use super::random::CodonRandom;
use crate::config::ConfigError;
use crate::objective::Objective;
use crate::optimizer::{Individual, Optimizer};
use crate::stats::GenerationStats;
use std::fmt;

/// The search algorithms over codon strings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CodonAlgorithm {
    /// Grammatical evolution ([`Ge`]).
    Ge,
    /// Random search over codon strings ([`CodonRandom`]).
    Random,
}

impl CodonAlgorithm {
    /// Every codon algorithm, in the order reports list them.
    pub const ALL: [CodonAlgorithm; 2] = [CodonAlgorithm::Ge, CodonAlgorithm::Random];

    /// Lower-case name, as on the command line.
    pub fn name(self) -> &'static str {
        match self {
            CodonAlgorithm::Ge => "ge",
            CodonAlgorithm::Random => "random",
        }
    }
}

impl fmt::Display for CodonAlgorithm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One of the codon optimizers, chosen at run time.
#[derive(Clone, Debug)]
pub enum AnyCodonOptimizer {
    /// [`Ge`].
    Ge(Ge),
    /// [`CodonRandom`].
    Random(CodonRandom),
}

impl AnyCodonOptimizer {
    /// Builds `algorithm`; random search takes its batch size, lengths and
    /// codon range from `config` ([`CodonRandomConfig::like`]).
    pub fn new(algorithm: CodonAlgorithm, config: &GeConfig, seed: u64) -> Result<Self, ConfigError> {
        Ok(match algorithm {
            CodonAlgorithm::Ge => AnyCodonOptimizer::Ge(Ge::new(config.clone(), seed)?),
            CodonAlgorithm::Random => {
                AnyCodonOptimizer::Random(CodonRandom::new(CodonRandomConfig::like(config), seed)?)
            }
        })
    }

    fn inner(&self) -> &dyn Optimizer<Codons> {
        match self {
            AnyCodonOptimizer::Ge(o) => o,
            AnyCodonOptimizer::Random(o) => o,
        }
    }
}

impl Optimizer<Codons> for AnyCodonOptimizer {
    fn step<O: Objective<Codons>>(&mut self, objective: &O) -> GenerationStats {
        match self {
            AnyCodonOptimizer::Ge(o) => o.step(objective),
            AnyCodonOptimizer::Random(o) => o.step(objective),
        }
    }

    fn population(&self) -> &[Individual<Codons>] {
        self.inner().population()
    }

    fn best(&self) -> Option<&Individual<Codons>> {
        self.inner().best()
    }

    fn generation(&self) -> usize {
        self.inner().generation()
    }

    fn evaluations(&self) -> u64 {
        self.inner().evaluations()
    }
}

impl crate::rescore::Rescore<Codons> for AnyCodonOptimizer {
    fn rescore<O: Objective<Codons>>(&mut self, objective: &O) -> u64 {
        match self {
            AnyCodonOptimizer::Ge(o) => o.rescore(objective),
            AnyCodonOptimizer::Random(o) => o.rescore(objective),
        }
    }
}
