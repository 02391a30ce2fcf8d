//! The reference implementation's grow and initial genomes (reference
//! §1.2–1.3), for runs that must start where the reference's start.
//!
//! The reference never reads slot probabilities: grow picks a gene that can
//! still have children uniformly, then one of its free child types with
//! `getRandomValue(0, n − 1)`, an exclusive upper bound, so the last free
//! type is never picked unless it is the only one (in the spaceship, a
//! body's top `T` comes only after its next body and its wing). No
//! mandatory closure: a `T` may stand without its `t`.

use super::shared::{Connection, Depths, grow_one};
use genform_core::genome::{GenePos, Link};
use genform_core::graph::SymbolId;
use genform_core::{GeneratorGraph, Genome, Limits, Rng};

/// Adds one gene as the reference's grow does: a gene chosen uniformly
/// among those with a free link (slots with probability > 0, whatever the
/// probability), then a free link of it with the reference's integer draw
/// (never the last of several), with freshly drawn parameters and no
/// mandatory closure. Respects `max_genes` and `max_depth`. Returns the new
/// gene's position, `None` when nothing can grow.
pub fn reference_grow(genome: &mut Genome, graph: &GeneratorGraph, limits: &Limits, rng: &mut Rng) -> Option<GenePos> {
    if genome.is_empty() || genome.len() >= limits.max_genes {
        return None;
    }
    let depths = Depths::of(genome);
    let free_links = |pos: GenePos| -> Vec<(usize, SymbolId)> {
        let g = genome.gene(pos);
        graph
            .symbol(g.symbol())
            .link_slots()
            .filter(|(link, slot)| slot.prob > 0.0 && g.link(*link) == Link::Empty)
            .map(|(link, slot)| (link, slot.target))
            .collect()
    };
    let growable: Vec<GenePos> = genome
        .iter()
        .filter(|g| depths.get(g.pos) < limits.max_depth)
        .map(|g| g.pos)
        .filter(|&p| !free_links(p).is_empty())
        .collect();
    if growable.is_empty() {
        return None;
    }
    let parent = growable[rng.index(growable.len())];
    let links = free_links(parent);
    // floor(0 + (n − 1)·u): uniform over all but the last of n > 1.
    let (link, symbol) = links[if links.len() > 1 { rng.index(links.len() - 1) } else { 0 }];
    let mut params = Vec::new();
    Some(grow_one(genome, graph, Connection { parent, link }, symbol, rng, &mut params))
}

/// The reference's initial individual: the root with drawn parameters, then
/// [`reference_grow`] until the length reaches a target drawn uniformly from
/// `length = [a, b]` (`initial_genome_length`: the root plus
/// `initial_genome_length − 1` grows) or nothing can grow.
pub fn reference_initial(graph: &GeneratorGraph, limits: &Limits, length: [usize; 2], rng: &mut Rng) -> Genome {
    let mut params = Vec::new();
    graph.draw_params(graph.root, rng, &mut params);
    let genome = Genome::with_root(graph, graph.root, &params);
    super::shared::grow_to_drawn_length(genome, length, rng, |g, rng| reference_grow(g, graph, limits, rng).is_some())
}
