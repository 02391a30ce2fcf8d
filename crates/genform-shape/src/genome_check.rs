//! A fast test that a genome fits the grammar, for the hot path of
//! expression.
//!
//! [`Genome::validate`] finds and describes every problem, but it allocates
//! and binary-searches per link; optimizers express tens of thousands of
//! genomes a second. [`GenomeCheck::surely_valid`] answers only "valid or
//! not" from per-symbol tables built once per grammar and a reused buffer.
//! When it says no, the caller runs `validate` to describe the problem, so
//! errors are exactly those of `validate`. It checks everything `validate`
//! does (see the argument at [`GenomeCheck::surely_valid`]; a property test
//! compares the two): were it ever stricter, only speed would suffer, but
//! it must never be laxer.

use genform_core::genome::{GenePos, Link};
use genform_core::{Distribution, GeneratorGraph, Genome};

/// Membership test of one parameter value.
#[derive(Clone, Debug)]
enum ParamCheck {
    /// Uniform and truncated normal: finite and in `[lo, hi]`.
    Interval(f64, f64),
    /// Anything else: ask the distribution.
    Other(Distribution),
}

impl ParamCheck {
    fn new(d: &Distribution) -> Self {
        match *d {
            Distribution::Uniform { min, max } | Distribution::Normal { min, max, .. } => {
                ParamCheck::Interval(min, max)
            }
            _ => ParamCheck::Other(d.clone()),
        }
    }

    /// Same as [`Distribution::contains`].
    #[inline]
    fn contains(&self, v: f64) -> bool {
        match self {
            ParamCheck::Interval(lo, hi) => v.is_finite() && v >= *lo && v <= *hi,
            ParamCheck::Other(d) => d.contains(v),
        }
    }
}

/// What a gene of one symbol must look like.
#[derive(Clone, Debug)]
struct SymbolShape {
    params: usize,
    links: usize,
    /// Start of the symbol's entries in [`GenomeCheck::params`].
    first_param: usize,
    /// Start of the symbol's entries in [`GenomeCheck::targets`].
    first_link: usize,
}

/// Per-symbol tables of a generator graph for [`GenomeCheck::surely_valid`].
#[derive(Clone, Debug)]
pub(crate) struct GenomeCheck {
    root: u32,
    symbols: Vec<SymbolShape>,
    /// Per symbol, per parameter value.
    params: Vec<ParamCheck>,
    /// Per symbol, per link: the symbol its slot holds.
    targets: Vec<u32>,
}

impl GenomeCheck {
    /// The tables of `graph`.
    pub fn new(graph: &GeneratorGraph) -> Self {
        let mut check = GenomeCheck { root: graph.root, symbols: Vec::new(), params: Vec::new(), targets: Vec::new() };
        for spec in &graph.symbols {
            check.symbols.push(SymbolShape {
                params: spec.param_len(),
                links: spec.link_len(),
                first_param: check.params.len(),
                first_link: check.targets.len(),
            });
            check.params.extend(spec.params.iter().flat_map(|p| &p.components).map(ParamCheck::new));
            for s in &spec.slots {
                check.targets.extend(std::iter::repeat_n(s.target, s.max_count as usize));
            }
        }
        check
    }

    /// Whether `genome` passes [`Genome::validate`] against the graph these
    /// tables were built from. `starts` is scratch space.
    ///
    /// Why `true` implies `validate` passes: genes, symbols, counts,
    /// values, the root and every parent record (a gene start before the
    /// child, a link of the right slot that points back) are checked as
    /// `validate` does. For links, every non-root gene owns the distinct
    /// parent link pointing at it, so if the genome holds exactly
    /// `len - 1` child links there is no other, dangling one.
    pub fn surely_valid(&self, genome: &Genome, starts: &mut Vec<bool>) -> bool {
        if genome.is_empty() {
            return false;
        }
        starts.clear();
        starts.resize(genome.word_len(), false);
        let mut genes = 0usize;
        let mut child_links = 0usize;
        // The public genome API keeps the packing consistent, so the walk
        // itself cannot fail.
        for g in genome.iter() {
            let Some(shape) = self.symbols.get(g.symbol() as usize) else {
                return false;
            };
            if g.param_len() != shape.params || g.link_len() != shape.links {
                return false;
            }
            let checks = &self.params[shape.first_param..shape.first_param + shape.params];
            if !checks.iter().enumerate().all(|(i, c)| c.contains(g.param(i))) {
                return false;
            }
            match g.parent() {
                None if genes == 0 => {
                    if g.symbol() != self.root {
                        return false;
                    }
                }
                None => return false,
                Some(_) if genes == 0 => return false,
                Some((q, link)) => {
                    if q.0 >= g.pos.0 || !starts[q.0 as usize] {
                        return false;
                    }
                    let parent = genome.gene(q);
                    // Checked when the parent was visited: its links match its symbol.
                    let shape = &self.symbols[parent.symbol() as usize];
                    if link >= shape.links
                        || self.targets[shape.first_link + link] != g.symbol()
                        || parent.link(link) != Link::Child(GenePos(g.pos.0))
                    {
                        return false;
                    }
                }
            }
            child_links += (0..shape.links).filter(|&i| matches!(g.link(i), Link::Child(_))).count();
            starts[g.pos.0 as usize] = true;
            genes += 1;
        }
        genes == genome.len() && child_links == genes - 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::NoAssets;
    use genform_core::{Generator, Limits, Rng, SourceFile};
    use proptest::prelude::*;

    /// Every kind of distribution, multi-link slots, nested children.
    const GRAMMAR: &str = "
        A { param n: int(1, 3); param k: choice(0: 2, 1: 1, 5: 1); slot b: B p 0.9 x 2; slot c: C p 0.5;
            b; b; c; }
        B { param s: vec2 uniform(0.5, 1.5); param z: normal(0, 1) in [-2, 2]; slot c: C p 0.7; c; box; }
        C { param w: normal(1, 0.2); slot b: B p 0.3; b; sphere; }";

    /// One way to damage a genome through its public API.
    #[derive(Clone, Debug)]
    enum Damage {
        /// Sets parameter `i % len` of gene `g % genes` to `v`.
        Param(usize, usize, f64),
        /// Grows a gene of symbol `sym` with `params` values and `links`
        /// links at the first empty link of gene `g % genes`.
        Grow { g: usize, sym: u32, params: usize, links: usize },
        /// Copies the subtree of gene `from % genes` under the first empty
        /// link of gene `g % genes`, whatever symbol that link holds.
        Graft { g: usize, from: usize },
        /// Cuts gene `g % genes` (not the root).
        Cut(usize),
    }

    fn damage() -> impl Strategy<Value = Damage> {
        let value =
            prop_oneof![-3.0..3.0f64, Just(f64::NAN), Just(f64::INFINITY), Just(1.0), Just(2.0), Just(5.0), Just(2.5)];
        prop_oneof![
            (any::<usize>(), any::<usize>(), value).prop_map(|(g, i, v)| Damage::Param(g, i, v)),
            (any::<usize>(), 0..4u32, 0..5usize, 0..4usize).prop_map(|(g, sym, params, links)| Damage::Grow {
                g,
                sym,
                params,
                links
            }),
            (any::<usize>(), any::<usize>()).prop_map(|(g, from)| Damage::Graft { g, from }),
            any::<usize>().prop_map(Damage::Cut),
        ]
    }

    fn apply(genome: &mut Genome, d: &Damage) {
        let mut pos = Vec::new();
        genome.positions_into(&mut pos);
        let at = |i: usize| pos[i % pos.len()];
        let empty_link = |g: &Genome, p: GenePos| g.gene(p).links().position(|l| l == Link::Empty);
        match *d {
            Damage::Param(g, i, v) => {
                let n = genome.gene(at(g)).param_len();
                if n > 0 {
                    genome.set_param(at(g), i % n, v);
                }
            }
            Damage::Grow { g, sym, params, links } => {
                if let Some(link) = empty_link(genome, at(g)) {
                    genome.grow(at(g), link, sym, &vec![1.0; params], links);
                }
            }
            Damage::Graft { g, from } => {
                if let Some(link) = empty_link(genome, at(g)) {
                    let src = genome.clone();
                    genome.graft(&src, at(from), at(g), link);
                }
            }
            Damage::Cut(g) => {
                if pos.len() > 1 {
                    genome.cut(pos[1 + g % (pos.len() - 1)]);
                }
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]

        /// The fast check says "valid" exactly when `validate` does, so
        /// expression errors are `validate`'s and valid genomes skip it.
        #[test]
        fn agrees_with_validate(seed in any::<u64>(), damages in proptest::collection::vec(damage(), 0..3)) {
            let file = SourceFile::new("t.sg", GRAMMAR);
            let (g, _) = crate::compile(&file, &NoAssets).unwrap();
            let limits = Limits { max_genes: 30, ..Limits::default() };
            let mut genome = g.sample(&mut Rng::from_seed(seed), &limits).unwrap().genome;
            for d in &damages {
                apply(&mut genome, d);
            }
            let check = GenomeCheck::new(g.graph());
            let valid = genome.validate(g.graph());
            prop_assert_eq!(check.surely_valid(&genome, &mut Vec::new()), valid.is_ok(), "{:?}", valid);
        }
    }

    #[test]
    fn param_checks_agree_with_the_distributions() {
        let dists = [
            Distribution::Uniform { min: -1.0, max: 2.0 },
            Distribution::Uniform { min: 1.0, max: 1.0 },
            Distribution::Normal { mean: 0.0, sd: 1.0, min: f64::NEG_INFINITY, max: 0.5 },
            Distribution::Choice { values: vec![0.0, 1.0, 2.0], weights: vec![1.0, 0.0, 2.0] },
            Distribution::IntRange { min: -2, max: 3 },
        ];
        let values = [
            -3.0,
            -2.0,
            -1.0,
            -0.5,
            -0.0,
            0.0,
            0.5,
            1.0,
            1.5,
            2.0,
            2.5,
            3.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MIN_POSITIVE,
        ];
        for d in &dists {
            let c = ParamCheck::new(d);
            for v in values {
                assert_eq!(c.contains(v), d.contains(v), "{d:?} at {v}");
            }
        }
    }
}
