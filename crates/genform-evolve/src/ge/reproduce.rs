//! Making the children of one pair.

use super::codons::Codons;
use super::config::GeConfig;
use super::operators::{crossover, effective_crossover, mutate};
use crate::evaluate::Child;
use crate::optimizer::Individual;
use crate::population::PairOutput;
use crate::selection::Selector;
use crate::stats::ReproductionCounts;
use genform_core::Rng;

/// Everything reproduction reads.
pub(crate) struct Context<'a> {
    pub config: &'a GeConfig,
    pub population: &'a [Individual<Codons>],
    pub selector: Selector<'a>,
    /// Expressed codons of each member (empty: unknown, whole genomes).
    pub expressed: &'a [usize],
}

/// Makes `need` (1 or 2) children: select two parents; with probability
/// `crossover_rate` cross them over, else copy them; mutate each child.
/// Counts: `crossovers` (pairs crossed), `mutations.alter` (children with
/// a changed codon), `copies` (children equal to a parent, which reuse its
/// fitness instead of being evaluated).
pub(crate) fn reproduce_pair(ctx: &Context, need: usize, rng: &mut Rng) -> PairOutput<Codons> {
    let config = ctx.config;
    let picks = [ctx.selector.select(rng), ctx.selector.select(rng)];
    let parents = picks.map(|p| &ctx.population[p]);
    // 0: no expressed region known, the whole genome counts.
    let reach = picks.map(|p| ctx.expressed.get(p).copied().unwrap_or(0));
    let mut counts = ReproductionCounts::default();
    let (mut genomes, reach) = if rng.bernoulli(config.crossover_rate) {
        counts.crossovers += 1;
        if ctx.expressed.is_empty() {
            (crossover(&parents[0].genome, &parents[1].genome, config.max_length, rng), [0, 0])
        } else {
            let (a, b) = (&parents[0].genome, &parents[1].genome);
            effective_crossover((a, reach[0]), (b, reach[1]), config.max_length, rng)
        }
    } else {
        ([parents[0].genome.clone(), parents[1].genome.clone()], reach)
    };
    let mut children = Vec::with_capacity(need);
    for (genome, reach) in genomes.iter_mut().zip(reach).take(need) {
        let region = if reach == 0 { genome.len() } else { reach.min(genome.len()) };
        if mutate(&mut genome[..region], config.mutation_rate, config.codon_range, rng) > 0 {
            counts.mutations.alter += 1;
        }
        let twin = parents.iter().find(|p| p.genome == *genome);
        counts.copies += u64::from(twin.is_some());
        children.push(Child { genome: std::mem::take(genome), fitness: twin.map(|p| p.fitness) });
    }
    PairOutput { children, counts }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::selection::Selection;

    fn individual(codon: u32, fitness: f64) -> Individual<Codons> {
        Individual { genome: vec![codon; 5], fitness }
    }

    #[test]
    fn invalid_individuals_never_win_a_tournament() {
        // Half the population invalid, and the invalid ones listed first
        // (where tournament ties would favour them).
        let mut population: Vec<Individual<Codons>> = (0..10).map(|i| individual(i, f64::NAN)).collect();
        population.extend((10..20).map(|i| individual(i, -(i as f64))));
        population[3].fitness = f64::INFINITY;
        population[4].fitness = f64::NEG_INFINITY;
        let fitness: Vec<f64> = population.iter().map(|i| i.fitness).collect();
        for selection in [Selection::Tournament(1), Selection::Tournament(3), Selection::Roulette, Selection::Random] {
            let config = GeConfig { crossover_rate: 0.0, mutation_rate: 0.0, selection, ..GeConfig::default() };
            let ctx = Context {
                config: &config,
                population: &population,
                selector: Selector::new(selection, &fitness),
                expressed: &[],
            };
            let mut rng = Rng::from_seed(3);
            for _ in 0..2000 {
                let out = reproduce_pair(&ctx, 2, &mut rng);
                assert_eq!(out.counts.copies, 2);
                for c in out.children {
                    assert!(c.genome[0] >= 10, "{selection:?} picked invalid parent {}", c.genome[0]);
                    assert!(c.fitness.is_some_and(f64::is_finite));
                }
            }
        }
    }

    #[test]
    fn changed_children_are_evaluated_and_odd_pairs_make_one() {
        let population = vec![individual(1, 1.0), individual(2, 2.0)];
        let fitness = [1.0, 2.0];
        let config = GeConfig { crossover_rate: 0.0, mutation_rate: 1.0, codon_range: 1000, ..GeConfig::default() };
        let ctx = Context {
            config: &config,
            population: &population,
            selector: Selector::new(config.selection, &fitness),
            expressed: &[],
        };
        let mut rng = Rng::from_seed(5);
        let out = reproduce_pair(&ctx, 1, &mut rng);
        assert_eq!(out.children.len(), 1);
        // Every codon redrawn from 1000 values: the child differs from both parents.
        assert_eq!((out.counts.mutations.alter, out.counts.copies), (1, 0));
        assert!(out.children[0].fitness.is_none());
    }
}
