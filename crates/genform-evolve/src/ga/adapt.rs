//! Self-adaptive operator rates (probability matching).
//!
//! Once a population has converged, crossover of near-identical parents
//! rarely beats them (on spaceship_volume: 9 % of crossover children in
//! the first quarter second, 0.1 % after two seconds, while mutations stay
//! at 2–3 %), yet the thesis' fixed 30 % mutation rate spends 70 % of the
//! evaluations on it. Each generation the GA therefore moves the share of
//! each operator towards its recent success rate: an exponential moving
//! average of children made and children that beat their parents, per
//! operator. Probabilities are floored so no enabled operator dies out, and
//! operators the configuration disables (weight 0, or a mutation rate of
//! exactly 0 or 1) stay as configured. The update reads only the previous
//! generations' tallies, so runs stay deterministic.

use crate::operators::MutationMix;
use crate::stats::{OperatorCounts, OperatorTally};

/// Weight of the newest generation in the moving averages.
const SMOOTHING: f64 = 0.2;
/// Smallest probability of an enabled operator: of crossover vs mutation,
/// and of each enabled mutation among the mutations.
const FLOOR: f64 = 0.05;

/// Moving averages of one operator's children and improvements.
#[derive(Clone, Copy, Debug, Default)]
struct Average {
    children: f64,
    improved: f64,
}

impl Average {
    fn update(&mut self, t: OperatorTally) {
        self.children = (1.0 - SMOOTHING) * self.children + SMOOTHING * t.children as f64;
        self.improved = (1.0 - SMOOTHING) * self.improved + SMOOTHING * t.improved as f64;
    }

    fn rate(&self) -> Option<f64> {
        (self.children > 0.0).then(|| self.improved / self.children)
    }
}

/// The operator rates a GA currently uses.
#[derive(Clone, Debug)]
pub(crate) struct Rates {
    adaptive: bool,
    /// Probability that a pair is mutated instead of crossed over.
    pub mutation_rate: f64,
    /// Mutation weights (the configured ones until adaptation moves them).
    pub mix: MutationMix,
    enabled: [bool; 5],
    crossover: Average,
    /// Alter, grow, cut, drift, regrow.
    mutations: [Average; 5],
}

impl Rates {
    /// The configured rates; they adapt when `adaptive`.
    pub fn new(mutation_rate: f64, mix: MutationMix, adaptive: bool) -> Self {
        let enabled = mix.weights().map(|w| w > 0.0);
        Rates {
            adaptive,
            mutation_rate,
            mix,
            enabled,
            crossover: Average::default(),
            mutations: [Average::default(); 5],
        }
    }

    /// Moves the rates towards the success rates seen so far, `counts`
    /// being the last generation's tallies.
    pub fn update(&mut self, counts: &OperatorCounts) {
        if !self.adaptive {
            return;
        }
        self.crossover.update(counts.crossover);
        let tallies = [counts.alter, counts.grow, counts.cut, counts.drift, counts.regrow];
        for (a, t) in self.mutations.iter_mut().zip(tallies) {
            a.update(t);
        }
        // Mutation vs crossover, from the pooled mutation children.
        let pooled = self.mutations.iter().fold(Average::default(), |acc, a| Average {
            children: acc.children + a.children,
            improved: acc.improved + a.improved,
        });
        if self.mutation_rate > 0.0
            && self.mutation_rate < 1.0
            && let (Some(m), Some(x)) = (pooled.rate(), self.crossover.rate())
            && m + x > 0.0
        {
            self.mutation_rate = (m / (m + x)).clamp(FLOOR, 1.0 - FLOOR);
        }
        // Among the enabled mutations, probability matching with a floor.
        let n = self.enabled.iter().filter(|e| **e).count();
        let rates: Vec<f64> = self.mutations.iter().map(|a| a.rate().unwrap_or(0.0)).collect();
        let total: f64 = rates.iter().zip(self.enabled).filter(|(_, e)| *e).map(|(r, _)| r).sum();
        if n > 1 && total > 0.0 {
            let w: Vec<f64> = (0..5)
                .map(|k| if self.enabled[k] { FLOOR + (1.0 - n as f64 * FLOOR) * rates[k] / total } else { 0.0 })
                .collect();
            self.mix = MutationMix { alter: w[0], grow: w[1], cut: w[2], drift: w[3], regrow: w[4], ..self.mix };
        }
    }
}
