//! Settings of MAP-Elites (a scene's `[map_elites]` section) and the grid
//! they define.
//!
//! Ranges are checked while the settings are read (each field has its own
//! checking deserializer), so a TOML reader reports a bad value at its
//! `line:col`; [`MapElitesConfig::validate`] repeats the checks for settings
//! built in code.

use crate::config::{ConfigError, probability, require};
use crate::selection::Selection;
use serde::{Deserialize, Deserializer, Serialize};

/// Most bins along one descriptor axis: 256 × 256 cells keep the archive
/// at a few megabytes whatever a scene asks for.
pub const MAX_BINS: usize = 256;

/// Most individuals per generation (initial or children), so a typo cannot
/// exhaust memory.
pub const MAX_BATCH: usize = 1_000_000;

/// One axis of the archive: which descriptor, its bins and its range.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DescriptorAxis {
    /// The descriptor's name; the objective knows what it means (the CLI
    /// offers `length`, `aspect`, `width`, `height`, `depth`, `primitives`).
    pub name: String,
    /// Cells along this axis.
    #[serde(default = "default_bins", deserialize_with = "de_bins")]
    pub bins: usize,
    /// Descriptor values `[low, high]` spread over the bins; values outside
    /// land in the edge cells. Unset: the objective's default for the name
    /// (the CLI fills it in before the run).
    #[serde(default, deserialize_with = "de_range")]
    pub range: Option<[f64; 2]>,
}

impl DescriptorAxis {
    /// An axis of `bins` cells over `[low, high]`.
    pub fn new(name: &str, bins: usize, range: [f64; 2]) -> Self {
        DescriptorAxis { name: name.into(), bins, range: Some(range) }
    }

    /// The bin of `value`: `bins` equal slices of the range, values below
    /// or above going to the first or last bin, NaN to the first. An axis
    /// without a range has one bin in effect (everything lands in bin 0).
    pub fn bin(&self, value: f64) -> usize {
        let Some([lo, hi]) = self.range else { return 0 };
        let t = (value - lo) / (hi - lo) * self.bins as f64;
        // `as` saturates: NaN → 0, ±∞ → the ends; `min` keeps `hi` in the last bin.
        (t.max(0.0) as usize).min(self.bins - 1)
    }

    fn validate(&self) -> Result<(), ConfigError> {
        check_bins(self.bins).map_err(|requirement| ConfigError::Setting {
            name: "descriptors.bins",
            requirement,
            value: self.bins as f64,
        })?;
        if let Some(r) = self.range {
            check_range(r).map_err(|requirement| ConfigError::Setting {
                name: "descriptors.range",
                requirement,
                value: r[1] - r[0],
            })?;
        }
        Ok(())
    }
}

/// Settings of MAP-Elites. Genome lengths and the variation operators
/// (mutation mix, crossover retries) come from the GA's settings, so both
/// search the same space with the same steps.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MapElitesConfig {
    /// Random individuals making generation 0.
    #[serde(deserialize_with = "de_batch")]
    pub initial: usize,
    /// Children per later generation, each from uniformly chosen elites.
    #[serde(deserialize_with = "de_batch")]
    pub batch: usize,
    /// Probability that a child is a crossover of two elites; otherwise it
    /// is a mutation of one.
    #[serde(deserialize_with = "de_probability")]
    pub crossover: f64,
    /// How parents are drawn from the elites: `{ tournament = k }` (the
    /// best of `k` uniform draws; default 4), `"random"` (uniformly, as
    /// Mouret & Clune) or `"roulette"`. Uniform draws spread the effort
    /// evenly over the cells and stay well behind the GA's best at equal
    /// evaluations; a small tournament keeps the archive filled and closes
    /// that gap (docs/evolve.md has the numbers).
    #[serde(deserialize_with = "de_selection")]
    pub selection: Selection,
    /// The two axes of the archive.
    pub descriptors: [DescriptorAxis; 2],
}

impl Default for MapElitesConfig {
    /// The GA's default batch sizes (150 initial, 120 children = population
    /// − elitism), so runs compare at equal evaluations per generation;
    /// genome length × bounding-box aspect, 8 × 8 cells; tournaments of 4.
    fn default() -> Self {
        MapElitesConfig {
            initial: 150,
            batch: 120,
            crossover: 0.3,
            selection: Selection::Tournament(4),
            descriptors: [
                DescriptorAxis { name: "length".into(), bins: default_bins(), range: None },
                DescriptorAxis { name: "aspect".into(), bins: default_bins(), range: None },
            ],
        }
    }
}

impl MapElitesConfig {
    /// Checks every setting; the first problem is returned. Ranges may be
    /// unset here (see [`MapElitesConfig::validate_ranges`]).
    pub fn validate(&self) -> Result<(), ConfigError> {
        for (name, n) in [("initial", self.initial), ("batch", self.batch)] {
            require(name, n as f64, "in [1, 1000000]", check_batch(n).is_ok())?;
        }
        probability("crossover", self.crossover)?;
        if self.selection == Selection::Tournament(0) {
            return Err(ConfigError::Tournament("map_elites"));
        }
        self.descriptors.iter().try_for_each(DescriptorAxis::validate)
    }

    /// [`MapElitesConfig::validate`], and every axis has a range (what a
    /// run needs).
    pub fn validate_ranges(&self) -> Result<(), ConfigError> {
        self.validate()?;
        let unset = self.descriptors.iter().any(|d| d.range.is_none());
        require("descriptors.range", f64::NAN, "set for every descriptor before a run", !unset)
    }

    /// Cells along each axis.
    pub fn shape(&self) -> [usize; 2] {
        self.descriptors.each_ref().map(|d| d.bins)
    }

    /// The cell `[column, row]` of a descriptor pair.
    pub fn cell(&self, descriptors: [f64; 2]) -> [usize; 2] {
        [self.descriptors[0].bin(descriptors[0]), self.descriptors[1].bin(descriptors[1])]
    }
}

fn default_bins() -> usize {
    8
}

fn check_bins(bins: usize) -> Result<(), &'static str> {
    if (1..=MAX_BINS).contains(&bins) { Ok(()) } else { Err("in [1, 256]") }
}

fn check_batch(n: usize) -> Result<(), &'static str> {
    if (1..=MAX_BATCH).contains(&n) { Ok(()) } else { Err("in [1, 1000000]") }
}

fn check_range([lo, hi]: [f64; 2]) -> Result<(), &'static str> {
    if lo.is_finite() && hi.is_finite() && lo < hi { Ok(()) } else { Err("[low, high] with finite low < high") }
}

/// Reads a value with `D` and checks it with `check`; a failure is a
/// deserialization error, so a TOML reader points at the value.
fn checked<'de, D: Deserializer<'de>, T: Deserialize<'de> + std::fmt::Debug>(
    d: D,
    what: &str,
    check: impl Fn(&T) -> Result<(), &'static str>,
) -> Result<T, D::Error> {
    let v = T::deserialize(d)?;
    check(&v).map_err(|req| serde::de::Error::custom(format!("{what} must be {req}, got {v:?}")))?;
    Ok(v)
}

fn de_bins<'de, D: Deserializer<'de>>(d: D) -> Result<usize, D::Error> {
    checked(d, "bins", |b: &usize| check_bins(*b))
}

fn de_batch<'de, D: Deserializer<'de>>(d: D) -> Result<usize, D::Error> {
    checked(d, "the number of individuals", |b: &usize| check_batch(*b))
}

fn de_probability<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    checked(d, "a probability", |p: &f64| if (0.0..=1.0).contains(p) { Ok(()) } else { Err("in [0, 1]") })
}

fn de_selection<'de, D: Deserializer<'de>>(d: D) -> Result<Selection, D::Error> {
    checked(d, "selection", |s: &Selection| {
        if *s == Selection::Tournament(0) {
            Err("\"random\", \"roulette\" or { tournament = k } with k ≥ 1")
        } else {
            Ok(())
        }
    })
}

fn de_range<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f64; 2]>, D::Error> {
    checked(d, "range", |r: &[f64; 2]| check_range(*r)).map(Some)
}
