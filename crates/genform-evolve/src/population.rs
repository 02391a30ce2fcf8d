//! The population a generational optimizer keeps (GA, GE and both random
//! searches) and the steps that renew it. The optimizers differ only in
//! how they make new genomes; making them in parallel, evaluating, sorting
//! and tracking the best is this module's.
//!
//! New genomes are made in parallel but collected in index order,
//! evaluations land in their own slots and sorting is stable, so a seed
//! gives the same populations and statistics at any thread count.

use crate::config::{ConfigError, room};
use crate::evaluate::{Child, evaluate};
use crate::objective::Objective;
use crate::optimizer::{Genotype, Individual, sort_population, update_best};
use crate::rescore::rescore_population;
use crate::stats::{GenerationStats, ReproductionCounts};
use rayon::prelude::*;
use std::time::Instant;

/// What one pair of parents contributed to the next generation.
pub(crate) struct PairOutput<G> {
    pub children: Vec<Child<G>>,
    pub counts: ReproductionCounts,
}

/// A population sorted best first, with the generation index, the
/// evaluations so far and the best valid individual seen.
#[derive(Clone, Debug)]
pub(crate) struct Population<G> {
    members: Vec<Individual<G>>,
    generation: usize,
    evaluations: u64,
    best: Option<Individual<G>>,
}

impl<G> Default for Population<G> {
    fn default() -> Self {
        Population { members: Vec::new(), generation: 0, evaluations: 0, best: None }
    }
}

impl<G> Population<G> {
    /// An empty population with room for `count` members, allocated
    /// fallibly (see [`room`]) and kept across [`Population::initialize`].
    pub fn with_room(count: usize, key: &'static str) -> Result<Self, ConfigError> {
        Ok(Population { members: room(count, key, "population")?, ..Population::default() })
    }
}

impl<G: Genotype + Clone + Send + Sync> Population<G> {
    /// Generation 0 made of `members` with the fitness they carry (nothing
    /// is evaluated).
    pub fn seeded(mut members: Vec<Individual<G>>) -> Self {
        sort_population(&mut members);
        let mut population = Population { members, ..Population::default() };
        update_best(&mut population.best, &population.members);
        population
    }

    /// The members, best first.
    pub fn members(&self) -> &[Individual<G>] {
        &self.members
    }

    /// The best valid individual seen so far.
    pub fn best(&self) -> Option<&Individual<G>> {
        self.best.as_ref()
    }

    /// Index of the current generation (0 = the initial one).
    pub fn generation(&self) -> usize {
        self.generation
    }

    /// Objective evaluations so far.
    pub fn evaluations(&self) -> u64 {
        self.evaluations
    }

    /// Adds `n` evaluations the caller made itself (children it evaluated
    /// before [`Population::advance`], e.g. to measure operator success).
    pub fn count_evaluations(&mut self, n: u64) {
        self.evaluations += n;
    }

    /// Whether there is no generation yet.
    pub fn is_empty(&self) -> bool {
        self.members.is_empty()
    }

    /// The members' fitness values, best first (what selectors read).
    pub fn fitness(&self) -> Vec<f64> {
        self.members.iter().map(|i| i.fitness).collect()
    }

    /// Index of the generation [`Population::keep_best`] makes next: 0 on
    /// an empty population.
    pub fn next_generation(&self) -> usize {
        if self.is_empty() { 0 } else { self.generation + 1 }
    }

    /// Starts over: generation 0 is genomes `make(i)` for `i` in `0..count`,
    /// evaluated and sorted.
    pub fn initialize<O: Objective<G>>(
        &mut self,
        objective: &O,
        count: usize,
        make: impl Fn(usize) -> G + Sync + Send,
    ) -> GenerationStats {
        let started = Instant::now();
        let children = sample(count, make);
        // Starts over in the room already allocated (see `with_room`).
        let mut members = std::mem::take(&mut self.members);
        members.clear();
        *self = Population { members, ..Population::default() };
        // Nothing to drop: the population is exactly the children.
        self.absorb(objective, children, 0, usize::MAX, started, ReproductionCounts::default())
    }

    /// The next generation of an elitist EA: the `elitism` best stay with
    /// their cached fitness, `children` (made since `started`, with
    /// `counts`) fill the rest.
    pub fn advance<O: Objective<G>>(
        &mut self,
        objective: &O,
        elitism: usize,
        children: Vec<Child<G>>,
        counts: ReproductionCounts,
        started: Instant,
    ) -> GenerationStats {
        self.members.truncate(elitism);
        let generation = self.generation + 1;
        self.absorb(objective, children, generation, usize::MAX, started, counts)
    }

    /// One round of random search: samples `make(i)` for `i` in
    /// `0..count` as generation [`Population::next_generation`] and keeps
    /// the best `count` individuals seen so far.
    pub fn keep_best<O: Objective<G>>(
        &mut self,
        objective: &O,
        count: usize,
        make: impl Fn(usize) -> G + Sync + Send,
    ) -> GenerationStats {
        let generation = self.next_generation();
        let started = Instant::now();
        let batch = sample(count, make);
        self.absorb(objective, batch, generation, count, started, ReproductionCounts::default())
    }

    /// Evaluates `children`, adds them, sorts best first, keeps the first
    /// `keep`, updates the best and summarizes `generation`.
    fn absorb<O: Objective<G>>(
        &mut self,
        objective: &O,
        mut children: Vec<Child<G>>,
        generation: usize,
        keep: usize,
        started: Instant,
        reproduction: ReproductionCounts,
    ) -> GenerationStats {
        let reproduction_time = started.elapsed();
        let (evaluations, eval_time) = evaluate(objective, &mut children);
        self.members.extend(
            children
                .into_iter()
                .map(|c| Individual { genome: c.genome, fitness: c.fitness.expect("every child is evaluated") }),
        );
        sort_population(&mut self.members);
        self.members.truncate(keep);
        update_best(&mut self.best, &self.members);
        self.generation = generation;
        self.evaluations += evaluations;
        GenerationStats {
            evaluations,
            total_evaluations: self.evaluations,
            eval_time,
            reproduction_time,
            reproduction,
            ..GenerationStats::summarize(generation, &self.members)
        }
    }
}

impl<G: Genotype + Clone + PartialEq + Send + Sync> Population<G> {
    /// Re-evaluates every member under `objective` (see
    /// [`Rescore`](crate::rescore::Rescore)), re-sorts, and makes the best
    /// the better of the re-scored old best and the new first member;
    /// returns the evaluations made (counted).
    pub fn rescore<O: Objective<G>>(&mut self, objective: &O) -> u64 {
        rescore_population(objective, &mut self.members, &mut self.best, &mut self.evaluations)
    }

    /// Makes the best valid of `candidates` (already scored under the
    /// current objective) the best so far when it is strictly better.
    pub fn consider_best(&mut self, candidates: &[Individual<G>]) {
        let top = candidates.iter().filter(|c| c.is_valid()).reduce(|a, b| if b.fitness > a.fitness { b } else { a });
        update_best(&mut self.best, top.map(std::slice::from_ref).unwrap_or_default());
    }
}

/// Genomes `make(i)` for `i` in `0..count`, made in parallel, in index
/// order, not yet evaluated.
fn sample<G: Send>(count: usize, make: impl Fn(usize) -> G + Sync + Send) -> Vec<Child<G>> {
    (0..count).into_par_iter().map(|i| Child { genome: make(i), fitness: None }).collect()
}

/// `wanted` children made pair by pair in parallel: pair `p` makes
/// `reproduce(p, need)` with `need` 2, or 1 for the last pair of an odd
/// count. Children and counts are collected in pair order.
pub(crate) fn breed<G: Send>(
    wanted: usize,
    reproduce: impl Fn(usize, usize) -> PairOutput<G> + Sync + Send,
) -> (Vec<Child<G>>, ReproductionCounts) {
    let outputs: Vec<PairOutput<G>> =
        (0..wanted.div_ceil(2)).into_par_iter().map(|pair| reproduce(pair, (wanted - 2 * pair).min(2))).collect();
    let mut counts = ReproductionCounts::default();
    let mut children = Vec::with_capacity(wanted);
    for out in outputs {
        counts += out.counts;
        children.extend(out.children);
    }
    (children, counts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_population_past_the_machine_is_an_error_not_an_abort() {
        let e = Population::<Vec<u32>>::with_room(usize::MAX / 8, "population").unwrap_err();
        let ConfigError::Allocation { key, what, count, bytes } = e.clone() else { panic!("{e:?}") };
        assert_eq!((key, what, count), ("population", "population", (usize::MAX / 8) as u128));
        assert_eq!(bytes, count * std::mem::size_of::<Individual<Vec<u32>>>() as u128);
        assert_eq!(e.key(), "population");
        assert!(e.to_string().starts_with("cannot allocate ") && e.to_string().ends_with("; lower `population`"));
        // A size the machine has is room kept for generation 0.
        let room = Population::<Vec<u32>>::with_room(1000, "population").unwrap();
        assert!(room.is_empty() && room.members.capacity() >= 1000);
    }

    #[test]
    fn breed_collects_pairs_in_order_and_the_odd_last_pair_makes_one() {
        // Each child records its pair and how many the pair was asked for.
        let reproduce = |pair: usize, need: usize| PairOutput {
            children: (0..need).map(|_| Child { genome: vec![pair as u32, need as u32], fitness: None }).collect(),
            counts: ReproductionCounts { crossovers: 1, copies: need as u64, ..ReproductionCounts::default() },
        };
        let pool = rayon::ThreadPoolBuilder::new().num_threads(4).build().unwrap();
        let (children, counts) = pool.install(|| breed(5, reproduce));
        let genomes: Vec<Vec<u32>> = children.into_iter().map(|c| c.genome).collect();
        assert_eq!(genomes, [[0, 2], [0, 2], [1, 2], [1, 2], [2, 1]]);
        assert_eq!((counts.crossovers, counts.copies), (3, 5));
    }
}
