//! Steering a run: changes of fitness weights and criteria targets that
//! take effect between generations, logged so a replay makes the same run.
//!
//! A change ([`SteerSet`]) names weights and targets; the run applies it
//! right before it makes generation `N` and logs `{"generation": N, "set":
//! …}` ([`SteerEntry`]) in `run.json`. `genform evolve --steering FILE`
//! applies a log's entries before the same generations, so the run is the
//! same, byte for byte.
//!
//! What a change means depends on how the scene scores:
//!
//! - `[fitness]` (tree scenes, and codon scenes with volume or image
//!   targets): the weights `good`, `bad`, `overlap`, `length`; no targets.
//! - `[surface]` (Genr8 surface scenes): the weight and the target of each
//!   criterion (`size`, `smoothness`, `soft_boundary`, `subdivisions`,
//!   `symmetry`, `undulation`).
//!
//! Right after a generation's changes are applied, the run re-scores what
//! the optimizer stores ([`genform_evolve::Rescore`]: populations, elites,
//! the best so far, MCMC chain states, SMC particles, MAP-Elites cells), so
//! nothing scored under the old weights outranks what is scored under the
//! new ones. Re-scoring is deterministic at any thread count, so a replay is
//! identical. See ARCHITECTURE.md ("genform serve").

use crate::codon_scene::CodonSceneConfig;
use crate::scene_config::FitnessConfig;
use anyhow::{Context, Result, bail};
use genform_score::{SurfaceCriterion, SurfaceObjective, SurfaceScorer};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// One change: new values of named weights and targets.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SteerSet {
    /// Weights by name.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub weights: BTreeMap<String, f64>,
    /// Targets by name (surface criteria only).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub targets: BTreeMap<String, f64>,
}

impl SteerSet {
    /// Whether it changes nothing.
    pub fn is_empty(&self) -> bool {
        self.weights.is_empty() && self.targets.is_empty()
    }

    /// `other`'s values over these (later changes win).
    pub fn merge(&mut self, other: SteerSet) {
        self.weights.extend(other.weights);
        self.targets.extend(other.targets);
    }
}

/// A change and the generation it took effect at (the first generation
/// made with it).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SteerEntry {
    /// The generation.
    pub generation: usize,
    /// The change.
    pub set: SteerSet,
}

/// The names `[fitness]` weights go by.
pub const FITNESS_WEIGHTS: [&str; 4] = ["good", "bad", "overlap", "length"];

/// What a scene's steering changes: its fitness constants or its surface goals.
#[derive(Clone, Debug)]
pub enum Steerable {
    /// `[fitness]` weights.
    Fitness(FitnessConfig),
    /// `[surface]` goals.
    Surface(SurfaceObjective),
}

impl Steerable {
    /// Applies `set`, refusing unknown names (with a did-you-mean) and
    /// non-finite values; surface weights must be at least 0 and one of
    /// them positive (`[fitness]` weights may be negative: a target to
    /// avoid). Nothing changes on error.
    pub fn apply(&mut self, set: &SteerSet) -> Result<()> {
        let mut next = self.clone();
        for (name, v) in set.weights.iter().chain(&set.targets) {
            if !v.is_finite() {
                bail!("`{name}` must be a finite number, not {v}");
            }
        }
        match &mut next {
            Steerable::Fitness(f) => {
                if let Some(name) = set.targets.keys().next() {
                    bail!(
                        "this scene's [fitness] has weights only ({}), no target `{name}`; targets belong to Genr8 \
                         surface scenes",
                        FITNESS_WEIGHTS.join(", ")
                    );
                }
                for (name, v) in &set.weights {
                    let slot = match name.as_str() {
                        "good" => &mut f.good,
                        "bad" => &mut f.bad,
                        "overlap" => &mut f.overlap,
                        "length" => &mut f.length,
                        _ => bail!("{}", unknown(name, "[fitness] weight", &FITNESS_WEIGHTS)),
                    };
                    *slot = *v;
                }
            }
            Steerable::Surface(s) => {
                let names = SurfaceCriterion::ALL.map(|c| c.name());
                if let Some((name, v)) = set.weights.iter().find(|(_, v)| **v < 0.0) {
                    bail!("the weight of `{name}` must be at least 0, not {v}");
                }
                for (name, v, weight) in
                    set.weights.iter().map(|(n, v)| (n, v, true)).chain(set.targets.iter().map(|(n, v)| (n, v, false)))
                {
                    let c = SurfaceCriterion::from_name(name)
                        .ok_or_else(|| anyhow::anyhow!("{}", unknown(name, "[surface] criterion", &names)))?;
                    let goal = s.goal_mut(c);
                    if weight {
                        goal.weight = *v;
                    } else {
                        goal.target = *v;
                    }
                }
                SurfaceScorer::new(*s).map_err(|e| anyhow::anyhow!("[surface]: {e}"))?;
            }
        }
        *self = next;
        Ok(())
    }

    /// The current values as a steering request would name them.
    pub fn values(&self) -> SteerSet {
        let mut set = SteerSet::default();
        match self {
            Steerable::Fitness(f) => {
                for (name, v) in FITNESS_WEIGHTS.iter().zip([f.good, f.bad, f.overlap, f.length]) {
                    set.weights.insert(name.to_string(), v);
                }
            }
            Steerable::Surface(s) => {
                for c in SurfaceCriterion::ALL {
                    let g = s.goal(c);
                    set.weights.insert(c.name().to_string(), g.weight);
                    set.targets.insert(c.name().to_string(), g.target);
                }
            }
        }
        set
    }

    /// What one criterion adds to a surface scene's fitness, in words
    /// (`w/(1+e)` or, in the paper form, `−w·e`); `None` for `[fitness]`.
    pub fn contribution_formula(&self) -> Option<&'static str> {
        match self {
            Steerable::Surface(s) => Some(s.form.contribution_formula()),
            Steerable::Fitness(_) => None,
        }
    }

    /// What a codon scene steers: `[surface]` when it has one, else `[fitness]`.
    pub fn of_codon_scene(config: &CodonSceneConfig) -> Steerable {
        match &config.surface {
            Some(s) => Steerable::Surface(*s),
            None => Steerable::Fitness(config.fitness.clone()),
        }
    }
}

/// "`x` is not a KIND; did you mean `y`? The KINDs are a, b, c".
fn unknown(name: &str, kind: &str, names: &[&str]) -> String {
    let hint = genform_core::expr::did_you_mean(name, names.iter().copied())
        .map(|n| format!("did you mean `{n}`? "))
        .unwrap_or_default();
    format!("`{name}` is not a {kind}; {hint}the names are {}", names.join(", "))
}

/// Reads a steering log: a `run.json` (its `steering` list) or a JSON list
/// of `{"generation": N, "set": {...}}` entries, sorted by generation
/// (entries of one generation keep their order).
pub fn read_log(path: &Path) -> Result<Vec<SteerEntry>> {
    let text = crate::source_text::read_text(path, "steering log")?;
    let value: serde_json::Value =
        serde_json::from_str(&text).with_context(|| format!("{} is not JSON", path.display()))?;
    let list = match value {
        serde_json::Value::Array(_) => value,
        serde_json::Value::Object(mut o) => o.remove("steering").unwrap_or(serde_json::Value::Array(Vec::new())),
        _ => bail!("{}: expected a run.json or a list of steering entries", path.display()),
    };
    let mut entries: Vec<SteerEntry> = serde_json::from_value(list).with_context(|| {
        format!(
            "{}: steering entries are {{\"generation\": N, \"set\": {{\"weights\": {{…}}, \"targets\": {{…}}}}}}",
            path.display()
        )
    })?;
    entries.sort_by_key(|e| e.generation);
    Ok(entries)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(weights: &[(&str, f64)], targets: &[(&str, f64)]) -> SteerSet {
        let m = |v: &[(&str, f64)]| v.iter().map(|(k, v)| (k.to_string(), *v)).collect();
        SteerSet { weights: m(weights), targets: m(targets) }
    }

    #[test]
    fn fitness_weights_change_and_mistakes_change_nothing() {
        let mut s = Steerable::Fitness(FitnessConfig::default());
        s.apply(&set(&[("good", 3.0), ("length", 0.0)], &[])).unwrap();
        let v = s.values();
        assert_eq!((v.weights["good"], v.weights["bad"], v.weights["length"]), (3.0, 15.0, 0.0));
        let e = s.apply(&set(&[("bda", 1.0)], &[])).unwrap_err().to_string();
        assert!(e.contains("did you mean `bad`"), "{e}");
        assert_eq!(s.values(), v, "a refused change changes nothing");
        s.apply(&set(&[("good", -1.0)], &[])).unwrap();
        assert_eq!(s.values().weights["good"], -1.0, "[fitness] weights may be negative");
        let before = s.values();
        assert!(s.apply(&set(&[("good", f64::NAN)], &[])).is_err());
        assert!(s.apply(&set(&[], &[("good", 1.0)])).unwrap_err().to_string().contains("no target"));
        assert_eq!(s.values(), before);
    }

    #[test]
    fn surface_goals_change_and_keep_a_positive_weight() {
        let mut s = Steerable::Surface(SurfaceObjective::default().with(SurfaceCriterion::Size, 10.0, 1.0));
        s.apply(&set(&[("symmetry", 2.0)], &[("size", 4.0), ("symmetry", 1.0)])).unwrap();
        let Steerable::Surface(o) = &s else { panic!() };
        assert_eq!((o.size.target, o.symmetry.weight, o.symmetry.target), (4.0, 2.0, 1.0));
        let e = s.apply(&set(&[("size", 0.0), ("symmetry", 0.0)], &[])).unwrap_err().to_string();
        assert!(e.starts_with("[surface]"), "{e}");
        assert!(s.apply(&set(&[("sise", 1.0)], &[])).unwrap_err().to_string().contains("did you mean `size`"));
        assert!(s.apply(&set(&[("size", -1.0)], &[])).unwrap_err().to_string().contains("at least 0"));
        assert_eq!(s.contribution_formula(), Some("w/(1+e)"));
    }

    #[test]
    fn steering_a_paper_form_scene_keeps_its_form() {
        let mut o = SurfaceObjective::default().with(SurfaceCriterion::Size, 10.0, 1.0);
        o.form = genform_score::SurfaceForm::Paper;
        let mut s = Steerable::Surface(o);
        s.apply(&set(&[("size", 2.0)], &[("size", 8.0)])).unwrap();
        let Steerable::Surface(now) = &s else { panic!() };
        assert_eq!((now.form, now.size.weight, now.size.target), (genform_score::SurfaceForm::Paper, 2.0, 8.0));
        assert_eq!(s.contribution_formula(), Some("−w·e"));
        assert_eq!(Steerable::Fitness(FitnessConfig::default()).contribution_formula(), None);
    }

    #[test]
    fn logs_are_read_from_run_json_or_a_list() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("run.json");
        std::fs::write(&p, r#"{"seed": 1, "steering": [{"generation": 4, "set": {"weights": {"good": 3}}}, {"generation": 2, "set": {}}]}"#).unwrap();
        let log = read_log(&p).unwrap();
        assert_eq!(log.iter().map(|e| e.generation).collect::<Vec<_>>(), [2, 4]);
        assert_eq!(log[1].set.weights["good"], 3.0);
        std::fs::write(&p, r#"[{"generation": 1, "set": {"targets": {"size": 5}}}]"#).unwrap();
        assert_eq!(read_log(&p).unwrap()[0].set.targets["size"], 5.0);
        std::fs::write(&p, r#"[{"generation": 1, "sett": {}}]"#).unwrap();
        assert!(format!("{:#}", read_log(&p).unwrap_err()).contains("steering entries are"));
    }
}
