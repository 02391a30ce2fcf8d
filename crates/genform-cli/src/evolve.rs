//! `genform evolve`: run an optimizer on a scene config and write the
//! results (best model, genome, statistics, plots) to a folder.
//!
//! Tree scenes live here, codon scenes in [`codon`]; both go through the
//! same run loop ([`drive`], with a [`Session`] for what differs) and the
//! same `compare` loop ([`race`], with a [`Contest`]). `genform serve`
//! runs the same loop ([`evolve_with`]) with a [`Watch`] that sees every
//! generation, pauses the run and steers it ([`steering`]).

use anyhow::{Context, Result, bail};
use genform_app::archive::Reports;
use genform_app::comparison::{self, Trace, TracePoint};
use genform_app::grammar::{self, LimitOverrides};
use genform_app::objective::{DescribedObjective, Descriptor, SceneObjective, Scorers};
use genform_app::output::write_atomic;
use genform_app::pictures::{self, BestHistory, TargetPicture};
use genform_app::report::{self, Row};
use genform_app::scene_config::{LoadedScene, RunConfig, SceneConfig, parse_duration};
use genform_app::targets;
use genform_core::{Generator, Genome, Limits, Scene};
use genform_evolve::{
    AnyOptimizer, GenerationStats, Genotype, Horizon, Individual, Objective, Optimizer, Rescore, Settings, Stop,
    StopReason, run,
};
use genform_export::{ExportOptions, Format, RenderOptions};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use crate::args::{Algorithm, CompareArgs, EvolveArgs, ScoreArgs};

mod codon;
pub mod steering;
mod sweep;

pub use steering::{SteerEntry, SteerSet, Steerable};
pub use sweep::sweep;

/// How often results are written during a run, so a crash loses little.
const CHECKPOINT_EVERY: Duration = Duration::from_secs(10);

/// The grammar's limits overridden by the scene's `[limits]`, then by flags.
fn scene_limits(config: &SceneConfig, grammar: Limits, flags: LimitOverrides) -> Limits {
    let scene = LimitOverrides {
        max_genes: config.limits.genes,
        max_depth: config.limits.depth,
        max_primitives: config.limits.primitives,
    };
    flags.or(scene).apply(grammar)
}

/// The tree optimizer `alg` names; `ge` is refused with the reason.
fn tree_algorithm(alg: Algorithm, scene: &Path) -> Result<genform_evolve::Algorithm> {
    alg.tree().ok_or_else(|| {
        anyhow::anyhow!(
            "--algorithm ge evolves codon genomes, but {} is a tree scene (its grammar's genomes are derivation \
             trees); use ga, mh, smc, sosmc, hybrid, map-elites or random, or a scene whose grammar is .bnf, .bsg or .gg.yaml",
            scene.display()
        )
    })
}

/// Runs `genform score`: one genome's counts and fitness against a scene.
pub fn score(a: ScoreArgs) -> Result<()> {
    if genform_app::codon_scene::is_codon_scene(&a.scene) {
        return codon::score(a);
    }
    let LoadedScene { mut config, .. } = SceneConfig::load(&a.scene)?;
    config.fitness.override_form(a.form.as_deref())?;
    let loaded = grammar::load(&config.grammar)?;
    let limits = scene_limits(&config, loaded.limits, a.limits.overrides());
    let scorers = targets::build(&config)?;
    let genome = loaded.read_genome(&a.genome)?;
    let objective = SceneObjective { generator: loaded.generator.as_ref(), limits, scorers: &scorers };
    let c = objective.counts(&genome, &mut objective.scratch()).context("cannot build the model")?;
    println!(
        "fitness {} (form {}, max reachable {}); genes {}; good {} bad {} overlap {} outside {} target {}",
        scorers.fitness.eval(&c, genome.len()),
        scorers.fitness.form.name(),
        scorers.fitness.max_reachable(genome.len()),
        genome.len(),
        c.good,
        c.bad,
        c.overlap,
        c.outside,
        c.target
    );
    Ok(())
}

/// The stop rules of `evolve`: the command line's replace the scene's
/// `[run]` as a whole; at least one is needed.
fn stop_rules(a: &EvolveArgs, scene: &RunConfig) -> Result<Horizon> {
    let cli_stops = a.generations.is_some() || a.budget.is_some() || a.evaluations.is_some();
    let (generations, budget, evaluations) = if cli_stops {
        (a.generations, a.budget.clone(), a.evaluations)
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

/// Runs `genform evolve`: Ctrl-C stops the run (its results are written),
/// `--steering` replays an earlier run's steering.
pub fn evolve(a: EvolveArgs) -> Result<()> {
    let schedule = match &a.steering {
        Some(path) => steering::read_log(path)?,
        None => Vec::new(),
    };
    evolve_with(&a, Control { cancel: cancel_on_ctrl_c(), schedule, watch: None })
}

/// How a run is controlled from outside the loop.
pub struct Control<'w> {
    /// Stops the run after the current generation (its results are written
    /// as for Ctrl-C).
    pub cancel: Arc<AtomicBool>,
    /// Changes to apply before given generations (a replayed log), sorted
    /// by generation.
    pub schedule: Vec<SteerEntry>,
    /// Sees every generation and may steer (the studio server).
    pub watch: Option<&'w mut (dyn Watch + Send)>,
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
}

/// Watches a run from another thread's point of view (`genform serve`):
/// called on the run's thread between generations.
pub trait Watch {
    /// Before the first generation: the fitness the best model could reach
    /// and the steerable values.
    fn started(&mut self, max_reachable: f64, steerable: &Steerable);
    /// After each generation. It may block (a paused run waits here); what
    /// it returns is applied before the next generation.
    fn generation(&mut self, tick: &Tick) -> Option<SteerSet>;
    /// Whether to render the gallery of the current population after `generation`.
    fn wants_gallery(&mut self, generation: usize) -> bool;
    /// The gallery picture (PNG) after `generation`.
    fn gallery(&mut self, generation: usize, png: Vec<u8>);
    /// The best model so far as GLB after `generation` (offered with the
    /// gallery when the best changed).
    fn best_model(&mut self, generation: usize, glb: Vec<u8>);
    /// A change took effect; `now` is what steering can change after it.
    fn steered(&mut self, entry: &SteerEntry, now: &Steerable);
}

/// Runs `genform evolve` on `a` under `control`.
pub fn evolve_with(a: &EvolveArgs, mut control: Control) -> Result<()> {
    if genform_app::codon_scene::is_codon_scene(&a.scene) {
        return codon::evolve(a, control);
    }
    let LoadedScene { path: scene_path, mut config } = SceneConfig::load(&a.scene)?;
    apply_preset(&mut config, a.preset.as_deref());
    let algorithm = tree_algorithm(a.algorithm.unwrap_or(Algorithm::Ga), &scene_path)?;
    let loaded = grammar::load(&config.grammar)?;
    let limits = scene_limits(&config, loaded.limits, a.limits.overrides());
    if config.ga.max_length > limits.max_genes + 1 {
        eprintln!(
            "note: [ga] max_length {} is above the gene limit {}; genomes stop at {} genes",
            config.ga.max_length, limits.max_genes, limits.max_genes
        );
    }
    let scorers = targets::build(&config)?;
    let horizon = stop_rules(a, &config.run)?;
    let pool = worker_pool(a.threads)?;
    let cancel = control.cancel.clone();
    let mut ctx = RunContext {
        common: Common {
            args: a,
            algorithm: algorithm.name(),
            scene_path: &scene_path,
            threads: pool.current_num_threads(),
        },
        config: &config,
        generator: loaded.generator.as_ref(),
        limits,
        scorers,
        steerable: Steerable::Fitness(config.fitness.clone()),
        descriptors: Descriptor::pair(&config.map_elites),
    };
    let opt = AnyOptimizer::new(algorithm, loaded.generator.graph(), &limits, &config.settings(), a.seed, horizon)
        .map_err(|e| anyhow::anyhow!("{}: {e}", section(algorithm)))?;
    pool.install(|| drive(&mut ctx, opt, stop_at(horizon, &cancel), &mut control))
}

/// Sets the scene's GA preset from a `--preset` flag (clap admits only
/// known names).
fn apply_preset(config: &mut SceneConfig, preset: Option<&str>) {
    if let Some(p) = preset.and_then(genform_evolve::GaPreset::from_name) {
        config.ga = config.ga.clone().with_preset(p);
    }
}

/// The scene section holding an algorithm's settings, for error messages.
fn section(a: genform_evolve::Algorithm) -> &'static str {
    match a {
        genform_evolve::Algorithm::Ga | genform_evolve::Algorithm::Random => "[ga]",
        genform_evolve::Algorithm::Mh => "[mh]",
        genform_evolve::Algorithm::Smc | genform_evolve::Algorithm::Sosmc => "[smc]",
        genform_evolve::Algorithm::Hybrid => "[hybrid]",
        genform_evolve::Algorithm::MapElites => "[map_elites]",
    }
}

/// `objective` with the descriptors of the scene's `[map_elites]` (what
/// MAP-Elites bins; other algorithms only read the fitness).
fn described<'a>(objective: SceneObjective<'a>, config: &SceneConfig) -> DescribedObjective<'a> {
    DescribedObjective { objective, descriptors: Descriptor::pair(&config.map_elites) }
}

fn worker_pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new().num_threads(threads.unwrap_or(0)).build().context("cannot start worker threads")
}

/// Ctrl-Cs received so far.
static INTERRUPTS: AtomicUsize = AtomicUsize::new(0);

/// A flag set by Ctrl-C. The run stops and writes its results; a second
/// Ctrl-C (often a key held or pressed twice) does not cut that short but
/// makes the process exit with 130 once they are written; a third quits at
/// once.
pub(crate) fn cancel_on_ctrl_c() -> Arc<AtomicBool> {
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    let _ = ctrlc::set_handler(move || {
        flag.store(true, Ordering::SeqCst);
        match INTERRUPTS.fetch_add(1, Ordering::SeqCst) + 1 {
            1 => {}
            2 => eprintln!("\nsaving the results first; Ctrl-C once more quits without them"),
            _ => std::process::exit(130),
        }
    });
    cancel
}

/// Whether Ctrl-C came at least twice (the command then exits with 130).
pub(crate) fn interrupted_twice() -> bool {
    INTERRUPTS.load(Ordering::SeqCst) >= 2
}

/// The scene file's name without its ending, for plot titles.
fn title(path: &Path) -> String {
    path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default()
}

/// The `stopped_by` word of `run.json` for `reason`.
fn stop_reason_name(reason: StopReason) -> &'static str {
    match reason {
        StopReason::Generations => "generations",
        StopReason::Budget => "budget",
        StopReason::Evaluations => "evaluations",
        StopReason::Cancelled => "interrupted",
    }
}

/// Runs `genform compare`: every algorithm `runs` times with the same
/// wall-clock budget, one run after another on the same worker pool.
pub fn compare(a: CompareArgs) -> Result<()> {
    if genform_app::codon_scene::is_codon_scene(&a.scene) {
        return codon::compare(a);
    }
    let LoadedScene { path: scene_path, mut config } = SceneConfig::load(&a.scene)?;
    apply_preset(&mut config, a.preset.as_deref());
    let loaded = grammar::load(&config.grammar)?;
    let limits = scene_limits(&config, loaded.limits, a.limits.overrides());
    let scorers = targets::build(&config)?;
    let budget = race_budget(&a)?;
    let default = [Algorithm::Ga, Algorithm::Mh, Algorithm::Smc, Algorithm::Sosmc];
    let algorithms = distinct(&a.algorithms, &default, |alg| tree_algorithm(alg, &scene_path))?;
    let contest = TreeContest {
        generator: loaded.generator.as_ref(),
        limits,
        settings: config.settings(),
        horizon: Horizon { budget: Some(budget), ..Horizon::default() },
    };
    for alg in &algorithms {
        contest.start(*alg, a.seed)?;
    }
    let objective =
        described(SceneObjective { generator: loaded.generator.as_ref(), limits, scorers: &scorers }, &config);
    race(&a, &scene_path, budget, &algorithms, &objective, &contest)
}

/// The `--budget` of `compare`, once `--runs` is checked too.
fn race_budget(a: &CompareArgs) -> Result<Duration> {
    let budget = parse_duration(&a.budget).context("--budget")?;
    if a.runs == 0 {
        bail!("--runs must be at least 1");
    }
    Ok(budget)
}

/// The algorithms `given` names (`default` when none), each once, as
/// `check` turns them into the scene's kind of algorithm.
fn distinct<A: PartialEq>(
    given: &[Algorithm],
    default: &[Algorithm],
    check: impl Fn(Algorithm) -> Result<A>,
) -> Result<Vec<A>> {
    let given = if given.is_empty() { default } else { given };
    let mut algorithms: Vec<A> = Vec::new();
    for alg in given {
        let alg = check(*alg)?;
        if !algorithms.contains(&alg) {
            algorithms.push(alg);
        }
    }
    Ok(algorithms)
}

/// What differs between tree and codon runs of `compare`.
trait Contest<G> {
    /// An algorithm to race.
    type Alg: Copy;
    /// Its optimizer.
    type Opt: Optimizer<G> + Send;
    /// The algorithm's name in logs, tables and file names.
    fn name(&self, alg: Self::Alg) -> &'static str;
    /// A fresh optimizer for one run.
    fn start(&self, alg: Self::Alg, seed: u64) -> Result<Self::Opt>;
    /// What a run's log line adds at its end.
    fn run_tail(&self) -> String;
    /// Writes into `out` the best individual algorithm `name` found in all its runs.
    fn save_best(&self, out: &Path, name: &str, best: &Individual<G>) -> Result<()>;
}

/// Tree scenes in `compare`.
struct TreeContest<'a> {
    generator: &'a dyn Generator,
    limits: Limits,
    settings: Settings,
    horizon: Horizon,
}

impl Contest<Genome> for TreeContest<'_> {
    type Alg = genform_evolve::Algorithm;
    type Opt = AnyOptimizer;

    fn name(&self, alg: Self::Alg) -> &'static str {
        alg.name()
    }

    fn start(&self, alg: Self::Alg, seed: u64) -> Result<AnyOptimizer> {
        AnyOptimizer::new(alg, self.generator.graph(), &self.limits, &self.settings, seed, self.horizon)
            .map_err(|e| anyhow::anyhow!("{}: {e}", section(alg)))
    }

    fn run_tail(&self) -> String {
        String::new()
    }

    fn save_best(&self, out: &Path, name: &str, best: &Individual<Genome>) -> Result<()> {
        let path = out.join(format!("best-{name}-genome.json"));
        write_atomic(&path, best.genome.to_json(self.generator.graph()).as_bytes())
    }
}

/// The shared loop of `compare`: every algorithm `a.runs` times for
/// `budget`, with the traces, the best individual of each algorithm, the
/// table and the plot written to `a.out`.
fn race<G: Clone + Send, C: Contest<G>, O: Objective<G> + Sync>(
    a: &CompareArgs,
    scene_path: &Path,
    budget: Duration,
    algorithms: &[C::Alg],
    objective: &O,
    contest: &C,
) -> Result<()> {
    std::fs::create_dir_all(&a.out).with_context(|| format!("cannot create output folder {}", a.out.display()))?;
    let pool = worker_pool(a.threads)?;
    let cancel = cancel_on_ctrl_c();
    let stop = Stop { generations: None, budget: Some(budget), evaluations: None, cancel: &cancel };
    let spacing = budget.as_secs_f64() / 200.0;
    let mut traces: Vec<Trace> = Vec::new();
    'all: for alg in algorithms {
        let name = contest.name(*alg);
        let mut best: Option<Individual<G>> = None;
        for r in 0..a.runs {
            let seed = a.seed + r as u64;
            let mut opt = contest.start(*alg, seed)?;
            let mut trace = Trace::new(name, r, seed);
            let start = Instant::now();
            let summary = pool.install(|| {
                run(&mut opt, objective, &stop, |stats, o| {
                    let point = TracePoint {
                        seconds: start.elapsed().as_secs_f64(),
                        evaluations: stats.total_evaluations,
                        best: o.best().map_or(f64::NAN, |b| b.fitness),
                    };
                    trace.record(point, spacing);
                })
            })?;
            if let Some(b) = opt.best()
                && best.as_ref().is_none_or(|old| b.fitness > old.fitness)
            {
                best = Some(b.clone());
            }
            if !a.quiet {
                eprintln!(
                    "{name} run {}/{}: best {:.6} after {} evaluations in {:.1} s{}",
                    r + 1,
                    a.runs,
                    opt.best().map_or(f64::NAN, |b| b.fitness),
                    opt.evaluations(),
                    summary.elapsed.as_secs_f64(),
                    contest.run_tail()
                );
            }
            let cancelled = summary.reason == StopReason::Cancelled;
            if !cancelled {
                traces.push(trace);
            }
            write_atomic(&a.out.join("comparison.csv"), comparison::csv(&traces).as_bytes())?;
            if cancelled {
                eprintln!("interrupted: the unfinished run is left out");
                break 'all;
            }
        }
        if let Some(b) = best {
            contest.save_best(&a.out, name, &b)?;
        }
    }
    write_atomic(&a.out.join("comparison.csv"), comparison::csv(&traces).as_bytes())?;
    let svg = comparison::svg(&title(scene_path), &traces, budget.as_secs_f64());
    write_atomic(&a.out.join("comparison.svg"), svg.as_bytes())?;
    print!("{}", comparison::summary(&traces));
    eprintln!(
        "{} runs of {} s each on {} → {}",
        traces.len(),
        budget.as_secs_f64(),
        scene_path.display(),
        a.out.display()
    );
    Ok(())
}

/// What every `evolve` run knows, tree or codon.
struct Common<'a> {
    args: &'a EvolveArgs,
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
    /// Writes `run.json`: the keys every run has, then `own` (an object
    /// with the kind's own keys).
    fn write_run_json<G: Genotype>(
        &self,
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
            "seed": self.args.seed,
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
        write_atomic(&self.args.out.join("run.json"), text.as_bytes())
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
    /// The fitness the shortest genome could reach, for the summary line.
    fn max_reachable(&self) -> f64;
    /// Records one generation; returns what the progress message adds at
    /// its end. `log`: whether the run logs each generation on stderr (no
    /// bar shows it and the run is not quiet).
    fn record(&self, rec: &mut Self::Record, stats: &GenerationStats, opt: &dyn Optimizer<G>, log: bool) -> String;
    /// Checkpoint: the files that matter if the run dies.
    fn write_progress(&self, opt: &dyn Optimizer<G>, rows: &[Row], rec: &Self::Record) -> Result<()>;
    /// Every result file.
    fn write_all(&self, opt: &dyn Optimizer<G>, rows: &[Row], rec: &Self::Record, ended: Ended) -> Result<()>;
    /// What the summary line adds before the output folder.
    fn summary_tail(&self, rec: &Self::Record) -> String;
}

/// The progress bar of a run: generations when they bound it, else the
/// time budget in milliseconds.
fn progress(stop: &Stop, quiet: bool) -> ProgressBar {
    let bar = match stop.generations {
        Some(g) => ProgressBar::new(g as u64),
        None => ProgressBar::new(stop.budget.map_or(0, |b| b.as_millis() as u64)),
    };
    if quiet {
        bar.set_draw_target(ProgressDrawTarget::hidden());
    }
    let template = if stop.generations.is_some() {
        "{elapsed_precise} [{bar:30}] gen {pos}/{len} · {msg}"
    } else {
        "{elapsed_precise} [{bar:30}] {msg}"
    };
    bar.set_style(ProgressStyle::with_template(template).expect("valid template").progress_chars("=> "));
    bar
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
}

/// The run loop of `evolve` (and of `genform serve`'s runs): the progress
/// bar, checkpoints, cancellation, steering changes before the generations
/// they take effect at (each followed by re-scoring what the optimizer
/// stores), the watcher, the result files and the summary line.
fn drive<G, S: Session<G>, P: Rescore<G>>(
    session: &mut S,
    mut opt: P,
    stop: Stop,
    control: &mut Control,
) -> Result<()> {
    let (out, quiet, scene) = {
        let c = session.common();
        (c.args.out.clone(), c.args.quiet, c.scene_path.display().to_string())
    };
    // A replayed log is checked whole before the run starts.
    let mut probe = session.steerable().clone();
    for e in &control.schedule {
        probe.apply(&e.set).with_context(|| format!("steering of generation {}", e.generation))?;
    }
    std::fs::create_dir_all(&out).with_context(|| format!("cannot create output folder {}", out.display()))?;
    let bar = progress(&stop, quiet);
    let mut rows: Vec<Row> = Vec::new();
    let mut rec = S::Record::default();
    let mut log: Vec<SteerEntry> = Vec::new();
    let mut scheduled = control.schedule.iter().peekable();
    let mut live: Option<SteerSet> = None;
    let mut last_checkpoint = Instant::now();
    // The fitness of the last live best model offered to the watcher.
    let mut shown_best: Option<u64> = None;
    if let Some(w) = control.watch.as_deref_mut() {
        w.started(session.max_reachable(), session.steerable());
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
                w.steered(&entry, session.steerable());
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
        let tail = session.record(&mut rec, &stats, &opt, !quiet && bar.is_hidden());
        let best = opt.best().map(|b| b.fitness);
        let rate = stats.total_evaluations as f64 / secs.max(1e-9);
        let msg = format!("best {:.4} · {rate:.0} evals/s{tail}", best.unwrap_or(f64::NAN));
        if stop.generations.is_some() {
            bar.set_position(stats.generation as u64);
            bar.set_message(msg);
        } else {
            bar.set_position((secs * 1000.0) as u64);
            bar.set_message(format!("gen {} · {msg}", stats.generation));
        }
        if last_checkpoint.elapsed() >= CHECKPOINT_EVERY {
            session.write_progress(&opt, &rows, &rec)?;
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
            let tick = Tick { stats: &stats, seconds: secs, best, criteria: session.criteria(&rec) };
            // A paused run waits in here: that time is not the run's (its
            // budget and its seconds leave it out).
            let held = Instant::now();
            live = w.generation(&tick);
            start += held.elapsed();
        }
    };
    let elapsed = start.elapsed();
    bar.finish_and_clear();
    if reason == StopReason::Cancelled {
        eprintln!("interrupted: writing the results of generation {}", opt.generation());
    }
    let ended = Ended { reason: stop_reason_name(reason), elapsed, steering: &log };
    session.write_all(&opt, &rows, &rec, ended)?;
    eprintln!(
        "{scene}: {} generations, {} evaluations in {:.1} s ({:.0}/s); best fitness {:.6} (max reachable {:.4}){} → {}",
        opt.generation(),
        opt.evaluations(),
        elapsed.as_secs_f64(),
        opt.evaluations() as f64 / elapsed.as_secs_f64().max(1e-9),
        opt.best().map_or(f64::NAN, |b| b.fitness),
        session.max_reachable(),
        session.summary_tail(&rec),
        out.display()
    );
    Ok(())
}

/// `best.glb` and `best.obj` of `scene`.
fn write_models(out: &Path, scene: &Scene) -> Result<()> {
    for (name, format) in [("best.glb", Format::Glb), ("best.obj", Format::Obj)] {
        let bytes = genform_export::export(scene, format, &ExportOptions::default())
            .with_context(|| format!("cannot export {name}"))?;
        write_atomic(&out.join(name), &bytes)?;
    }
    Ok(())
}

/// One `evolve` run of a tree scene.
struct RunContext<'a> {
    common: Common<'a>,
    /// The scene as written (steering changes `scorers` and `steerable` only).
    config: &'a SceneConfig,
    generator: &'a dyn Generator,
    limits: Limits,
    /// The targets, with the fitness constants as steered so far.
    scorers: Scorers,
    /// The `[fitness]` constants as steered so far.
    steerable: Steerable,
    descriptors: [Descriptor; 2],
}

impl Session<Genome> for RunContext<'_> {
    type Record = BestHistory<Genome>;
    type Objective<'s>
        = DescribedObjective<'s>
    where
        Self: 's;

    fn common(&self) -> &Common<'_> {
        &self.common
    }

    fn objective(&self) -> DescribedObjective<'_> {
        let objective = SceneObjective { generator: self.generator, limits: self.limits, scorers: &self.scorers };
        DescribedObjective { objective, descriptors: self.descriptors }
    }

    fn steerable(&self) -> &Steerable {
        &self.steerable
    }

    fn steer(&mut self, set: &SteerSet) -> Result<()> {
        self.steerable.apply(set)?;
        if let Steerable::Fitness(f) = &self.steerable {
            let mut config = self.config.clone();
            config.fitness = f.clone();
            self.scorers.fitness = config.fitness();
        }
        Ok(())
    }

    fn best_scene(&self, opt: &dyn Optimizer) -> Result<Option<Scene>> {
        opt.best().map(|b| self.express(&b.genome)).transpose()
    }

    fn gallery(&self, opt: &dyn Optimizer) -> Result<Vec<u8>> {
        let reports = self.reports();
        // Earlier epochs' champions compete too: after a restart the best
        // answer so far may no longer be in the population.
        let pool: Vec<Individual> = opt.population().iter().chain(opt.champions()).cloned().collect();
        Ok(reports.gallery_png(&reports.describe(&pool)?))
    }

    fn max_reachable(&self) -> f64 {
        self.scorers.fitness.max_reachable(self.config.ga.min_length)
    }

    fn record(&self, rec: &mut BestHistory<Genome>, stats: &GenerationStats, opt: &dyn Optimizer, _: bool) -> String {
        rec.record(stats.generation, opt.best().map(|b| (&b.genome, b.fitness)));
        String::new()
    }

    fn write_progress(&self, opt: &dyn Optimizer, rows: &[Row], _: &BestHistory<Genome>) -> Result<()> {
        let out = &self.common.args.out;
        write_atomic(&out.join("stats.csv"), report::stats_csv(rows).as_bytes())?;
        if let Some(best) = opt.best() {
            write_atomic(&out.join("best-genome.json"), best.genome.to_json(self.generator.graph()).as_bytes())?;
        }
        Ok(())
    }

    fn write_all(&self, opt: &dyn Optimizer, rows: &[Row], rec: &BestHistory<Genome>, ended: Ended) -> Result<()> {
        let out = &self.common.args.out;
        self.write_progress(opt, rows, rec)?;
        let title = title(self.common.scene_path);
        write_atomic(&out.join("fitness.svg"), report::fitness_svg(&title, rows).as_bytes())?;
        if let Some(best) = opt.best() {
            let scene = self.express(&best.genome)?;
            write_models(out, &scene)?;
            // best-model.png: the model alone in a fitted 3/4 view;
            // best.png: with its target behind it (see genform_app::pictures).
            write_atomic(&out.join("best-model.png"), &genform_export::render_png(&scene, &RenderOptions::default()))?;
            let target = TargetPicture::new(self.config, &self.scorers)?;
            write_atomic(&out.join("best.png"), &target.best_png(&scene))?;
            pictures::write_silhouettes(out, &self.scorers.images, &scene)?;
            self.write_evolution(&target, rec)?;
        }
        self.write_diversity(opt.population())?;
        let l = &self.limits;
        let own = serde_json::json!({
            "limits": { "genes": l.max_genes, "depth": l.max_depth, "primitives": l.max_primitives },
            "config": self.config,
        });
        self.common.write_run_json(opt, rows, ended, self.max_reachable(), own)
    }

    fn summary_tail(&self, _: &BestHistory<Genome>) -> String {
        String::new()
    }
}

impl RunContext<'_> {
    /// `evolution.png`: the best so far at about [`pictures::FRAMES`]
    /// moments of the run, with the target behind it, as an animated PNG.
    fn write_evolution(&self, target: &TargetPicture, rec: &BestHistory<Genome>) -> Result<()> {
        let frames = rec
            .frames(pictures::FRAMES)
            .into_iter()
            .map(|(g, f, genome)| Ok((g, f, self.express(genome)?)))
            .collect::<Result<Vec<_>>>()?;
        match target.evolution_apng(&frames) {
            Some(apng) => write_atomic(&self.common.args.out.join("evolution.png"), &apng),
            None => Ok(()),
        }
    }

    fn express(&self, genome: &Genome) -> Result<Scene> {
        let mut scene = Scene::new();
        self.generator.express(genome, &self.limits, &mut scene).context("cannot build the best model")?;
        Ok(scene)
    }

    fn reports(&self) -> Reports<'_> {
        Reports { generator: self.generator, limits: self.limits, config: self.config.map_elites() }
    }

    /// `gallery.png` (the best distinct individuals of `population`) and,
    /// for MAP-Elites, whose population is its archive, `archive.csv`,
    /// `archive.png` and `elites/`.
    fn write_diversity(&self, population: &[Individual]) -> Result<()> {
        let out = &self.common.args.out;
        let reports = self.reports();
        let described = reports.describe(population)?;
        write_atomic(&out.join("gallery.png"), &reports.gallery_png(&described))?;
        if self.common.algorithm == genform_evolve::Algorithm::MapElites.name() {
            reports.write_archive(out, &described)?;
        }
        Ok(())
    }
}
