//! The grow, cut and alter mutations, and the mix that chooses among them.

use super::shared::{Connection, Depths, grow_mandatory_with, grow_one};
use super::{drift, regrow};
use genform_core::genome::{GenePos, Link};
use genform_core::graph::SymbolId;
use genform_core::{GeneratorGraph, Genome, Limits, Rng};
use serde::{Deserialize, Serialize};

/// Which mutation changed a genome.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MutationKind {
    /// [`alter`]: parameters redrawn.
    Alter,
    /// [`grow`]: a subtree added.
    Grow,
    /// [`cut`]: a subtree removed.
    Cut,
    /// [`drift`]: parameters moved by a small Gaussian step.
    Drift,
    /// [`regrow`]: a subtree regrown from the prior.
    Regrow,
}

impl MutationKind {
    /// All kinds, in the order of [`MutationMix`]'s weights.
    pub const ALL: [MutationKind; 5] =
        [MutationKind::Alter, MutationKind::Grow, MutationKind::Cut, MutationKind::Drift, MutationKind::Regrow];
}

/// Relative weights of the mutations (the reference's `permutate_prob`,
/// `grow_prob`, `cut_prob`; 10/45/45 in every paper experiment, which had
/// no drift), and the step size of drift.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MutationMix {
    /// Weight of [`alter`].
    pub alter: f64,
    /// Weight of [`grow`].
    pub grow: f64,
    /// Weight of [`cut`].
    pub cut: f64,
    /// Weight of [`drift`] (0 in the thesis; the default GA's fine tuning).
    pub drift: f64,
    /// Weight of [`regrow`] (0 in the thesis).
    pub regrow: f64,
    /// Standard deviation of a drift step as a fraction of the parameter's
    /// range (uniform) or standard deviation (normal), as MH's `drift_scale`.
    pub drift_scale: f64,
}

/// Drift weight of the default GA: beside the thesis' 10/45/45, so scenes
/// that spell out those three weights still get drift.
pub const DEFAULT_DRIFT_WEIGHT: f64 = 100.0;

/// Regrow weight of the default GA: 0, as regrow did not help on
/// spaceship_volume (see docs/evolve.md); available for other scenes.
pub const DEFAULT_REGROW_WEIGHT: f64 = 0.0;

impl Default for MutationMix {
    fn default() -> Self {
        MutationMix {
            alter: 10.0,
            grow: 45.0,
            cut: 45.0,
            drift: DEFAULT_DRIFT_WEIGHT,
            regrow: DEFAULT_REGROW_WEIGHT,
            drift_scale: 0.1,
        }
    }
}

impl MutationMix {
    /// The weights in [`MutationKind::ALL`] order.
    pub fn weights(&self) -> [f64; 5] {
        [self.alter, self.grow, self.cut, self.drift, self.regrow]
    }

    /// The thesis' mix: these weights without drift and regrow.
    pub fn thesis_only(self) -> Self {
        MutationMix { drift: 0.0, regrow: 0.0, ..self }
    }

    /// Whether the weights are usable: finite, ≥ 0, not all 0, and the
    /// drift scale finite and > 0.
    pub fn is_valid(&self) -> bool {
        let w = self.weights();
        w.iter().all(|x| x.is_finite() && *x >= 0.0)
            && w.iter().any(|x| *x > 0.0)
            && self.drift_scale.is_finite()
            && self.drift_scale > 0.0
    }
}

/// What [`grow`] added.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GrowOutcome {
    /// The link that received the new gene.
    pub at: Connection,
    /// Position of the new gene.
    pub pos: GenePos,
    /// Genes added, including the mandatory closure.
    pub added: usize,
}

/// What [`cut`] removed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CutOutcome {
    /// The link that held the removed subtree (now empty).
    pub at: Connection,
    /// Symbol of the removed subtree's root.
    pub symbol: SymbolId,
    /// Genes removed.
    pub removed: usize,
}

/// Adds one gene, with parameters drawn from their distributions and its
/// mandatory closure, at an empty link chosen anywhere in the genome with
/// probability ∝ its slot's probability. Links whose child would pass
/// `max_depth`, and any growth once the genome has `max_genes` genes, are
/// excluded. `None` when no link can grow.
pub fn grow(genome: &mut Genome, graph: &GeneratorGraph, limits: &Limits, rng: &mut Rng) -> Option<GrowOutcome> {
    if genome.is_empty() || genome.len() >= limits.max_genes {
        return None;
    }
    // A gene's depth is below the genome's length, so depths matter only
    // when the genome is longer than the depth limit.
    let depths = (genome.len() > limits.max_depth).then(|| Depths::of(genome));
    let mut links = Vec::new();
    let mut weights = Vec::new();
    for g in genome.iter() {
        let depth = depths.as_ref().map_or(0, |d| d.get(g.pos));
        if depth >= limits.max_depth {
            continue;
        }
        for (link, slot) in graph.symbol(g.symbol()).link_slots() {
            if slot.prob > 0.0 && g.link(link) == Link::Empty {
                links.push((Connection { parent: g.pos, link }, slot.target, depth));
                weights.push(slot.prob);
            }
        }
    }
    let (at, symbol, depth) = links[rng.weighted_index(&weights)?];
    let mut params = Vec::new();
    let pos = grow_one(genome, graph, at, symbol, rng, &mut params);
    let closure = grow_mandatory_with(genome, pos, depth + 1, graph, limits, rng, &mut params);
    Some(GrowOutcome { at, pos, added: 1 + closure })
}

/// Removes a non-root gene and its subtree, chosen with probability ∝
/// 1 − p of the slot it sits in: genes in `p = 1` slots are never cut.
/// `None` when nothing can be cut (only the root, or only mandatory genes).
pub fn cut(genome: &mut Genome, graph: &GeneratorGraph, rng: &mut Rng) -> Option<CutOutcome> {
    let mut genes = Vec::new();
    let mut weights = Vec::new();
    for g in genome.iter().skip(1) {
        let (parent, link) = g.parent()?;
        let spec = graph.symbol(genome.gene(parent).symbol());
        let (slot, _) = spec.slot_of_link(link)?;
        let w = 1.0 - spec.slots[slot].prob;
        if w > 0.0 {
            genes.push((g.pos, Connection { parent, link }, g.symbol()));
            weights.push(w);
        }
    }
    let (pos, at, symbol) = genes[rng.weighted_index(&weights)?];
    let removed = genome.cut(pos);
    Some(CutOutcome { at, symbol, removed })
}

/// Redraws every parameter of a gene chosen uniformly among the genes that
/// have parameters (the reference's "permutate"); returns its position.
/// `None` when no gene has parameters.
pub fn alter(genome: &mut Genome, graph: &GeneratorGraph, rng: &mut Rng) -> Option<GenePos> {
    let with_params = genome.iter().filter(|g| g.param_len() > 0).count();
    if with_params == 0 {
        return None;
    }
    let g = genome.iter().filter(|g| g.param_len() > 0).nth(rng.index(with_params))?;
    let (pos, symbol) = (g.pos, g.symbol());
    let mut params = Vec::with_capacity(g.param_len());
    graph.draw_params(symbol, rng, &mut params);
    genome.set_params(pos, &params);
    Some(pos)
}

/// Applies one mutation chosen by `mix`; when the chosen one cannot apply
/// (nothing to cut, no link to grow, no parameters) the others are tried,
/// again by weight, skipping zero weights. Returns the kind applied, `None`
/// when none could.
pub fn mutate(
    genome: &mut Genome,
    graph: &GeneratorGraph,
    limits: &Limits,
    mix: &MutationMix,
    rng: &mut Rng,
) -> Option<MutationKind> {
    let mut weights = mix.weights();
    loop {
        let k = rng.weighted_index(&weights)?;
        let kind = MutationKind::ALL[k];
        let applied = match kind {
            MutationKind::Alter => alter(genome, graph, rng).is_some(),
            MutationKind::Grow => grow(genome, graph, limits, rng).is_some(),
            MutationKind::Cut => cut(genome, graph, rng).is_some(),
            MutationKind::Drift => drift(genome, graph, mix.drift_scale, rng).is_some(),
            MutationKind::Regrow => regrow(genome, graph, limits, rng).is_some(),
        };
        if applied {
            return Some(kind);
        }
        weights[k] = 0.0;
    }
}
