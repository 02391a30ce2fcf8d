//! Genetic operators on packed derivation-tree genomes (paper §3.1.2–3.1.3).
//!
//! Every operator knows only the [`GeneratorGraph`]: which symbols exist,
//! their parameter distributions and their child slots (target, probability,
//! max count). Operators keep genomes valid for the graph and within
//! [`Limits`]; callers that need tighter length bounds pass limits with a
//! smaller `max_genes` and check [`LengthBounds`] on the result.
//!
//! Slot probabilities steer the operators (the reference ignored them, §1.2):
//! - **mandatory closure**: a gene grown by any operator also gets children in
//!   every link of its `p = 1` slots, recursively ([`grow_mandatory`]), so
//!   e.g. `S → Body` is always present. The closure stops at `max_genes` and
//!   `max_depth`, leaving such links empty (as prior sampling truncates);
//!   [`grow`] may fill them later.
//! - [`grow`] picks an empty link with probability ∝ its slot probability
//!   (never a `p = 0` slot's).
//! - [`cut`] picks a non-root gene with probability ∝ 1 − p of its slot, so a
//!   gene in a `p = 1` slot is never cut.
//! - [`alter`] redraws the parameters of a uniformly chosen gene.
//! - [`drift`] moves the parameters of a uniformly chosen gene by a Gaussian
//!   step scaled to each parameter's range (as MH's diffusion).
//! - [`regrow`] regrows the subtree below a level-biased gene from the prior,
//!   keeping the parameters of surviving genes (MH's jump).
//! - [`crossover`] exchanges subtrees hanging on the same graph edge.
//! - [`reference_grow`] is the reference implementation's grow (slot
//!   probabilities unused, its integer-draw quirk kept), for
//!   `initialization = "reference"`.
//!
//! Choices the reference made with its exclusive-upper-bound integer draws
//! (never the last candidate) are uniform here.

mod crossover;
pub(crate) mod drift;
mod mutate;
mod reference;
mod regrow;
pub(crate) mod shared;
#[cfg(test)]
mod tests;

pub use crossover::{Crossed, CrossoverOutcome, crossover};
pub use drift::drift;
pub use mutate::{
    CutOutcome, DEFAULT_DRIFT_WEIGHT, DEFAULT_REGROW_WEIGHT, GrowOutcome, MutationKind, MutationMix, alter, cut, grow,
    mutate,
};
pub use reference::{reference_grow, reference_initial};
pub use regrow::regrow;
pub(crate) use shared::grow_one;
pub use shared::{Connection, LengthBounds, grow_mandatory};

use genform_core::genome::GenePos;
use genform_core::{GeneratorGraph, Genome, Limits, Rng};
use shared::{grow_mandatory_with, grow_to_drawn_length};

/// A fresh individual: the root with drawn parameters and its mandatory
/// closure, then [`grow`] until the length reaches a target drawn uniformly
/// from `length = [a, b]` (the reference's `initial_genome_length`), or no
/// link can grow within `limits`. The closure may overshoot the target.
pub fn initial(graph: &GeneratorGraph, limits: &Limits, length: [usize; 2], rng: &mut Rng) -> Genome {
    let mut params = Vec::new();
    graph.draw_params(graph.root, rng, &mut params);
    let mut genome = Genome::with_root(graph, graph.root, &params);
    grow_mandatory_with(&mut genome, GenePos(0), 0, graph, limits, rng, &mut params);
    grow_to_drawn_length(genome, length, rng, |g, rng| grow(g, graph, limits, rng).is_some())
}
