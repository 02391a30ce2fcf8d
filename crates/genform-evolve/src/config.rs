//! Optimizer settings, their defaults (the paper's spaceship experiment,
//! reference §1.9) and their validation.

pub(crate) mod gene_choice;

pub use gene_choice::GeneChoice;

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
    #[error(
        "elitism ({elitism}) must be smaller than the population ({population}) to leave room for children \
         (leave `elitism` out for its default)"
    )]
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
    #[error(
        "mutation weights must be finite and ≥ 0, and alter, grow, cut and regrow not all 0 (drift alone never \
         changes a derivation's rules or length); got alter {alter}, grow \
         {grow}, cut {cut}"
    )]
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
    /// A tournament larger than the population it draws from.
    #[error(
        "the tournament size {size} in {key} is larger than the population ({population}): a tournament draws \
         its contestants from the population"
    )]
    TournamentSize {
        /// The setting, e.g. `selection.first`.
        key: &'static str,
        /// The size given.
        size: usize,
        /// The population.
        population: usize,
    },
    /// A codon genome's initial length range is empty or passes the cap.
    #[error("initial_length [{a}, {b}] needs 1 ≤ {a} ≤ {b} ≤ max_length ({max})")]
    CodonLength {
        /// Lower end.
        a: usize,
        /// Upper end.
        b: usize,
        /// `max_length` (inclusive for codon genomes).
        max: usize,
    },
    /// A numeric setting outside its range.
    #[error("{name} must be {requirement}, got {value}")]
    Setting {
        /// The setting's name.
        name: &'static str,
        /// What it must be, e.g. "in [0, 1]".
        requirement: &'static str,
        /// The value given.
        value: f64,
    },
    /// Memory for a size the user set could not be had: the estimate the
    /// application checked it against was off, or the machine is short.
    #[error("cannot allocate {bytes} bytes for the {what} of {count}; lower `{key}`")]
    Allocation {
        /// The setting that sized it, e.g. `population`.
        key: &'static str,
        /// What was allocated, e.g. "population" or "archive".
        what: &'static str,
        /// Items asked for.
        count: u128,
        /// Bytes asked for.
        bytes: u128,
    },
}

impl ConfigError {
    /// The key of the refused setting in its scene table, dotted when it
    /// is nested (`selection.first`, `mutation.drift`), so a scene can name
    /// its position.
    pub fn key(&self) -> &'static str {
        match self {
            ConfigError::Population(_) => "population",
            ConfigError::Elitism { .. } => "elitism",
            ConfigError::LengthBounds { min, max } if *min > 0 && *min < *max => "max_length",
            ConfigError::LengthBounds { .. } => "min_length",
            ConfigError::InitialLength { .. } | ConfigError::CodonLength { .. } => "initial_length",
            ConfigError::MutationRate(_) => "mutation_rate",
            ConfigError::MutationMix { .. } => "mutation",
            ConfigError::CrossoverRetries => "crossover_retries",
            ConfigError::Tournament("first") => "selection.first",
            ConfigError::Tournament(_) => "selection.second",
            ConfigError::TournamentSize { key, .. } => key,
            ConfigError::Setting { name, .. } => name,
            ConfigError::Allocation { key, .. } => key,
        }
    }
}

/// An empty `Vec` with room for `count` items, or [`ConfigError::Allocation`]
/// (naming `key` and `what`) when the memory cannot be had: the big
/// user-sized buffers (populations, archives, particles) are allocated
/// fallibly, so a size past the machine is an error, not an abort.
pub(crate) fn room<T>(count: usize, key: &'static str, what: &'static str) -> Result<Vec<T>, ConfigError> {
    let mut v = Vec::new();
    v.try_reserve_exact(count).map_err(|_| ConfigError::Allocation {
        key,
        what,
        count: count as u128,
        bytes: count as u128 * std::mem::size_of::<T>() as u128,
    })?;
    Ok(v)
}

/// Fails with [`ConfigError::Setting`] unless `ok(value)`.
pub(crate) fn require(name: &'static str, value: f64, requirement: &'static str, ok: bool) -> Result<(), ConfigError> {
    if ok { Ok(()) } else { Err(ConfigError::Setting { name, requirement, value }) }
}

pub(crate) fn probability(name: &'static str, value: f64) -> Result<(), ConfigError> {
    require(name, value, "in [0, 1]", (0.0..=1.0).contains(&value))
}

/// The default tournament size (the thesis' 10).
pub const DEFAULT_TOURNAMENT: usize = 10;

/// Whether a tournament of `size` draws more contestants than a selection
/// can use: contestants are drawn with replacement, so past the population
/// a tournament only costs time (a million draws per parent). Sizes up to
/// the default stay allowed for small populations, which keep the default.
pub(crate) fn too_large_tournament(size: usize, population: usize) -> bool {
    size > population && size > DEFAULT_TOURNAMENT
}

/// An elitist EA's sizes: at least one pair to reproduce, and room for
/// children beside the elites.
pub(crate) fn check_elitism(population: usize, elitism: usize) -> Result<(), ConfigError> {
    if population < 2 {
        return Err(ConfigError::Population(population));
    }
    if elitism >= population {
        return Err(ConfigError::Elitism { elitism, population });
    }
    Ok(())
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
        SelectionPair { first: Selection::Tournament(DEFAULT_TOURNAMENT), second: Selection::Roulette }
    }
}

/// Which GA: the improved default, or the thesis' exact operators.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GaPreset {
    /// The improved GA: the thesis' operators plus drift mutation,
    /// duplicate avoidance and restarts of stalled epochs.
    #[default]
    Default,
    /// The thesis' GA exactly: no drift (`mutation.drift` is taken as 0), no
    /// duplicate avoidance, fixed rates and no restarts, whatever those
    /// settings say.
    Thesis,
}

impl GaPreset {
    /// The preset called `name` (`default`, `thesis`).
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "default" => Some(GaPreset::Default),
            "thesis" => Some(GaPreset::Thesis),
            _ => None,
        }
    }
}

/// How the GA builds generation 0.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Initialization {
    /// The root and its mandatory closure, then grows weighted by slot
    /// probability (see `operators::initial`).
    #[default]
    Grammar,
    /// The reference implementation's: the root plus `initial_length − 1`
    /// grows that ignore slot probabilities, with its integer-draw quirk
    /// (see `operators::reference_initial`); for fidelity runs.
    Reference,
}

/// Default of [`GaConfig::tune_after`].
pub const DEFAULT_TUNE_AFTER: usize = 20;

/// Default of [`GaConfig::restart_after`].
pub const DEFAULT_RESTART_AFTER: usize = 400;
/// Default of [`GaConfig::restart_tolerance`].
pub const DEFAULT_RESTART_TOLERANCE: f64 = 0.0;

/// Settings of the genetic algorithm. Every field has a default (the
/// paper's spaceship experiment, with the improved GA's additions);
/// unknown fields are errors.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GaConfig {
    /// Individuals per generation.
    pub population: usize,
    /// Best individuals copied unchanged (with their cached fitness) into
    /// the next generation. `None` (the default, a key left out of
    /// `[ga]`): a fifth of the population, rounded down (the thesis' 30 of
    /// 150), so a smaller population still breeds; see [`GaConfig::elites`].
    /// A number given is taken as it is and must be smaller than the
    /// population.
    pub elitism: Option<usize>,
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
    /// `thesis` turns the additions below off (see [`GaPreset`]).
    pub preset: GaPreset,
    /// Whether, in the tuning phase, a child identical to a member of the
    /// parents' population or to an earlier child is mutated again (up to
    /// three times) rather than evaluated again.
    pub avoid_duplicates: bool,
    /// How generation 0 is built.
    pub initialization: Initialization,
    /// Generations without a new best before the tuning phase starts: drift
    /// mutation and duplicate avoidance, which then stay on (0: from the
    /// start). Until then the GA is the thesis' GA, whose structural search
    /// does better early on (city_volume at 10,000 evaluations: 67.2 with
    /// it, 62.4 with both from the start).
    pub tune_after: usize,
    /// Whether the mutation rate and the mutation weights adapt to each
    /// operator's recent success (the configured values are the start). On
    /// by default: within the reference's 130 generations on
    /// spaceship_volume it lifts the median best of 10 seeds from 0.14 to
    /// 0.87 on the reference's scale (`form = "reference-cpu"`) and from
    /// 1.56 to 1.65 on the paper's, and no scene's standard run is worse by
    /// more than its spread (docs/comparison.md).
    pub adapt_rates: bool,
    /// Generations without a gain of the current epoch's best (see
    /// `restart_tolerance`) before the GA restarts: the best individual
    /// seen stays in the archive ([`crate::Ga::best`]), `restart_keep` of
    /// the best members stay, the rest is a fresh generation 0 and the
    /// tuning phase ends. 0: never restart. Within 10 s, 400 restarts
    /// city_skyline at most once, late, and never city_volume or the trees
    /// (their best keeps rising by small steps), and gives spaceship_volume
    /// 1.826 instead of 1.765 at 486,000 evaluations; 200 restarted
    /// city_volume too often at 60 s (93.02 against 93.25 with 400).
    pub restart_after: usize,
    /// Smallest gain of the epoch's best that resets the `restart_after`
    /// count, as a fraction of the best's absolute value, measured from the
    /// best at the last counted gain (so small steps add up); 0: any gain.
    /// A relative threshold restarted city_skyline, whose best creeps up
    /// near 1, before its refinement was done (0.9939 against 0.9952).
    pub restart_tolerance: f64,
    /// Best members kept through a restart (0: a completely fresh
    /// population; the best seen is kept in the archive either way).
    pub restart_keep: usize,
}

impl Default for GaConfig {
    fn default() -> Self {
        GaConfig {
            population: 150,
            elitism: None,
            initial_length: [50, 50],
            min_length: 4,
            max_length: 100,
            mutation_rate: 0.3,
            mutation: MutationMix::default(),
            crossover_retries: 3,
            selection: SelectionPair::default(),
            preset: GaPreset::Default,
            avoid_duplicates: true,
            initialization: Initialization::Grammar,
            adapt_rates: true,
            tune_after: DEFAULT_TUNE_AFTER,
            restart_after: DEFAULT_RESTART_AFTER,
            restart_tolerance: DEFAULT_RESTART_TOLERANCE,
            restart_keep: 0,
        }
    }
}

/// Share of the population kept as elites when [`GaConfig::elitism`] is
/// not given: one in this many (the thesis' 30 of 150).
pub const DEFAULT_ELITISM_DIVISOR: usize = 5;

impl GaConfig {
    /// Individuals copied unchanged into the next generation: the given
    /// [`GaConfig::elitism`], else a fifth of the population (rounded down).
    pub fn elites(&self) -> usize {
        self.elitism.unwrap_or(self.population / DEFAULT_ELITISM_DIVISOR)
    }

    /// The length bounds children must satisfy.
    pub fn length_bounds(&self) -> LengthBounds {
        LengthBounds { min: self.min_length, max: self.max_length }
    }

    /// The thesis' GA with the paper's spaceship settings.
    pub fn thesis() -> Self {
        GaConfig::default().with_preset(GaPreset::Thesis)
    }

    /// These settings under `preset` (e.g. a `--preset` flag overriding the
    /// scene's).
    pub fn with_preset(self, preset: GaPreset) -> Self {
        GaConfig { preset, ..self }
    }

    /// The settings the GA runs with: under [`GaPreset::Thesis`] drift,
    /// duplicate avoidance, rate adaptation and restarts are off.
    pub fn effective(&self) -> Self {
        match self.preset {
            GaPreset::Default => self.clone(),
            GaPreset::Thesis => {
                let mutation = self.mutation.thesis_only();
                GaConfig { mutation, avoid_duplicates: false, adapt_rates: false, restart_after: 0, ..self.clone() }
            }
        }
    }

    /// Checks every setting; the first problem is returned.
    pub fn validate(&self) -> Result<(), ConfigError> {
        check_elitism(self.population, self.elites())?;
        check_lengths(self.min_length, self.max_length, self.initial_length)?;
        if !(0.0..=1.0).contains(&self.mutation_rate) {
            return Err(ConfigError::MutationRate(self.mutation_rate));
        }
        let MutationMix { alter, grow, cut, drift, regrow, drift_scale } = self.mutation;
        require("mutation.drift", drift, "finite and ≥ 0", drift.is_finite() && drift >= 0.0)?;
        require("mutation.regrow", regrow, "finite and ≥ 0", regrow.is_finite() && regrow >= 0.0)?;
        require("mutation.drift_scale", drift_scale, "finite and > 0", drift_scale.is_finite() && drift_scale > 0.0)?;
        let effective = self.effective().mutation;
        // Drift alone only nudges parameters: no derivation could ever
        // change its rules or its length by mutation.
        let structural = effective.alter + effective.grow + effective.cut + effective.regrow;
        if !effective.is_valid() || structural <= 0.0 {
            return Err(ConfigError::MutationMix { alter, grow, cut });
        }
        if self.crossover_retries == 0 {
            return Err(ConfigError::CrossoverRetries);
        }
        let t = self.restart_tolerance;
        require("restart_tolerance", t, "in [0, 1]", (0.0..=1.0).contains(&t))?;
        let keep = self.restart_keep;
        require("restart_keep", keep as f64, "smaller than the population", keep < self.population)?;
        for (which, s) in [("first", self.selection.first), ("second", self.selection.second)] {
            if s == Selection::Tournament(0) {
                return Err(ConfigError::Tournament(which));
            }
            if let Selection::Tournament(size) = s
                && too_large_tournament(size, self.population)
            {
                let key = if which == "first" { "selection.first" } else { "selection.second" };
                return Err(ConfigError::TournamentSize { key, size, population: self.population });
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

/// Settings of the RJMCMC chains (Talton et al. 2011 as the thesis runs
/// it: diffusion and jump moves, nonterminal selection, parallel
/// tempering, delayed rejection and annealing). Defaults: the paper's
/// spaceship experiment (70 chains, initial length 50, 50 % jumps,
/// annealing 1.1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MhConfig {
    /// Chains, one per rung of the temperature ladder.
    pub chains: usize,
    /// Initial genome length, drawn uniformly from `[a, b]` (as the GA's).
    pub initial_length: [usize; 2],
    /// States shorter than this are outside the support (rejected).
    pub min_length: usize,
    /// States this long or longer are outside the support (exclusive).
    pub max_length: usize,
    /// Probability that a step is a jump (else a diffusion).
    pub jump: f64,
    /// How moves pick their gene.
    pub gene_choice: GeneChoice,
    /// Fraction of diffusion moves that drift continuous parameters by a
    /// Gaussian step instead of redrawing them from their distribution.
    pub drift: f64,
    /// Standard deviation of a drift step, as a fraction of the
    /// parameter's range (uniform) or standard deviation (normal).
    pub drift_scale: f64,
    /// Temperature of the coldest chain, in fitness units: a move that
    /// loses `t` fitness is accepted with probability 1/e there. Unset:
    /// the hottest chain's temperature is the standard deviation of the
    /// initial fitness values, and the coldest is that over `ladder`.
    pub temperature: Option<f64>,
    /// Hottest over coldest temperature; chains are spaced geometrically.
    /// 12.9 is Talton et al.'s rule: a move accepted with probability 0.7 in
    /// the hottest chain is accepted with 0.01 in the coldest.
    pub ladder: f64,
    /// Factor applied to every chain's inverse temperature after each
    /// generation (1 = no annealing; the thesis uses 1.1).
    pub anneal: f64,
    /// Whether a rejected jump gets a second try at the same gene
    /// (Tierney–Mira delayed rejection).
    pub delayed_rejection: bool,
}

impl Default for MhConfig {
    fn default() -> Self {
        MhConfig {
            chains: 70,
            initial_length: [50, 50],
            min_length: 4,
            max_length: 100,
            jump: 0.5,
            gene_choice: GeneChoice::Level,
            drift: 0.5,
            drift_scale: 0.1,
            temperature: None,
            ladder: TALTON_LADDER,
            anneal: 1.1,
            delayed_rejection: true,
        }
    }
}

/// Hottest over coldest temperature such that a move accepted with
/// probability 0.7 in the hottest chain is accepted with 0.01 in the
/// coldest: ln 0.01 / ln 0.7.
pub const TALTON_LADDER: f64 = 12.911_368_260_251_52;

impl MhConfig {
    /// The length bounds states must satisfy.
    pub fn length_bounds(&self) -> LengthBounds {
        LengthBounds { min: self.min_length, max: self.max_length }
    }

    /// Checks every setting; the first problem is returned.
    pub fn validate(&self) -> Result<(), ConfigError> {
        require("chains", self.chains as f64, "at least 1", self.chains >= 1)?;
        check_lengths(self.min_length, self.max_length, self.initial_length)?;
        probability("jump", self.jump)?;
        probability("drift", self.drift)?;
        require(
            "drift_scale",
            self.drift_scale,
            "finite and > 0",
            self.drift_scale.is_finite() && self.drift_scale > 0.0,
        )?;
        if let Some(t) = self.temperature {
            require("temperature", t, "finite and > 0", t.is_finite() && t > 0.0)?;
        }
        require("ladder", self.ladder, "finite and ≥ 1", self.ladder.is_finite() && self.ladder >= 1.0)?;
        require("anneal", self.anneal, "finite and ≥ 1", self.anneal.is_finite() && self.anneal >= 1.0)
    }
}

/// How SMC weights particles for resampling.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Weighting {
    /// exp(fitness / T), as Ritchie et al. (who use the score itself, a log
    /// likelihood, so T = 1 there).
    Boltzmann,
    /// fitness − the worst valid fitness, as the reference implementation
    /// meant to (it dropped the shift when every fitness was negative).
    Shifted,
}

/// Settings of SMC and SOSMC (Ritchie et al. 2015 in the thesis' genome
/// framework). Defaults: the paper's spaceship experiment (500 particles).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SmcConfig {
    /// Particles.
    pub particles: usize,
    /// Resampling weight.
    pub weight: Weighting,
    /// Temperature of [`Weighting::Boltzmann`]. Unset: the standard
    /// deviation of the particles' fitness at each step, which makes the
    /// weights independent of the fitness scale.
    pub temperature: Option<f64>,
    /// Particles stop growing before this length (exclusive bound).
    pub max_length: usize,
}

impl Default for SmcConfig {
    fn default() -> Self {
        SmcConfig { particles: 500, weight: Weighting::Boltzmann, temperature: None, max_length: 100 }
    }
}

impl SmcConfig {
    /// Checks every setting; the first problem is returned.
    pub fn validate(&self) -> Result<(), ConfigError> {
        // One particle is a single random walk: resampling has nothing to choose from.
        require("particles", self.particles as f64, "at least 2", self.particles >= 2)?;
        if let Some(t) = self.temperature {
            require("temperature", t, "finite and > 0", t.is_finite() && t > 0.0)?;
        }
        require("max_length", self.max_length as f64, "at least 2", self.max_length >= 2)
    }
}

/// Settings of the hybrid: SOSMC seeds the GA's population, the GA runs
/// until it stagnates (or a share of the run's horizon is used), then MH
/// chains polish its best individuals. Each phase takes its own settings
/// from the `[smc]`, `[ga]` and `[mh]` sections.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct HybridConfig {
    /// GA generations without a new best before switching to MH.
    pub stagnation: usize,
    /// Share of the run's horizon (time, evaluations or generations) after
    /// which the GA hands over to MH even while it still improves.
    pub polish_after: f64,
}

impl Default for HybridConfig {
    fn default() -> Self {
        HybridConfig { stagnation: 40, polish_after: 0.8 }
    }
}

impl HybridConfig {
    /// Checks every setting; the first problem is returned.
    pub fn validate(&self) -> Result<(), ConfigError> {
        require("stagnation", self.stagnation as f64, "at least 1", self.stagnation >= 1)?;
        probability("polish_after", self.polish_after)
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
        assert_eq!((c.population, c.elites(), c.initial_length, c.crossover_retries), (150, 30, [50, 50], 3));
        assert_eq!(c.length_bounds(), LengthBounds { min: 4, max: 100 });
        assert_eq!(
            c.mutation.weights(),
            [10.0, 45.0, 45.0, crate::operators::DEFAULT_DRIFT_WEIGHT, crate::operators::DEFAULT_REGROW_WEIGHT]
        );
        assert_eq!(
            (c.preset, c.avoid_duplicates, c.initialization, c.adapt_rates),
            (GaPreset::Default, true, Initialization::Grammar, true)
        );
        assert_eq!(c.selection.first, Selection::Tournament(10));
        assert_eq!((c.restart_after, c.restart_tolerance, c.restart_keep), (400, 0.0, 0));
        c.validate().unwrap();
    }

    #[test]
    fn parses_partial_settings() {
        let c = parse(
            "population = 40\nelitism = 5\nmutation = { grow = 0 }\nrestart_after = 7\nrestart_keep = 2\n\
             selection = { first = \"roulette\", second = { tournament = 4 } }",
        )
        .unwrap();
        assert_eq!((c.population, c.elites(), c.restart_after, c.restart_keep), (40, 5, 7, 2));
        assert_eq!(c.mutation, MutationMix { grow: 0.0, ..MutationMix::default() });
        assert_eq!(c.selection, SelectionPair { first: Selection::Roulette, second: Selection::Tournament(4) });
    }

    #[test]
    fn presets_and_initialization_parse_and_the_thesis_preset_turns_the_additions_off() {
        let c =
            parse("preset = \"thesis\"\ninitialization = \"reference\"\nmutation = { drift = 5, drift_scale = 0.2 }")
                .unwrap();
        assert_eq!((c.preset, c.initialization), (GaPreset::Thesis, Initialization::Reference));
        assert_eq!((c.mutation.drift, c.mutation.drift_scale), (5.0, 0.2));
        let e = c.effective();
        assert_eq!((e.mutation.drift, e.mutation.regrow, e.avoid_duplicates, e.adapt_rates), (0.0, 0.0, false, false));
        assert_eq!(e.restart_after, 0, "the thesis GA never restarts");
        assert_eq!(e.mutation.weights()[..3], [10.0, 45.0, 45.0]);
        assert_eq!(e.initialization, Initialization::Reference, "initialization is not part of the preset");
        assert_eq!(GaConfig::thesis().effective(), GaConfig::thesis().effective().effective());
        let d = GaConfig::default().effective();
        assert_eq!(d, GaConfig::default(), "the default preset changes nothing");
        assert_eq!(c.clone().with_preset(GaPreset::Default).effective().mutation.drift, 5.0);
        assert!(parse("preset = \"modern\"").unwrap_err().contains("modern"));
        assert!(parse("initialization = \"random\"").unwrap_err().contains("random"));
        assert_eq!(GaPreset::from_name("thesis"), Some(GaPreset::Thesis));
        assert_eq!(GaPreset::from_name("THESIS"), None);
    }

    #[test]
    fn elitism_left_out_is_a_fifth_of_the_population_and_a_given_one_stays_strict() {
        for (population, elites) in [(2, 0), (10, 2), (20, 4), (40, 8), (50, 10), (150, 30), (151, 30)] {
            let c = parse(&format!("population = {population}")).unwrap();
            assert_eq!((c.elitism, c.elites()), (None, elites), "population {population}");
            c.validate().unwrap();
        }
        let c = parse("population = 10\nelitism = 30").unwrap();
        assert_eq!(c.elites(), 30);
        let e = c.validate().unwrap_err().to_string();
        assert!(e.contains("elitism (30) must be smaller than the population (10)"), "{e}");
        assert!(e.contains("leave `elitism` out"), "{e}");
        assert_eq!(parse("population = 10\nelitism = 0").unwrap().elites(), 0);
    }

    #[test]
    fn smc_needs_two_particles_and_small_populations_keep_the_default_tournament() {
        let one = SmcConfig { particles: 1, ..SmcConfig::default() }.validate().unwrap_err();
        assert_eq!(one.to_string(), "particles must be at least 2, got 1");
        SmcConfig { particles: 2, ..SmcConfig::default() }.validate().unwrap();
        // Contestants are drawn with replacement: the default 10 of 6 is allowed.
        GaConfig { population: 6, elitism: Some(1), ..GaConfig::default() }.validate().unwrap();
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
            (GaConfig { population: 1, elitism: Some(0), ..base.clone() }, "population must be at least 2"),
            (GaConfig { elitism: Some(150), ..base.clone() }, "elitism (150) must be smaller"),
            (GaConfig { min_length: 100, ..base.clone() }, "min_length 100, max_length 100"),
            (GaConfig { min_length: 0, ..base.clone() }, "1 ≤ min_length"),
            (GaConfig { initial_length: [60, 50], ..base.clone() }, "initial_length [60, 50]"),
            (GaConfig { initial_length: [50, 100], ..base.clone() }, "< max_length (100)"),
            (GaConfig { mutation_rate: 1.5, ..base.clone() }, "mutation_rate must lie in [0, 1], got 1.5"),
            (GaConfig { mutation_rate: f64::NAN, ..base.clone() }, "mutation_rate"),
            (
                GaConfig {
                    mutation: MutationMix {
                        alter: 0.0,
                        grow: 0.0,
                        cut: 0.0,
                        drift: 0.0,
                        regrow: 0.0,
                        ..MutationMix::default()
                    },
                    ..base.clone()
                },
                "not all 0",
            ),
            (
                GaConfig {
                    mutation: MutationMix { alter: 0.0, grow: 0.0, cut: 0.0, ..MutationMix::default() },
                    ..GaConfig::thesis()
                },
                "not all 0",
            ),
            (
                GaConfig { mutation: MutationMix { drift: -1.0, ..MutationMix::default() }, ..base.clone() },
                "mutation.drift must be finite and ≥ 0, got -1",
            ),
            (
                GaConfig { mutation: MutationMix { regrow: f64::NAN, ..MutationMix::default() }, ..base.clone() },
                "mutation.regrow must be finite and ≥ 0",
            ),
            (
                GaConfig { mutation: MutationMix { drift: f64::INFINITY, ..MutationMix::default() }, ..base.clone() },
                "mutation.drift must",
            ),
            (
                GaConfig { mutation: MutationMix { drift_scale: 0.0, ..MutationMix::default() }, ..base.clone() },
                "mutation.drift_scale must be finite and > 0, got 0",
            ),
            (
                GaConfig { mutation: MutationMix { drift_scale: f64::NAN, ..MutationMix::default() }, ..base.clone() },
                "mutation.drift_scale",
            ),
            (GaConfig { mutation: MutationMix { alter: -1.0, ..MutationMix::default() }, ..base.clone() }, "≥ 0"),
            (GaConfig { crossover_retries: 0, ..base.clone() }, "crossover_retries"),
            (
                GaConfig {
                    mutation: MutationMix { alter: 0.0, grow: 0.0, cut: 0.0, ..MutationMix::default() },
                    ..base.clone()
                },
                "drift alone never changes",
            ),
            (
                GaConfig {
                    population: 20,
                    elitism: Some(2),
                    selection: SelectionPair { first: Selection::Tournament(21), second: Selection::Roulette },
                    ..base.clone()
                },
                "tournament size 21 in selection.first is larger than the population (20)",
            ),
            (GaConfig { restart_tolerance: -0.1, ..base.clone() }, "restart_tolerance must be in [0, 1], got -0.1"),
            (GaConfig { restart_tolerance: f64::NAN, ..base.clone() }, "restart_tolerance"),
            (GaConfig { restart_keep: 150, ..base.clone() }, "restart_keep must be smaller than the population"),
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
