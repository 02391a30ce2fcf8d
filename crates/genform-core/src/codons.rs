//! Codon genomes as a source of random choices, for grammatical evolution.
//!
//! In grammatical evolution (GE) a genome is a list of integer codons and
//! every random decision of a generator consumes the next one. A
//! [`CodonSource`] reads a codon slice that way and answers the three kinds
//! of question generators ask:
//!
//! - [`Draws::next_f64`]: a uniform in `(0, 1)`, `(c + 0.5) / range`;
//! - [`CodonSource::below`]: an index in `0..n`, `c mod n` (the GE mod rule);
//! - [`CodonSource::choose`]: an index drawn by weight, by roulette over the
//!   weights with the uniform of one codon, so a weight keeps its meaning
//!   (an option of weight 3 next to one of weight 1 takes three quarters of
//!   the codon values) and an option of weight zero is never chosen.
//!
//! Each call reads exactly one codon, `c = codon mod range`. Reading past
//! the end wraps to the start, at most `max_wraps` times (the GE mapper's
//! rule, see `genform-ge`); the read after that *exhausts* the source. An
//! exhausted source keeps answering as if every codon were 0 (the first
//! option, the first positive weight, `0.5 / range`), so the derivation it
//! drives still terminates, and [`CodonSource::exhausted`] tells the caller
//! to mark the individual invalid. An empty genome is exhausted at its
//! first read.
//!
//! ```
//! use genform_core::codons::CodonSource;
//! use genform_core::Draws;
//! let genome = [7, 1002, 5];
//! let mut c = CodonSource::new(&genome, 1000, 1);
//! assert_eq!(c.below(3), 1); // 7 mod 3
//! assert_eq!(c.choose(&[1.0, 0.0, 3.0]), 0); // codon 2 of 1000: the first quarter
//! assert_eq!(c.next_f64(), 5.5 / 1000.0);
//! assert_eq!((c.used(), c.wraps(), c.exhausted()), (3, 0, false));
//! c.below(2); // wraps to the start
//! assert_eq!((c.used(), c.wraps()), (4, 1));
//! c.below(2);
//! c.below(2);
//! assert!(!c.exhausted());
//! assert_eq!(c.below(2), 0); // past the last allowed wrap
//! assert!(c.exhausted());
//! ```

use crate::rng::Draws;

/// The codon range GE genomes use by default (codons `0..1000`).
pub const DEFAULT_RANGE: u32 = 1000;

/// How often a [`CodonSource`] wraps to the start of its genome by default
/// before it is exhausted.
pub const DEFAULT_MAX_WRAPS: u32 = 2;

/// Random choices read from a codon genome, one codon per choice (see the
/// [module documentation](self)).
#[derive(Clone, Debug)]
pub struct CodonSource<'a> {
    codons: &'a [u32],
    /// The modulus, widened so that a range of 0 can mean 2³².
    range: u64,
    max_wraps: u32,
    pos: usize,
    used: usize,
    wraps: u32,
    exhausted: bool,
}

impl<'a> CodonSource<'a> {
    /// A source reading `codons`, each taken modulo `range` (0 means no
    /// reduction: the range is 2³²), wrapping to the start at most
    /// `max_wraps` times. Draws resolve at most `range` distinct values,
    /// so the range should be well above the largest `n` asked of
    /// [`below`](Self::below).
    pub fn new(codons: &'a [u32], range: u32, max_wraps: u32) -> CodonSource<'a> {
        let range = if range == 0 { 1u64 << 32 } else { u64::from(range) };
        CodonSource { codons, range, max_wraps, pos: 0, used: 0, wraps: 0, exhausted: false }
    }

    /// A source with [`DEFAULT_RANGE`] and [`DEFAULT_MAX_WRAPS`].
    pub fn with_defaults(codons: &'a [u32]) -> CodonSource<'a> {
        CodonSource::new(codons, DEFAULT_RANGE, DEFAULT_MAX_WRAPS)
    }

    /// The next codon modulo the range (0 once exhausted).
    pub fn codon(&mut self) -> u64 {
        if self.exhausted {
            return 0;
        }
        if self.pos >= self.codons.len() {
            if self.codons.is_empty() || self.wraps >= self.max_wraps {
                self.exhausted = true;
                return 0;
            }
            self.wraps += 1;
            self.pos = 0;
        }
        let c = self.codons[self.pos];
        self.pos += 1;
        self.used += 1;
        u64::from(c) % self.range
    }

    /// An index in `0..n` from one codon: `codon mod n`. For `n = 0` it
    /// returns 0 and reads nothing (there is no index to pick). Callers
    /// with a single option usually skip the call, as the GE mapper does.
    pub fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            return 0;
        }
        (self.codon() % n as u64) as usize
    }

    /// An index into `weights` drawn by weight from one codon: the codon's
    /// uniform `(c + 0.5) / range` walks the cumulative weights (roulette),
    /// so option `i` takes about `range · wᵢ / Σw` of the codon values.
    /// Weights that are not positive (zero, negative, NaN) are never
    /// chosen; when infinite weights are present they share the choice
    /// equally and the finite ones are never chosen. Returns 0 when no
    /// weight is positive (or `weights` is empty), after reading the codon
    /// all the same, so a choice always costs one codon.
    pub fn choose(&mut self, weights: &[f64]) -> usize {
        let u = self.unit();
        let positive = |w: f64| w > 0.0;
        let mut total: f64 = weights.iter().copied().filter(|&w| positive(w)).sum();
        let infinite = total.is_infinite();
        let weight = |w: f64| {
            if !positive(w) {
                0.0
            } else if infinite {
                if w.is_infinite() { 1.0 } else { 0.0 }
            } else {
                w
            }
        };
        if infinite {
            total = weights.iter().filter(|w| w.is_infinite() && **w > 0.0).count() as f64;
        }
        if total <= 0.0 {
            return 0;
        }
        let target = u * total;
        let mut acc = 0.0;
        let mut last = 0;
        for (i, &w) in weights.iter().enumerate() {
            let w = weight(w);
            if w > 0.0 {
                acc += w;
                if target < acc {
                    return i;
                }
                last = i;
            }
        }
        // Rounding left the uniform past the last cumulative sum.
        last
    }

    /// Codons read so far, re-reads after wrapping included (reads answered
    /// after exhaustion are not counted).
    pub fn used(&self) -> usize {
        self.used
    }

    /// How often the source wrapped to the start of the genome.
    pub fn wraps(&self) -> u32 {
        self.wraps
    }

    /// Whether a read was asked for after the last allowed wrap (or of an
    /// empty genome): the choices since then are all 0 and the individual
    /// should be marked invalid.
    pub fn exhausted(&self) -> bool {
        self.exhausted
    }

    /// The genome.
    pub fn codons(&self) -> &'a [u32] {
        self.codons
    }

    /// The modulus codons are taken by (2³² for a range given as 0).
    pub fn range(&self) -> u64 {
        self.range
    }

    /// How many wraps are allowed.
    pub fn max_wraps(&self) -> u32 {
        self.max_wraps
    }

    /// The uniform of one codon, `(c + 0.5) / range`, in `(0, 1)`.
    fn unit(&mut self) -> f64 {
        (self.codon() as f64 + 0.5) / self.range as f64
    }
}

impl Draws for CodonSource<'_> {
    /// `(c + 0.5) / range` from one codon: strictly inside `(0, 1)`, so a
    /// draw feeding a logarithm (normal samples) stays finite.
    fn next_f64(&mut self) -> f64 {
        self.unit()
    }

    /// `codon mod n` ([`CodonSource::below`]).
    fn below(&mut self, n: usize) -> usize {
        CodonSource::below(self, n)
    }

    /// One codon walks the weights ([`CodonSource::choose`]).
    fn choose(&mut self, weights: &[f64]) -> usize {
        CodonSource::choose(self, weights)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn codons_are_read_in_order_modulo_the_range() {
        let g = [3, 1004, 999, 1000];
        let mut c = CodonSource::new(&g, 1000, 0);
        let read: Vec<u64> = (0..4).map(|_| c.codon()).collect();
        assert_eq!(read, [3, 4, 999, 0]);
        assert_eq!((c.used(), c.wraps(), c.exhausted()), (4, 0, false));
        assert_eq!(c.codon(), 0);
        assert!(c.exhausted(), "no wraps allowed");
        assert_eq!(c.used(), 4, "exhausted reads are not counted");
    }

    #[test]
    fn wrapping_rereads_and_then_exhausts() {
        let g = [5, 6];
        let mut c = CodonSource::new(&g, 1000, 2);
        let read: Vec<u64> = (0..6).map(|_| c.codon()).collect();
        assert_eq!(read, [5, 6, 5, 6, 5, 6]);
        assert_eq!((c.used(), c.wraps(), c.exhausted()), (6, 2, false));
        // Exhausted: every answer is that of codon 0, and stays so.
        assert_eq!(c.below(7), 0);
        assert!(c.exhausted());
        assert_eq!(c.choose(&[0.0, 2.0, 1.0]), 1, "the first positive weight");
        assert_eq!(c.next_f64(), 0.5 / 1000.0);
        assert_eq!((c.used(), c.wraps()), (6, 2));
    }

    #[test]
    fn an_empty_genome_is_exhausted_at_once() {
        let mut c = CodonSource::with_defaults(&[]);
        assert!(!c.exhausted());
        assert_eq!(c.below(4), 0);
        assert!(c.exhausted());
        assert_eq!((c.used(), c.wraps()), (0, 0));
    }

    #[test]
    fn below_is_the_mod_rule() {
        let g = [0, 1, 2, 3, 4, 5, 17];
        let mut c = CodonSource::new(&g, 1000, 0);
        let picks: Vec<usize> = (0..7).map(|_| c.below(3)).collect();
        assert_eq!(picks, [0, 1, 2, 0, 1, 2, 2]);
        // n = 0 has no answer and reads nothing.
        let mut c = CodonSource::new(&g, 1000, 0);
        assert_eq!(c.below(0), 0);
        assert_eq!(c.used(), 0);
    }

    #[test]
    fn unit_draws_are_codon_midpoints() {
        let g = [0, 999, 250];
        let mut c = CodonSource::new(&g, 1000, 0);
        assert_eq!(c.next_f64(), 0.0005);
        assert_eq!(c.next_f64(), 0.9995);
        assert_eq!(c.next_f64(), 0.2505);
        // A range of 0 means 2³²: codons are used as they are.
        let g = [u32::MAX];
        let mut c = CodonSource::new(&g, 0, 0);
        assert_eq!(c.range(), 1 << 32);
        let u = c.next_f64();
        assert!(u < 1.0 && u > 0.999_999_999, "{u}");
    }

    #[test]
    fn choose_gives_each_option_its_share_of_the_codon_values() {
        // Over every codon value once, the shares are the weights' exactly.
        let g: Vec<u32> = (0..1000).collect();
        let mut c = CodonSource::new(&g, 1000, 0);
        let mut counts = [0usize; 4];
        for _ in 0..1000 {
            counts[c.choose(&[1.0, 0.0, 3.0, -2.0])] += 1;
        }
        assert_eq!(counts, [250, 0, 750, 0]);
        assert_eq!(c.used(), 1000, "one codon per choice");
        // Codons just either side of the boundary.
        let g = [249, 250];
        let mut c = CodonSource::new(&g, 1000, 0);
        assert_eq!((c.choose(&[1.0, 3.0]), c.choose(&[1.0, 3.0])), (0, 1));
    }

    #[test]
    fn choose_without_positive_weights_still_reads_a_codon() {
        let g = [7, 8];
        let mut c = CodonSource::new(&g, 1000, 0);
        assert_eq!(c.choose(&[]), 0);
        assert_eq!(c.choose(&[0.0, f64::NAN, -1.0]), 0);
        assert_eq!(c.used(), 2);
    }

    #[test]
    fn infinite_weights_share_the_choice() {
        let g = [100, 900];
        let mut c = CodonSource::new(&g, 1000, 0);
        let w = [1.0, f64::INFINITY, 5.0, f64::INFINITY];
        assert_eq!((c.choose(&w), c.choose(&w)), (1, 3));
    }

    proptest! {
        #[test]
        fn reads_never_panic_and_keep_their_books(
            genome in prop::collection::vec(any::<u32>(), 0..20),
            range in 0u32..2000,
            max_wraps in 0u32..4,
            calls in prop::collection::vec((0u8..3, 0usize..50, prop::collection::vec(-1.0f64..5.0, 0..6)), 0..120),
        ) {
            let mut c = CodonSource::new(&genome, range, max_wraps);
            let capacity = genome.len() * (max_wraps as usize + 1);
            let mut asked = 0usize;
            for (kind, n, weights) in &calls {
                match kind {
                    0 => {
                        let i = c.below(*n);
                        prop_assert!(i < (*n).max(1));
                        // below(0) has no answer and reads nothing.
                        asked += usize::from(*n > 0);
                    }
                    1 => {
                        let i = c.choose(weights);
                        if weights.iter().any(|&w| w > 0.0) {
                            prop_assert!(weights[i] > 0.0, "chose weight {} of {:?}", weights[i], weights);
                        } else {
                            prop_assert_eq!(i, 0);
                        }
                        asked += 1;
                    }
                    _ => {
                        let u = c.next_f64();
                        prop_assert!(u > 0.0 && u < 1.0);
                        asked += 1;
                    }
                }
                // One codon a call until the genome and its wraps are spent.
                prop_assert_eq!(c.used(), asked.min(capacity));
                prop_assert_eq!(c.exhausted(), asked > capacity);
                prop_assert!(c.wraps() <= max_wraps);
                if c.used() > 0 {
                    // Whole passes plus the position in the current one.
                    prop_assert_eq!(c.used(), c.wraps() as usize * genome.len() + c.pos);
                }
            }
        }
    }
}
