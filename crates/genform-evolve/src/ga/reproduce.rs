//! Making the children of one pair.

use crate::config::GaConfig;
use crate::evaluate::Child;
use crate::operators::{LengthBounds, MutationKind, MutationMix, crossover, mutate};
use crate::optimizer::Individual;
use crate::population::PairOutput;
use crate::selection::Selector;
use crate::stats::ReproductionCounts;
use genform_core::{GeneratorGraph, Genome, Limits, Rng};

/// Reproduction attempts per pair (each selects new parents) before the
/// missing children are copied from the last parents.
const PAIR_ATTEMPTS: usize = 5;

/// Which operator made a child.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Operator {
    Crossover,
    Mutation(MutationKind),
    /// A parent copied because reproduction kept failing.
    Copy,
}

/// A child's operator and the fitness it must beat to count as an
/// improvement: its parent's, or the fitter parent's for crossover.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Origin {
    pub operator: Operator,
    pub parent_fitness: f64,
}

/// A child genome with its origin, as pairs make them.
pub(crate) type Tagged = (Genome, Origin);

/// Everything reproduction reads.
pub(crate) struct Context<'a> {
    pub graph: &'a GeneratorGraph,
    /// Limits with `max_genes` already below the length bound.
    pub limits: &'a Limits,
    pub bounds: LengthBounds,
    pub config: &'a GaConfig,
    /// Current probability that a pair is mutated (see `super::adapt`).
    pub mutation_rate: f64,
    /// Current mutation weights.
    pub mix: &'a MutationMix,
    pub population: &'a [Individual],
    pub selectors: [Selector<'a>; 2],
}

/// Makes `need` (1 or 2) children: select two parents; with probability
/// `mutation_rate` mutate a copy of each, otherwise cross them over. Only
/// children within the length bounds are kept; missing ones come from new
/// attempts, and after [`PAIR_ATTEMPTS`] from copies of the last parents.
pub(crate) fn reproduce_pair(ctx: &Context, need: usize, rng: &mut Rng) -> PairOutput<Tagged> {
    let mut children = Vec::with_capacity(need);
    let mut counts = ReproductionCounts::default();
    let mut parents = [0usize; 2];
    for _ in 0..PAIR_ATTEMPTS {
        parents = [ctx.selectors[0].select(rng), ctx.selectors[1].select(rng)];
        if rng.bernoulli(ctx.mutation_rate) {
            for &p in &parents {
                if children.len() == need {
                    break;
                }
                let mut genome = ctx.population[p].genome.clone();
                if let Some(kind) = mutate(&mut genome, ctx.graph, ctx.limits, ctx.mix, rng) {
                    if ctx.bounds.contains(genome.len()) {
                        counts.mutations.add(kind);
                        let origin =
                            Origin { operator: Operator::Mutation(kind), parent_fitness: ctx.population[p].fitness };
                        children.push(Child { genome: (genome, origin), fitness: None });
                    } else {
                        counts.rejected += 1;
                    }
                }
            }
        } else {
            let [a, b] = parents.map(|p| &ctx.population[p].genome);
            let out = crossover([a, b], ctx.graph, ctx.limits, &ctx.bounds, ctx.config.crossover_retries, rng);
            counts.crossover_retries += out.retries as u64;
            match out.crossed {
                Some(crossed) => {
                    counts.crossovers += 1;
                    let room = need - children.len();
                    let parent_fitness = ctx.population[parents[0]].fitness.max(ctx.population[parents[1]].fitness);
                    let origin = Origin { operator: Operator::Crossover, parent_fitness };
                    children.extend(
                        crossed
                            .children
                            .into_iter()
                            .take(room)
                            .map(|genome| Child { genome: (genome, origin), fitness: None }),
                    );
                }
                None => counts.crossover_failures += 1,
            }
        }
        if children.len() == need {
            break;
        }
    }
    let mut k = 0;
    while children.len() < need {
        let parent = &ctx.population[parents[k % 2]];
        let origin = Origin { operator: Operator::Copy, parent_fitness: parent.fitness };
        children.push(Child { genome: (parent.genome.clone(), origin), fitness: Some(parent.fitness) });
        counts.copies += 1;
        k += 1;
    }
    PairOutput { children, counts }
}
