//! Regrow: MH's jump move as a GA mutation (shared code, not a copy).

use crate::config::gene_choice::GeneChoice;
use crate::mcmc::moves::{Eligible, choose, jump};
use genform_core::genome::GenePos;
use genform_core::{GeneratorGraph, Genome, Limits, Rng};

/// Regrows everything below one gene from the grammar's prior, keeping the
/// parameters of the genes that still exist at the same place (MH's jump).
/// The gene is chosen level-biased among the genes with links: a depth
/// uniformly, then a gene at that depth, so the few shallow structural
/// genes change as often as the many deep ones. `None` when no gene has
/// links or the regrowth passes `max_genes` or `max_depth` (the genome is
/// then unchanged).
pub fn regrow(genome: &mut Genome, graph: &GeneratorGraph, limits: &Limits, rng: &mut Rng) -> Option<GenePos> {
    let v = choose(genome, Eligible::Nonterminals, GeneChoice::Level, rng)?;
    *genome = jump(genome, v, graph, limits, rng)?;
    Some(v)
}
