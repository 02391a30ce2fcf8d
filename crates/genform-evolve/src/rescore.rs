//! Re-scoring: what an optimizer does when the objective changes mid-run
//! (a person steering the fitness weights, Genr8 §5.3).
//!
//! Optimizers cache fitness: elites, the best so far, MCMC chain states,
//! SMC particles and MAP-Elites cells keep the value they were given.
//! After a change those values are on the old scale, and stale elites
//! would outrank everything new. [`Rescore::rescore`] re-evaluates every
//! stored individual under the new objective, re-sorts, and makes the best
//! so far the best of the re-scored population and the re-scored old best.
//!
//! Evaluations run on the current rayon pool with results collected in
//! index order, so a re-scored run is the same at any thread count. A
//! genome equal to its predecessor in a population (elites copied,
//! resampled particles) reuses its value instead of being evaluated again.

use crate::objective::Objective;
use crate::optimizer::{Individual, Optimizer, update_best};
use genform_core::Genome;
use rayon::prelude::*;

/// An optimizer that can re-score what it stores when the objective changes.
///
/// Kept apart from [`Optimizer`] so that `&dyn Optimizer` stays usable; like
/// [`Optimizer::step`], `rescore` is generic over the objective.
pub trait Rescore<G = Genome>: Optimizer<G> {
    /// Re-evaluates every stored individual under `objective` (the
    /// population, the best so far and whatever else the optimizer keeps
    /// with a fitness), re-sorts, and recomputes the best so far as the
    /// best of the re-scored population and the re-scored old best.
    /// Returns the evaluations made; they count in
    /// [`Optimizer::evaluations`]. Does nothing before generation 0.
    fn rescore<O: Objective<G>>(&mut self, objective: &O) -> u64;
}

/// Re-evaluates `individuals` in place, in parallel, in index order; an
/// individual whose genome equals its predecessor's takes its value.
/// Returns the evaluations made.
pub(crate) fn reevaluate<G: PartialEq + Send + Sync, O: Objective<G>>(
    objective: &O,
    individuals: &mut [Individual<G>],
) -> u64 {
    let fresh: Vec<usize> =
        (0..individuals.len()).filter(|&i| i == 0 || individuals[i].genome != individuals[i - 1].genome).collect();
    let shared: &[Individual<G>] = individuals;
    let values: Vec<f64> = fresh
        .par_iter()
        .map_init(|| objective.scratch(), |scratch, &i| objective.evaluate(&shared[i].genome, scratch))
        .collect();
    let mut next = fresh.iter().zip(values).peekable();
    for i in 0..individuals.len() {
        match next.next_if(|(at, _)| **at == i) {
            Some((_, value)) => individuals[i].fitness = value,
            None => individuals[i].fitness = individuals[i - 1].fitness,
        }
    }
    fresh.len() as u64
}

/// The best so far after re-scoring: `old` re-scored (its value taken from
/// an equal genome of `sorted` when there is one, else evaluated) unless it
/// is now invalid, replaced by the first of `sorted` (already re-scored,
/// best first) when that is strictly better. Returns it and the
/// evaluations made (0 or 1).
pub(crate) fn rescored_best<G: PartialEq + Clone, O: Objective<G>>(
    objective: &O,
    old: Option<Individual<G>>,
    sorted: &[Individual<G>],
) -> (Option<Individual<G>>, u64) {
    let mut evaluations = 0;
    let mut best = old.map(|mut b| {
        match sorted.iter().find(|i| i.genome == b.genome) {
            Some(same) => b.fitness = same.fitness,
            None => {
                b.fitness = objective.evaluate(&b.genome, &mut objective.scratch());
                evaluations += 1;
            }
        }
        b
    });
    best = best.filter(|b| b.is_valid());
    update_best(&mut best, sorted);
    (best, evaluations)
}

/// Re-scores a sorted population and its best so far (the common case:
/// GA-like populations, SMC particles): re-evaluates `members`, re-sorts
/// them, recomputes `best` and adds the evaluations made to `evaluations`.
/// Returns them.
pub(crate) fn rescore_population<G: PartialEq + Clone + Send + Sync, O: Objective<G>>(
    objective: &O,
    members: &mut [Individual<G>],
    best: &mut Option<Individual<G>>,
    evaluations: &mut u64,
) -> u64 {
    if members.is_empty() {
        return 0;
    }
    let mut made = reevaluate(objective, members);
    crate::optimizer::sort_population(members);
    let (rescored, more) = rescored_best(objective, best.take(), members);
    *best = rescored;
    made += more;
    *evaluations += made;
    made
}

#[cfg(test)]
mod tests;
