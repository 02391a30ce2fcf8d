//! What a run is asked for and how it is watched: the requests of
//! `evolve` and `score`, the [`Control`] a door holds, the [`Watch`] that
//! sees every generation, the [`RunOutcome`] a door reports, and the stop
//! rules.

use anyhow::{Context, Result, bail};
use genform_core::Scene;
use genform_evolve::{GenerationStats, Horizon, StopReason};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use super::steering::{SteerEntry, SteerSet, Steerable};
use crate::formalism::LimitOverrides;
use crate::optimizers::OptimizerRow;
use crate::scene::patch::parse_patch;
use crate::scene::{RunConfig, Scene as SceneFile};
use crate::units::parse_duration;

/// How often results are written during a run, so a crash loses little.
pub const CHECKPOINT_EVERY: Duration = Duration::from_secs(10);

/// One `evolve` run, as a door asks for it.
#[derive(Clone, Debug, Default)]
pub struct EvolveRequest {
    /// The scene config (tree or codon scene).
    pub scene: PathBuf,
    /// Seed of the optimizer.
    pub seed: u64,
    /// Stop after this many generations (with the next two: replaces the
    /// scene's `[run]` as a whole when any is given).
    pub generations: Option<usize>,
    /// Stop after this wall-clock time, e.g. `"30s"`.
    pub budget: Option<String>,
    /// Stop after this many evaluations.
    pub evaluations: Option<u64>,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// The run folder; `None` writes nothing (Python without `out`).
    pub out: Option<PathBuf>,
    /// The algorithm's name (`None`: the first of the optimizer table that
    /// searches the scene's genomes: `ga` or `ge`).
    pub algorithm: Option<String>,
    /// A GA preset name (`thesis`, …).
    pub preset: Option<String>,
    /// Derivation limits over the scene's (tree scenes only).
    pub limits: LimitOverrides,
    /// A settings patch over the scene file: `section.key=value` each
    /// (`ga.population=20`), values in TOML.
    pub set: Vec<String>,
}

/// How a run is controlled from outside the loop.
pub struct Control<'w> {
    /// Stops the run after the current generation (its results are written).
    pub cancel: Arc<AtomicBool>,
    /// Changes to apply before given generations (a replayed log), sorted
    /// by generation.
    pub schedule: Vec<SteerEntry>,
    /// Sees every generation and may steer.
    pub watch: Option<&'w mut (dyn Watch + Send)>,
}

impl Control<'_> {
    /// A run with no watcher and no steering, stopped by `cancel`.
    pub fn plain(cancel: Arc<AtomicBool>) -> Control<'static> {
        Control { cancel, schedule: Vec::new(), watch: None }
    }
}

/// What a [`Watch`] learns before the first generation.
pub struct Start<'a> {
    /// The fitness the best model could reach.
    pub max_reachable: f64,
    /// The steerable values.
    pub steerable: &'a Steerable,
    /// When the run stops.
    pub horizon: Horizon,
}

/// What a [`Watch`] sees after each generation.
pub struct Tick<'a> {
    /// The optimizer's statistics of the generation.
    pub stats: &'a GenerationStats,
    /// Wall-clock seconds since the run began.
    pub seconds: f64,
    /// The best fitness so far.
    pub best: Option<f64>,
    /// Scorers that chart their criteria: each criterion's contribution
    /// (`w / (1 + e)`, or `−w·e` in the paper form) for the best so far;
    /// empty otherwise.
    pub criteria: Vec<(&'static str, f64)>,
    /// What a progress line adds after the best and the rate (codon
    /// scenes: invalid evaluations), starting with ` · `; often empty.
    pub tail: String,
    /// A line worth logging when no progress bar shows the run (codon
    /// scenes: invalid evaluations by reason), if any.
    pub log: Option<String>,
}

/// Watches a run: called on the run's thread between generations.
/// Every method has a default that does nothing.
pub trait Watch {
    /// Before the first generation.
    fn started(&mut self, _start: &Start) {}
    /// After each generation. It may block (a paused run waits here); what
    /// it returns is applied before the next generation.
    fn generation(&mut self, _tick: &Tick) -> Option<SteerSet> {
        None
    }
    /// Whether to render the gallery of the current population after `generation`.
    fn wants_gallery(&mut self, _generation: usize) -> bool {
        false
    }
    /// The gallery picture (PNG) after `generation`.
    fn gallery(&mut self, _generation: usize, _png: Vec<u8>) {}
    /// The best model so far as GLB after `generation` (offered with the
    /// gallery when the best changed).
    fn best_model(&mut self, _generation: usize, _glb: Vec<u8>) {}
    /// A change took effect; `now` is what steering can change after it,
    /// `max_reachable` the fitness the best model can reach under it.
    fn steered(&mut self, _entry: &SteerEntry, _now: &Steerable, _max_reachable: f64) {}
    /// A progress line (a finished run of `compare`), which a quiet door
    /// leaves out.
    fn line(&mut self, _text: &str) {}
    /// A note or warning for the user (`note: …`, `warning: …`,
    /// `interrupted: …`), at the moment it applies.
    fn note(&mut self, _text: &str) {}
}

/// How a run ended, as a door reports it.
#[derive(Clone)]
pub struct RunOutcome {
    /// The scene file.
    pub scene: PathBuf,
    /// The run folder, when one was written.
    pub out: Option<PathBuf>,
    /// The algorithm's name.
    pub algorithm: &'static str,
    /// Why it stopped.
    pub stopped_by: StopReason,
    /// Generations run (index of the last).
    pub generations: usize,
    /// Objective evaluations.
    pub evaluations: u64,
    /// The run's own time (pauses left out).
    pub elapsed: Duration,
    /// The best fitness found.
    pub best_fitness: Option<f64>,
    /// The fitness the best model could reach.
    pub max_reachable: f64,
    /// The best individual's model.
    pub best_scene: Option<Scene>,
    /// The best tree genome (tree scenes).
    pub best_genome: Option<genform_core::Genome>,
    /// Tree scenes: the grammar file, its generator and the limits the run
    /// derived under (to derive the best genome again without reopening
    /// the scene).
    pub generator: Option<(PathBuf, Arc<crate::formalism::Loaded>, genform_core::Limits)>,
    /// What the summary line adds before the output folder (codon
    /// scenes: invalid evaluations).
    pub tail: String,
}

impl RunOutcome {
    /// The one-line summary every door prints at the end of a run.
    pub fn summary(&self) -> String {
        let secs = self.elapsed.as_secs_f64();
        let to = self.out.as_ref().map(|o| format!(" → {}", o.display())).unwrap_or_default();
        format!(
            "{}: {} generations, {} evaluations in {:.1} s ({:.0}/s); best fitness {:.6} (max reachable {:.4}){}{to}",
            self.scene.display(),
            self.generations,
            self.evaluations,
            secs,
            self.evaluations as f64 / secs.max(1e-9),
            self.best_fitness.unwrap_or(f64::NAN),
            self.max_reachable,
            self.tail,
        )
    }
}

/// One genome's score against a scene (`genform score`).
#[derive(Clone, Debug, Default)]
pub struct ScoreRequest {
    /// The scene config.
    pub scene: PathBuf,
    /// The genome file (tree genome JSON or codons).
    pub genome: PathBuf,
    /// A fitness form overriding the scene's.
    pub form: Option<String>,
    /// Derivation limits over the scene's (tree scenes only).
    pub limits: LimitOverrides,
    /// A settings patch over the scene file (see [`EvolveRequest::set`]).
    pub set: Vec<String>,
}

/// The scene of a request, read once with its settings patch applied and
/// a GA preset set.
pub(crate) fn load_scene(path: &std::path::Path, set: &[String], preset: Option<&str>) -> Result<SceneFile> {
    let mut scene = SceneFile::load(path, &parse_patch(set)?)?;
    if let Some(p) = preset.and_then(genform_evolve::GaPreset::from_name) {
        scene.optimizers.ga = scene.optimizers.ga.clone().with_preset(p);
    }
    Ok(scene)
}

/// The row of the algorithm `name` asks for (`None`: the scene's default).
pub(crate) fn algorithm(name: Option<&str>, scene: &SceneFile) -> Result<&'static OptimizerRow> {
    match name {
        Some(n) => crate::optimizers::find(n, scene.searches, &scene.path),
        None => Ok(crate::optimizers::default_for(scene.searches)),
    }
}

/// The stop rules of a run: the request's replace the scene's `[run]` as a
/// whole; at least one is needed.
pub(crate) fn stop_rules(r: &EvolveRequest, scene: &RunConfig) -> Result<Horizon> {
    horizon(r.generations, r.budget.as_deref(), r.evaluations, scene, "the run")
}

/// The stop rules given (any of them replaces `scene` as a whole), or the
/// scene's; `what` names what they stop in the refusal.
pub(crate) fn horizon(
    generations: Option<usize>,
    budget: Option<&str>,
    evaluations: Option<u64>,
    scene: &RunConfig,
    what: &str,
) -> Result<Horizon> {
    let asked = generations.is_some() || budget.is_some() || evaluations.is_some();
    if let Some(why) = generations.and_then(|g| crate::caps::generations("--generations", g)) {
        bail!(why);
    }
    if let Some(why) = evaluations.and_then(|e| crate::caps::count("--evaluations", e, crate::caps::MAX_EVALUATIONS)) {
        bail!(why);
    }
    let (generations, budget, evaluations) = if asked {
        (generations, budget.map(str::to_string), evaluations)
    } else {
        (scene.generations, scene.budget.clone(), scene.evaluations)
    };
    let budget = budget.map(|b| parse_duration(&b)).transpose().context("budget")?;
    if generations.is_none() && budget.is_none() && evaluations.is_none() {
        bail!(
            "nothing tells {what} when to stop: give --generations, --budget or --evaluations (or [run] in the scene)"
        );
    }
    Ok(Horizon { generations, budget, evaluations })
}

/// The `stopped_by` word of `run.json` for `reason`.
pub fn stop_reason_name(reason: StopReason) -> &'static str {
    match reason {
        StopReason::Generations => "generations",
        StopReason::Budget => "budget",
        StopReason::Evaluations => "evaluations",
        StopReason::Cancelled => "interrupted",
    }
}
