//! Settings of grammatical evolution and its random-search baseline.
//!
//! The Genr8 paper states almost none of its EA settings (reference
//! `genr8.md` §7); the defaults are the reference's recommended GE
//! defaults: population 50, tournament of 3, one-point crossover at 0.9,
//! per-codon mutation at 0.01, 1 elite, codons 0..999, initial length
//! 50–200. The length cap (1000) is ours: variable-length crossover lets
//! lengths drift, and the cap keeps them bounded.

use crate::config::{ConfigError, check_elitism, probability, require};
use crate::selection::Selection;
use serde::{Deserialize, Serialize};

/// Settings of the [`Ge`](super::Ge) optimizer. Every field has a default;
/// unknown fields are errors.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GeConfig {
    /// Individuals per generation.
    pub population: usize,
    /// Best individuals copied unchanged (with their cached fitness) into
    /// the next generation.
    pub elitism: usize,
    /// Initial genome length in codons, drawn uniformly from `[a, b]`.
    pub initial_length: [usize; 2],
    /// Longest genome in codons (inclusive, unlike the GA's exclusive
    /// `max_length`): crossover children past it lose their tail codons,
    /// which the left-to-right mapping reads last (often unread introns).
    pub max_length: usize,
    /// Codons are drawn uniformly from `0..codon_range`. The mapper takes
    /// them modulo a rule's production count, so the range only needs to
    /// be well above the largest count to keep that choice near uniform.
    pub codon_range: u32,
    /// Parent selection. In configuration files `{ tournament = 3 }`,
    /// `"roulette"` or `"random"`.
    pub selection: Selection,
    /// Probability that a pair of parents is crossed over (else both are
    /// copied before mutation).
    pub crossover_rate: f64,
    /// Probability, per codon of every child, that it is redrawn uniformly.
    pub mutation_rate: f64,
    /// Effective operators (PonyGE2's): crossover cuts and mutation fall
    /// inside the codons the mapping reads, when the objective tells
    /// ([`Objective::expressed`](crate::Objective::expressed)). Without
    /// them most cuts land in the unread tail and give back a parent's
    /// phenotype. Default on.
    pub effective: bool,
    /// Parents are distinct: of individuals with bit-identical fitness
    /// only the best-placed one may be selected, so copies of one system
    /// cannot take over the mating pool. Meant for continuous fitness
    /// (Genr8's surface criteria), where equal scores mean the same
    /// surface; with a fitness of few values (counts) it would starve the
    /// mating pool, so it is off by default and the Genr8 scenes turn it on.
    pub distinct_parents: bool,
    /// Phenotype-level duplicate removal: a child whose expressed codons
    /// were evaluated before is point-mutated (up to 8 times) until it
    /// reads something new, else it reuses the known fitness without an
    /// evaluation. Needs [`Objective::expressed`](crate::Objective::expressed).
    /// Default on.
    pub novel_children: bool,
    /// What makes a child a duplicate for `novel_children`: `"phenotype"`
    /// compares what the objective says decides the model
    /// ([`Objective::phenotype_key`](crate::Objective::phenotype_key), the
    /// mapped phenotype text of GE scenes), `"codons"` the codons the
    /// mapping reads. Many codon strings write one phenotype (a codon is
    /// read modulo a small choice count), so with `"codons"` about a fifth
    /// of the Genr8 scenes' evaluations re-grew a known rule set
    /// (docs/evolve.md). Where the objective knows no phenotype key the
    /// read codons are compared. Default `"codons"`: on the Genr8 scenes
    /// `"phenotype"` saved those evaluations but did not raise the best
    /// found at 10,000 evaluations (docs/evolve.md).
    pub novel_key: NovelKey,
    /// Probability, per child, of a subtree mutation after crossover and
    /// point mutation: one derivation subtree of the child (drawn
    /// uniformly from [`Objective::subtrees`](crate::Objective::subtrees))
    /// is regrown from fresh random codons, and what the mapping reads
    /// after it stays aligned, so the rest of the phenotype is kept
    /// (PonyGE2's subtree mutation, on codons). 0 turns it off; it needs
    /// an objective that tells the subtrees (ask/tell replays, as in the
    /// studio's breeding, do not, so there it changes nothing).
    pub subtree_mutation: f64,
    /// Generations without a new best (strictly better than every
    /// individual seen) after which GE restarts: the `elitism` best stay,
    /// every other member is a fresh random genome, drawn as generation 0's
    /// are. The best seen is never lost. 0 turns it off (the default).
    pub restart_after: usize,
    /// Share of each generation's children made by local search around the
    /// best: a copy of the population's first member with one to three of
    /// the codons its mapping reads redrawn (a (1 + λ) step on what
    /// decides its phenotype), instead of selection, crossover and
    /// mutation. Needs [`Objective::expressed`](crate::Objective::expressed);
    /// without it the whole genome counts. 0 turns it off (the default).
    pub local_search: f64,
    /// How generation 0 (and a restart's fresh genomes) is drawn:
    /// `"random"` codon strings of `initial_length`, or `"sensible"`:
    /// PonyGE2's ramped half-and-half, genomes written from random
    /// derivation trees under depth limits ramped up to `init_depth`, half
    /// grown and half full, each with a random tail half as long as its
    /// read codons, no two with one phenotype where the objective can tell
    /// ([`Objective::sensible_genome`](crate::Objective::sensible_genome);
    /// where it cannot, random codons). Default `"random"`.
    pub init: Init,
    /// Deepest derivation-tree limit of `init = "sensible"` (root = 1);
    /// the ramp starts at the grammar's shallowest tree. Default 10, as
    /// PonyGE2's `MAX_INIT_TREE_DEPTH`.
    pub init_depth: u32,
}

/// How GE draws its initial genomes ([`GeConfig::init`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Init {
    /// Uniform random codons, lengths from `initial_length`.
    #[default]
    Random,
    /// Ramped half-and-half derivation trees, unmapped into codons.
    Sensible,
}

/// What [`GeConfig::novel_children`] compares.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum NovelKey {
    /// The codons the mapping reads.
    #[default]
    Codons,
    /// The objective's phenotype key, else the codons read.
    Phenotype,
}

impl Default for GeConfig {
    fn default() -> Self {
        GeConfig {
            population: 50,
            elitism: 1,
            initial_length: [50, 200],
            max_length: 1000,
            codon_range: 1000,
            selection: Selection::Tournament(3),
            crossover_rate: 0.9,
            mutation_rate: 0.01,
            effective: true,
            distinct_parents: false,
            novel_children: true,
            novel_key: NovelKey::Codons,
            subtree_mutation: 0.0,
            restart_after: 0,
            local_search: 0.0,
            init: Init::Random,
            init_depth: 10,
        }
    }
}

impl GeConfig {
    /// Checks every setting; the first problem is returned.
    pub fn validate(&self) -> Result<(), ConfigError> {
        check_elitism(self.population, self.elitism)?;
        check_codon_lengths(self.initial_length, self.max_length)?;
        check_codon_range(self.codon_range)?;
        if self.selection == Selection::Tournament(0) {
            return Err(ConfigError::Setting { name: "selection.tournament", requirement: "at least 1", value: 0.0 });
        }
        if let Selection::Tournament(size) = self.selection
            && crate::config::too_large_tournament(size, self.population)
        {
            return Err(ConfigError::TournamentSize { key: "selection.tournament", size, population: self.population });
        }
        probability("crossover_rate", self.crossover_rate)?;
        probability("mutation_rate", self.mutation_rate)?;
        probability("subtree_mutation", self.subtree_mutation)?;
        probability("local_search", self.local_search)?;
        require("init_depth", f64::from(self.init_depth), "at least 1", self.init_depth >= 1)
    }
}

/// Settings of the [`CodonRandom`](super::CodonRandom) baseline.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CodonRandomConfig {
    /// Fresh genomes per generation, and individuals kept.
    pub population: usize,
    /// Genome length in codons, drawn uniformly from `[a, b]`.
    pub initial_length: [usize; 2],
    /// Codons are drawn uniformly from `0..codon_range`.
    pub codon_range: u32,
}

impl Default for CodonRandomConfig {
    fn default() -> Self {
        CodonRandomConfig::like(&GeConfig::default())
    }
}

impl CodonRandomConfig {
    /// The random search matching a GE configuration: same batch size and
    /// the same distribution as GE's initial genomes, for comparisons at
    /// equal evaluations.
    pub fn like(ge: &GeConfig) -> Self {
        CodonRandomConfig { population: ge.population, initial_length: ge.initial_length, codon_range: ge.codon_range }
    }

    /// Checks every setting; the first problem is returned.
    pub fn validate(&self) -> Result<(), ConfigError> {
        if self.population == 0 {
            return Err(ConfigError::Population(0));
        }
        check_codon_lengths(self.initial_length, usize::MAX)?;
        check_codon_range(self.codon_range)
    }
}

fn check_codon_lengths([a, b]: [usize; 2], max: usize) -> Result<(), ConfigError> {
    if a == 0 || a > b || b > max {
        return Err(ConfigError::CodonLength { a, b, max });
    }
    Ok(())
}

fn check_codon_range(range: u32) -> Result<(), ConfigError> {
    // A single value could never choose between two productions.
    require("codon_range", range as f64, "at least 2", range >= 2)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<GeConfig, String> {
        toml::from_str::<GeConfig>(text).map_err(|e| e.to_string())
    }

    #[test]
    fn defaults_are_the_recommended_ge_settings() {
        let c = parse("").unwrap();
        assert_eq!(c, GeConfig::default());
        assert_eq!((c.population, c.elitism, c.initial_length, c.max_length), (50, 1, [50, 200], 1000));
        assert_eq!((c.codon_range, c.selection), (1000, Selection::Tournament(3)));
        assert_eq!((c.crossover_rate, c.mutation_rate), (0.9, 0.01));
        c.validate().unwrap();
        let r = CodonRandomConfig::default();
        assert_eq!((r.population, r.initial_length, r.codon_range), (50, [50, 200], 1000));
        r.validate().unwrap();
    }

    #[test]
    fn parses_partial_settings_and_rejects_unknown_ones() {
        let c = parse("population = 80\nselection = { tournament = 5 }\nmutation_rate = 0.02").unwrap();
        assert_eq!((c.population, c.selection, c.mutation_rate), (80, Selection::Tournament(5), 0.02));
        assert_eq!(c.crossover_rate, 0.9);
        assert!(parse("codon_rnage = 256").unwrap_err().contains("codon_rnage"));
        // Off by default: the old behaviour.
        assert_eq!((c.novel_key, c.subtree_mutation), (NovelKey::Codons, 0.0));
        let c = parse("novel_key = \"phenotype\"\nsubtree_mutation = 0.3").unwrap();
        assert_eq!((c.novel_key, c.subtree_mutation), (NovelKey::Phenotype, 0.3));
        assert!(parse("novel_key = \"genes\"").unwrap_err().contains("codons"));
        assert_eq!((c.init, c.init_depth), (Init::Random, 10));
        let c = parse("init = \"sensible\"\ninit_depth = 8").unwrap();
        assert_eq!((c.init, c.init_depth), (Init::Sensible, 8));
        assert!(parse("init = \"ramped\"").unwrap_err().contains("sensible"));
    }

    #[test]
    fn validation_names_the_problem() {
        let base = GeConfig::default();
        let cases: Vec<(GeConfig, &str)> = vec![
            (GeConfig { population: 1, elitism: 0, ..base.clone() }, "population must be at least 2"),
            (GeConfig { elitism: 50, ..base.clone() }, "elitism (50) must be smaller"),
            (GeConfig { initial_length: [0, 10], ..base.clone() }, "initial_length [0, 10]"),
            (GeConfig { initial_length: [20, 10], ..base.clone() }, "initial_length [20, 10]"),
            (GeConfig { max_length: 150, ..base.clone() }, "≤ max_length (150)"),
            (GeConfig { codon_range: 1, ..base.clone() }, "codon_range must be at least 2, got 1"),
            (GeConfig { selection: Selection::Tournament(0), ..base.clone() }, "selection.tournament"),
            (GeConfig { crossover_rate: 1.2, ..base.clone() }, "crossover_rate must be in [0, 1], got 1.2"),
            (GeConfig { mutation_rate: f64::NAN, ..base.clone() }, "mutation_rate"),
            (GeConfig { subtree_mutation: -0.5, ..base.clone() }, "subtree_mutation must be in [0, 1]"),
            (GeConfig { init_depth: 0, ..base.clone() }, "init_depth must be at least 1"),
        ];
        for (c, want) in cases {
            let e = c.validate().unwrap_err().to_string();
            assert!(e.contains(want), "{c:?}\n→ {e}\nwanted {want}");
        }
        let r = CodonRandomConfig { population: 0, ..CodonRandomConfig::default() };
        assert!(r.validate().unwrap_err().to_string().contains("population"));
        // The cap only binds GE: the baseline draws lengths from the initial range alone.
        CodonRandomConfig::like(&GeConfig { max_length: 200, ..base }).validate().unwrap();
    }
}
