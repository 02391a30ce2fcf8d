//! Grammatical evolution: the Genr8 EA over codon strings.
//!
//! The optimizer never sees a grammar. Its genomes are [`Codons`], and an
//! [`Objective<Codons>`](crate::Objective) (typically a GE mapper followed by a
//! fitness) scores them; a non-finite score marks the individual invalid
//! (e.g. the mapping ran out of codons), and it then loses every tournament
//! and sorts last.
//!
//! Generation loop of [`Ge`]: sort best first; copy the `elitism` best with
//! their cached fitness; fill the rest pair by pair, each pair from its own
//! random stream `(seed, GE_PAIR_STREAM, generation, pair)`: select two
//! parents; with probability `crossover_rate` cross them over
//! ([`crossover`](operators::crossover)), else copy them; mutate every codon
//! of each child with probability `mutation_rate`
//! ([`mutate`](operators::mutate)). A child equal to one of its parents
//! reuses that parent's fitness (objectives are deterministic); the others
//! are evaluated in parallel. Pairs and evaluations are collected in index
//! order, so a seed gives the same populations and statistics at any
//! thread count.
//!
//! When the objective tells which codons its mapping reads
//! ([`Objective::expressed`]), three things change (each a [`GeConfig`]
//! switch): crossover cuts and mutation fall inside the read codons
//! (`effective`, PonyGE2's effective operators); a child whose read codons
//! were evaluated before is point-mutated until it reads something new,
//! sequentially from its own stream `(seed, GE_NOVEL_STREAM, generation,
//! child)` (`novel_children`); and with `distinct_parents` only the first
//! of members with bit-identical fitness can be selected. The Genr8 scenes
//! stalled without them: most children re-read a parent's codons, and the
//! population filled with copies of one surface (docs/evolve.md).
//! Two more switches are off by default: `novel_key = "phenotype"` makes
//! novel children compare the objective's phenotype key
//! ([`Objective::phenotype_key`]) instead of the read codons, and
//! `subtree_mutation` regrows one derivation subtree of a child
//! ([`Objective::subtrees`]) from its own stream `(seed,
//! GE_SUBTREE_STREAM, generation, child)`, after point mutation and before
//! the novelty pass. Also off by default: `local_search` makes a share of
//! the children as copies of the best with 1–3 read codons redrawn (stream
//! `(seed, GE_LOCAL_STREAM, generation, child)`), and `restart_after`
//! replaces all but the elites by fresh genomes (stream `(seed,
//! GE_RESTART_STREAM, generation, index)`) once the best has not risen for
//! that many generations. None of the three beat the defaults on all three
//! Genr8 scenes (docs/evolve.md).
//!
//! - [`config`]: [`GeConfig`], [`CodonRandomConfig`].
//! - [`operators`]: random genomes, crossover, mutation.
//! - [`random`]: [`CodonRandom`], the random-search baseline.
//! - [`algorithm`]: [`CodonAlgorithm`], [`AnyCodonOptimizer`].
//!
//! [`Objective::expressed`]: crate::Objective::expressed
//! [`Objective::phenotype_key`]: crate::Objective::phenotype_key
//! [`Objective::subtrees`]: crate::Objective::subtrees

pub mod algorithm;
mod codons;
pub mod config;
mod ea;
pub mod operators;
pub mod random;
mod reproduce;
#[cfg(test)]
mod tests;

pub use algorithm::{AnyCodonOptimizer, CodonAlgorithm};
pub use codons::Codons;
pub use config::{CodonRandomConfig, GeConfig, Init, NovelKey};
pub use ea::{
    GE_INIT_STREAM, GE_LOCAL_STREAM, GE_NOVEL_STREAM, GE_PAIR_STREAM, GE_RESTART_STREAM, GE_SUBTREE_STREAM, Ge,
};
pub use random::CodonRandom;
