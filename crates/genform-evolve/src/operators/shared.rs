//! What the operators share: the length bounds kept genomes must meet,
//! where a subtree hangs ([`Connection`]), gene depths, and growing one gene
//! with fresh parameters and its mandatory closure. Kept apart from the
//! operators' module so every operator can use them without importing the
//! module that gathers the operators.

use genform_core::genome::{GenePos, Link};
use genform_core::graph::SymbolId;
use genform_core::{GeneratorGraph, Genome, Limits, Rng};
use serde::{Deserialize, Serialize};

/// Lengths (gene counts) a kept genome must have: `min ≤ len < max`, as the
/// reference's `min_length`/`max_length`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct LengthBounds {
    /// Smallest allowed length.
    pub min: usize,
    /// Smallest length no longer allowed.
    pub max: usize,
}

impl LengthBounds {
    /// No bound beyond a non-empty genome.
    pub const ANY: LengthBounds = LengthBounds { min: 1, max: usize::MAX };

    /// Whether a genome of `len` genes is allowed.
    pub fn contains(&self, len: usize) -> bool {
        self.min <= len && len < self.max
    }
}

/// Where a subtree hangs: a gene and the index of one of its links.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Connection {
    /// The parent gene.
    pub parent: GenePos,
    /// Index of the parent's link.
    pub link: usize,
}

/// Depth of every gene, indexed by word position (genes are stored after
/// their parents, so one forward pass fills it).
pub(crate) struct Depths(Vec<u32>);

impl Depths {
    pub(crate) fn of(genome: &Genome) -> Self {
        let mut d = vec![0u32; genome.word_len()];
        for g in genome.iter() {
            if let Some((q, _)) = g.parent() {
                d[g.pos.0 as usize] = d[q.0 as usize] + 1;
            }
        }
        Depths(d)
    }

    pub(crate) fn get(&self, pos: GenePos) -> usize {
        self.0[pos.0 as usize] as usize
    }
}

/// Appends a child of `symbol` with freshly drawn parameters under
/// `parent`'s `link`; `params` is a reusable buffer.
pub(crate) fn grow_one(
    genome: &mut Genome,
    graph: &GeneratorGraph,
    at: Connection,
    symbol: SymbolId,
    rng: &mut Rng,
    params: &mut Vec<f64>,
) -> GenePos {
    params.clear();
    graph.draw_params(symbol, rng, params);
    genome.grow(at.parent, at.link, symbol, params, graph.symbol(symbol).link_len())
}

/// Grows children into every empty link of the `p = 1` slots of the gene at
/// `pos` (at depth `depth`), and of those children, recursively; returns the
/// number of genes added. Links that would pass `max_genes` or `max_depth`
/// stay empty.
pub fn grow_mandatory(
    genome: &mut Genome,
    pos: GenePos,
    depth: usize,
    graph: &GeneratorGraph,
    limits: &Limits,
    rng: &mut Rng,
) -> usize {
    let mut params = Vec::new();
    grow_mandatory_with(genome, pos, depth, graph, limits, rng, &mut params)
}

/// [`grow_mandatory`] with a reusable parameter buffer.
pub(super) fn grow_mandatory_with(
    genome: &mut Genome,
    pos: GenePos,
    depth: usize,
    graph: &GeneratorGraph,
    limits: &Limits,
    rng: &mut Rng,
    params: &mut Vec<f64>,
) -> usize {
    let mut added = 0;
    let mut stack = vec![(pos, depth)];
    while let Some((p, d)) = stack.pop() {
        for (link, slot) in graph.symbol(genome.gene(p).symbol()).link_slots() {
            let free = genome.gene(p).link(link) == Link::Empty;
            if slot.prob >= 1.0 && free && d < limits.max_depth && genome.len() < limits.max_genes {
                let child = grow_one(genome, graph, Connection { parent: p, link }, slot.target, rng, params);
                added += 1;
                stack.push((child, d + 1));
            }
        }
    }
    added
}

/// Applies `grow` until the genome's length reaches a target drawn
/// uniformly from `length = [a, b]` or `grow` reports that nothing grew.
pub(crate) fn grow_to_drawn_length(
    mut genome: Genome,
    length: [usize; 2],
    rng: &mut Rng,
    mut grow: impl FnMut(&mut Genome, &mut Rng) -> bool,
) -> Genome {
    let [a, b] = length;
    let target = rng.int_inclusive(a as i64, b.max(a) as i64) as usize;
    while genome.len() < target && grow(&mut genome, rng) {}
    genome
}
