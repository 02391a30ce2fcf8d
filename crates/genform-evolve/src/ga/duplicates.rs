//! Duplicate children, the population's diversity and operator success.
//!
//! A converged GA keeps producing copies of its best genomes (crossover of
//! equal parents, copies after failed reproduction); each one costs an
//! evaluation or a population slot without adding anything. Children are
//! checked in index order against the parents' population and the earlier
//! children, so the outcome does not depend on the thread count.

use super::reproduce::{Context, Operator, Origin};
use crate::evaluate::Child;
use crate::operators::mutate;
use crate::optimizer::Individual;
use crate::stats::{OperatorCounts, ReproductionCounts};
use genform_core::{Genome, Rng};
use std::collections::HashSet;
use std::hash::{Hash, Hasher};

/// Stream id of duplicate replacement: `(seed, DEDUP_STREAM, generation, child)`.
pub const DEDUP_STREAM: u64 = 0x4741_4444_5550; // "GADDUP"

/// Re-mutations of a duplicate before it is kept as it is.
const REPLACE_TRIES: usize = 3;

/// A fixed-key hash of a genome (the same in every process). Spaceship
/// evaluations take tens of microseconds, so the hash must be much cheaper
/// than SipHash: a multiply-rotate fold of the packed words (FxHash's
/// mixing). Collisions only make a new child count as a duplicate.
fn genome_hash(genome: &Genome) -> u64 {
    let mut h = Fold(0);
    genome.hash(&mut h);
    h.finish()
}

/// FxHash-style hasher over 8-byte words.
struct Fold(u64);

impl Fold {
    const K: u64 = 0x517c_c1b7_2722_0a95;

    fn add(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(5) ^ word).wrapping_mul(Self::K);
    }
}

impl Hasher for Fold {
    fn write(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for c in &mut chunks {
            self.add(u64::from_le_bytes(c.try_into().expect("8 bytes")));
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut last = [0u8; 8];
            last[..rest.len()].copy_from_slice(rest);
            self.add(u64::from_le_bytes(last) ^ ((rest.len() as u64) << 56));
        }
    }

    fn write_u64(&mut self, v: u64) {
        self.add(v);
    }

    fn write_u32(&mut self, v: u32) {
        self.add(v as u64);
    }

    fn write_usize(&mut self, v: usize) {
        self.add(v as u64);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

/// Counts the children that repeat a member of `ctx.population` or an
/// earlier child; with `replace`, each such child is mutated again (by the
/// configured mix, from its own stream) until it is new, up to
/// [`REPLACE_TRIES`] times.
pub(crate) fn handle_duplicates(
    ctx: &Context,
    children: &mut [Child],
    origins: &mut [Origin],
    counts: &mut ReproductionCounts,
    replace: bool,
    stream: (u64, u64),
) {
    let mut seen: HashSet<u64> = ctx.population.iter().map(|i| genome_hash(&i.genome)).collect();
    for (i, (child, origin)) in children.iter_mut().zip(origins.iter_mut()).enumerate() {
        let mut h = genome_hash(&child.genome);
        if seen.contains(&h) {
            counts.duplicates += 1;
            if replace {
                let mut rng = Rng::stream(stream.0, &[DEDUP_STREAM, stream.1, i as u64]);
                for _ in 0..REPLACE_TRIES {
                    let mut g = child.genome.clone();
                    let Some(kind) = mutate(&mut g, ctx.graph, ctx.limits, ctx.mix, &mut rng) else {
                        break;
                    };
                    let h2 = genome_hash(&g);
                    if ctx.bounds.contains(g.len()) && !seen.contains(&h2) {
                        if child.fitness.is_some() {
                            // A copy became a new child: it no longer counts as copied.
                            counts.copies -= 1;
                        }
                        let parent_fitness = child.fitness.unwrap_or(origin.parent_fitness);
                        *origin = Origin { operator: Operator::Mutation(kind), parent_fitness };
                        *child = Child { genome: g, fitness: None };
                        counts.duplicates_replaced += 1;
                        h = h2;
                        break;
                    }
                }
            }
        }
        seen.insert(h);
    }
}

/// Adds each evaluated child's outcome to its operator's tally (copies
/// are not counted: nothing was made).
pub(crate) fn tally(children: &[Child], origins: &[Origin], evaluated: &[bool], counts: &mut OperatorCounts) {
    for ((child, origin), &fresh) in children.iter().zip(origins).zip(evaluated) {
        let tally = match origin.operator {
            Operator::Crossover => &mut counts.crossover,
            Operator::Mutation(kind) => counts.mutation(kind),
            Operator::Copy => continue,
        };
        if !fresh {
            continue;
        }
        tally.children += 1;
        if child.fitness.is_some_and(|f| f > origin.parent_fitness) {
            tally.improved += 1;
        }
    }
}

/// Distinct genomes in a population.
pub(crate) fn distinct(population: &[Individual]) -> usize {
    population.iter().map(|i| genome_hash(&i.genome)).collect::<HashSet<_>>().len()
}
