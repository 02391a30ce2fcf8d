//! Optimizer settings, their defaults (the paper's spaceship experiment,
//! reference §1.9) and their validation.

use crate::operators::{LengthBounds, MutationMix};
use crate::selection::Selection;
use serde::{Deserialize, Serialize};

/// Why a configuration cannot run. Each message names the setting to fix.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ConfigError {
    /// Fewer than two individuals: no pair to reproduce.
    #[error("population must be at least 2, got {0}")]
    Population(usize),
    /// Elitism fills the whole population, so nothing would ever change.
    #[error("elitism ({elitism}) must be smaller than the population ({population}) to leave room for children")]
    Elitism {
        /// The elitism.
        elitism: usize,
        /// The population.
        population: usize,
    },
    /// The length bounds admit no genome.
    #[error("length bounds need 1 ≤ min_length < max_length, got min_length {min}, max_length {max}")]
    LengthBounds {
        /// `min_length`.
        min: usize,
        /// `max_length`.
        max: usize,
    },
    /// The initial length range is empty or reaches `max_length`.
    #[error("initial_length [{a}, {b}] needs 1 ≤ {a} ≤ {b} < max_length ({max})")]
    InitialLength {
        /// Lower end.
        a: usize,
        /// Upper end.
        b: usize,
        /// `max_length`.
        max: usize,
    },
    /// The mutation rate is not a probability.
    #[error("mutation_rate must lie in [0, 1], got {0}")]
    MutationRate(f64),
    /// The mutation weights are unusable.
    #[error("mutation weights must be finite, ≥ 0 and not all 0; got alter {alter}, grow {grow}, cut {cut}")]
    MutationMix {
        /// Alter weight.
        alter: f64,
        /// Grow weight.
        grow: f64,
        /// Cut weight.
        cut: f64,
    },
    /// Crossover would never be tried.
    #[error("crossover_retries must be at least 1")]
    CrossoverRetries,
    /// A tournament without contestants.
    #[error("the tournament size in selection.{0} must be at least 1")]
    Tournament(&'static str),
}

/// The selector for each parent of a pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SelectionPair {
    /// Selector of parent 1.
    pub first: Selection,
    /// Selector of parent 2.
    pub second: Selection,
}

impl Default for SelectionPair {
    /// Tournament of 10, then roulette, as every reference experiment but
    /// `eg_target`.
    fn default() -> Self {
        SelectionPair { first: Selection::Tournament(10), second: Selection::Roulette }
    }
}

/// Settings of the genetic algorithm. Every field has a default (the
/// paper's spaceship experiment); unknown fields are errors.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GaConfig {
    /// Individuals per generation.
    pub population: usize,
    /// Best individuals copied unchanged (with their cached fitness) into
    /// the next generation.
    pub elitism: usize,
    /// Initial genome length, drawn uniformly from `[a, b]`.
    pub initial_length: [usize; 2],
    /// Children shorter than this are dropped.
    pub min_length: usize,
    /// Children this long or longer are dropped (exclusive bound).
    pub max_length: usize,
    /// Probability that a pair is mutated instead of crossed over (the
    /// reference's `basic_prob`).
    pub mutation_rate: f64,
    /// Relative weights of the mutations.
    pub mutation: MutationMix,
    /// Tries per crossover before it gives up.
    pub crossover_retries: usize,
    /// Parent selectors.
    pub selection: SelectionPair,
}

impl Default for GaConfig {
    fn default() -> Self {
        GaConfig {
            population: 150,
            elitism: 30,
            initial_length: [50, 50],
            min_length: 4,
            max_length: 100,
            mutation_rate: 0.3,
            mutation: MutationMix::default(),
            crossover_retries: 3,
            selection: SelectionPair::default(),
        }
    }
}

impl GaConfig {
    /// The length bounds children must satisfy.
    pub fn length_bounds(&self) -> LengthBounds {
        LengthBounds { min: self.min_length, max: self.max_length }
    }

    /// Checks every setting; the first problem is returned.
    pub fn validate(&self) -> Result<(), ConfigError> {
        if self.population < 2 {
            return Err(ConfigError::Population(self.population));
        }
        if self.elitism >= self.population {
            return Err(ConfigError::Elitism { elitism: self.elitism, population: self.population });
        }
        check_lengths(self.min_length, self.max_length, self.initial_length)?;
        if !(0.0..=1.0).contains(&self.mutation_rate) {
            return Err(ConfigError::MutationRate(self.mutation_rate));
        }
        if !self.mutation.is_valid() {
            let MutationMix { alter, grow, cut } = self.mutation;
            return Err(ConfigError::MutationMix { alter, grow, cut });
        }
        if self.crossover_retries == 0 {
            return Err(ConfigError::CrossoverRetries);
        }
        for (which, s) in [("first", self.selection.first), ("second", self.selection.second)] {
            if s == Selection::Tournament(0) {
                return Err(ConfigError::Tournament(which));
            }
        }
        Ok(())
    }
}

/// Settings of the random-search baseline.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RandomConfig {
    /// Fresh individuals per generation, and individuals kept.
    pub population: usize,
    /// Genome length, drawn uniformly from `[a, b]`.
    pub initial_length: [usize; 2],
    /// Genomes stay below this length.
    pub max_length: usize,
}

impl Default for RandomConfig {
    fn default() -> Self {
        let ga = GaConfig::default();
        RandomConfig { population: ga.population, initial_length: ga.initial_length, max_length: ga.max_length }
    }
}

impl RandomConfig {
    /// The random search matching a GA configuration: same batch size and
    /// initial individuals, for comparisons at equal evaluations.
    pub fn like(ga: &GaConfig) -> Self {
        RandomConfig { population: ga.population, initial_length: ga.initial_length, max_length: ga.max_length }
    }

    /// Checks every setting; the first problem is returned.
    pub fn validate(&self) -> Result<(), ConfigError> {
        if self.population == 0 {
            return Err(ConfigError::Population(self.population));
        }
        check_lengths(1, self.max_length, self.initial_length)
    }
}

fn check_lengths(min: usize, max: usize, [a, b]: [usize; 2]) -> Result<(), ConfigError> {
    if min == 0 || min >= max {
        return Err(ConfigError::LengthBounds { min, max });
    }
    if a == 0 || a > b || b >= max {
        return Err(ConfigError::InitialLength { a, b, max });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<GaConfig, String> {
        toml::from_str::<GaConfig>(text).map_err(|e| e.to_string())
    }

    #[test]
    fn defaults_are_the_papers_spaceship_settings() {
        let c = parse("").unwrap();
        assert_eq!(c, GaConfig::default());
        assert_eq!((c.population, c.elitism, c.initial_length, c.crossover_retries), (150, 30, [50, 50], 3));
        assert_eq!(c.length_bounds(), LengthBounds { min: 4, max: 100 });
        assert_eq!(c.mutation.weights(), [10.0, 45.0, 45.0]);
        assert_eq!(c.selection.first, Selection::Tournament(10));
        c.validate().unwrap();
    }

    #[test]
    fn parses_partial_settings() {
        let c = parse(
            "population = 40\nelitism = 5\nmutation = { grow = 0 }\n\
             selection = { first = \"roulette\", second = { tournament = 4 } }",
        )
        .unwrap();
        assert_eq!((c.population, c.elitism), (40, 5));
        assert_eq!(c.mutation, MutationMix { alter: 10.0, grow: 0.0, cut: 45.0 });
        assert_eq!(c.selection, SelectionPair { first: Selection::Roulette, second: Selection::Tournament(4) });
    }

    #[test]
    fn unknown_fields_are_errors() {
        assert!(parse("populaton = 3").unwrap_err().contains("populaton"));
        assert!(parse("mutation = { shrink = 3 }").unwrap_err().contains("shrink"));
    }

    #[test]
    fn validation_names_the_problem() {
        let base = GaConfig::default();
        let cases: Vec<(GaConfig, &str)> = vec![
            (GaConfig { population: 1, elitism: 0, ..base.clone() }, "population must be at least 2"),
            (GaConfig { elitism: 150, ..base.clone() }, "elitism (150) must be smaller"),
            (GaConfig { min_length: 100, ..base.clone() }, "min_length 100, max_length 100"),
            (GaConfig { min_length: 0, ..base.clone() }, "1 ≤ min_length"),
            (GaConfig { initial_length: [60, 50], ..base.clone() }, "initial_length [60, 50]"),
            (GaConfig { initial_length: [50, 100], ..base.clone() }, "< max_length (100)"),
            (GaConfig { mutation_rate: 1.5, ..base.clone() }, "mutation_rate must lie in [0, 1], got 1.5"),
            (GaConfig { mutation_rate: f64::NAN, ..base.clone() }, "mutation_rate"),
            (GaConfig { mutation: MutationMix { alter: 0.0, grow: 0.0, cut: 0.0 }, ..base.clone() }, "not all 0"),
            (GaConfig { mutation: MutationMix { alter: -1.0, ..MutationMix::default() }, ..base.clone() }, "≥ 0"),
            (GaConfig { crossover_retries: 0, ..base.clone() }, "crossover_retries"),
            (
                GaConfig {
                    selection: SelectionPair { first: Selection::Roulette, second: Selection::Tournament(0) },
                    ..base.clone()
                },
                "selection.second",
            ),
        ];
        for (c, want) in cases {
            let e = c.validate().unwrap_err().to_string();
            assert!(e.contains(want), "{c:?}\n→ {e}\nwanted {want}");
        }
        let random = RandomConfig { initial_length: [5, 4], ..RandomConfig::default() };
        assert!(random.validate().unwrap_err().to_string().contains("initial_length [5, 4]"));
        RandomConfig::like(&base).validate().unwrap();
    }
}
