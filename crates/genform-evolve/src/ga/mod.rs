//! The ShapeGenetics genetic algorithm (paper §3.1, reference §1.3).
//!
//! Generation loop: sort best first; copy the `elitism` best with their
//! cached fitness (the reference re-evaluated them every generation); fill
//! the rest pair by pair, each pair from its own random stream
//! `(seed, PAIR_STREAM, generation, pair)`: select two parents; with
//! probability `mutation_rate` mutate a copy of each, otherwise cross them
//! over; keep children within the length bounds, retrying with new parents
//! up to five times and then copying the parents. Once the best has not
//! improved for `tune_after` generations, the default GA adds a drift
//! mutation (`mutation.drift`) and replaces children that duplicate a
//! member or an earlier child (`avoid_duplicates`); the thesis preset
//! turns both off. Evaluate only the new children, tallying which
//! operators beat their parents. Pairs and evaluations run on the current
//! rayon pool and are collected in index order, so a seed gives the same
//! populations and statistics at any thread count.

mod adapt;
mod duplicates;
mod reproduce;
#[cfg(test)]
mod tests;

use crate::config::{ConfigError, GaConfig, Initialization};
use crate::evaluate::{Child, evaluate};
use crate::objective::Objective;
use crate::operators::{MutationMix, initial, reference_initial};
use crate::optimizer::{Individual, Optimizer, sort_population};
use crate::population::{Population, breed};
use crate::selection::Selector;
use crate::stats::GenerationStats;
use adapt::Rates;
use duplicates::{distinct, handle_duplicates, tally};
use genform_core::{GeneratorGraph, Genome, Limits, Rng};
use reproduce::{Context, reproduce_pair};

pub use duplicates::DEDUP_STREAM;
use std::time::Instant;

/// Stream id of the initial individuals: `(seed, INIT_STREAM, index)`.
pub const INIT_STREAM: u64 = 0x4741_494e_4954; // "GAINIT"
/// Stream id of reproduction: `(seed, PAIR_STREAM, generation, pair)`.
pub const PAIR_STREAM: u64 = 0x4741_5041_4952; // "GAPAIR"

/// The genetic algorithm over one generator graph.
#[derive(Clone, Debug)]
pub struct Ga {
    graph: GeneratorGraph,
    /// The caller's limits with `max_genes` below `max_length`, so growth
    /// never produces a child the length bound would drop.
    limits: Limits,
    config: GaConfig,
    seed: u64,
    state: Population<Genome>,
    rates: Rates,
    /// Generations since the best improved.
    stagnant: usize,
    /// Whether the tuning phase (drift, duplicate avoidance) has started
    /// (see [`GaConfig::tune_after`]).
    tuning: bool,
}

impl Ga {
    /// A GA with no population yet (see [`Ga::initialize`]). The graph must
    /// pass [`GeneratorGraph::check`] (compiled grammars do). The GA runs
    /// with [`GaConfig::effective`] (the preset applied).
    pub fn new(graph: &GeneratorGraph, limits: &Limits, config: GaConfig, seed: u64) -> Result<Self, ConfigError> {
        config.validate()?;
        let config = config.effective();
        let limits = crate::optimizer::length_capped(limits, config.max_length);
        let rates = Rates::new(config.mutation_rate, config.mutation, config.adapt_rates);
        let tuning = config.tune_after == 0;
        Ok(Ga { graph: graph.clone(), limits, config, seed, state: Population::default(), rates, stagnant: 0, tuning })
    }

    /// A GA whose generation 0 is `individuals` (with the fitness they
    /// carry), e.g. the particles of an SMC run: the best
    /// `config.population` are kept, repeated in order when there are
    /// fewer. Individuals outside the length bounds are dropped; an error
    /// when none is left.
    pub fn from_population(
        graph: &GeneratorGraph,
        limits: &Limits,
        config: GaConfig,
        seed: u64,
        mut individuals: Vec<Individual>,
    ) -> Result<Self, ConfigError> {
        let mut ga = Ga::new(graph, limits, config, seed)?;
        let bounds = ga.config.length_bounds();
        individuals.retain(|i| bounds.contains(i.genome.len()));
        if individuals.is_empty() {
            return Err(ConfigError::Population(0));
        }
        sort_population(&mut individuals);
        let n = ga.config.population;
        ga.state = Population::seeded(individuals.iter().cycle().take(n).cloned().collect());
        Ok(ga)
    }

    /// The configuration.
    pub fn config(&self) -> &GaConfig {
        &self.config
    }

    /// The limits operators work under (`max_genes` capped below `max_length`).
    pub fn limits(&self) -> &Limits {
        &self.limits
    }

    /// The current population, best first.
    pub fn population(&self) -> &[Individual] {
        self.state.members()
    }

    /// The best valid individual seen so far (with elitism, the population's first).
    pub fn best(&self) -> Option<&Individual> {
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
    /// individual `i` is [`initial`] (or [`reference_initial`]) from stream
    /// `(seed, INIT_STREAM, i)`.
    pub fn initialize<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        let (graph, limits, length, seed) = (&self.graph, &self.limits, self.config.initial_length, self.seed);
        let make = match self.config.initialization {
            Initialization::Grammar => initial,
            Initialization::Reference => reference_initial,
        };
        self.rates = Rates::new(self.config.mutation_rate, self.config.mutation, self.config.adapt_rates);
        (self.stagnant, self.tuning) = (0, self.config.tune_after == 0);
        let stats = self.state.initialize(objective, self.config.population, |i| {
            make(graph, limits, length, &mut Rng::stream(seed, &[INIT_STREAM, i as u64]))
        });
        GenerationStats { distinct: Some(distinct(self.state.members())), ..stats }
    }

    /// Makes the next generation; initializes first if there is no population.
    pub fn step<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        if self.state.is_empty() {
            return self.initialize(objective);
        }
        let started = Instant::now();
        let generation = self.state.generation() + 1;
        let fitness = self.state.fitness();
        let held = MutationMix { drift: 0.0, ..self.rates.mix };
        let mix = if self.tuning || !held.is_valid() { &self.rates.mix } else { &held };
        let best_before = self.state.best().map(|b| b.fitness);
        let ctx = Context {
            graph: &self.graph,
            limits: &self.limits,
            bounds: self.config.length_bounds(),
            config: &self.config,
            mutation_rate: self.rates.mutation_rate,
            mix,
            population: self.state.members(),
            selectors: [
                Selector::new(self.config.selection.first, &fitness),
                Selector::new(self.config.selection.second, &fitness),
            ],
        };
        let seed = self.seed;
        let (tagged, mut counts) = breed(self.config.population - self.config.elitism, |pair, need| {
            reproduce_pair(&ctx, need, &mut Rng::stream(seed, &[PAIR_STREAM, generation as u64, pair as u64]))
        });
        let (mut children, mut origins): (Vec<Child>, Vec<_>) =
            tagged.into_iter().map(|c| (Child { genome: c.genome.0, fitness: c.fitness }, c.genome.1)).unzip();
        let replace = self.config.avoid_duplicates && self.tuning;
        handle_duplicates(&ctx, &mut children, &mut origins, &mut counts, replace, (seed, generation as u64));
        let reproduction_time = started.elapsed();
        let fresh: Vec<bool> = children.iter().map(|c| c.fitness.is_none()).collect();
        let (evaluations, eval_time) = evaluate(objective, &mut children);
        tally(&children, &origins, &fresh, &mut counts.operators);
        self.state.count_evaluations(evaluations);
        self.rates.update(&counts.operators);
        let stats = self.state.advance(objective, self.config.elitism, children, counts, started);
        let best_after = self.state.best().map(|b| b.fitness);
        let improved = match (best_before, best_after) {
            (Some(a), Some(b)) => b > a,
            (None, b) => b.is_some(),
            _ => false,
        };
        self.stagnant = if improved { 0 } else { self.stagnant + 1 };
        self.tuning |= self.stagnant >= self.config.tune_after;
        GenerationStats {
            evaluations,
            eval_time,
            reproduction_time,
            distinct: Some(distinct(self.state.members())),
            ..stats
        }
    }
}

impl Optimizer for Ga {
    fn step<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        Ga::step(self, objective)
    }

    fn population(&self) -> &[Individual] {
        Ga::population(self)
    }

    fn best(&self) -> Option<&Individual> {
        Ga::best(self)
    }

    fn generation(&self) -> usize {
        Ga::generation(self)
    }

    fn evaluations(&self) -> u64 {
        Ga::evaluations(self)
    }
}
