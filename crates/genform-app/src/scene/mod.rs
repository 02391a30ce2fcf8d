//! One scene: a TOML file naming a grammar, the scorers its models are
//! scored by and the settings of the optimizers that evolve them, read
//! once into one typed [`Scene`] whatever the grammar's genomes are.
//!
//! Each part of the file is read by its owner: `grammar`, `description`,
//! `[run]` and `[limits]` here; the formalism's keys (`phenotype`,
//! `environment`, `steps`, `box`, `[mapper]`) by the grammar's row of the
//! formalism table; every scoring section by its row of the scorer
//! registry; every optimizer section by its row of the optimizer table.
//! Whether the genomes are derivation trees or codons is the formalism
//! row's answer; sections of the other kind are refused with the reason.
//! Every refusal — a wrong type, an unknown key, a value out of range,
//! settings that do not go together, a size past the memory budget — names
//! the `file:line:col` of the value (or, for a scene edited by `--set`,
//! the setting).

pub mod patch;

use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

use crate::formalism::{FORMALISMS, Formalism, Genomes, LIMIT_KEYS, MODEL_KEYS, ModelSettings, SceneLimits};
use crate::memory::{Reservation, Size};
use crate::optimizers::{OptimizerSettings, SECTIONS, Searches};
use crate::scoring::{FITNESS, FitnessConfig, SCORERS, Scoring};
use crate::toml_doc::{Doc, unknown_name};
use patch::Axis;

/// `[run]`: stopping rules.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RunConfig {
    /// Stop after this many generations.
    #[serde(default)]
    pub generations: Option<usize>,
    /// Stop after this wall-clock time, e.g. "30s", "2m", "1h".
    #[serde(default)]
    pub budget: Option<String>,
    /// Stop after this many evaluations.
    #[serde(default)]
    pub evaluations: Option<u64>,
}

/// The scene-level keys read here.
const SCENE_KEYS: [&str; 4] = ["grammar", "description", "run", "limits"];

/// A loaded, checked scene (paths resolved against its folder).
#[derive(Clone)]
pub struct Scene {
    /// The scene file.
    pub path: PathBuf,
    /// The grammar file.
    pub grammar: PathBuf,
    /// A one-line description, shown in `run.json` and the plots.
    pub description: String,
    /// The grammar's formalism.
    pub(crate) formalism: &'static dyn Formalism,
    /// The genomes its optimizers search.
    pub searches: Searches,
    /// The formalism's settings.
    pub model: ModelSettings,
    /// `[limits]`.
    pub limits: SceneLimits,
    /// `[run]`.
    pub run: RunConfig,
    /// The scoring sections and `[fitness]`.
    pub scoring: Scoring,
    /// The optimizer sections.
    pub optimizers: OptimizerSettings,
}

impl std::fmt::Debug for Scene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Scene")
            .field("path", &self.path)
            .field("grammar", &self.grammar)
            .field("formalism", &self.formalism.name())
            .field("searches", &self.searches)
            .finish_non_exhaustive()
    }
}

impl Scene {
    /// Reads and checks the scene at `path`, with `patch` (a settings
    /// patch, possibly empty) applied: the scene as written is checked
    /// first, so its own mistakes keep their positions.
    pub fn load(path: &Path, patch: &[Axis]) -> Result<Scene> {
        let text = crate::text::read_text(path, "scene")?;
        let scene = Scene::from_text(path, &text, None)?;
        if patch.is_empty() {
            return Ok(scene);
        }
        let settings: Vec<(&Axis, usize)> = patch.iter().map(|a| (a, 0)).collect();
        Scene::from_patched(path, &text, &settings)
    }

    /// Every combination of the axes' values (the first axis varies
    /// slowest) applied to the scene at `path` (text `text`) and checked,
    /// with the values of each.
    pub fn variants(path: &Path, text: &str, axes: &[Axis]) -> Result<Vec<(patch::Combination, Scene)>> {
        patch::combinations(axes)
            .into_iter()
            .map(|combo| {
                let settings: Vec<(&Axis, usize)> = axes.iter().zip(&combo).map(|(a, &i)| (a, i)).collect();
                let names = settings.iter().map(|(a, i)| a.values[*i].clone()).collect();
                Ok((names, Scene::from_patched(path, text, &settings)?))
            })
            .collect()
    }

    /// The scene `text` with `settings` applied; refusals name the settings.
    fn from_patched(path: &Path, text: &str, settings: &[(&Axis, usize)]) -> Result<Scene> {
        let p = patch::apply(path, text, settings)?;
        Scene::from_text(path, &p.text, Some((p.shown, p.keys)))
    }

    /// Reads `text` as the scene at `path` (whose folder relative paths
    /// start from); `patch`: the text is a settings patch's edit.
    pub(crate) fn from_text(path: &Path, text: &str, patch: Option<(String, Vec<Vec<String>>)>) -> Result<Scene> {
        let mut doc = Doc::parse(path, text)?;
        if let Some((shown, keys)) = patch {
            doc = doc.patched(shown, keys);
        }
        read(&doc, path.parent().unwrap_or(Path::new(".")))
    }

    /// The formalism's name (`shape grammar`, `GE grammar`, …).
    pub fn formalism_name(&self) -> &'static str {
        self.formalism.name()
    }

    /// `run.json`'s `kind` of the scene (`tree`, `ge-gr8`, `box-split`, …).
    pub fn kind(&self) -> &'static str {
        self.formalism.kind(&self.model)
    }

    /// Whether its models are grown surfaces (previews turn them +z up).
    pub fn grows_surfaces(&self) -> bool {
        self.formalism.grows_surfaces(&self.model)
    }

    /// The name of the algorithm `name` asks for (`None`: the scene's
    /// default), refused when it cannot evolve this scene's genomes.
    pub fn algorithm(&self, name: Option<&str>) -> Result<&'static str> {
        Ok(match name {
            Some(n) => crate::optimizers::find(n, self.searches, &self.path)?.name(),
            None => crate::optimizers::default_for(self.searches).name(),
        })
    }

    /// The names of the algorithms that can evolve it.
    pub fn algorithms(&self) -> Vec<&'static str> {
        crate::optimizers::names_for(self.searches)
    }

    /// The `[volume]` grid's sides, if the scene has a volume target (for
    /// descriptors' default ranges).
    pub(crate) fn box_size(&self) -> Option<[f64; 3]> {
        self.scoring.extent()
    }

    /// The settings of every tree optimizer, ranges filled in.
    pub fn tree_settings(&self) -> genform_evolve::Settings {
        self.optimizers.tree(self.box_size())
    }

    /// The genome length bounds of its optimizers.
    pub(crate) fn lengths(&self) -> [f64; 2] {
        self.optimizers.lengths(self.searches)
    }

    /// Whether its scorers have target models to show (volume targets).
    pub fn has_target_model(&self) -> bool {
        self.scoring.sections().any(|s| s.has_target_meshes())
    }

    /// Its target pictures (image targets' files, PNG or PFM), in order.
    pub fn target_pictures(&self) -> Vec<PathBuf> {
        self.scoring.sections().flat_map(|s| s.target_pictures()).collect()
    }

    /// Its target models (volume targets' meshes, fixed genomes' models)
    /// as one GLB, for showing beside a model.
    pub fn target_glb(&self) -> Result<Vec<u8>> {
        let mut scene = genform_core::Scene::new();
        let tag = scene.tag("target");
        for section in self.scoring.sections() {
            for mesh in section.target_meshes()? {
                let id = scene.mesh(&std::sync::Arc::new(mesh));
                scene.instances.push(genform_core::Instance {
                    transform: glam::Affine3A::IDENTITY,
                    primitive: genform_core::Primitive::Mesh(id),
                    tag,
                });
            }
        }
        genform_export::export(&scene, genform_export::Format::Glb, &Default::default())
            .map_err(|e| anyhow::anyhow!("cannot export the target: {e}"))
    }

    /// The scene as a run ran it, for `run.json`: every section it gives,
    /// defaults written out.
    pub fn to_json(&self) -> serde_json::Value {
        let mut out = serde_json::Map::new();
        out.insert("grammar".into(), self.grammar.display().to_string().into());
        out.insert("description".into(), self.description.clone().into());
        if let serde_json::Value::Object(model) = serde_json::to_value(&self.model).unwrap_or_default() {
            for (k, v) in model {
                if self.formalism.scene_keys().iter().any(|s| *s == k || s.starts_with(&format!("{k}."))) {
                    out.insert(k, v);
                }
            }
        }
        let limits: serde_json::Map<String, serde_json::Value> = self
            .formalism
            .limit_keys(&self.model)
            .iter()
            .map(|k| (k.to_string(), serde_json::json!(self.limits.get(k))))
            .collect();
        out.insert("limits".into(), limits.into());
        out.insert("run".into(), serde_json::to_value(&self.run).unwrap_or_default());
        for (name, value) in self.scoring.to_json() {
            out.insert(name.into(), value);
        }
        out.insert(FITNESS.into(), serde_json::to_value(&self.scoring.fitness).unwrap_or_default());
        for s in SECTIONS.iter().filter(|s| s.searches == self.searches) {
            out.insert(s.name.into(), s.echo(&self.optimizers));
        }
        out.into()
    }
}

/// What the studio's lists show of a scene file, even one with mistakes.
pub struct SceneSummary {
    /// Its `description`, if it reads as text.
    pub description: Option<String>,
    /// Whether its grammar is evolved with codons.
    pub codons: bool,
    /// The algorithms that can evolve it.
    pub algorithms: Vec<&'static str>,
    /// The scene, or why it does not load.
    pub scene: Result<Scene>,
}

impl Scene {
    /// What a scene file is, for lists; `None` when `path` is no scene (no
    /// TOML with a `grammar` key).
    pub fn summary(path: &Path) -> Option<SceneSummary> {
        let text = crate::text::read_text(path, "scene").ok()?;
        let doc = Doc::parse(path, &text).ok()?;
        let grammar: String = doc.read(doc.get("grammar")?).ok()?;
        let codons = crate::formalism::for_path(Path::new(&grammar)).is_ok_and(|f| f.genomes() != Genomes::Tree);
        let description = doc.get("description").and_then(|d| doc.read::<String>(d).ok());
        let searches = if codons { Searches::Codons } else { Searches::Trees };
        let algorithms = crate::optimizers::names_for(searches);
        Some(SceneSummary { description, codons, algorithms, scene: Scene::from_text(path, &text, None) })
    }
}

/// Bytes one codon read may take while a genome is mapped (its pending
/// symbols and output; no trace is kept in a run).
const MAPPING_CODON_BYTES: u64 = 32;

/// What one mapping may grow to under `[mapper] max_wraps`: reading stops
/// after `max_wraps + 1` passes over a genome of up to `max_length`
/// codons, per worker thread.
fn mapping_size(max_wraps: u32, max_length: usize) -> crate::memory::Size<'static> {
    let codons = (u64::from(max_wraps) + 1).saturating_mul(max_length as u64);
    crate::memory::Size {
        section: "mapper",
        key: "max_wraps",
        value: u128::from(max_wraps),
        bytes: crate::memory::estimate(codons, MAPPING_CODON_BYTES),
        what: format!(
            "{codons} codons read by one mapping ([ge] max_length {max_length}, {} passes)",
            u64::from(max_wraps) + 1
        ),
    }
}

/// Refuses `[run]` values no run could reach, at their positions.
fn check_run(doc: &Doc, run: &RunConfig) -> Result<()> {
    if let Some(b) = &run.budget {
        crate::units::parse_duration(b).map_err(|e| doc.refuse(&["run", "budget"], format!("[run] budget: {e:#}")))?;
    }
    if let Some(why) = run.generations.and_then(|g| crate::caps::generations("[run] generations", g)) {
        return Err(doc.refuse(&["run", "generations"], why));
    }
    let evaluations =
        run.evaluations.and_then(|e| crate::caps::count("[run] evaluations", e, crate::caps::MAX_EVALUATIONS));
    if let Some(why) = evaluations {
        return Err(doc.refuse(&["run", "evaluations"], why));
    }
    Ok(())
}

/// Reads and checks the scene in `doc`, paths relative to `base`.
fn read(doc: &Doc, base: &Path) -> Result<Scene> {
    doc.check_integers()?;
    let grammar_value = doc.get("grammar").ok_or_else(|| {
        doc.refuse(&[], "a scene names its grammar: add `grammar = \"file\"` (relative to the scene)")
    })?;
    let grammar = base.join(doc.read::<PathBuf>(grammar_value)?);
    crate::gate::admit_path(&grammar).map_err(|e| crate::gate::placed(doc.place(&["grammar"]), e))?;
    let formalism = crate::formalism::for_path(&grammar).map_err(|e| doc.refuse(&["grammar"], e))?;
    let searches = match formalism.genomes() {
        Genomes::Tree => Searches::Trees,
        Genomes::Codons => Searches::Codons,
        Genomes::Phenotype => {
            return Err(doc.refuse(
                &["grammar"],
                format!(
                    "{} are not evolved directly: evolve a codon scene of a GE grammar (.bnf) that writes them \
                     (`phenotype = \"gr8\"`, see examples/scenes/genr8_canopy.toml)",
                    formalism.plural()
                ),
            ));
        }
    };
    let description = match doc.get("description") {
        Some(v) => doc.read(v)?,
        None => String::new(),
    };
    let mut model: ModelSettings = doc.read_root()?;
    if let Some(env) = &mut model.environment {
        *env = base.join(&*env);
        crate::gate::admit_path(env).map_err(|e| crate::gate::placed(doc.place(&["environment"]), e))?;
    }
    let (mut limits, mut run) = (SceneLimits::default(), RunConfig::default());
    let mut scoring = Scoring::default();
    let mut optimizers = OptimizerSettings::default();
    for (key, value, _) in doc.entries() {
        if key == "grammar" || key == "description" {
            continue;
        } else if key == "run" {
            run = doc.read(value)?;
        } else if key == "limits" {
            limits = doc.read(value)?;
        } else if key == FITNESS {
            scoring.fitness = FitnessConfig::read(doc, value)?;
        } else if MODEL_KEYS.contains(&key) {
            check_model_key(doc, formalism, key, value)?;
        } else if let Some(i) = SCORERS.iter().position(|r| r.section() == key) {
            let row = SCORERS[i];
            if row.for_surfaces() != formalism.grows_surfaces(&model) {
                return Err(doc.refuse(&[key], wrong_scorer(key, row.for_surfaces())));
            }
            scoring.sections.push((i, row.read(doc, value, base)?));
        } else if let Some(section) = SECTIONS.iter().find(|s| s.name == key) {
            if section.searches != searches {
                return Err(doc.refuse(&[key], wrong_optimizer(key, &grammar, searches)));
            }
            section.read(doc, value, &mut optimizers)?;
        } else {
            let known = all_keys();
            let at = doc.refuse(&[key], format!("unknown key: {}", unknown_name(key, "scene key", &known)));
            return Err(at);
        }
    }
    scoring.sections.sort_by_key(|(i, _)| *i);
    check_limits(doc, formalism, &model, &limits)?;
    formalism.check_scene(doc, &model)?;
    if let Some(s) = model.steps.filter(|&s| u64::from(s) > crate::caps::MAX_STEPS) {
        let cap = crate::caps::MAX_STEPS;
        return Err(doc.refuse(&["steps"], format!("steps = {s} is past the cap of {cap} derivation steps")));
    }
    if scoring.sections.is_empty() {
        return Err(doc.refuse(&["grammar"], missing_scorer(formalism.grows_surfaces(&model))));
    }
    check_run(doc, &run)?;
    for section in SECTIONS.iter().filter(|s| s.searches == searches) {
        section.check(doc, &optimizers)?;
    }
    check_layout(doc, &model, &optimizers)?;
    let mut sizes = crate::optimizers::sizes(searches, &optimizers);
    sizes.extend(scoring.memory());
    if let (Searches::Codons, Some(w)) = (searches, model.mapper.max_wraps) {
        sizes.push(mapping_size(w, optimizers.ge.max_length));
    }
    sizes.extend(limit_sizes(&limits));
    crate::memory::check_sizes(doc, &sizes)?;
    Ok(Scene {
        path: doc.path().to_path_buf(),
        grammar,
        description,
        formalism,
        searches,
        model,
        limits,
        run,
        scoring,
        optimizers,
    })
}

/// Every key a scene may have at its top level.
fn all_keys() -> Vec<&'static str> {
    let mut keys: Vec<&str> = SCENE_KEYS.to_vec();
    keys.extend(MODEL_KEYS);
    keys.extend(SCORERS.iter().map(|r| r.section()));
    keys.push(FITNESS);
    keys.extend(SECTIONS.iter().map(|s| s.name));
    keys
}

/// The formalisms (plural, with extensions) whose scenes read `key`.
fn readers(key: &str) -> String {
    let owners: Vec<String> = FORMALISMS
        .iter()
        .filter(|f| f.scene_keys().contains(&key))
        .map(|f| format!("{} ({})", f.plural(), f.extensions().join(" ")))
        .collect();
    match owners.as_slice() {
        [] => "no formalism".to_string(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// Refuses a formalism key (or a `[mapper]` key) the grammar's formalism
/// does not read, naming those that do.
fn check_model_key(doc: &Doc, formalism: &dyn Formalism, key: &str, value: &crate::toml_doc::Value) -> Result<()> {
    let this = format!("{} ({})", formalism.plural(), formalism.extensions().join(" "));
    if key == "mapper" {
        for (sub, _, _) in Doc::table_entries(value) {
            let full = format!("mapper.{sub}");
            if !formalism.scene_keys().contains(&full.as_str()) {
                let message = format!("`[mapper] {sub}` applies to {} only, not to {this}", readers(&full));
                return Err(doc.refuse(&["mapper", sub], message));
            }
        }
        return Ok(());
    }
    if !formalism.scene_keys().contains(&key) {
        return Err(doc.refuse(&[key], format!("`{key}` applies to {} only, not to {this}", readers(key))));
    }
    Ok(())
}

/// Refuses `[limits]` keys the formalism does not read and limits of 0.
fn check_limits(doc: &Doc, formalism: &dyn Formalism, model: &ModelSettings, limits: &SceneLimits) -> Result<()> {
    let ours = formalism.limit_keys(model);
    for key in limits.given() {
        if !ours.contains(&key) {
            let theirs = if ours.is_empty() { "none".to_string() } else { ours.join(", ") };
            return Err(doc.refuse(
                &["limits", key],
                format!(
                    "[limits] `{key}` is no limit of this scene's grammar ({}); its limits: {theirs}",
                    formalism.name()
                ),
            ));
        }
        if limits.get(key) == Some(0) {
            return Err(doc.refuse(&["limits", key], format!("[limits] {key} must be at least 1")));
        }
    }
    Ok(())
}

/// The refusal of a scorer section that does not fit the scene's models.
fn wrong_scorer(key: &str, for_surfaces: bool) -> String {
    if for_surfaces {
        format!(
            "[{key}] scores grown surfaces (phenotype = \"gr8\" scenes); this scene's models are scored by targets such as [volume] or [[image]]"
        )
    } else {
        format!(
            "[{key}] applies to models with volume or silhouette targets; phenotype = \"gr8\" scenes are scored by [surface]"
        )
    }
}

/// The refusal of a scene without any scorer.
fn missing_scorer(surfaces: bool) -> String {
    if surfaces {
        "a phenotype = \"gr8\" scene is scored by Genr8's surface criteria: add a [surface] table, e.g. \
         `size = { target = 10, weight = 1 }`"
            .to_string()
    } else {
        let names: Vec<String> =
            SCORERS.iter().filter(|r| !r.for_surfaces()).map(|r| format!("[{}]", r.section())).collect();
        format!("no target: add a {} section", names.join(" or "))
    }
}

/// The refusal of an optimizer section of the other kind of genome.
fn wrong_optimizer(key: &str, grammar: &Path, searches: Searches) -> String {
    let ours: Vec<&str> = SECTIONS.iter().filter(|s| s.searches == searches).map(|s| s.name).collect();
    let (kind, other) = match searches {
        Searches::Trees => ("derivation trees", "codon lists"),
        Searches::Codons => ("codon lists", "derivation trees"),
    };
    format!(
        "[{key}] sets optimizers of {other}, but {} is evolved as {kind}: its optimizer settings go in [{}]",
        grammar.display(),
        ours.join("], [")
    )
}

/// Refuses a per-choice codon layout with what writes or cuts genomes as
/// one left-to-right reading.
fn check_layout(doc: &Doc, model: &ModelSettings, optimizers: &OptimizerSettings) -> Result<()> {
    if model.mapper.layout != Some(genform_ge::CodonLayout::PerChoice) {
        return Ok(());
    }
    let ge = &optimizers.ge;
    if ge.init == genform_evolve::Init::Sensible {
        return Err(doc.refuse(
            &["mapper", "layout"],
            "[mapper] layout = \"per-choice\" cannot be combined with [ge] init = \"sensible\"; use init = \"random\" or layout = \"sequential\"",
        ));
    }
    if ge.subtree_mutation > 0.0 {
        return Err(doc.refuse(
            &["mapper", "layout"],
            "[mapper] layout = \"per-choice\" cannot be combined with [ge] subtree_mutation (subtrees are not contiguous codon spans there); set subtree_mutation = 0 or layout = \"sequential\"",
        ));
    }
    Ok(())
}

/// The optimizer settings of the scene at `scene` (`None`: the defaults,
/// for a bare grammar) with `patch` applied, checked as a scene file's are
/// (ask/tell optimizers take their settings this way).
pub fn optimizer_settings(scene: Option<&Path>, patch: &[Axis]) -> Result<OptimizerSettings> {
    let (path, text) = match scene {
        Some(p) => (p.to_path_buf(), crate::text::read_text(p, "scene")?),
        None => (PathBuf::from("(defaults)"), String::new()),
    };
    let settings: Vec<(&Axis, usize)> = patch.iter().map(|a| (a, 0)).collect();
    let patched = patch::apply(&path, &text, &settings)?;
    let mut doc = Doc::parse(&path, &patched.text)?;
    if !patch.is_empty() {
        doc = doc.patched(patched.shown, patched.keys);
    }
    let mut settings = OptimizerSettings::default();
    for section in SECTIONS {
        if let Some(value) = doc.get(section.name) {
            section.read(&doc, value, &mut settings)?;
            section.check(&doc, &settings).context("optimizer settings")?;
        }
    }
    Ok(settings)
}

/// The sizes of a scene's `[limits]`.
fn limit_sizes(limits: &SceneLimits) -> Vec<Size<'static>> {
    crate::memory::limit_sizes(
        &LIMIT_KEYS.iter().map(|&(key, bytes, what)| (key, limits.get(key), bytes, what)).collect::<Vec<_>>(),
    )
}

/// What a scene asks memory for: the sizes checked when it is read, and
/// the reservations its runs hold in the process's ledger.
impl Scene {
    /// Every size its settings ask for (its optimizers', its scorers' and
    /// its `[limits]`), as the memory budget checks them when it is read.
    pub(crate) fn sizes(&self) -> Vec<Size<'static>> {
        let mut sizes = crate::optimizers::sizes(self.searches, &self.optimizers);
        sizes.extend(self.scoring.memory());
        sizes.extend(limit_sizes(&self.limits));
        sizes
    }

    /// The sizes of its `[limits]` alone.
    pub(crate) fn limit_sizes(&self) -> Vec<Size<'static>> {
        limit_sizes(&self.limits)
    }

    /// The bytes its settings ask for together (an estimate, generous by
    /// constant factors): what a run of it reserves for its whole life.
    pub fn estimated_bytes(&self) -> u128 {
        self.sizes().iter().map(|s| s.bytes).fold(0, u128::saturating_add)
    }

    /// Reserves [`Scene::estimated_bytes`] for `what` ("run",
    /// "comparison") in the process's memory ledger, refused while others
    /// hold too much of the budget.
    pub(crate) fn reserve(&self, what: &str) -> Result<Reservation> {
        crate::memory::reserve_sizes(&self.sizes(), what)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tree scene of the shipped spaceship grammar (its target is not
    /// read: loading a scene only checks it).
    fn ship(extra: &str) -> String {
        let grammar = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/shape/spaceship.sg");
        format!(
            "grammar = {:?}\n[volume]\nmin = [-1.0, -1.0, -1.0]\nmax = [1.0, 1.0, 1.0]\nvoxels = [4, 4, 4]\n\
             [[volume.target]]\nmesh = \"t.obj\"\n{extra}",
            grammar.display().to_string()
        )
    }

    /// A Genr8 surface scene of the shipped GE grammar.
    fn canopy(extra: &str) -> String {
        let grammar = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/ge/genr8.bnf");
        format!("grammar = {:?}\nphenotype = \"gr8\"\n{extra}", grammar.display().to_string())
    }

    /// The error of loading `text` as `s.toml`.
    fn refusal(text: &str) -> String {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.toml");
        std::fs::write(&path, text).unwrap();
        let e = format!("{:#}", Scene::load(&path, &[]).unwrap_err());
        e.replace(&dir.path().display().to_string(), "DIR")
    }

    /// `DIR/s.toml:LINE:COL` of the first `needle` on the line starting with `on`.
    fn at(text: &str, on: &str, needle: &str) -> String {
        // `starts_with`, not `contains`: the grammar line holds a path, which
        // may contain a key (a checkout under `/work/lpygenes` holds `genes`).
        let (n, line) = text.lines().enumerate().find(|(_, l)| l.starts_with(on)).unwrap();
        let col = line[..line.find(needle).unwrap()].chars().count() + 1;
        format!("DIR/s.toml:{}:{col}: ", n + 1)
    }

    #[test]
    fn every_scene_level_refusal_names_the_value_it_refuses() {
        let cases: [(String, &str, &str, &str); 20] = [
            (ship("[ga]\npopulation = 0\n"), "population", "0", "[ga] population must be at least 2, got 0"),
            (ship("[ga]\npopulation = 1\n"), "population", "1", "[ga] population must be at least 2, got 1"),
            (
                ship("[ga]\nmutation_rate = nan\n"),
                "mutation_rate",
                "nan",
                "[ga] mutation_rate must lie in [0, 1], got NaN",
            ),
            (ship("[mh]\nchains = 0\n"), "chains", "0", "[mh] chains must be at least 1, got 0"),
            (ship("[smc]\nparticles = 0\n"), "particles", "0", "[smc] particles must be at least 2, got 0"),
            (ship("[smc]\nparticles = 1\n"), "particles", "1", "[smc] particles must be at least 2, got 1"),
            (ship("[run]\nevaluations = 0\n"), "evaluations", "0", "[run] evaluations must be at least 1"),
            (
                ship("[run]\ngenerations = 1000000001\n"),
                "generations",
                "1",
                "[run] generations = 1000000001 is past the cap of 1,000,000,000",
            ),
            (
                ship("[run]\ngenerations = 18446744073709551615\n"),
                "generations",
                "1",
                "18446744073709551615 is beyond TOML's integers",
            ),
            (
                ship("[ga]\npopulation = 20\nselection = { first = { tournament = 21 } }\n"),
                "selection",
                "{ tournament",
                "[ga] the tournament size 21 in selection.first is larger than the population (20)",
            ),
            (
                ship("[ga]\nmutation = { alter = 0, grow = 0, cut = 0 }\n"),
                "mutation",
                "{",
                "[ga] mutation weights must be finite and ≥ 0, and alter, grow, cut and regrow not all 0",
            ),
            (ship("[fitness]\nbad = -1e308\n"), "bad", "-", "[fitness] `bad` = -1e308 is past ±1e9"),
            (
                canopy("[surface]\nsize = { target = 5, weight = 1e308 }\n"),
                "size =",
                "{",
                "[surface]: surface criterion `size`: the weight must be a number from 0 to 1e9",
            ),
            (
                ship("[ga]\nselection = { first = { tournament = 0 } }\n"),
                "selection",
                "{ tournament",
                "[ga] the tournament size in selection.first must be at least 1",
            ),
            (
                ship("[ga]\npopulation = 10\nelitism = 10\n"),
                "elitism",
                "10",
                "[ga] elitism (10) must be smaller than the population (10)",
            ),
            (ship("[limits]\ngenes = 0\n"), "genes", "0", "[limits] genes must be at least 1"),
            (
                ship("").replace("min = [-1.0, -1.0, -1.0]", "min = [-1.0, nan, -1.0]"),
                "min =",
                "[",
                "[volume]: the voxel grid bounds must be finite",
            ),
            (
                ship("").replace("max = [1.0, 1.0, 1.0]", "max = [1.0, -2.0, 1.0]"),
                "max =",
                "[",
                "[volume]: the voxel grid is empty along y",
            ),
            (
                canopy("[surface]\nsize = { target = 5, weight = 0 }\n"),
                "[surface]",
                "[",
                "[surface]: the surface objective has no criterion with a weight above 0",
            ),
            (
                canopy("[surface]\nsize = { target = 5 }\n[limits]\nvertices = 9223372036854775807\n"),
                "vertices",
                "9",
                "[limits] vertices = 9223372036854775807 needs about",
            ),
        ];
        for (text, on, needle, message) in cases {
            let e = refusal(&text);
            let want = format!("{}{message}", at(&text, on, needle));
            assert!(e.starts_with(&want), "want `{want}…`, got `{e}`\nin\n{text}");
        }
    }

    #[test]
    fn keys_of_another_formalism_or_genome_are_refused_with_whose_they_are() {
        let e = refusal(&canopy("[surface]\nsize = { target = 5 }\n[ga]\npopulation = 10\n"));
        assert!(e.contains("[ga] sets optimizers of derivation trees") && e.contains("go in [ge]"), "{e}");
        let text = format!("box = [0, 0, 0, 1, 1, 1]\n{}", ship(""));
        let e = refusal(&text);
        assert!(
            e.starts_with(&at(&text, "box", "[")) && e.contains("`box` applies to box-split grammars (.bsg) only"),
            "{e}"
        );
        let e = refusal(&ship("[limits]\nvertices = 10\n"));
        assert!(e.contains("[limits] `vertices` is no limit of this scene's grammar (shape grammar)"), "{e}");
        let e = refusal(&ship("[surface]\nsize = { target = 5 }\n"));
        assert!(e.contains("[surface] scores grown surfaces"), "{e}");
        let e = refusal(&canopy("[surface]\nsize = { target = 5 }\n[mapper]\nmax_dpeth = 3\n"));
        assert!(e.contains("unknown field `max_dpeth`"), "{e}");
        let e = refusal(&ship("[gaa]\npopulation = 5\n"));
        assert!(e.contains("unknown key: `gaa` is not a scene key; did you mean `ga`?"), "{e}");
        assert!(refusal(&canopy("")).contains("add a [surface] table"));
        let e = refusal(&ship("").replace("[volume]", "[nothing]").replace("[[volume.target]]", "[[nothing.target]]"));
        assert!(e.contains("unknown key"), "{e}");
    }

    #[test]
    fn a_patched_scene_names_the_setting_not_a_position() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.toml");
        std::fs::write(&path, ship("")).unwrap();
        let patch = patch::parse_patch(&["ga.population=1".to_string()]).unwrap();
        let e = format!("{:#}", Scene::load(&path, &patch).unwrap_err());
        assert_eq!(e, "--set ga.population=1: [ga] population must be at least 2, got 1");
        let patch = patch::parse_patch(&["ga.populaton=5".to_string()]).unwrap();
        let e = format!("{:#}", Scene::load(&path, &patch).unwrap_err());
        assert!(
            e.starts_with("--set ga.populaton=5: unknown key `populaton` in [ga]; did you mean `population`?"),
            "{e}"
        );
        let patch = patch::parse_patch(&["ga.population=30".to_string()]).unwrap();
        assert_eq!(Scene::load(&path, &patch).unwrap().optimizers.ga.population, 30);
    }

    #[test]
    fn one_scene_tells_trees_from_codons_by_the_grammars_row() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.toml");
        std::fs::write(&path, ship("")).unwrap();
        let tree = Scene::load(&path, &[]).unwrap();
        assert_eq!((tree.searches, tree.kind(), tree.algorithms()[0]), (Searches::Trees, "tree", "ga"));
        std::fs::write(&path, canopy("[surface]\nsize = { target = 5 }\n")).unwrap();
        let codons = Scene::load(&path, &[]).unwrap();
        assert_eq!(
            (codons.searches, codons.kind(), codons.algorithms()),
            (Searches::Codons, "ge-gr8", vec!["ge", "random"])
        );
        assert!(codons.grows_surfaces());
        let e = codons.algorithm(Some("mh")).unwrap_err().to_string();
        assert!(e.contains("is a codon scene"), "{e}");
        let json = codons.to_json();
        assert!(json.get("ga").is_none() && json["ge"]["population"].is_number(), "{json}");
    }
}
