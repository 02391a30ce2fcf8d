//! What every optimizer shares: individuals and the [`Optimizer`] trait,
//! both generic over the genome type (default: the derivation-tree
//! [`Genome`]; grammatical evolution uses [`Codons`](crate::ge::Codons)).

pub use crate::individual::{Genotype, Individual};

use crate::objective::Objective;
use crate::selection::rank;
use crate::stats::GenerationStats;
use genform_core::{Genome, Limits};

/// Sorts best first, stably: ties (and all invalid individuals) keep their
/// order, so the result depends only on the input order.
pub fn sort_population<G>(population: &mut [Individual<G>]) {
    population.sort_by(|a, b| rank(a.fitness, b.fitness));
}

/// A population-based search over genomes of type `G`, driven one
/// generation at a time (GA, random search; MH, SMC and SOSMC follow the
/// same shape; [`Ge`](crate::ge::Ge) and [`CodonRandom`](crate::ge::CodonRandom)
/// search codon strings).
///
/// The generic [`Optimizer::step`] is left out of the vtable, so drivers can
/// hand `&dyn Optimizer` to callbacks that only read the state. Drivers
/// whose objective changes mid-run also need
/// [`Rescore`](crate::rescore::Rescore).
pub trait Optimizer<G = Genome> {
    /// Runs one generation; the first call builds and evaluates generation 0.
    fn step<O: Objective<G>>(&mut self, objective: &O) -> GenerationStats
    where
        Self: Sized;

    /// The current population, best first.
    fn population(&self) -> &[Individual<G>];

    /// Earlier answers the current population no longer holds (the GA's
    /// best of each epoch that ended in a restart); empty by default.
    fn champions(&self) -> &[Individual<G>] {
        &[]
    }

    /// The best valid individual seen so far; `None` before the first
    /// generation or while none was valid.
    fn best(&self) -> Option<&Individual<G>>;

    /// Index of the current generation (0 = the initial one).
    fn generation(&self) -> usize;

    /// Objective evaluations so far.
    fn evaluations(&self) -> u64;

    /// Whether generation 0 exists.
    fn is_initialized(&self) -> bool {
        !self.population().is_empty()
    }
}

/// Replaces `best` with the first valid individual of a sorted population
/// when it is better.
pub(crate) fn update_best<G: Clone>(best: &mut Option<Individual<G>>, sorted: &[Individual<G>]) {
    if let Some(top) = sorted.first().filter(|i| i.is_valid())
        && best.as_ref().is_none_or(|b| top.fitness > b.fitness)
    {
        *best = Some(top.clone());
    }
}

/// `limits` with the gene limit lowered below the exclusive length bound
/// `max_length`, so growth never makes a genome the bound would drop.
pub(crate) fn length_capped(limits: &Limits, max_length: usize) -> Limits {
    Limits { max_genes: limits.max_genes.min(max_length - 1), ..*limits }
}
