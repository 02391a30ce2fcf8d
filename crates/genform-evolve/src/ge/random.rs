//! Random search over codon strings: the baseline GE must beat at equal
//! evaluations.
//!
//! Every generation samples `population` fresh genomes exactly as GE
//! initializes (genome `i` of generation `g` from stream
//! `(seed, CODON_RANDOM_STREAM, g, i)`), evaluates them, and keeps the best
//! `population` individuals seen so far.

use super::config::CodonRandomConfig;
use super::{Codons, operators};
use crate::config::ConfigError;
use crate::evaluate::{Child, evaluate};
use crate::objective::Objective;
use crate::optimizer::{Individual, Optimizer, sort_population, update_best};
use crate::stats::GenerationStats;
use genform_core::Rng;
use rayon::prelude::*;
use std::time::Instant;

/// Stream id of codon random search: `(seed, CODON_RANDOM_STREAM, generation, index)`.
pub const CODON_RANDOM_STREAM: u64 = 0x4745_5241_4e44; // "GERAND"

/// Random search over codon strings.
#[derive(Clone, Debug)]
pub struct CodonRandom {
    config: CodonRandomConfig,
    seed: u64,
    population: Vec<Individual<Codons>>,
    generation: usize,
    evaluations: u64,
    best: Option<Individual<Codons>>,
}

impl CodonRandom {
    /// A search with nothing sampled yet.
    pub fn new(config: CodonRandomConfig, seed: u64) -> Result<Self, ConfigError> {
        config.validate()?;
        Ok(CodonRandom { config, seed, population: Vec::new(), generation: 0, evaluations: 0, best: None })
    }

    /// The configuration.
    pub fn config(&self) -> &CodonRandomConfig {
        &self.config
    }

    /// Samples and evaluates one batch; the first call is generation 0.
    pub fn step<O: Objective<Codons>>(&mut self, objective: &O) -> GenerationStats {
        let generation = if self.population.is_empty() { 0 } else { self.generation + 1 };
        let start = Instant::now();
        let (length, range, seed) = (self.config.initial_length, self.config.codon_range, self.seed);
        let mut batch: Vec<Child<Codons>> = (0..self.config.population)
            .into_par_iter()
            .map(|i| {
                let mut rng = Rng::stream(seed, &[CODON_RANDOM_STREAM, generation as u64, i as u64]);
                Child { genome: operators::random_codons(length, range, &mut rng), fitness: None }
            })
            .collect();
        let reproduction_time = start.elapsed();
        let (evaluations, eval_time) = evaluate(objective, &mut batch);
        self.population.extend(
            batch
                .into_iter()
                .map(|c| Individual { genome: c.genome, fitness: c.fitness.expect("every child is evaluated") }),
        );
        sort_population(&mut self.population);
        self.population.truncate(self.config.population);
        update_best(&mut self.best, &self.population);
        self.generation = generation;
        self.evaluations += evaluations;
        GenerationStats {
            evaluations,
            total_evaluations: self.evaluations,
            eval_time,
            reproduction_time,
            ..GenerationStats::summarize(generation, &self.population)
        }
    }
}

impl Optimizer<Codons> for CodonRandom {
    fn step<O: Objective<Codons>>(&mut self, objective: &O) -> GenerationStats {
        CodonRandom::step(self, objective)
    }

    fn population(&self) -> &[Individual<Codons>] {
        &self.population
    }

    fn best(&self) -> Option<&Individual<Codons>> {
        self.best.as_ref()
    }

    fn generation(&self) -> usize {
        self.generation
    }

    fn evaluations(&self) -> u64 {
        self.evaluations
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
