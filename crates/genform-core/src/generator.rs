//! The [`Generator`] trait every formalism implements, derivation limits,
//! and sampling from the prior over a generator graph.

use crate::genome::{GenePos, Genome, GenomeError, Link};
use crate::graph::GeneratorGraph;
use crate::rng::Rng;
use crate::scene::Scene;
use std::fmt;

/// Bounds on a derivation, so runaway grammars stop with a message.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Most genes in a genome (sampling truncates here; expression rejects).
    pub max_genes: usize,
    /// Deepest gene (root = 0).
    pub max_depth: usize,
    /// Most primitives (instances, polylines, polygons) in a Scene.
    pub max_primitives: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits { max_genes: 20_000, max_depth: 200, max_primitives: 200_000 }
    }
}

/// Which limit was hit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LimitKind {
    /// [`Limits::max_genes`].
    Genes,
    /// [`Limits::max_depth`].
    Depth,
    /// [`Limits::max_primitives`].
    Primitives,
}

impl LimitKind {
    /// The limit's value in `limits`.
    pub fn value(self, limits: &Limits) -> usize {
        match self {
            LimitKind::Genes => limits.max_genes,
            LimitKind::Depth => limits.max_depth,
            LimitKind::Primitives => limits.max_primitives,
        }
    }

    /// The command-line flag that raises it.
    pub fn flag(self) -> &'static str {
        match self {
            LimitKind::Genes => "--max-genes",
            LimitKind::Depth => "--max-depth",
            LimitKind::Primitives => "--max-primitives",
        }
    }
}

impl fmt::Display for LimitKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            LimitKind::Genes => "gene",
            LimitKind::Depth => "depth",
            LimitKind::Primitives => "primitive",
        })
    }
}

/// Why a genome could not be expressed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ExpressError {
    /// A limit was reached.
    #[error("the {kind} limit ({limit}) was reached; raise it with {flag} or make the grammar terminate sooner", flag = kind.flag())]
    Limit {
        /// Which limit.
        kind: LimitKind,
        /// Its value.
        limit: usize,
    },
    /// The genome does not fit the generator.
    #[error("invalid genome: {0}")]
    Genome(#[from] GenomeError),
    /// A formula produced something unusable (message names the rule).
    #[error("{0}")]
    Eval(String),
}

/// A genome drawn from a generator's prior.
#[derive(Clone, Debug)]
pub struct Sampled {
    /// The genome.
    pub genome: Genome,
    /// Set when growth stopped at a limit; the genome is valid but truncated.
    pub truncated: Option<LimitKind>,
}

/// What every formalism compiles to.
pub trait Generator: Send + Sync {
    /// The generator graph: the space optimizers search.
    fn graph(&self) -> &GeneratorGraph;

    /// Expresses a genome into `scene` (which the caller has cleared).
    /// Deterministic: the same genome gives the same scene.
    fn express(&self, genome: &Genome, limits: &Limits, scene: &mut Scene) -> Result<(), ExpressError>;

    /// Draws a genome from the generator's prior. The default grows every
    /// link with its slot probability ([`sample_prior`]); generators whose
    /// slots are conditional override it to grow only what a derivation
    /// actually reaches.
    fn sample(&self, rng: &mut Rng, limits: &Limits) -> Result<Sampled, ExpressError> {
        Ok(sample_prior(self.graph(), rng, limits))
    }
}

/// Grows a genome from the root: each gene's parameters are drawn from their
/// distributions and each of its links is expressed with its slot's
/// probability, breadth-first in storage order. Growth stops at the gene
/// or depth limit and reports the truncation.
pub fn sample_prior(graph: &GeneratorGraph, rng: &mut Rng, limits: &Limits) -> Sampled {
    let mut params = Vec::new();
    graph.draw_params(graph.root, rng, &mut params);
    let mut genome = Genome::with_root(graph, graph.root, &params);
    let mut truncated = None;
    let mut depths = vec![0usize];
    let mut queue = std::collections::VecDeque::from([GenePos(0)]);
    let mut ordinal = 0usize;
    while let Some(pos) = queue.pop_front() {
        let depth = depths[ordinal];
        ordinal += 1;
        let sym = genome.gene(pos).symbol();
        let spec = graph.symbol(sym);
        for (s, slot) in spec.slots.iter().enumerate() {
            for k in 0..slot.max_count as usize {
                let link = spec.link_offset(s) + k;
                if genome.gene(pos).link(link) != Link::Empty || !rng.bernoulli(slot.prob) {
                    continue;
                }
                if depth + 1 > limits.max_depth {
                    truncated.get_or_insert(LimitKind::Depth);
                    continue;
                }
                if genome.len() >= limits.max_genes {
                    truncated.get_or_insert(LimitKind::Genes);
                    continue;
                }
                params.clear();
                graph.draw_params(slot.target, rng, &mut params);
                let child = genome.grow(pos, link, slot.target, &params, graph.symbol(slot.target).link_len());
                depths.push(depth + 1);
                queue.push_back(child);
            }
        }
    }
    Sampled { genome, truncated }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::tests::tiny;

    #[test]
    fn prior_samples_are_valid_and_reproducible() {
        let g = tiny();
        let limits = Limits::default();
        for seed in 0..200 {
            let a = sample_prior(&g, &mut Rng::from_seed(seed), &limits);
            a.genome.validate(&g).unwrap();
            let b = sample_prior(&g, &mut Rng::from_seed(seed), &limits);
            assert_eq!(a.genome, b.genome);
        }
    }

    #[test]
    fn slot_frequencies_match_probabilities() {
        // S always has its A child; A's `leaf` link is expressed with p = 0.3.
        let g = tiny();
        let limits = Limits::default();
        let n = 4000;
        let mut leaf = 0;
        for seed in 0..n {
            let s = sample_prior(&g, &mut Rng::stream(11, &[seed]), &limits).genome;
            let a = match s.gene(GenePos(0)).link(0) {
                Link::Child(a) => a,
                other => panic!("S without A: {other:?}"),
            };
            if let Link::Child(_) = s.gene(a).link(2) {
                leaf += 1;
            }
        }
        let p = leaf as f64 / n as f64;
        let sigma = (0.3f64 * 0.7 / n as f64).sqrt();
        assert!((p - 0.3).abs() < 3.0 * sigma, "leaf frequency {p}");
    }

    #[test]
    fn growth_stops_at_limits() {
        let mut g = tiny();
        g.symbols[1].slots[0].prob = 1.0; // A → A A always: infinite.
        let limits = Limits { max_genes: 50, max_depth: 1000, max_primitives: 10 };
        let s = sample_prior(&g, &mut Rng::from_seed(1), &limits);
        assert_eq!(s.truncated, Some(LimitKind::Genes));
        assert_eq!(s.genome.len(), 50);
        s.genome.validate(&g).unwrap();
        let limits = Limits { max_genes: 10_000, max_depth: 4, max_primitives: 10 };
        let s = sample_prior(&g, &mut Rng::from_seed(1), &limits);
        assert_eq!(s.truncated, Some(LimitKind::Depth));
        assert!(s.genome.iter().all(|x| s.genome.depth(x.pos) <= 4));
    }
}
