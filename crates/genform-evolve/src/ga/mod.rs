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
//! member or an earlier child (`avoid_duplicates`). Once the best has not
//! improved for `restart_after` generations, the default GA restarts: a
//! new epoch from fresh individuals, the best seen kept (see `epoch`). The
//! thesis preset turns all three off. Evaluate only the new children,
//! tallying which operators beat their parents. Pairs and evaluations run on the current
//! rayon pool and are collected in index order, so a seed gives the same
//! populations and statistics at any thread count.

mod adapt;
mod duplicates;
mod epoch;
mod reproduce;
mod rescore;
#[cfg(test)]
mod tests;

use crate::config::{ConfigError, GaConfig, Initialization};
use crate::evaluate::{Child, evaluate};
use crate::objective::Objective;
use crate::operators::{MutationMix, initial, reference_initial};
use crate::optimizer::{Individual, Optimizer, sort_population};
use crate::population::{Population, breed};
use crate::selection::Selector;
use crate::stats::{GenerationStats, ReproductionCounts};
use adapt::Rates;
use duplicates::{distinct, handle_duplicates, tally};
use epoch::Epoch;
use genform_core::{GeneratorGraph, Genome, Limits, Rng};
use rayon::prelude::*;
use reproduce::{Context, reproduce_pair};

pub use duplicates::DEDUP_STREAM;
use std::time::Instant;

/// Stream id of the initial individuals: `(seed, INIT_STREAM, index)`.
pub const INIT_STREAM: u64 = 0x4741_494e_4954; // "GAINIT"
/// Stream id of reproduction: `(seed, PAIR_STREAM, generation, pair)`.
pub const PAIR_STREAM: u64 = 0x4741_5041_4952; // "GAPAIR"
/// Stream id of restarted individuals: `(seed, RESTART_STREAM, restart, index)`.
pub const RESTART_STREAM: u64 = 0x4741_5253_5452; // "GARSTR"

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
    /// The current epoch's phase and stall counts.
    epoch: Epoch,
    /// Restarts so far.
    restarts: usize,
    /// The best member of each finished epoch, in order.
    champions: Vec<Individual>,
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
        let epoch = Epoch::start(&config, f64::NEG_INFINITY);
        let state = Population::with_room(config.population, "population")?;
        Ok(Ga { graph: graph.clone(), limits, config, seed, state, rates, epoch, restarts: 0, champions: Vec::new() })
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
        ga.epoch = Epoch::start(&ga.config, ga.epoch_top());
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

    /// Restarts so far (see [`GaConfig::restart_after`]).
    pub fn restarts(&self) -> usize {
        self.restarts
    }

    /// The best member of each epoch that ended in a restart, oldest first:
    /// usually different structures (the current population holds only the
    /// current epoch's; [`Ga::best`] is the best of all).
    pub fn champions(&self) -> &[Individual] {
        &self.champions
    }

    /// The maker of generation-0 genomes for the configured initialization.
    fn maker(&self) -> fn(&GeneratorGraph, &Limits, [usize; 2], &mut Rng) -> Genome {
        match self.config.initialization {
            Initialization::Grammar => initial,
            Initialization::Reference => reference_initial,
        }
    }

    /// Back to the state of a new run for the phase and rate bookkeeping.
    fn reset_epoch(&mut self) {
        self.rates = Rates::new(self.config.mutation_rate, self.config.mutation, self.config.adapt_rates);
        self.epoch = Epoch::start(&self.config, self.epoch_top());
    }

    /// The best valid fitness in the current population.
    fn epoch_top(&self) -> f64 {
        self.state.members().first().filter(|i| i.is_valid()).map_or(f64::NEG_INFINITY, |i| i.fitness)
    }

    /// A restart: the `restart_keep` best members stay, the rest is new
    /// generation-0 individuals from stream `(seed, RESTART_STREAM,
    /// restart, i)`. The best seen so far is kept by the population either
    /// way.
    fn restart<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        let started = Instant::now();
        self.restarts += 1;
        self.champions.extend(self.state.members().first().filter(|i| i.is_valid()).cloned());
        let (graph, limits, length, seed) = (&self.graph, &self.limits, self.config.initial_length, self.seed);
        let (make, restart) = (self.maker(), self.restarts as u64);
        let keep = self.config.restart_keep;
        let fresh: Vec<Child> = (0..self.config.population - keep)
            .into_par_iter()
            .map(|i| Child {
                genome: make(graph, limits, length, &mut Rng::stream(seed, &[RESTART_STREAM, restart, i as u64])),
                fitness: None,
            })
            .collect();
        let stats = self.state.advance(objective, keep, fresh, ReproductionCounts::default(), started);
        self.reset_epoch();
        GenerationStats { distinct: Some(distinct(self.state.members())), ..stats }
    }

    /// Builds and evaluates generation 0 (discarding any population):
    /// individual `i` is [`initial`] (or [`reference_initial`]) from stream
    /// `(seed, INIT_STREAM, i)`.
    pub fn initialize<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        let make = self.maker();
        let (graph, limits, length, seed) = (&self.graph, &self.limits, self.config.initial_length, self.seed);
        let stats = self.state.initialize(objective, self.config.population, |i| {
            make(graph, limits, length, &mut Rng::stream(seed, &[INIT_STREAM, i as u64]))
        });
        self.restarts = 0;
        self.champions.clear();
        self.reset_epoch();
        GenerationStats { distinct: Some(distinct(self.state.members())), ..stats }
    }

    /// Makes the next generation; initializes first if there is no population.
    pub fn step<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        if self.state.is_empty() {
            return self.initialize(objective);
        }
        if self.epoch.restart_due(&self.config) {
            return self.restart(objective);
        }
        let started = Instant::now();
        let generation = self.state.generation() + 1;
        let fitness = self.state.fitness();
        let held = MutationMix { drift: 0.0, ..self.rates.mix };
        let mix = if self.epoch.tuning || !held.is_valid() { &self.rates.mix } else { &held };
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
        let (tagged, mut counts) = breed(self.config.population - self.config.elites(), |pair, need| {
            reproduce_pair(&ctx, need, &mut Rng::stream(seed, &[PAIR_STREAM, generation as u64, pair as u64]))
        });
        let (mut children, mut origins): (Vec<Child>, Vec<_>) =
            tagged.into_iter().map(|c| (Child { genome: c.genome.0, fitness: c.fitness }, c.genome.1)).unzip();
        let replace = self.config.avoid_duplicates && self.epoch.tuning;
        handle_duplicates(&ctx, &mut children, &mut origins, &mut counts, replace, (seed, generation as u64));
        let reproduction_time = started.elapsed();
        let fresh: Vec<bool> = children.iter().map(|c| c.fitness.is_none()).collect();
        let (evaluations, eval_time) = evaluate(objective, &mut children);
        tally(&children, &origins, &fresh, &mut counts.operators);
        self.state.count_evaluations(evaluations);
        self.rates.update(&counts.operators);
        let stats = self.state.advance(objective, self.config.elites(), children, counts, started);
        let top = self.epoch_top();
        self.epoch.observe(&self.config, top);
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

    fn champions(&self) -> &[Individual] {
        Ga::champions(self)
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
