//! Random search: the baseline the GA must beat at equal evaluations.
//!
//! Every generation samples a batch of fresh individuals exactly as the GA
//! initializes (individual `i` of generation `g` from stream
//! `(seed, RANDOM_STREAM, g, i)`), evaluates them, and keeps the best
//! `population` individuals seen so far.

use crate::config::{ConfigError, RandomConfig};
use crate::objective::Objective;
use crate::operators::initial;
use crate::optimizer::{Individual, Optimizer};
use crate::population::Population;
use crate::stats::GenerationStats;
use genform_core::{GeneratorGraph, Genome, Limits, Rng};

/// Stream id of random search: `(seed, RANDOM_STREAM, generation, index)`.
pub const RANDOM_STREAM: u64 = 0x5241_4e44; // "RAND"

/// Random search over one generator graph.
#[derive(Clone, Debug)]
pub struct RandomSearch {
    graph: GeneratorGraph,
    limits: Limits,
    config: RandomConfig,
    seed: u64,
    state: Population<Genome>,
}

impl RandomSearch {
    /// A search with nothing sampled yet.
    pub fn new(graph: &GeneratorGraph, limits: &Limits, config: RandomConfig, seed: u64) -> Result<Self, ConfigError> {
        config.validate()?;
        let limits = crate::optimizer::length_capped(limits, config.max_length);
        let state = Population::with_room(config.population, "population")?;
        Ok(RandomSearch { graph: graph.clone(), limits, config, seed, state })
    }

    /// Samples and evaluates one batch; the first call is generation 0.
    pub fn step<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        let generation = self.state.next_generation() as u64;
        let (graph, limits, length, seed) = (&self.graph, &self.limits, self.config.initial_length, self.seed);
        self.state.keep_best(objective, self.config.population, |i| {
            initial(graph, limits, length, &mut Rng::stream(seed, &[RANDOM_STREAM, generation, i as u64]))
        })
    }
}

impl Optimizer for RandomSearch {
    fn step<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        RandomSearch::step(self, objective)
    }

    fn population(&self) -> &[Individual] {
        self.state.members()
    }

    fn best(&self) -> Option<&Individual> {
        self.state.best()
    }

    fn generation(&self) -> usize {
        self.state.generation()
    }

    fn evaluations(&self) -> u64 {
        self.state.evaluations()
    }
}

impl crate::rescore::Rescore for RandomSearch {
    /// Re-scores the kept individuals and the best.
    fn rescore<O: Objective>(&mut self, objective: &O) -> u64 {
        self.state.rescore(objective)
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

    /// `--evaluations N` with the GA's count: random search runs whole
    /// batches of the population size until it has at least N, so at a
    /// count the batches divide it matches the GA exactly, and otherwise
    /// gets less than one batch more, never fewer. Every objective call is
    /// counted, and another seed draws other genomes.
    #[test]
    fn the_driver_stops_it_at_the_gas_evaluation_count() {
        use crate::config::GaConfig;
        use crate::ga::Ga;
        use crate::run::{Stop, run};
        use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

        let ga_config = GaConfig {
            population: 10,
            elitism: Some(2),
            initial_length: [3, 20],
            max_length: 40,
            ..GaConfig::default()
        };
        let objective = ShipToy { target: 12 };
        let cancel = AtomicBool::new(false);
        for generations in [5, 6] {
            let mut ga = Ga::new(&ship(), &Limits::default(), ga_config.clone(), 4).unwrap();
            let stop = Stop { generations: Some(generations), budget: None, evaluations: None, cancel: &cancel };
            run(&mut ga, &objective, &stop, |_, _| {}).unwrap();
            let wanted = ga.evaluations();
            assert_eq!(wanted, 10 + generations as u64 * 8);

            let calls = AtomicU64::new(0);
            let counting = crate::objective::FnObjective(|g: &Genome| {
                calls.fetch_add(1, Ordering::Relaxed);
                objective.evaluate(g, &mut ())
            });
            let mut random = RandomSearch::new(&ship(), &Limits::default(), RandomConfig::like(&ga_config), 4).unwrap();
            let stop = Stop { generations: None, budget: None, evaluations: Some(wanted), cancel: &cancel };
            let summary = run(&mut random, &counting, &stop, |_, _| {}).unwrap();
            assert_eq!(summary.evaluations, wanted.div_ceil(10) * 10, "{generations} GA generations");
            assert_eq!(calls.load(Ordering::Relaxed), summary.evaluations);
            assert!(summary.evaluations - wanted < 10);
        }
        let [mut a, mut b] = [1, 2]
            .map(|seed| RandomSearch::new(&ship(), &Limits::default(), RandomConfig::like(&ga_config), seed).unwrap());
        a.step(&objective);
        b.step(&objective);
        assert_ne!(a.population(), b.population(), "seeds 1 and 2 draw the same genomes");
    }
}
