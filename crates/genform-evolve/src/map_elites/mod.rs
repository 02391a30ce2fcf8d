//! MAP-Elites (Mouret & Clune 2015): quality-diversity search that keeps,
//! instead of one converging population, the best individual found in each
//! cell of a grid over two behaviour descriptors (e.g. genome length ×
//! bounding-box aspect).
//!
//! Generation 0 is `initial` random individuals made as the GA's
//! (individual `i` from stream `(seed, INIT_STREAM, i)`). Every later
//! generation makes `batch` children, child `i` from its own stream
//! `(seed, CHILD_STREAM, generation, i)`: with probability `crossover` one
//! child of a crossover between two uniformly chosen elites, otherwise a
//! mutation of one; children outside the GA's length bounds are retried,
//! and after five failures the slot stays empty (nothing new to evaluate).
//! Children are made and evaluated (with their descriptors, by
//! [`Objective::evaluate_described`]) in parallel, then inserted in index
//! order: a child takes its cell when the cell is empty or the child is
//! strictly better. So a seed gives the same archive at any thread count.
//!
//! Descriptors come from the objective because they usually need the
//! derived model; the optimizer only bins the two numbers it is given.

mod config;
#[cfg(test)]
mod tests;

pub use config::{DescriptorAxis, MAX_BATCH, MAX_BINS, MapElitesConfig};

use crate::config::{ConfigError, GaConfig, room};
use crate::objective::Objective;
use crate::operators::{crossover, initial, mutate};
use crate::optimizer::{Individual, Optimizer, sort_population};
use crate::rescore::{Rescore, reevaluate, rescored_best};
use crate::selection::Selector;
use crate::stats::{GenerationStats, ReproductionCounts};
use genform_core::{GeneratorGraph, Genome, Limits, Rng};
use rayon::prelude::*;
use std::time::Instant;

/// Stream id of the initial individuals: `(seed, INIT_STREAM, index)`.
pub const INIT_STREAM: u64 = 0x4d45_494e_4954; // "MEINIT"
/// Stream id of children: `(seed, CHILD_STREAM, generation, index)`.
pub const CHILD_STREAM: u64 = 0x4d45_4348_4c44; // "MECHLD"

/// Tries per child (each picks new parents) before its slot is left empty.
const ATTEMPTS: usize = 5;

/// The occupant of one archive cell.
#[derive(Clone, Debug, PartialEq)]
pub struct Elite {
    /// The individual.
    pub individual: Individual,
    /// Its descriptor values, as the objective returned them.
    pub descriptors: [f64; 2],
    /// Its cell `[column, row]`: bins along the first and second descriptor.
    pub cell: [usize; 2],
}

/// MAP-Elites over one generator graph.
#[derive(Clone, Debug)]
pub struct MapElites {
    graph: GeneratorGraph,
    /// The caller's limits with `max_genes` below the GA's `max_length`.
    limits: Limits,
    /// Lengths and operators.
    variation: GaConfig,
    config: MapElitesConfig,
    seed: u64,
    /// Cell `[c, r]` at `c * rows + r`.
    cells: Vec<Option<Elite>>,
    /// Indices of the filled cells, ascending: what parents are drawn from.
    filled: Vec<usize>,
    /// The elites, best first (ties by cell index).
    population: Vec<Individual>,
    best: Option<Individual>,
    generation: usize,
    evaluations: u64,
    initialized: bool,
}

/// A new genome with what evaluating it gave.
struct Candidate {
    genome: Genome,
    fitness: f64,
    descriptors: [f64; 2],
}

/// The empty archive of `cols` × `rows` cells, allocated fallibly (a grid
/// of bins past the machine is an error, not an abort).
fn archive(cols: usize, rows: usize) -> Result<Vec<Option<Elite>>, ConfigError> {
    let Some(n) = cols.checked_mul(rows) else {
        let count = cols as u128 * rows as u128;
        let bytes = count * std::mem::size_of::<Option<Elite>>() as u128;
        return Err(ConfigError::Allocation { key: "descriptors", what: "archive", count, bytes });
    };
    let mut cells = room(n, "descriptors", "archive")?;
    cells.resize(n, None);
    Ok(cells)
}

impl MapElites {
    /// An empty archive. Genome lengths and operators come from `variation`
    /// (the GA's settings: `initial_length`, `min_length`, `max_length`,
    /// `mutation`, `crossover_retries`); every descriptor needs a range.
    pub fn new(
        graph: &GeneratorGraph,
        limits: &Limits,
        variation: &GaConfig,
        config: MapElitesConfig,
        seed: u64,
    ) -> Result<Self, ConfigError> {
        variation.validate()?;
        config.validate_ranges()?;
        let limits = crate::optimizer::length_capped(limits, variation.max_length);
        let [cols, rows] = config.shape();
        let cells = archive(cols, rows)?;
        Ok(MapElites {
            graph: graph.clone(),
            limits,
            variation: variation.clone(),
            config,
            seed,
            cells,
            filled: Vec::new(),
            population: Vec::new(),
            best: None,
            generation: 0,
            evaluations: 0,
            initialized: false,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &MapElitesConfig {
        &self.config
    }

    /// The filled cells' elites in cell order (column by column).
    pub fn elites(&self) -> impl Iterator<Item = &Elite> {
        self.filled.iter().map(|&i| self.cells[i].as_ref().expect("filled cell"))
    }

    /// How many cells hold an elite.
    pub fn filled(&self) -> usize {
        self.filled.len()
    }

    /// Cells in all (`bins` × `bins`).
    pub fn capacity(&self) -> usize {
        self.cells.len()
    }

    /// Runs one generation; the first call makes and evaluates generation 0.
    pub fn step<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        let started = Instant::now();
        let (genomes, counts) = if self.initialized {
            self.generation += 1;
            self.children()
        } else {
            self.initialized = true;
            (self.initial_genomes(), ReproductionCounts::default())
        };
        let reproduction_time = started.elapsed();
        let eval_started = Instant::now();
        let candidates = evaluate(objective, genomes);
        let eval_time = eval_started.elapsed();
        let evaluations = candidates.len() as u64;
        self.evaluations += evaluations;
        for c in candidates {
            self.insert(c);
        }
        self.population = self.elites().map(|e| e.individual.clone()).collect();
        sort_population(&mut self.population);
        crate::optimizer::update_best(&mut self.best, &self.population);
        GenerationStats {
            evaluations,
            total_evaluations: self.evaluations,
            eval_time,
            reproduction_time,
            reproduction: counts,
            ..GenerationStats::of_population(self.generation, &self.population)
        }
    }

    fn initial_genomes(&self) -> Vec<Genome> {
        let (graph, limits, length, seed) = (&self.graph, &self.limits, self.variation.initial_length, self.seed);
        (0..self.config.initial)
            .into_par_iter()
            .map(|i| initial(graph, limits, length, &mut Rng::stream(seed, &[INIT_STREAM, i as u64])))
            .collect()
    }

    /// This generation's children, in index order; slots whose every try
    /// failed are left out (and counted as copies).
    fn children(&self) -> (Vec<Genome>, ReproductionCounts) {
        if self.filled.is_empty() {
            // Nothing valid yet to vary: sample afresh, as generation 0 did.
            let (graph, limits, length, seed, g) =
                (&self.graph, &self.limits, self.variation.initial_length, self.seed, self.generation as u64);
            let fresh = (0..self.config.batch)
                .into_par_iter()
                .map(|i| initial(graph, limits, length, &mut Rng::stream(seed, &[CHILD_STREAM, g, i as u64])))
                .collect();
            return (fresh, ReproductionCounts::default());
        }
        let fitness: Vec<f64> = self.elites().map(|e| e.individual.fitness).collect();
        let selector = Selector::new(self.config.selection, &fitness);
        let outputs: Vec<(Option<Genome>, ReproductionCounts)> = (0..self.config.batch)
            .into_par_iter()
            .map(|i| {
                let mut rng = Rng::stream(self.seed, &[CHILD_STREAM, self.generation as u64, i as u64]);
                self.child(&selector, &mut rng)
            })
            .collect();
        let mut counts = ReproductionCounts::default();
        let mut genomes = Vec::with_capacity(outputs.len());
        for (genome, c) in outputs {
            counts += c;
            genomes.extend(genome);
        }
        (genomes, counts)
    }

    /// One child of elites drawn by `selector` (over the filled cells in
    /// order), or `None` after [`ATTEMPTS`] failures.
    fn child(&self, selector: &Selector, rng: &mut Rng) -> (Option<Genome>, ReproductionCounts) {
        let mut counts = ReproductionCounts::default();
        let bounds = self.variation.length_bounds();
        let pick = |rng: &mut Rng| &self.elite_at(self.filled[selector.select(rng)]).individual.genome;
        for _ in 0..ATTEMPTS {
            if rng.bernoulli(self.config.crossover) {
                let parents = [pick(rng), pick(rng)];
                let tries = self.variation.crossover_retries;
                let out = crossover(parents, &self.graph, &self.limits, &bounds, tries, rng);
                counts.crossover_retries += out.retries as u64;
                match out.crossed {
                    Some(crossed) => {
                        counts.crossovers += 1;
                        let [a, b] = crossed.children;
                        return (Some(if rng.bernoulli(0.5) { a } else { b }), counts);
                    }
                    None => counts.crossover_failures += 1,
                }
            } else {
                let mut genome = pick(rng).clone();
                if let Some(kind) = mutate(&mut genome, &self.graph, &self.limits, &self.variation.mutation, rng) {
                    if bounds.contains(genome.len()) {
                        counts.mutations.add(kind);
                        return (Some(genome), counts);
                    }
                    counts.rejected += 1;
                }
            }
        }
        counts.copies += 1;
        (None, counts)
    }

    fn elite_at(&self, index: usize) -> &Elite {
        self.cells[index].as_ref().expect("filled cell")
    }

    /// Files `c` in its cell when the cell is empty or `c` is strictly
    /// better; invalid candidates are dropped.
    fn insert(&mut self, c: Candidate) {
        if !c.fitness.is_finite() {
            return;
        }
        let cell = self.config.cell(c.descriptors);
        let index = cell[0] * self.config.descriptors[1].bins + cell[1];
        let slot = &mut self.cells[index];
        match slot {
            Some(e) if e.individual.fitness >= c.fitness => {}
            _ => {
                if slot.is_none() {
                    let at = self.filled.partition_point(|&i| i < index);
                    self.filled.insert(at, index);
                }
                let individual = Individual { genome: c.genome, fitness: c.fitness };
                *slot = Some(Elite { individual, descriptors: c.descriptors, cell });
            }
        }
    }
}

impl Rescore for MapElites {
    /// Re-scores every cell's elite, then the population and the best. A
    /// cell keeps its elite (descriptors do not depend on the weights),
    /// unless the elite is now invalid: invalid individuals are never
    /// filed, so its cell is emptied.
    fn rescore<O: Objective>(&mut self, objective: &O) -> u64 {
        if !self.initialized {
            return 0;
        }
        let mut elites: Vec<Individual> = self.elites().map(|e| e.individual.clone()).collect();
        let mut evaluations = reevaluate(objective, &mut elites);
        let cells = &mut self.cells;
        for (&index, rescored) in self.filled.iter().zip(&elites) {
            cells[index].as_mut().expect("filled cell").individual.fitness = rescored.fitness;
        }
        self.filled.retain(|&index| {
            let valid = cells[index].as_ref().is_some_and(|e| e.individual.is_valid());
            if !valid {
                cells[index] = None;
            }
            valid
        });
        self.population = self.elites().map(|e| e.individual.clone()).collect();
        sort_population(&mut self.population);
        let (best, more) = rescored_best(objective, self.best.take(), &self.population);
        self.best = best;
        evaluations += more;
        self.evaluations += evaluations;
        evaluations
    }
}

/// Evaluates `genomes` with their descriptors on the current rayon pool,
/// one scratch per worker task; results stay in index order.
fn evaluate<O: Objective>(objective: &O, genomes: Vec<Genome>) -> Vec<Candidate> {
    genomes
        .into_par_iter()
        .map_init(
            || objective.scratch(),
            |scratch, genome| {
                let mut descriptors = [f64::NAN; 2];
                let fitness = objective.evaluate_described(&genome, scratch, &mut descriptors);
                Candidate { genome, fitness, descriptors }
            },
        )
        .collect()
}

impl Optimizer for MapElites {
    fn step<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        MapElites::step(self, objective)
    }

    /// The elites, best first.
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

    fn is_initialized(&self) -> bool {
        self.initialized
    }
}
