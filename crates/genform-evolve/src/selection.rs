//! Parent selection: roulette wheel, k-tournament and uniform (paper §3.1.4).
//!
//! Invalid individuals (non-finite fitness) get weight 0 in roulette and
//! never enter tournaments or uniform draws, unless no individual is valid.

use genform_core::Rng;
use serde::{Deserialize, Serialize};
use std::cmp::Ordering;

/// How one parent is chosen. In configuration files: `"roulette"`,
/// `"random"` or `{ tournament = 10 }`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Selection {
    /// Probability ∝ fitness − worst valid fitness (the worst gets 0; when
    /// every weight is 0, uniform).
    Roulette,
    /// `k` individuals drawn uniformly with replacement; the best wins, ties
    /// going to the lower index. Invalid individuals never enter (they would
    /// lose anyway), unless none is valid.
    Tournament(usize),
    /// Uniform.
    Random,
}

/// Orders fitness values best first; every non-finite value is worse than
/// every finite one and ties with the other non-finite ones.
pub fn rank(a: f64, b: f64) -> Ordering {
    match (a.is_finite(), b.is_finite()) {
        (true, true) => b.total_cmp(&a),
        (true, false) => Ordering::Less,
        (false, true) => Ordering::Greater,
        (false, false) => Ordering::Equal,
    }
}

/// A [`Selection`] prepared for one population's fitness values.
#[derive(Clone, Debug)]
pub struct Selector<'a> {
    kind: Selection,
    fitness: &'a [f64],
    /// Roulette: cumulative weights in index order.
    cumulative: Vec<f64>,
    /// Indices of the valid individuals (all indices when none is valid).
    valid: Vec<usize>,
}

impl<'a> Selector<'a> {
    /// Prepares `kind` over `fitness` (one value per individual, at least one).
    pub fn new(kind: Selection, fitness: &'a [f64]) -> Self {
        assert!(!fitness.is_empty(), "selection from an empty population");
        let mut valid: Vec<usize> = (0..fitness.len()).filter(|&i| fitness[i].is_finite()).collect();
        if valid.is_empty() {
            valid = (0..fitness.len()).collect();
        }
        let mut cumulative = Vec::new();
        if kind == Selection::Roulette {
            let worst = fitness.iter().copied().filter(|f| f.is_finite()).fold(f64::INFINITY, f64::min);
            let mut sum = 0.0;
            for &f in fitness {
                // Differences of huge finite values may overflow; such weights count as 0.
                let w = if f.is_finite() { f - worst } else { 0.0 };
                sum += if w.is_finite() && w > 0.0 { w } else { 0.0 };
                cumulative.push(sum);
            }
        }
        Selector { kind, fitness, cumulative, valid }
    }

    /// Draws one index.
    pub fn select(&self, rng: &mut Rng) -> usize {
        match self.kind {
            Selection::Roulette => {
                let total = self.cumulative.last().copied().unwrap_or(0.0);
                if total > 0.0 && total.is_finite() {
                    let u = rng.next_f64() * total;
                    let i = self.cumulative.partition_point(|&c| c <= u);
                    // Rounding can put `u` at the very top; take the last weighted one.
                    i.min(self.cumulative.partition_point(|&c| c < total))
                } else {
                    self.valid[rng.index(self.valid.len())]
                }
            }
            Selection::Tournament(k) => {
                let mut best = self.valid[rng.index(self.valid.len())];
                for _ in 1..k.max(1) {
                    let c = self.valid[rng.index(self.valid.len())];
                    match rank(self.fitness[c], self.fitness[best]) {
                        Ordering::Less => best = c,
                        Ordering::Equal if c < best => best = c,
                        _ => {}
                    }
                }
                best
            }
            Selection::Random => self.valid[rng.index(self.valid.len())],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frequencies(kind: Selection, fitness: &[f64], n: usize) -> Vec<f64> {
        let s = Selector::new(kind, fitness);
        let mut rng = Rng::from_seed(4);
        let mut counts = vec![0usize; fitness.len()];
        for _ in 0..n {
            counts[s.select(&mut rng)] += 1;
        }
        counts.iter().map(|&c| c as f64 / n as f64).collect()
    }

    #[test]
    fn roulette_is_proportional_to_shifted_fitness() {
        // Shifted weights: 2, 0, 6, 0 (invalid) → 0.25, 0, 0.75, 0.
        let p = frequencies(Selection::Roulette, &[3.0, 1.0, 7.0, f64::NAN], 40_000);
        assert_eq!(p[1], 0.0);
        assert_eq!(p[3], 0.0);
        assert!((p[0] - 0.25).abs() < 0.015, "{p:?}");
    }

    #[test]
    fn roulette_is_uniform_over_valid_when_all_equal() {
        let p = frequencies(Selection::Roulette, &[2.0, f64::NEG_INFINITY, 2.0], 20_000);
        assert_eq!(p[1], 0.0);
        assert!((p[0] - 0.5).abs() < 0.02, "{p:?}");
    }

    #[test]
    fn tournament_never_picks_invalid_and_prefers_the_best() {
        let fitness = [1.0, f64::NAN, 5.0, f64::INFINITY, 2.0];
        let p = frequencies(Selection::Tournament(3), &fitness, 20_000);
        assert_eq!(p[1], 0.0);
        assert_eq!(p[3], 0.0);
        // Draws come from the 3 valid ones; the best wins unless all 3 draws
        // miss it: 1 − (2/3)³ = 0.704.
        assert!((p[2] - 0.704).abs() < 0.02, "{p:?}");
        assert!(p[2] > p[4] && p[4] > p[0]);
    }

    #[test]
    fn tournament_ties_go_to_the_lower_index() {
        let p = frequencies(Selection::Tournament(50), &[1.0, 1.0], 2_000);
        assert!(p[0] > 0.99, "{p:?}");
    }

    #[test]
    fn all_invalid_still_selects() {
        for kind in [Selection::Roulette, Selection::Tournament(2), Selection::Random] {
            let p = frequencies(kind, &[f64::NAN, f64::NAN], 2_000);
            assert!(p.iter().all(|&x| x > 0.0), "{kind:?}: {p:?}");
        }
    }

    #[test]
    fn rank_puts_non_finite_last() {
        let mut v = [f64::NAN, 1.0, f64::NEG_INFINITY, 3.0, f64::INFINITY, -2.0];
        v.sort_by(|a, b| rank(*a, *b));
        assert_eq!(&v[..3], &[3.0, 1.0, -2.0]);
        assert!(v[3..].iter().all(|x| !x.is_finite()));
    }
}
