//! Random search over codon strings: the baseline GE must beat at equal
//! evaluations.
//!
//! Every generation samples `population` fresh genomes exactly as GE
//! initializes (genome `i` of generation `g` from stream
//! `(seed, CODON_RANDOM_STREAM, g, i)`), evaluates them, and keeps the best
//! `population` individuals seen so far.

use super::codons::Codons;
use super::config::CodonRandomConfig;
use super::operators;
use crate::config::ConfigError;
use crate::objective::Objective;
use crate::optimizer::{Individual, Optimizer};
use crate::population::Population;
use crate::stats::GenerationStats;
use genform_core::Rng;

/// Stream id of codon random search: `(seed, CODON_RANDOM_STREAM, generation, index)`.
pub const CODON_RANDOM_STREAM: u64 = 0x4745_5241_4e44; // "GERAND"

/// Random search over codon strings.
#[derive(Clone, Debug)]
pub struct CodonRandom {
    config: CodonRandomConfig,
    seed: u64,
    state: Population<Codons>,
}

impl CodonRandom {
    /// A search with nothing sampled yet.
    pub fn new(config: CodonRandomConfig, seed: u64) -> Result<Self, ConfigError> {
        config.validate()?;
        let state = Population::with_room(config.population, "population")?;
        Ok(CodonRandom { config, seed, state })
    }

    /// The configuration.
    pub fn config(&self) -> &CodonRandomConfig {
        &self.config
    }

    /// Samples and evaluates one batch; the first call is generation 0.
    pub fn step<O: Objective<Codons>>(&mut self, objective: &O) -> GenerationStats {
        let generation = self.state.next_generation() as u64;
        let (length, range, seed) = (self.config.initial_length, self.config.codon_range, self.seed);
        self.state.keep_best(objective, self.config.population, |i| {
            let mut rng = Rng::stream(seed, &[CODON_RANDOM_STREAM, generation, i as u64]);
            operators::random_codons(length, range, &mut rng)
        })
    }
}

impl Optimizer<Codons> for CodonRandom {
    fn step<O: Objective<Codons>>(&mut self, objective: &O) -> GenerationStats {
        CodonRandom::step(self, objective)
    }

    fn population(&self) -> &[Individual<Codons>] {
        self.state.members()
    }

    fn best(&self) -> Option<&Individual<Codons>> {
        self.state.best()
    }

    fn generation(&self) -> usize {
        self.state.generation()
    }

    fn evaluations(&self) -> u64 {
        self.state.evaluations()
    }
}

impl crate::rescore::Rescore<Codons> for CodonRandom {
    /// Re-scores the kept individuals and the best.
    fn rescore<O: Objective<Codons>>(&mut self, objective: &O) -> u64 {
        self.state.rescore(objective)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::objective::FnObjective;

    #[test]
    fn keeps_the_best_seen_and_samples_fresh_genomes() {
        let objective = FnObjective(|c: &Codons| c.iter().take(5).map(|&x| x as f64).sum::<f64>());
        let config = CodonRandomConfig { population: 8, initial_length: [3, 9], codon_range: 100 };
        let mut r = CodonRandom::new(config, 4).unwrap();
        let mut last = f64::NEG_INFINITY;
        for g in 0..5 {
            let s = r.step(&objective);
            assert_eq!((s.generation, s.evaluations, s.total_evaluations), (g, 8, 8 * (g as u64 + 1)));
            assert!(s.max >= last);
            last = s.max;
            assert_eq!(r.population().len(), 8);
            assert!(r.population().windows(2).all(|w| w[0].fitness >= w[1].fitness));
            assert!(r.population().iter().all(|i| (3..=9).contains(&i.genome.len())));
            assert!(r.population().iter().all(|i| i.genome.iter().all(|&c| c < 100)));
            assert_eq!(r.best().unwrap().fitness, s.max);
        }
    }
}
