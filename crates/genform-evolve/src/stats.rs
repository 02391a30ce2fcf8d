//! Per-generation statistics (the reference's CSV columns and more).

use crate::individual::{Genotype, Individual};
use crate::operators::MutationKind;
use serde::Serialize;
use std::time::Duration;

/// Accepted children made by each mutation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct MutationCounts {
    /// By alter (parameters redrawn).
    pub alter: u64,
    /// By grow.
    pub grow: u64,
    /// By cut.
    pub cut: u64,
    /// By drift (parameters moved by a Gaussian step).
    pub drift: u64,
    /// By regrow (a subtree regrown from the prior).
    pub regrow: u64,
}

impl MutationCounts {
    /// Counts one child made by `kind`.
    pub fn add(&mut self, kind: MutationKind) {
        match kind {
            MutationKind::Alter => self.alter += 1,
            MutationKind::Grow => self.grow += 1,
            MutationKind::Cut => self.cut += 1,
            MutationKind::Drift => self.drift += 1,
            MutationKind::Regrow => self.regrow += 1,
        }
    }
}

/// How the evaluated children of one operator fared.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct OperatorTally {
    /// Children evaluated.
    pub children: u64,
    /// Of those, children fitter than their fitter parent.
    pub improved: u64,
}

impl std::ops::AddAssign for OperatorTally {
    fn add_assign(&mut self, o: Self) {
        self.children += o.children;
        self.improved += o.improved;
    }
}

/// Per-operator success of a GA generation: which operators make children
/// that beat their parents (the evidence for the operator weights).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct OperatorCounts {
    /// Crossover children (compared with the fitter parent).
    pub crossover: OperatorTally,
    /// Alter children.
    pub alter: OperatorTally,
    /// Grow children.
    pub grow: OperatorTally,
    /// Cut children.
    pub cut: OperatorTally,
    /// Drift children.
    pub drift: OperatorTally,
    /// Regrow children.
    pub regrow: OperatorTally,
}

impl OperatorCounts {
    /// The tally of mutation `kind`.
    pub fn mutation(&mut self, kind: MutationKind) -> &mut OperatorTally {
        match kind {
            MutationKind::Alter => &mut self.alter,
            MutationKind::Grow => &mut self.grow,
            MutationKind::Cut => &mut self.cut,
            MutationKind::Drift => &mut self.drift,
            MutationKind::Regrow => &mut self.regrow,
        }
    }
}

impl std::ops::AddAssign for OperatorCounts {
    fn add_assign(&mut self, o: Self) {
        self.crossover += o.crossover;
        self.alter += o.alter;
        self.grow += o.grow;
        self.cut += o.cut;
        self.drift += o.drift;
        self.regrow += o.regrow;
    }
}

/// How the children of one generation were made; all zero for optimizers
/// without these operators.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct ReproductionCounts {
    /// Successful crossovers (each makes two children).
    pub crossovers: u64,
    /// Failed crossover tries (the reference's "crossover retries").
    pub crossover_retries: u64,
    /// Crossovers that failed every try.
    pub crossover_failures: u64,
    /// Children made by mutation, per kind.
    pub mutations: MutationCounts,
    /// Mutated children dropped for leaving the length bounds.
    pub rejected: u64,
    /// Parents copied unchanged because reproduction kept failing.
    pub copies: u64,
    /// Children identical to a member of the parents' population or to an
    /// earlier child of the same generation, as first made (GA).
    pub duplicates: u64,
    /// Of those, children mutated again until new (duplicate avoidance);
    /// the rest were kept (and, unless copies, evaluated again).
    pub duplicates_replaced: u64,
    /// How each operator's evaluated children fared (GA).
    pub operators: OperatorCounts,
}

impl std::ops::AddAssign for ReproductionCounts {
    fn add_assign(&mut self, o: Self) {
        self.crossovers += o.crossovers;
        self.crossover_retries += o.crossover_retries;
        self.crossover_failures += o.crossover_failures;
        self.mutations.alter += o.mutations.alter;
        self.mutations.grow += o.mutations.grow;
        self.mutations.cut += o.mutations.cut;
        self.mutations.drift += o.mutations.drift;
        self.mutations.regrow += o.mutations.regrow;
        self.rejected += o.rejected;
        self.copies += o.copies;
        self.duplicates += o.duplicates;
        self.duplicates_replaced += o.duplicates_replaced;
        self.operators += o.operators;
    }
}

/// Proposals and acceptances of the MCMC moves in one generation; all
/// zero for other optimizers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct MoveCounts {
    /// Jump moves proposed.
    pub jumps_proposed: u64,
    /// Jump moves accepted at the first stage.
    pub jumps_accepted: u64,
    /// Second (delayed-rejection) jump stages tried.
    pub delayed_proposed: u64,
    /// Second stages accepted.
    pub delayed_accepted: u64,
    /// Diffusion moves proposed.
    pub diffusions_proposed: u64,
    /// Diffusion moves accepted.
    pub diffusions_accepted: u64,
    /// Parallel-tempering swaps proposed.
    pub swaps_proposed: u64,
    /// Swaps accepted.
    pub swaps_accepted: u64,
}

impl std::ops::AddAssign for MoveCounts {
    fn add_assign(&mut self, o: Self) {
        self.jumps_proposed += o.jumps_proposed;
        self.jumps_accepted += o.jumps_accepted;
        self.delayed_proposed += o.delayed_proposed;
        self.delayed_accepted += o.delayed_accepted;
        self.diffusions_proposed += o.diffusions_proposed;
        self.diffusions_accepted += o.diffusions_accepted;
        self.swaps_proposed += o.swaps_proposed;
        self.swaps_accepted += o.swaps_accepted;
    }
}

/// One generation, summarized. Every value except the two durations is a
/// pure function of (seed, configuration, objective): floats are reduced in
/// population order.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GenerationStats {
    /// Generation index (0 = the initial population).
    pub generation: usize,
    /// Best valid fitness in the population; NaN when none is valid.
    pub max: f64,
    /// Mean valid fitness; NaN when none is valid.
    pub avg: f64,
    /// Worst valid fitness; NaN when none is valid.
    pub min: f64,
    /// Individuals with a non-finite fitness.
    pub invalid: usize,
    /// Objective evaluations made in this generation.
    pub evaluations: u64,
    /// Objective evaluations so far.
    pub total_evaluations: u64,
    /// Wall time spent evaluating.
    pub eval_time: Duration,
    /// Wall time spent making children (or fresh individuals).
    pub reproduction_time: Duration,
    /// How children were made.
    pub reproduction: ReproductionCounts,
    /// MCMC moves made.
    pub moves: MoveCounts,
    /// SMC: effective sample size of the resampling weights.
    pub ess: Option<f64>,
    /// Shortest genome (genes; codons for codon genomes).
    pub len_min: usize,
    /// Mean genome length.
    pub len_avg: f64,
    /// Longest genome.
    pub len_max: usize,
    /// Length of the population's best individual.
    pub best_len: usize,
    /// Distinct genomes in the population (GA; `None` for optimizers that
    /// do not count them).
    pub distinct: Option<usize>,
}

impl GenerationStats {
    /// Fitness and length statistics of a population of derivation-tree
    /// genomes sorted best first; the counters and durations are left zero
    /// for the caller. See [`GenerationStats::summarize`] for any genome type.
    pub fn of_population(generation: usize, population: &[Individual]) -> Self {
        Self::summarize(generation, population)
    }

    /// [`GenerationStats::of_population`] for any genome type (lengths in
    /// the type's own unit, e.g. codons).
    pub fn summarize<G: Genotype>(generation: usize, population: &[Individual<G>]) -> Self {
        let mut valid = 0usize;
        let (mut sum, mut max, mut min) = (0.0, f64::NEG_INFINITY, f64::INFINITY);
        let (mut len_sum, mut len_min, mut len_max) = (0usize, usize::MAX, 0usize);
        for ind in population {
            if ind.is_valid() {
                valid += 1;
                sum += ind.fitness;
                max = max.max(ind.fitness);
                min = min.min(ind.fitness);
            }
            let len = ind.genome.length();
            len_sum += len;
            len_min = len_min.min(len);
            len_max = len_max.max(len);
        }
        let n = population.len();
        let (max, avg, min) = if valid > 0 { (max, sum / valid as f64, min) } else { (f64::NAN, f64::NAN, f64::NAN) };
        GenerationStats {
            generation,
            max,
            avg,
            min,
            invalid: n - valid,
            evaluations: 0,
            total_evaluations: 0,
            eval_time: Duration::ZERO,
            reproduction_time: Duration::ZERO,
            reproduction: ReproductionCounts::default(),
            moves: MoveCounts::default(),
            ess: None,
            len_min: if n == 0 { 0 } else { len_min },
            len_avg: if n == 0 { 0.0 } else { len_sum as f64 / n as f64 },
            len_max,
            best_len: population.first().map_or(0, |i| i.genome.length()),
            distinct: None,
        }
    }
}
