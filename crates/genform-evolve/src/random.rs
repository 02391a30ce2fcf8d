//! Random search: the baseline the GA must beat at equal evaluations.
//!
//! Every generation samples a batch of fresh individuals exactly as the GA
//! initializes (individual `i` of generation `g` from stream
//! `(seed, RANDOM_STREAM, g, i)`), evaluates them, and keeps the best
//! `population` individuals seen so far.

use crate::config::{ConfigError, RandomConfig};
use crate::evaluate::{Child, evaluate};
use crate::objective::Objective;
use crate::operators::initial;
use crate::optimizer::{Individual, Optimizer, sort_population, update_best};
use crate::stats::{GenerationStats, ReproductionCounts};
use genform_core::{GeneratorGraph, Limits, Rng};
use rayon::prelude::*;
use std::time::Instant;

/// Stream id of random search: `(seed, RANDOM_STREAM, generation, index)`.
pub const RANDOM_STREAM: u64 = 0x5241_4e44; // "RAND"

/// Random search over one generator graph.
#[derive(Clone, Debug)]
pub struct RandomSearch {
    graph: GeneratorGraph,
    limits: Limits,
    config: RandomConfig,
    seed: u64,
    population: Vec<Individual>,
    generation: usize,
    evaluations: u64,
    best: Option<Individual>,
}

impl RandomSearch {
    /// A search with nothing sampled yet.
    pub fn new(graph: &GeneratorGraph, limits: &Limits, config: RandomConfig, seed: u64) -> Result<Self, ConfigError> {
        config.validate()?;
        let limits = crate::optimizer::length_capped(limits, config.max_length);
        Ok(RandomSearch {
            graph: graph.clone(),
            limits,
            config,
            seed,
            population: Vec::new(),
            generation: 0,
            evaluations: 0,
            best: None,
        })
    }

    /// Samples and evaluates one batch; the first call is generation 0.
    pub fn step<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        let generation = if self.population.is_empty() { 0 } else { self.generation + 1 };
        let start = Instant::now();
        let (graph, limits, length, seed) = (&self.graph, &self.limits, self.config.initial_length, self.seed);
        let mut batch: Vec<Child> = (0..self.config.population)
            .into_par_iter()
            .map(|i| {
                let mut rng = Rng::stream(seed, &[RANDOM_STREAM, generation as u64, i as u64]);
                Child { genome: initial(graph, limits, length, &mut rng), fitness: None }
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
            reproduction: ReproductionCounts::default(),
            ..GenerationStats::of_population(generation, &self.population)
        }
    }
}

impl Optimizer for RandomSearch {
    fn step<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        RandomSearch::step(self, objective)
    }

    fn population(&self) -> &[Individual] {
        &self.population
    }

    fn best(&self) -> Option<&Individual> {
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
    use crate::fixtures::{ShipToy, ship};

    #[test]
    fn keeps_the_best_seen_and_is_reproducible() {
        let objective = ShipToy { target: 12 };
        let config = RandomConfig { population: 12, initial_length: [3, 20], max_length: 40 };
        let mut a = RandomSearch::new(&ship(), &Limits::default(), config.clone(), 8).unwrap();
        let mut last = f64::NEG_INFINITY;
        for g in 0..6 {
            let s = a.step(&objective);
            assert_eq!((s.generation, s.evaluations, s.total_evaluations), (g, 12, 12 * (g as u64 + 1)));
            assert!(s.max >= last);
            last = s.max;
            assert_eq!(a.population().len(), 12);
            assert!(a.population().windows(2).all(|w| w[0].fitness >= w[1].fitness));
            assert!(a.population().iter().all(|i| i.genome.len() < 40));
        }
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        let mut b = RandomSearch::new(&ship(), &Limits::default(), config, 8).unwrap();
        pool.install(|| {
            for _ in 0..6 {
                b.step(&objective);
            }
        });
        assert_eq!(a.population(), b.population());
    }
}
