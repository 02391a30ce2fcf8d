//! Small generator graphs and objectives for tests, benchmarks and examples:
//! [`ship`] with [`ShipToy`] for the tree optimizers; [`SevensToy`],
//! [`TargetToy`] and [`HalfInvalidToy`] for the codon optimizers.

use crate::ge::Codons;
use crate::objective::Objective;
use genform_core::{Distribution, GeneratorGraph, Genome, ParamSpec, SlotSpec, SymbolSpec};

fn uniform(min: f64, max: f64) -> Distribution {
    Distribution::Uniform { min, max }
}

fn param(name: &str, components: Vec<Distribution>) -> ParamSpec {
    ParamSpec { name: name.into(), components }
}

fn slot(name: &str, target: u32, prob: f64, max_count: u32) -> SlotSpec {
    SlotSpec { name: name.into(), target, prob, max_count }
}

fn symbol(name: &str, params: Vec<ParamSpec>, slots: Vec<SlotSpec>) -> SymbolSpec {
    SymbolSpec { name: name.into(), params, slots, emits_geometry: true }
}

/// Symbol ids of [`ship`].
pub mod ship_ids {
    /// `S`, the root.
    pub const S: u32 = 0;
    /// `Body`, recursive.
    pub const BODY: u32 = 1;
    /// `Wing`, recursive, with a mandatory `Tip`.
    pub const WING: u32 = 2;
    /// `Tip`, a leaf.
    pub const TIP: u32 = 3;
    /// `Top`, a leaf.
    pub const TOP: u32 = 4;
}

/// A spaceship-like graph exercising every slot kind:
///
/// ```text
/// S                        → body: Body (p 1)
/// Body(size: 3 × U[0.5, 1.5]) → next: Body (p 0.6), wing: Wing (p 0.5, max 2),
///                             top: Top (p 0.3), ghost: Top (p 0)
/// Wing(len: U[0, 2], kind: int 1..3) → tip: Tip (p 1), sub: Wing (p 0.4)
/// Tip(style: choice {0: 1, 1: 2})
/// Top(h: normal(1, 0.3) in [0, 2])
/// ```
pub fn ship() -> GeneratorGraph {
    use ship_ids::*;
    GeneratorGraph {
        name: "ship".into(),
        root: S,
        symbols: vec![
            SymbolSpec { emits_geometry: false, ..symbol("S", vec![], vec![slot("body", BODY, 1.0, 1)]) },
            symbol(
                "Body",
                vec![param("size", vec![uniform(0.5, 1.5); 3])],
                vec![
                    slot("next", BODY, 0.6, 1),
                    slot("wing", WING, 0.5, 2),
                    slot("top", TOP, 0.3, 1),
                    slot("ghost", TOP, 0.0, 1),
                ],
            ),
            symbol(
                "Wing",
                vec![
                    param("len", vec![uniform(0.0, 2.0)]),
                    param("kind", vec![Distribution::IntRange { min: 1, max: 3 }]),
                ],
                vec![slot("tip", TIP, 1.0, 1), slot("sub", WING, 0.4, 1)],
            ),
            symbol(
                "Tip",
                vec![param("style", vec![Distribution::Choice { values: vec![0.0, 1.0], weights: vec![1.0, 2.0] }])],
                vec![],
            ),
            symbol(
                "Top",
                vec![param("h", vec![Distribution::Normal { mean: 1.0, sd: 0.3, min: 0.0, max: 2.0 }])],
                vec![],
            ),
        ],
    }
}

/// A toy objective on [`ship`] genomes: reach a target length while pushing
/// every gene's first parameter towards the top of its range.
///
/// `fitness = −|len − target| / 4 + 4 · mean over genes with parameters of
/// (first value − low) / (high − low)`, bounded above by 4. Random genomes
/// of the right length average about 2 on the second term; only selection
/// and many small improvements get close to 4.
#[derive(Clone, Copy, Debug)]
pub struct ShipToy {
    /// The length with no penalty.
    pub target: usize,
}

impl Objective for ShipToy {
    type Scratch = ();

    fn scratch(&self) {}

    fn evaluate(&self, genome: &Genome, _: &mut ()) -> f64 {
        use ship_ids::*;
        let (mut sum, mut n) = (0.0, 0usize);
        for g in genome.iter() {
            let (lo, hi) = match g.symbol() {
                BODY => (0.5, 1.5),
                WING | TOP => (0.0, 2.0),
                TIP => (0.0, 1.0),
                _ => continue,
            };
            sum += (g.param(0) - lo) / (hi - lo);
            n += 1;
        }
        let quality = if n == 0 { 0.0 } else { sum / n as f64 };
        -(genome.len() as f64 - self.target as f64).abs() / 4.0 + 4.0 * quality
    }
}

/// A toy codon objective: how many of the first 20 codons are ≡ 0 (mod 7),
/// 0 to 20. A random codon in 0..1000 qualifies with probability 0.143, so
/// random genomes score about 3 and the best of thousands about 9.
#[derive(Clone, Copy, Debug)]
pub struct SevensToy;

impl Objective<Codons> for SevensToy {
    type Scratch = ();

    fn scratch(&self) {}

    fn evaluate(&self, codons: &Codons, _: &mut ()) -> f64 {
        codons.iter().take(20).filter(|&&c| c % 7 == 0).count() as f64
    }
}

/// A toy codon objective that, like a GE mapper, reads a prefix whose
/// length the genome decides: the first codon picks `k = 8 + c₀ mod 16`,
/// and the fitness is how many of the first `k` codons are ≡ 0 (mod 7)
/// (NaN when the genome is shorter than `k`). It tells GE what it reads.
#[derive(Clone, Copy, Debug)]
pub struct PrefixToy;

impl PrefixToy {
    fn reads(codons: &Codons) -> usize {
        codons.first().map_or(0, |c| 8 + (c % 16) as usize)
    }
}

impl Objective<Codons> for PrefixToy {
    type Scratch = ();

    fn scratch(&self) {}

    fn evaluate(&self, codons: &Codons, _: &mut ()) -> f64 {
        let k = Self::reads(codons);
        if k == 0 || codons.len() < k {
            return f64::NAN;
        }
        codons[..k].iter().filter(|&&c| c % 7 == 0).count() as f64
    }

    fn expressed(&self, codons: &Codons, _: &mut ()) -> Option<usize> {
        Some(Self::reads(codons).min(codons.len()))
    }
}

/// A toy codon objective: match a target codon sequence.
/// `fitness = −Σ_i |codon_i − target_i|` over the target's positions; a
/// missing codon costs 1000. 0 is a perfect match.
#[derive(Clone, Debug)]
pub struct TargetToy {
    /// The codons to match, from the first position on.
    pub target: Vec<u32>,
}

impl Objective<Codons> for TargetToy {
    type Scratch = ();

    fn scratch(&self) {}

    fn evaluate(&self, codons: &Codons, _: &mut ()) -> f64 {
        let distance = |(i, &t): (usize, &u32)| codons.get(i).map_or(1000.0, |&c| (c as f64 - t as f64).abs());
        -self.target.iter().enumerate().map(distance).sum::<f64>()
    }
}

/// [`SevensToy`], but invalid (NaN) when the first codon is odd: half the
/// random genomes, as when a GE mapping fails.
#[derive(Clone, Copy, Debug)]
pub struct HalfInvalidToy;

impl Objective<Codons> for HalfInvalidToy {
    type Scratch = ();

    fn scratch(&self) {}

    fn evaluate(&self, codons: &Codons, s: &mut ()) -> f64 {
        match codons.first() {
            Some(c) if c % 2 == 0 => SevensToy.evaluate(codons, s),
            _ => f64::NAN,
        }
    }
}
