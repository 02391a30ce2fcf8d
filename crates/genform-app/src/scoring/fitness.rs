//! `[fitness]`: how the counts of a scene's counting targets (volume,
//! images, views) become one fitness — the form and its weights.

use anyhow::Result;
use serde::{Deserialize, Serialize};

use crate::toml_doc::{Doc, Value};

/// `[fitness]`: the constants of the fitness formula.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FitnessConfig {
    /// "paper", "separate-overlap", "image", "linear" or "reference-cpu";
    /// an unknown name is an error at its line:col.
    #[serde(default, deserialize_with = "known_form")]
    pub form: Option<String>,
    /// Weight of covered target (α).
    #[serde(default = "two")]
    pub good: f64,
    /// Weight of covered non-target (β).
    #[serde(default = "fifteen")]
    pub bad: f64,
    /// Weight of self-overlap.
    #[serde(default = "one")]
    pub overlap: f64,
    /// Weight of the genome-length penalty (γ).
    #[serde(default = "tenth")]
    pub length: f64,
    /// Lengths over which the penalty rises from 0 to full; defaults to
    /// the genome length bounds of the scene's optimizers.
    #[serde(default)]
    pub length_range: Option<[f64; 2]>,
}

fn one() -> f64 {
    1.0
}
fn two() -> f64 {
    2.0
}
fn fifteen() -> f64 {
    15.0
}
fn tenth() -> f64 {
    0.1
}

impl Default for FitnessConfig {
    fn default() -> Self {
        FitnessConfig { form: None, good: 2.0, bad: 15.0, overlap: 1.0, length: 0.1, length_range: None }
    }
}

/// Reads a `form` value, refusing names that are not a fitness form (the
/// TOML reader adds the value's position).
fn known_form<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Option<String>, D::Error> {
    let name = String::deserialize(d)?;
    check_form(&name).map_err(serde::de::Error::custom)?;
    Ok(Some(name))
}

/// Whether `name` is a fitness form; the error lists the forms.
fn check_form(name: &str) -> std::result::Result<(), String> {
    match genform_score::Form::from_name(name) {
        Some(_) => Ok(()),
        None => {
            let names: Vec<&str> = genform_score::Form::NAMES.iter().map(|(n, _)| *n).collect();
            Err(format!("form `{name}` is unknown; use one of: {}", names.join(", ")))
        }
    }
}

impl FitnessConfig {
    /// Reads and checks `[fitness]`.
    pub(crate) fn read(doc: &Doc, value: &Value) -> Result<FitnessConfig> {
        let config: FitnessConfig = doc.read(value)?;
        config.check(doc)?;
        Ok(config)
    }

    /// Refuses weights and length ranges that are not finite numbers, at
    /// their positions.
    fn check(&self, doc: &Doc) -> Result<()> {
        for (k, v) in [("good", self.good), ("bad", self.bad), ("overlap", self.overlap), ("length", self.length)] {
            if let Some(why) = crate::caps::weight(&format!("[fitness] `{k}`"), v) {
                return Err(doc.refuse(&["fitness", k], why));
            }
        }
        if let Some([a, b]) = self.length_range
            && !(a.is_finite() && b.is_finite())
        {
            return Err(doc.refuse(
                &["fitness", "length_range"],
                format!("[fitness] length_range [{a}, {b}] needs two finite lengths"),
            ));
        }
        Ok(())
    }

    /// Replaces the form with `form` (e.g. `genform score --form`) after
    /// checking its name.
    pub fn override_form(&mut self, form: Option<&str>) -> Result<()> {
        if let Some(form) = form {
            check_form(form).map_err(anyhow::Error::msg)?;
            self.form = Some(form.to_string());
        }
        Ok(())
    }

    /// The fitness function: the configured form, or `default` (the first
    /// counting section's); the length range defaults to `lengths`, the
    /// genome length bounds of the scene's optimizers.
    pub fn fitness(&self, default: genform_score::Form, lengths: [f64; 2]) -> genform_score::Fitness {
        let form = self.form.as_deref().and_then(genform_score::Form::from_name).unwrap_or(default);
        let [from, to] = self.length_range.unwrap_or(lengths);
        genform_score::Fitness {
            form,
            good: self.good,
            bad: self.bad,
            overlap: self.overlap,
            length: self.length,
            length_from: from,
            length_to: to,
        }
    }
}
