//! Runs of an optimizer on a scene — the one run loop under every front
//! door (`genform evolve`, the studio's runs, `genform.evolve` in Python).
//!
//! A door fills an [`EvolveRequest`] and calls [`evolve`] with a
//! [`Control`]: a cancel flag (Ctrl-C, a stop button, Python's
//! KeyboardInterrupt), a replayed steering log and a [`Watch`] that sees
//! every generation (a progress bar, the studio's event stream, a Python
//! callable) and may pause and steer the run. The loop ([`drive`]) writes
//! the run folder — checkpoints every [`CHECKPOINT_EVERY`], the whole
//! folder at the end — and returns a [`RunOutcome`]; it prints nothing:
//! notes reach the watcher as text.
//!
//! Tree scenes live in [`tree`], codon scenes in [`codon`]; both go through
//! the same loop, with a [`Session`] for what differs, and the same
//! `compare` loop ([`compare::race`]).

use anyhow::{Context, Result, bail};
use genform_core::{Limits, Scene};
use genform_evolve::{GenerationStats, Genotype, Horizon, Objective, Optimizer, Rescore, Stop, StopReason};
use genform_export::{ExportOptions, Format};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use crate::grammar::LimitOverrides;
use crate::output::write_atomic;
use crate::report::Row;
use crate::scene_config::{RunConfig, SceneConfig, parse_duration};
use crate::scene_file::SceneFile;
use crate::sweep::set::parse_patch;

pub mod codon;
pub mod compare;
pub mod derive;
pub mod steering;
pub mod tree;

pub use compare::{CompareOutcome, CompareRequest, compare};
pub use derive::{DeriveRequest, Derived, derive};
pub use steering::{SteerEntry, SteerSet, Steerable};

/// How often results are written during a run, so a crash loses little.
pub const CHECKPOINT_EVERY: Duration = Duration::from_secs(10);

/// The search algorithms a door can ask for, tree and codon together
/// (each scene kind accepts its own; the others are refused with why).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AlgorithmChoice {
    /// The genetic algorithm over derivation trees.
    Ga,
    /// Metropolis–Hastings (RJMCMC).
    Mh,
    /// Sequential Monte Carlo.
    Smc,
    /// Stochastic-ordering SMC.
    Sosmc,
    /// GA with MH refinement.
    Hybrid,
    /// MAP-Elites (quality diversity).
    MapElites,
    /// Random search (trees or codons).
    Random,
    /// Grammatical evolution (codon scenes).
    Ge,
}

impl AlgorithmChoice {
    /// Every algorithm, in the order help texts list them.
    pub const ALL: [AlgorithmChoice; 8] = [
        AlgorithmChoice::Ga,
        AlgorithmChoice::Mh,
        AlgorithmChoice::Smc,
        AlgorithmChoice::Sosmc,
        AlgorithmChoice::Hybrid,
        AlgorithmChoice::MapElites,
        AlgorithmChoice::Random,
        AlgorithmChoice::Ge,
    ];

    /// The name on the command line and in `run.json`.
    pub fn name(self) -> &'static str {
        match self {
            AlgorithmChoice::Ga => "ga",
            AlgorithmChoice::Mh => "mh",
            AlgorithmChoice::Smc => "smc",
            AlgorithmChoice::Sosmc => "sosmc",
            AlgorithmChoice::Hybrid => "hybrid",
            AlgorithmChoice::MapElites => "map-elites",
            AlgorithmChoice::Random => "random",
            AlgorithmChoice::Ge => "ge",
        }
    }

    /// One line on what the algorithm is (help texts, the studio).
    pub fn about(self) -> &'static str {
        match self {
            AlgorithmChoice::Ga => "The ShapeGenetics genetic algorithm",
            AlgorithmChoice::Mh => "RJMCMC with parallel tempering, delayed rejection and annealing",
            AlgorithmChoice::Smc => "Sequential Monte Carlo, fixed (depth-first) growth order",
            AlgorithmChoice::Sosmc => "Stochastically-ordered SMC",
            AlgorithmChoice::Hybrid => "SOSMC seeds a GA, MH polishes its best",
            AlgorithmChoice::MapElites => {
                "MAP-Elites: the best individual per cell of a grid over two descriptors (quality-diversity)"
            }
            AlgorithmChoice::Random => "Random search: fresh random individuals, keep the best (a baseline)",
            AlgorithmChoice::Ge => {
                "Grammatical evolution over codon genomes (codon scenes: .bnf, .bsg, .gg.yaml grammars)"
            }
        }
    }

    /// The algorithm named `name` (`map_elites` and `map-elites` both work).
    pub fn from_name(name: &str) -> Result<AlgorithmChoice> {
        let wanted = name.replace('_', "-").to_ascii_lowercase();
        match AlgorithmChoice::ALL.iter().find(|a| a.name() == wanted) {
            Some(a) => Ok(*a),
            None => {
                let names: Vec<&str> = AlgorithmChoice::ALL.iter().map(|a| a.name()).collect();
                bail!("unknown algorithm `{name}`; use one of {}", names.join(", "))
            }
        }
    }

    /// The table of a scene file holding this algorithm's settings (`codon`:
    /// for a codon scene).
    pub fn section(self, codon: bool) -> &'static str {
        match self {
            _ if codon => "ge",
            AlgorithmChoice::Ga | AlgorithmChoice::Random | AlgorithmChoice::Ge => "ga",
            AlgorithmChoice::Mh => "mh",
            AlgorithmChoice::Smc | AlgorithmChoice::Sosmc => "smc",
            AlgorithmChoice::Hybrid => "hybrid",
            AlgorithmChoice::MapElites => "map_elites",
        }
    }

    /// The tree optimizer, if it is one.
    pub fn tree(self) -> Option<genform_evolve::Algorithm> {
        Some(match self {
            AlgorithmChoice::Ga => genform_evolve::Algorithm::Ga,
            AlgorithmChoice::Mh => genform_evolve::Algorithm::Mh,
            AlgorithmChoice::Smc => genform_evolve::Algorithm::Smc,
            AlgorithmChoice::Sosmc => genform_evolve::Algorithm::Sosmc,
            AlgorithmChoice::Hybrid => genform_evolve::Algorithm::Hybrid,
            AlgorithmChoice::MapElites => genform_evolve::Algorithm::MapElites,
            AlgorithmChoice::Random => genform_evolve::Algorithm::Random,
            AlgorithmChoice::Ge => return None,
        })
    }

    /// The codon optimizer, if it is one.
    pub fn codon(self) -> Option<genform_evolve::CodonAlgorithm> {
        match self {
            AlgorithmChoice::Ge => Some(genform_evolve::CodonAlgorithm::Ge),
            AlgorithmChoice::Random => Some(genform_evolve::CodonAlgorithm::Random),
            _ => None,
        }
    }
}

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
    /// The algorithm (`None`: GA for tree scenes, GE for codon scenes).
    pub algorithm: Option<AlgorithmChoice>,
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
    /// Surface scenes: each criterion's contribution (`w / (1 + e)`, or
    /// `−w·e` in the paper form) for the best so far; empty otherwise.
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
#[derive(Clone, Debug)]
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

/// Runs `request` under `control`: a tree or codon scene, whichever the
/// scene file is.
pub fn evolve(request: &EvolveRequest, control: Control) -> Result<RunOutcome> {
    match SceneFile::load(&request.scene, &parse_patch(&request.set)?)? {
        SceneFile::Tree(scene) => tree::evolve(request, scene, control),
        SceneFile::Codon(scene) => codon::evolve(request, scene, control),
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

/// The score of one genome, as lines of text (the first the total).
pub fn score(request: &ScoreRequest) -> Result<Vec<String>> {
    match SceneFile::load(&request.scene, &parse_patch(&request.set)?)? {
        SceneFile::Tree(scene) => tree::score(request, scene),
        SceneFile::Codon(scene) => codon::score(request, scene),
    }
}

/// The grammar's limits overridden by the scene's `[limits]`, then by flags.
fn scene_limits(config: &SceneConfig, grammar: Limits, flags: LimitOverrides) -> Limits {
    flags.or(config.limits.overrides()).apply(grammar)
}

/// The stop rules of a run: the request's replace the scene's `[run]` as a
/// whole; at least one is needed.
fn stop_rules(r: &EvolveRequest, scene: &RunConfig) -> Result<Horizon> {
    let asked = r.generations.is_some() || r.budget.is_some() || r.evaluations.is_some();
    let (generations, budget, evaluations) = if asked {
        (r.generations, r.budget.clone(), r.evaluations)
    } else {
        (scene.generations, scene.budget.clone(), scene.evaluations)
    };
    let budget = budget.map(|b| parse_duration(&b)).transpose().context("budget")?;
    if generations.is_none() && budget.is_none() && evaluations.is_none() {
        bail!(
            "nothing tells the run when to stop: give --generations, --budget or --evaluations (or [run] in the scene)"
        );
    }
    Ok(Horizon { generations, budget, evaluations })
}

/// [`Stop`] for `horizon`, cancelled by `cancel`.
fn stop_at(horizon: Horizon, cancel: &AtomicBool) -> Stop<'_> {
    Stop { generations: horizon.generations, budget: horizon.budget, evaluations: horizon.evaluations, cancel }
}

fn worker_pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new().num_threads(threads.unwrap_or(0)).build().context("cannot start worker threads")
}

/// The scene file's name without its ending, for plot titles.
fn title(path: &Path) -> String {
    path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default()
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

/// `best.glb`, and `best.obj` with its materials `best.mtl`, of `scene`.
fn write_models(out: &Path, scene: &Scene) -> Result<()> {
    crate::output::write_model(scene, &out.join("best.glb"))?;
    crate::output::write_model(scene, &out.join("best.obj"))?;
    Ok(())
}

/// What every `evolve` run knows, tree or codon.
struct Common<'a> {
    request: &'a EvolveRequest,
    /// The algorithm's name.
    algorithm: &'static str,
    scene_path: &'a Path,
    threads: usize,
}

/// How a run ended.
#[derive(Clone, Copy)]
struct Ended<'s> {
    /// The `stopped_by` word.
    reason: &'static str,
    elapsed: Duration,
    /// The changes that took effect, for `run.json`.
    steering: &'s [SteerEntry],
}

impl Common<'_> {
    /// Writes `run.json` into `out`: the keys every run has, then `own` (an
    /// object with the kind's own keys).
    fn write_run_json<G: Genotype>(
        &self,
        out: &Path,
        opt: &dyn Optimizer<G>,
        rows: &[Row],
        ended: Ended,
        max_reachable: f64,
        own: serde_json::Value,
    ) -> Result<()> {
        let best = opt.best();
        let elapsed = ended.elapsed.as_secs_f64();
        let mut run = serde_json::json!({
            "genform": env!("CARGO_PKG_VERSION"),
            "scene": self.scene_path.display().to_string(),
            "algorithm": self.algorithm,
            "seed": self.request.seed,
            "threads": self.threads,
            "stopped_by": ended.reason,
            "generations": opt.generation(),
            "evaluations": opt.evaluations(),
            "seconds": elapsed,
            "evaluations_per_second": opt.evaluations() as f64 / elapsed.max(1e-9),
            "eval_seconds": rows.iter().map(|(r, _)| r.eval_time.as_secs_f64()).sum::<f64>(),
            "reproduction_seconds": rows.iter().map(|(r, _)| r.reproduction_time.as_secs_f64()).sum::<f64>(),
            "best_fitness": best.map(|b| b.fitness),
            "best_length": best.map(|b| b.genome.length()),
            "max_reachable_fitness": max_reachable,
        });
        if !ended.steering.is_empty() {
            run["steering"] = serde_json::to_value(ended.steering).context("cannot encode the steering log")?;
        }
        if let (Some(all), serde_json::Value::Object(own)) = (run.as_object_mut(), own) {
            all.extend(own);
        }
        let text = serde_json::to_string_pretty(&run).context("cannot encode run.json")?;
        write_atomic(&out.join("run.json"), text.as_bytes())
    }
}

/// What differs between tree and codon runs of `evolve`; [`drive`] does the rest.
trait Session<G> {
    /// What the run records per generation beside the statistics rows.
    type Record: Default;
    /// The objective as steered so far.
    type Objective<'s>: Objective<G>
    where
        Self: 's;
    /// What every run knows.
    fn common(&self) -> &Common<'_>;
    /// The objective of the next generation.
    fn objective(&self) -> Self::Objective<'_>;
    /// The weights and targets steering can change, as they are now.
    fn steerable(&self) -> &Steerable;
    /// Applies a change to the objective (nothing changes on error).
    fn steer(&mut self, set: &SteerSet) -> Result<()>;
    /// Surface scenes: the best's per-criterion scores of the last generation.
    fn criteria(&self, _rec: &Self::Record) -> Vec<(&'static str, f64)> {
        Vec::new()
    }
    /// The gallery picture of the population's distinct best (`gallery.png`).
    fn gallery(&self, opt: &dyn Optimizer<G>) -> Result<Vec<u8>>;
    /// The best individual's model, if there is a best.
    fn best_scene(&self, opt: &dyn Optimizer<G>) -> Result<Option<Scene>>;
    /// The best tree genome, for tree runs.
    fn best_genome(&self, _opt: &dyn Optimizer<G>) -> Option<genform_core::Genome> {
        None
    }
    /// The fitness the shortest genome could reach, for the summary line.
    fn max_reachable(&self) -> f64;
    /// Records one generation; returns what the progress line adds at its
    /// end and a line to log when no progress bar shows the run.
    fn record(
        &self,
        rec: &mut Self::Record,
        stats: &GenerationStats,
        opt: &dyn Optimizer<G>,
    ) -> (String, Option<String>);
    /// Checkpoint: the files that matter if the run dies.
    fn write_progress(&self, out: &Path, opt: &dyn Optimizer<G>, rows: &[Row], rec: &Self::Record) -> Result<()>;
    /// Every result file; warnings go to `note`.
    fn write_all(
        &self,
        out: &Path,
        opt: &dyn Optimizer<G>,
        rows: &[Row],
        rec: &Self::Record,
        ended: Ended,
        note: &mut dyn FnMut(&str),
    ) -> Result<()>;
    /// What the summary line adds before the output folder.
    fn summary_tail(&self, rec: &Self::Record) -> String;
}

/// An objective used through a reference (a session that owns its objective).
struct ByRef<'a, O>(&'a O);

impl<G, O: Objective<G>> Objective<G> for ByRef<'_, O> {
    type Scratch = O::Scratch;

    fn scratch(&self) -> O::Scratch {
        self.0.scratch()
    }

    fn evaluate(&self, genome: &G, scratch: &mut O::Scratch) -> f64 {
        self.0.evaluate(genome, scratch)
    }

    fn evaluate_described(&self, genome: &G, scratch: &mut O::Scratch, descriptors: &mut [f64; 2]) -> f64 {
        self.0.evaluate_described(genome, scratch, descriptors)
    }

    fn expressed(&self, genome: &G, scratch: &mut O::Scratch) -> Option<usize> {
        self.0.expressed(genome, scratch)
    }

    fn phenotype_key(&self, genome: &G, scratch: &mut O::Scratch) -> Option<u64> {
        self.0.phenotype_key(genome, scratch)
    }

    fn subtrees(&self, genome: &G, scratch: &mut O::Scratch, out: &mut Vec<genform_evolve::CodonSpan>) {
        self.0.subtrees(genome, scratch, out)
    }

    fn sensible_genome(
        &self,
        index: usize,
        plan: genform_evolve::SensiblePlan,
        rng: &mut genform_core::Rng,
        scratch: &mut O::Scratch,
    ) -> Option<G> {
        self.0.sensible_genome(index, plan, rng, scratch)
    }
}

/// The run loop: checkpoints, cancellation, steering changes before the
/// generations they take effect at (each followed by re-scoring what the
/// optimizer stores), the watcher, the result files and the outcome.
fn drive<G, S: Session<G>, P: Rescore<G>>(
    session: &mut S,
    mut opt: P,
    stop: Stop,
    control: &mut Control,
) -> Result<RunOutcome> {
    let (out, scene) = {
        let c = session.common();
        (c.request.out.clone(), c.scene_path.to_path_buf())
    };
    // A replayed log is checked whole before the run starts.
    let mut probe = session.steerable().clone();
    for e in &control.schedule {
        probe.apply(&e.set).with_context(|| format!("steering of generation {}", e.generation))?;
    }
    if let Some(out) = &out {
        std::fs::create_dir_all(out).with_context(|| format!("cannot create output folder {}", out.display()))?;
    }
    let mut rows: Vec<Row> = Vec::new();
    let mut rec = S::Record::default();
    let mut log: Vec<SteerEntry> = Vec::new();
    let mut scheduled = control.schedule.iter().peekable();
    let mut live: Option<SteerSet> = None;
    let mut last_checkpoint = Instant::now();
    // The fitness of the last live best model offered to the watcher.
    let mut shown_best: Option<u64> = None;
    if let Some(w) = control.watch.as_deref_mut() {
        let horizon = Horizon { generations: stop.generations, budget: stop.budget, evaluations: stop.evaluations };
        w.started(&Start { max_reachable: session.max_reachable(), steerable: session.steerable(), horizon });
    }
    let mut start = Instant::now();
    let reason = loop {
        if let Some(reason) = genform_evolve::run::reached(&opt, &stop, start) {
            break reason;
        }
        // Changes take effect at the generation made next.
        let next = if opt.is_initialized() { opt.generation() + 1 } else { 0 };
        let mut changes: Vec<SteerEntry> = Vec::new();
        while let Some(e) = scheduled.next_if(|e| e.generation <= next) {
            changes.push(e.clone());
        }
        if let Some(set) = live.take().filter(|s| !s.is_empty()) {
            changes.push(SteerEntry { generation: next, set });
        }
        let steered = changes.iter().any(|e| !e.set.is_empty());
        for entry in changes {
            session.steer(&entry.set).with_context(|| format!("steering of generation {}", entry.generation))?;
            if let Some(w) = control.watch.as_deref_mut() {
                w.steered(&entry, session.steerable(), session.max_reachable());
            }
            log.push(entry);
        }
        // What the optimizer stores was scored under the old weights: re-score
        // it, so elites and the best compete on the new scale.
        if steered && opt.is_initialized() {
            opt.rescore(&session.objective());
        }
        let stats = opt.step(&session.objective());
        let secs = start.elapsed().as_secs_f64();
        rows.push((stats.clone(), secs));
        let (tail, line) = session.record(&mut rec, &stats, &opt);
        if let Some(out) = &out
            && last_checkpoint.elapsed() >= CHECKPOINT_EVERY
        {
            session.write_progress(out, &opt, &rows, &rec)?;
            last_checkpoint = Instant::now();
        }
        if let Some(w) = control.watch.as_deref_mut() {
            if w.wants_gallery(stats.generation) {
                if let Ok(png) = session.gallery(&opt) {
                    w.gallery(stats.generation, png);
                }
                // The live best model, when the best changed since the last one.
                let now = opt.best().map(|b| b.fitness.to_bits());
                if now != shown_best
                    && let Ok(Some(scene)) = session.best_scene(&opt)
                    && let Ok(glb) = genform_export::export(&scene, Format::Glb, &ExportOptions::default())
                {
                    shown_best = now;
                    w.best_model(stats.generation, glb);
                }
            }
            let best = opt.best().map(|b| b.fitness);
            let tick = Tick { stats: &stats, seconds: secs, best, criteria: session.criteria(&rec), tail, log: line };
            // A paused run waits in here: that time is not the run's (its
            // budget and its seconds leave it out).
            let held = Instant::now();
            live = w.generation(&tick);
            start += held.elapsed();
        }
    };
    let elapsed = start.elapsed();
    let mut note = |text: &str| {
        if let Some(w) = control.watch.as_deref_mut() {
            w.note(text);
        }
    };
    if let Some(out) = &out {
        if reason == StopReason::Cancelled {
            note(&format!("interrupted: writing the results of generation {}", opt.generation()));
        }
        let ended = Ended { reason: stop_reason_name(reason), elapsed, steering: &log };
        session.write_all(out, &opt, &rows, &rec, ended, &mut note)?;
    }
    Ok(RunOutcome {
        scene,
        out,
        algorithm: session.common().algorithm,
        stopped_by: reason,
        generations: opt.generation(),
        evaluations: opt.evaluations(),
        elapsed,
        best_fitness: opt.best().map(|b| b.fitness),
        max_reachable: session.max_reachable(),
        best_scene: session.best_scene(&opt)?,
        best_genome: session.best_genome(&opt),
        tail: session.summary_tail(&rec),
    })
}
