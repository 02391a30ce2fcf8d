//! The generator graph: what every formalism compiles to and every
//! optimizer works on.
//!
//! Nodes are *symbols* (parameterized operations). Each symbol declares its
//! random parameters ([`ParamSpec`], each component drawn from a
//! [`Distribution`]) and its *child slots* ([`SlotSpec`]): the objects it may
//! produce, each expressed with a probability, up to a maximum count. A slot
//! with `max_count = k` owns `k` *links* in a gene; each link is expressed
//! independently with the slot's probability.

use crate::rng::Rng;
use serde::{Deserialize, Serialize};

/// Index into [`GeneratorGraph::symbols`].
pub type SymbolId = u32;

/// Distribution of one scalar parameter component.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Distribution {
    /// Uniform on `[min, max]` (a point mass when `min == max`).
    Uniform {
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
    },
    /// Normal with mean and standard deviation, truncated to `[min, max]`
    /// (use infinities for no bound).
    Normal {
        /// Mean.
        mean: f64,
        /// Standard deviation (≥ 0).
        sd: f64,
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
    },
    /// One of `values`, drawn with probability proportional to `weights`.
    /// Weighted alternatives compile to this with values 0, 1, 2, ….
    Choice {
        /// The possible values.
        values: Vec<f64>,
        /// Non-negative weights, same length, not all zero.
        weights: Vec<f64>,
    },
    /// A uniform integer in the inclusive range `[min, max]`.
    IntRange {
        /// Smallest value.
        min: i64,
        /// Largest value.
        max: i64,
    },
}

/// How many rejection tries a truncated normal gets before clamping.
const NORMAL_TRIES: usize = 64;

impl Distribution {
    /// Checks the distribution's own consistency (bounds in order, finite,
    /// weights usable); the message says what is wrong.
    pub fn check(&self) -> Result<(), String> {
        match self {
            Distribution::Uniform { min, max } => {
                if !min.is_finite() || !max.is_finite() {
                    return Err(format!("uniform bounds must be finite, got [{min}, {max}]"));
                }
                if min > max {
                    return Err(format!("uniform range is empty: min {min} > max {max}"));
                }
            }
            Distribution::Normal { mean, sd, min, max } => {
                if !mean.is_finite() || !sd.is_finite() || *sd < 0.0 {
                    return Err(format!("normal needs a finite mean and sd ≥ 0, got mean {mean}, sd {sd}"));
                }
                if min.is_nan() || max.is_nan() || min > max {
                    return Err(format!("normal bounds are empty: [{min}, {max}]"));
                }
            }
            Distribution::Choice { values, weights } => {
                if values.is_empty() || values.len() != weights.len() {
                    return Err("choice needs one weight per value and at least one value".into());
                }
                if values.iter().any(|v| !v.is_finite()) {
                    return Err("choice values must be finite".into());
                }
                if weights.iter().any(|w| !w.is_finite() || *w < 0.0) || weights.iter().all(|w| *w == 0.0) {
                    return Err("choice weights must be finite, ≥ 0 and not all 0".into());
                }
            }
            Distribution::IntRange { min, max } => {
                if min > max {
                    return Err(format!("integer range is empty: min {min} > max {max}"));
                }
            }
        }
        Ok(())
    }

    /// Draws one value.
    pub fn sample(&self, rng: &mut Rng) -> f64 {
        match self {
            Distribution::Uniform { min, max } => rng.uniform(*min, *max),
            Distribution::Normal { mean, sd, min, max } => {
                for _ in 0..NORMAL_TRIES {
                    let v = rng.normal(*mean, *sd);
                    if v >= *min && v <= *max {
                        return v;
                    }
                }
                mean.clamp(*min, *max)
            }
            Distribution::Choice { values, weights } => values[rng.weighted_index(weights).unwrap_or(0)],
            Distribution::IntRange { min, max } => rng.int_inclusive(*min, *max) as f64,
        }
    }

    /// Whether `v` is a value this distribution can produce.
    pub fn contains(&self, v: f64) -> bool {
        if !v.is_finite() {
            return false;
        }
        match self {
            Distribution::Uniform { min, max } => v >= *min && v <= *max,
            Distribution::Normal { min, max, .. } => v >= *min && v <= *max,
            Distribution::Choice { values, weights } => values.iter().zip(weights).any(|(x, w)| *x == v && *w > 0.0),
            Distribution::IntRange { min, max } => v.fract() == 0.0 && v >= *min as f64 && v <= *max as f64,
        }
    }

    /// Log density (continuous) or log probability (discrete) of `v`,
    /// `-inf` outside the support. Truncated normals are renormalized only
    /// approximately (the normalizing constant is omitted), which cancels in
    /// ratios of the same distribution.
    pub fn log_prob(&self, v: f64) -> f64 {
        if !self.contains(v) {
            return f64::NEG_INFINITY;
        }
        match self {
            Distribution::Uniform { min, max } => {
                if max > min {
                    -(max - min).ln()
                } else {
                    0.0
                }
            }
            Distribution::Normal { mean, sd, .. } => {
                if *sd == 0.0 {
                    return 0.0;
                }
                let z = (v - mean) / sd;
                -0.5 * z * z - sd.ln() - 0.5 * (std::f64::consts::TAU).ln()
            }
            Distribution::Choice { values, weights } => {
                let total: f64 = weights.iter().sum();
                let w: f64 = values.iter().zip(weights).filter(|(x, _)| **x == v).map(|(_, w)| w).sum();
                (w / total).ln()
            }
            Distribution::IntRange { min, max } => -((max - min + 1) as f64).ln(),
        }
    }

    /// A short human-readable form, e.g. `uniform(0.6, 1.5)`.
    pub fn describe(&self) -> String {
        match self {
            Distribution::Uniform { min, max } => format!("uniform({min}, {max})"),
            Distribution::Normal { mean, sd, min, max } => {
                if min.is_infinite() && max.is_infinite() {
                    format!("normal({mean}, {sd})")
                } else {
                    format!("normal({mean}, {sd}) in [{min}, {max}]")
                }
            }
            Distribution::Choice { values, weights } => {
                let items: Vec<String> = values.iter().zip(weights).map(|(v, w)| format!("{v}: {w}")).collect();
                format!("choice({})", items.join(", "))
            }
            Distribution::IntRange { min, max } => format!("int({min}, {max})"),
        }
    }
}

/// A named random parameter of a symbol: a scalar or a vector whose
/// components each have a distribution.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ParamSpec {
    /// Name as written in the grammar.
    pub name: String,
    /// One distribution per component (length 1 for scalars).
    pub components: Vec<Distribution>,
}

impl ParamSpec {
    /// Number of scalar values this parameter occupies in a gene.
    pub fn dim(&self) -> usize {
        self.components.len()
    }
}

/// A child slot: an object a symbol may produce.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SlotSpec {
    /// Name, unique within its symbol.
    pub name: String,
    /// Symbol of the child.
    pub target: SymbolId,
    /// Probability that each of the slot's links is expressed in an
    /// uncontrolled derivation (1 = always; never cut by optimizers).
    pub prob: f64,
    /// How many children the slot can hold (links per gene).
    pub max_count: u32,
}

/// A node of the generator graph.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SymbolSpec {
    /// Name as written in the grammar.
    pub name: String,
    /// Random parameters, in gene order.
    pub params: Vec<ParamSpec>,
    /// Child slots, in gene order.
    pub slots: Vec<SlotSpec>,
    /// Whether expressing this symbol emits geometry by itself (SMC grows
    /// until a new geometric object appears).
    pub emits_geometry: bool,
}

impl SymbolSpec {
    /// Scalar values per gene of this symbol.
    pub fn param_len(&self) -> usize {
        self.params.iter().map(ParamSpec::dim).sum()
    }

    /// Links per gene of this symbol.
    pub fn link_len(&self) -> usize {
        self.slots.iter().map(|s| s.max_count as usize).sum()
    }

    /// Offset of parameter `i`'s first value within the gene's values.
    pub fn param_offset(&self, i: usize) -> usize {
        self.params[..i].iter().map(ParamSpec::dim).sum()
    }

    /// First link index of slot `i`.
    pub fn link_offset(&self, slot: usize) -> usize {
        self.slots[..slot].iter().map(|s| s.max_count as usize).sum()
    }

    /// The slot index and the position within the slot of link `link`.
    pub fn slot_of_link(&self, link: usize) -> Option<(usize, u32)> {
        let mut base = 0usize;
        for (i, s) in self.slots.iter().enumerate() {
            if link < base + s.max_count as usize {
                return Some((i, (link - base) as u32));
            }
            base += s.max_count as usize;
        }
        None
    }

    /// Index of the slot named `name`.
    pub fn slot_index(&self, name: &str) -> Option<usize> {
        self.slots.iter().position(|s| s.name == name)
    }

    /// Every link of a gene of this symbol with the slot it belongs to, in
    /// gene order: `(link index, slot)`, a slot repeated `max_count` times.
    pub fn link_slots(&self) -> impl Iterator<Item = (usize, &SlotSpec)> {
        self.slots.iter().flat_map(|s| std::iter::repeat_n(s, s.max_count as usize)).enumerate()
    }

    /// Iterator over the flat component distributions, in gene order.
    pub fn components(&self) -> impl Iterator<Item = &Distribution> {
        self.params.iter().flat_map(|p| p.components.iter())
    }
}

/// Largest number of parameter values or links a gene may have.
pub const MAX_GENE_FIELDS: usize = u16::MAX as usize;

/// Symbols and their slots: the search space of a generator.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GeneratorGraph {
    /// Name of the generator (for messages and genome files).
    pub name: String,
    /// All symbols.
    pub symbols: Vec<SymbolSpec>,
    /// The start symbol.
    pub root: SymbolId,
}

impl GeneratorGraph {
    /// The symbol with id `id`.
    #[inline]
    pub fn symbol(&self, id: SymbolId) -> &SymbolSpec {
        &self.symbols[id as usize]
    }

    /// The id of the symbol named `name`.
    pub fn symbol_id(&self, name: &str) -> Option<SymbolId> {
        self.symbols.iter().position(|s| s.name == name).map(|i| i as SymbolId)
    }

    /// Checks internal consistency: root and slot targets exist, names are
    /// unique, distributions are valid, probabilities lie in [0, 1], genes fit
    /// the packed layout. Each problem is one message.
    pub fn check(&self) -> Result<(), Vec<String>> {
        let mut errs = Vec::new();
        let n = self.symbols.len() as u32;
        if self.root >= n {
            errs.push(format!("root symbol {} does not exist", self.root));
        }
        for (i, s) in self.symbols.iter().enumerate() {
            if self.symbols[..i].iter().any(|t| t.name == s.name) {
                errs.push(format!("symbol `{}` is defined twice", s.name));
            }
            for p in &s.params {
                if p.components.is_empty() {
                    errs.push(format!("parameter `{}.{}` has no components", s.name, p.name));
                }
                for d in &p.components {
                    if let Err(e) = d.check() {
                        errs.push(format!("parameter `{}.{}`: {e}", s.name, p.name));
                    }
                }
            }
            for (j, slot) in s.slots.iter().enumerate() {
                if slot.target >= n {
                    errs.push(format!("slot `{}.{}` targets a missing symbol", s.name, slot.name));
                }
                if !(0.0..=1.0).contains(&slot.prob) {
                    errs.push(format!("slot `{}.{}` has probability {} outside [0, 1]", s.name, slot.name, slot.prob));
                }
                if slot.max_count == 0 {
                    errs.push(format!("slot `{}.{}` has max count 0", s.name, slot.name));
                }
                if s.slots[..j].iter().any(|t| t.name == slot.name) {
                    errs.push(format!("slot `{}.{}` is declared twice", s.name, slot.name));
                }
            }
            if s.param_len() > MAX_GENE_FIELDS || s.link_len() > MAX_GENE_FIELDS {
                errs.push(format!("symbol `{}` has more than {MAX_GENE_FIELDS} parameter values or links", s.name));
            }
        }
        if errs.is_empty() { Ok(()) } else { Err(errs) }
    }

    /// Draws fresh parameter values for `symbol`, appending them to `out`.
    pub fn draw_params(&self, symbol: SymbolId, rng: &mut Rng, out: &mut Vec<f64>) {
        out.extend(self.symbol(symbol).components().map(|d| d.sample(rng)));
    }

    /// Every edge of the graph as `(parent symbol, slot index)`.
    pub fn edges(&self) -> impl Iterator<Item = (SymbolId, usize)> + '_ {
        self.symbols.iter().enumerate().flat_map(|(i, s)| (0..s.slots.len()).map(move |j| (i as SymbolId, j)))
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A small graph used by core tests: S → A (p 1), A → A (p 0.5, max 2), A → B (p 0.3).
    pub fn tiny() -> GeneratorGraph {
        GeneratorGraph {
            name: "tiny".into(),
            root: 0,
            symbols: vec![
                SymbolSpec {
                    name: "S".into(),
                    params: vec![],
                    slots: vec![SlotSpec { name: "a".into(), target: 1, prob: 1.0, max_count: 1 }],
                    emits_geometry: false,
                },
                SymbolSpec {
                    name: "A".into(),
                    params: vec![
                        ParamSpec {
                            name: "size".into(),
                            components: vec![Distribution::Uniform { min: 0.5, max: 1.5 }; 3],
                        },
                        ParamSpec { name: "k".into(), components: vec![Distribution::IntRange { min: 1, max: 3 }] },
                    ],
                    slots: vec![
                        SlotSpec { name: "next".into(), target: 1, prob: 0.5, max_count: 2 },
                        SlotSpec { name: "leaf".into(), target: 2, prob: 0.3, max_count: 1 },
                    ],
                    emits_geometry: true,
                },
                SymbolSpec {
                    name: "B".into(),
                    params: vec![ParamSpec {
                        name: "kind".into(),
                        components: vec![Distribution::Choice { values: vec![0.0, 1.0], weights: vec![1.0, 2.0] }],
                    }],
                    slots: vec![],
                    emits_geometry: true,
                },
            ],
        }
    }

    #[test]
    fn layout_helpers() {
        let g = tiny();
        g.check().unwrap();
        let a = g.symbol(1);
        assert_eq!(a.param_len(), 4);
        assert_eq!(a.link_len(), 3);
        assert_eq!(a.param_offset(1), 3);
        assert_eq!(a.link_offset(1), 2);
        assert_eq!(a.slot_of_link(1), Some((0, 1)));
        assert_eq!(a.slot_of_link(2), Some((1, 0)));
        assert_eq!(a.slot_of_link(3), None);
        assert_eq!(g.edges().count(), 3);
    }

    #[test]
    fn check_reports_every_problem() {
        let mut g = tiny();
        g.symbols[1].params[0].components[0] = Distribution::Uniform { min: 2.0, max: 1.0 };
        g.symbols[1].slots[0].prob = 1.5;
        g.symbols[1].slots[1].target = 9;
        let errs = g.check().unwrap_err();
        assert_eq!(errs.len(), 3, "{errs:?}");
        assert!(errs[0].contains("min 2 > max 1"));
    }

    #[test]
    fn distributions_sample_inside_their_support() {
        let mut rng = Rng::from_seed(9);
        let ds = [
            Distribution::Uniform { min: -1.0, max: 2.0 },
            Distribution::Normal { mean: 0.0, sd: 1.0, min: -0.5, max: 0.5 },
            Distribution::Choice { values: vec![3.0, 7.0], weights: vec![0.0, 1.0] },
            Distribution::IntRange { min: 2, max: 4 },
        ];
        for d in &ds {
            for _ in 0..1000 {
                let v = d.sample(&mut rng);
                assert!(d.contains(v), "{d:?} gave {v}");
                assert!(d.log_prob(v).is_finite());
            }
        }
        assert_eq!(ds[2].sample(&mut rng), 7.0);
        assert!(!ds[2].contains(3.0));
        assert_eq!(ds[3].log_prob(2.5), f64::NEG_INFINITY);
    }
}
