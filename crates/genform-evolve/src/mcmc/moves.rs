//! The proposals of the RJMCMC chains and their probabilities.
//!
//! - Gene choice: which gene a move changes, uniformly or level-biased, and
//!   the log probability of that choice in any state (jumps change the
//!   structure, so the reverse choice probability differs).
//! - Jump: regrow everything below a gene from the generator graph's prior
//!   (each link expressed with its slot probability), keeping the
//!   parameters of every gene that still exists at the same place — the
//!   thesis' "reuse the old random values where they fit". Kept genes are
//!   an identity map on shared coordinates, so the acceptance ratio stays
//!   the likelihood ratio times the gene-choice ratio (see `super`).
//! - Diffusion: new parameters for one gene, redrawn from their
//!   distributions or drifted by a symmetric Gaussian step.

use crate::config::gene_choice::GeneChoice;
use crate::operators::drift::drift_sd;
use crate::operators::shared::Depths;
use genform_core::genome::{GenePos, GeneRef, Link};
use genform_core::{GeneratorGraph, Genome, Limits, Rng};
use std::collections::BTreeMap;

/// The genes a move may act on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Eligible {
    /// Genes with at least one link (jumps regrow below them).
    Nonterminals,
    /// Genes with parameters (diffusions change them).
    Parameters,
}

impl Eligible {
    fn admits(self, g: &GeneRef<'_>) -> bool {
        match self {
            Eligible::Nonterminals => g.link_len() > 0,
            Eligible::Parameters => g.param_len() > 0,
        }
    }
}

/// Eligible genes with their depths, and how many sit at each depth.
struct Census {
    genes: Vec<(GenePos, usize)>,
    per_depth: Vec<u32>,
}

impl Census {
    fn of(genome: &Genome, eligible: Eligible) -> Self {
        let depths = Depths::of(genome);
        let mut genes = Vec::new();
        let mut per_depth = Vec::new();
        for g in genome.iter().filter(|g| eligible.admits(g)) {
            let d = depths.get(g.pos);
            if per_depth.len() <= d {
                per_depth.resize(d + 1, 0);
            }
            per_depth[d] += 1;
            genes.push((g.pos, d));
        }
        Census { genes, per_depth }
    }

    fn levels(&self) -> usize {
        self.per_depth.iter().filter(|&&n| n > 0).count()
    }
}

/// Picks the gene a move changes; `None` when no gene is eligible.
pub(crate) fn choose(genome: &Genome, eligible: Eligible, choice: GeneChoice, rng: &mut Rng) -> Option<GenePos> {
    let census = Census::of(genome, eligible);
    if census.genes.is_empty() {
        return None;
    }
    match choice {
        GeneChoice::Uniform => Some(census.genes[rng.index(census.genes.len())].0),
        GeneChoice::Level => {
            let level = rng.index(census.levels());
            let depth = census.per_depth.iter().enumerate().filter(|(_, n)| **n > 0).nth(level)?.0;
            let k = rng.index(census.per_depth[depth] as usize);
            census.genes.iter().filter(|(_, d)| *d == depth).nth(k).map(|(p, _)| *p)
        }
    }
}

/// Log probability that [`choose`] picks `pos` in `genome`.
pub(crate) fn ln_choice(genome: &Genome, eligible: Eligible, choice: GeneChoice, pos: GenePos) -> f64 {
    let census = Census::of(genome, eligible);
    match choice {
        GeneChoice::Uniform => -(census.genes.len() as f64).ln(),
        GeneChoice::Level => {
            let d = census.genes.iter().find(|(p, _)| *p == pos).map_or(usize::MAX, |(_, d)| *d);
            match census.per_depth.get(d) {
                Some(&n) if n > 0 => -(census.levels() as f64).ln() - (n as f64).ln(),
                _ => f64::NEG_INFINITY,
            }
        }
    }
}

/// The jump: `x` with everything below `v` regrown from the prior, genes
/// at unchanged places keeping their parameters. `None` when the regrowth
/// leaves the support (a gene deeper than `max_depth` or more than
/// `max_genes` genes): such a proposal has target density 0.
pub(crate) fn jump(x: &Genome, v: GenePos, graph: &GeneratorGraph, limits: &Limits, rng: &mut Rng) -> Option<Genome> {
    let mut y = x.clone();
    // `v` precedes its children, so cutting them never moves it.
    loop {
        let Some(c) = y.gene(v).links().find_map(child) else { break };
        y.cut(c);
    }
    let mut params = Vec::new();
    let mut stack = vec![(v, Some(v), x.depth(v))];
    while let Some((at, old, depth)) = stack.pop() {
        for (link, slot) in graph.symbol(y.gene(at).symbol()).link_slots() {
            if !rng.bernoulli(slot.prob) {
                continue;
            }
            if depth + 1 > limits.max_depth || y.len() >= limits.max_genes {
                return None;
            }
            let old_child = old.and_then(|o| child(x.gene(o).link(link)));
            params.clear();
            match old_child {
                Some(c) => params.extend(x.gene(c).params()),
                None => graph.draw_params(slot.target, rng, &mut params),
            }
            let c = y.grow(at, link, slot.target, &params, graph.symbol(slot.target).link_len());
            stack.push((c, old_child, depth + 1));
        }
    }
    Some(y)
}

fn child(link: Link) -> Option<GenePos> {
    match link {
        Link::Child(c) => Some(c),
        _ => None,
    }
}

/// The genes strictly below `v`, keyed by their path of link indices from
/// `v`: a jump at `v` keeps the parameters of the genes whose path exists
/// before and after.
pub(crate) fn paths_below(genome: &Genome, v: GenePos) -> BTreeMap<Vec<u32>, GenePos> {
    let mut out = BTreeMap::new();
    let mut stack = vec![(v, Vec::new())];
    while let Some((at, path)) = stack.pop() {
        for (i, l) in genome.gene(at).links().enumerate() {
            if let Some(c) = child(l) {
                let mut p = path.clone();
                p.push(i as u32);
                out.insert(p.clone(), c);
                stack.push((c, p));
            }
        }
    }
    out
}

/// The diffusion: new parameters for the gene at `pos`. With `drift`, each
/// continuous component moves by a Gaussian step of `scale` times its
/// range (uniform) or standard deviation (normal) and discrete ones are
/// redrawn; otherwise all are redrawn. Returns the log prior ratio
/// new/old of the drifted components (redrawn ones cancel against their
/// proposal), `-inf` when a step leaves the support.
pub(crate) fn diffuse(
    genome: &mut Genome,
    pos: GenePos,
    graph: &GeneratorGraph,
    drift: Option<f64>,
    rng: &mut Rng,
) -> f64 {
    let old: Vec<f64> = genome.gene(pos).params().collect();
    let mut ln_ratio = 0.0;
    let mut new = Vec::with_capacity(old.len());
    for (d, &v) in graph.symbol(genome.gene(pos).symbol()).components().zip(&old) {
        let sd = drift.and_then(|s| drift_sd(d, s));
        match sd {
            Some(sd) => {
                let w = rng.normal(v, sd);
                ln_ratio += d.log_prob(w) - d.log_prob(v);
                new.push(w);
            }
            None => new.push(d.sample(rng)),
        }
    }
    if ln_ratio.is_nan() {
        ln_ratio = f64::NEG_INFINITY;
    }
    if ln_ratio > f64::NEG_INFINITY {
        genome.set_params(pos, &new);
    }
    ln_ratio
}
