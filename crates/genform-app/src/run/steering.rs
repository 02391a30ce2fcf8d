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

use anyhow::{Context, Result, bail};
use genform_score::{Knob, Scorer};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

use crate::toml_doc::unknown_name;

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

/// What a run's steering can change: the knobs of its scorer, as they
/// are now ([`genform_score::Scorer::knobs`]), with a scorer to check
/// changes against.
#[derive(Clone)]
pub struct Steerable {
    knobs: Vec<Knob>,
    formula: Option<&'static str>,
    /// A scorer with these knobs (cheap: no targets), which refuses what
    /// the real one would.
    probe: Arc<dyn Scorer>,
}

impl std::fmt::Debug for Steerable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Steerable").field("knobs", &self.knobs).field("formula", &self.formula).finish()
    }
}

impl Default for Steerable {
    fn default() -> Self {
        let probe: Arc<dyn Scorer> = Arc::new(genform_score::Sum(Vec::new()));
        Steerable { knobs: Vec::new(), formula: None, probe }
    }
}

impl Steerable {
    /// The knobs of `scorer`.
    pub fn of(scorer: &dyn Scorer) -> Steerable {
        let probe: Arc<dyn Scorer> = match scorer.with_knobs(&[]) {
            Ok(p) => Arc::from(p),
            Err(_) => Arc::new(genform_score::Sum(Vec::new())),
        };
        Steerable { knobs: scorer.knobs(), formula: scorer.chart(), probe }
    }

    /// The knobs of `scene`'s scorers as its file sets them (no target is
    /// read: listing scenes reads this).
    pub fn of_scene(scene: &crate::scene::Scene) -> Steerable {
        let probe: Arc<dyn Scorer> = Arc::from(scene.scoring.probe());
        Steerable { knobs: probe.knobs(), formula: probe.chart(), probe }
    }

    /// Refuses `set` as applying it would (unknown names, values out of
    /// range, a scorer left without a weight); changes nothing.
    pub fn check(&self, set: &SteerSet) -> Result<()> {
        let changes = self.changes(set)?;
        self.probe.with_knobs(&changes).map(drop).map_err(anyhow::Error::msg)
    }

    /// The current values as a steering request would name them.
    pub fn values(&self) -> SteerSet {
        let mut set = SteerSet::default();
        for k in &self.knobs {
            set.weights.insert(k.name.to_string(), k.weight);
            if let Some(t) = k.target {
                set.targets.insert(k.name.to_string(), t);
            }
        }
        set
    }

    /// What one criterion adds to the fitness, in words (`w/(1+e)` or, in
    /// the paper form, `−w·e`), for scorers whose criteria are charted.
    pub fn contribution_formula(&self) -> Option<&'static str> {
        self.formula
    }

    /// The knobs `set` changes, with their new values: unknown names are
    /// refused (with a did-you-mean), as are non-finite values, targets of
    /// knobs without one and negative weights of unsigned knobs.
    fn changes(&self, set: &SteerSet) -> Result<Vec<Knob>> {
        for (name, v) in &set.weights {
            if let Some(why) = crate::caps::weight(&format!("`{name}`"), *v) {
                bail!(why);
            }
        }
        for (name, v) in &set.targets {
            if !v.is_finite() {
                bail!("`{name}` must be a finite number, not {v}");
            }
        }
        let names: Vec<&str> = self.knobs.iter().map(|k| k.name).collect();
        let kind = self.knobs.first().map_or("steerable value", |k| k.kind);
        let find = |name: &str| {
            self.knobs
                .iter()
                .find(|k| k.name == name)
                .copied()
                .ok_or_else(|| anyhow::anyhow!("{}", unknown_name(name, kind, &names)))
        };
        let mut out: Vec<Knob> = Vec::new();
        for (name, v) in &set.weights {
            let mut k = find(name)?;
            if !k.signed && *v < 0.0 {
                bail!("the weight of `{name}` must be at least 0, not {v}");
            }
            k.weight = *v;
            out.push(k);
        }
        for (name, v) in &set.targets {
            let Some(known) = self.knobs.iter().find(|k| k.name == name.as_str()) else {
                if self.knobs.iter().all(|k| k.target.is_none()) {
                    bail!(
                        "this scene's {}s have no targets ({}), no target `{name}`; targets belong to Genr8 surface \
                         scenes",
                        kind,
                        names.join(", ")
                    );
                }
                return Err(find(name).unwrap_err());
            };
            if known.target.is_none() {
                bail!("`{name}` is a {} with a weight only, no target", known.kind);
            }
            match out.iter_mut().find(|k| k.name == name.as_str()) {
                Some(k) => k.target = Some(*v),
                None => out.push(Knob { target: Some(*v), ..*known }),
            }
        }
        Ok(out)
    }

    /// `scorer` (whose knobs these are) with `set` applied, and what
    /// steering can change after it; nothing changes on error.
    pub(crate) fn apply(&self, scorer: &dyn Scorer, set: &SteerSet) -> Result<(Box<dyn Scorer>, Steerable)> {
        let changes = self.changes(set)?;
        let steered = scorer.with_knobs(&changes).map_err(anyhow::Error::msg)?;
        let now = Steerable::of(steered.as_ref());
        Ok((steered, now))
    }
}

/// Reads a steering log: a `run.json` (its `steering` list) or a JSON list
/// of `{"generation": N, "set": {...}}` entries, sorted by generation
/// (entries of one generation keep their order).
pub fn read_log(path: &Path) -> Result<Vec<SteerEntry>> {
    let text = crate::text::read_text(path, "steering log")?;
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
    use genform_score::{SurfaceCriterion, SurfaceObjective};

    fn set(weights: &[(&str, f64)], targets: &[(&str, f64)]) -> SteerSet {
        let m = |v: &[(&str, f64)]| v.iter().map(|(k, v)| (k.to_string(), *v)).collect();
        SteerSet { weights: m(weights), targets: m(targets) }
    }

    fn targets() -> Box<dyn Scorer> {
        Box::new(genform_score::Targets::new(Vec::new(), genform_score::Fitness::default()))
    }

    fn surface(o: SurfaceObjective) -> Box<dyn Scorer> {
        Box::new(genform_score::SurfaceScorer::new(o).unwrap())
    }

    #[test]
    fn fitness_weights_change_and_mistakes_change_nothing() {
        let scorer = targets();
        let s = Steerable::of(scorer.as_ref());
        let (steered, now) = s.apply(scorer.as_ref(), &set(&[("good", 3.0), ("length", 0.0)], &[])).unwrap();
        let v = now.values();
        assert_eq!((v.weights["good"], v.weights["bad"], v.weights["length"]), (3.0, 15.0, 0.0));
        assert_eq!(Steerable::of(steered.as_ref()).values(), v);
        let e = now.apply(steered.as_ref(), &set(&[("bda", 1.0)], &[])).err().unwrap().to_string();
        assert!(e.contains("did you mean `bad`"), "{e}");
        let (_, neg) = now.apply(steered.as_ref(), &set(&[("good", -1.0)], &[])).unwrap();
        assert_eq!(neg.values().weights["good"], -1.0, "[fitness] weights may be negative");
        assert!(now.apply(steered.as_ref(), &set(&[("good", f64::NAN)], &[])).is_err());
        let e = now.apply(steered.as_ref(), &set(&[], &[("good", 1.0)])).err().unwrap().to_string();
        assert!(e.contains("no target"), "{e}");
        assert_eq!(now.contribution_formula(), None);
    }

    #[test]
    fn surface_goals_change_and_keep_a_positive_weight() {
        let scorer = surface(SurfaceObjective::default().with(SurfaceCriterion::Size, 10.0, 1.0));
        let s = Steerable::of(scorer.as_ref());
        let (steered, now) =
            s.apply(scorer.as_ref(), &set(&[("symmetry", 2.0)], &[("size", 4.0), ("symmetry", 1.0)])).unwrap();
        let v = now.values();
        assert_eq!((v.targets["size"], v.weights["symmetry"], v.targets["symmetry"]), (4.0, 2.0, 1.0));
        let e = now.apply(steered.as_ref(), &set(&[("size", 0.0), ("symmetry", 0.0)], &[])).err().unwrap().to_string();
        assert!(e.starts_with("[surface]"), "{e}");
        let e = now.apply(steered.as_ref(), &set(&[("sise", 1.0)], &[])).err().unwrap().to_string();
        assert!(e.contains("did you mean `size`"), "{e}");
        let e = now.apply(steered.as_ref(), &set(&[("size", -1.0)], &[])).err().unwrap().to_string();
        assert!(e.contains("at least 0"), "{e}");
        assert_eq!(now.contribution_formula(), Some("w/(1+e)"));
    }

    #[test]
    fn steering_a_paper_form_scene_keeps_its_form() {
        let mut o = SurfaceObjective::default().with(SurfaceCriterion::Size, 10.0, 1.0);
        o.form = genform_score::SurfaceForm::Paper;
        let scorer = surface(o);
        let s = Steerable::of(scorer.as_ref());
        let (steered, now) = s.apply(scorer.as_ref(), &set(&[("size", 2.0)], &[("size", 8.0)])).unwrap();
        assert_eq!(steered.form(), "paper");
        assert_eq!((now.values().weights["size"], now.values().targets["size"]), (2.0, 8.0));
        assert_eq!(now.contribution_formula(), Some("−w·e"));
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
