//! `genform sweep`: a parameter study. One or two scene keys take several
//! values (`--set ga.population=10,50,100`; more `--set`s with one value
//! each fix other settings for every run); every value combination is
//! run `runs` times (run r with seed `seed + r`, the same seeds for every
//! combination) and the best fitness per generation is reported as the
//! ShapeGenetics paper's Figures 4–9 do.
//!
//! All runs of all combinations go to one worker pool at once and their
//! results are collected in (combination, run) order; since a run's
//! results do not depend on the threads it gets, `sweep.csv` is the same
//! bytes at any thread count (with generation or evaluation limits; a
//! wall-clock budget makes runs depend on the machine's load).

use anyhow::{Context, Result, anyhow, bail};
use genform_core::Limits;
use genform_evolve::{AnyOptimizer, Horizon, Stop, StopReason};
use genform_score::{Descriptor, Scorer};
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use crate::files::write_atomic;
use crate::formalism::Loaded;
use crate::memory::{Reservation, Size};
use crate::objective::{Model, TreeObjective};
use crate::optimizers::{Kind, Searches};
pub use crate::report::sweep::{GenPoint, RunTrace, SweepResult};
use crate::scene::Scene;
pub use crate::scene::patch::Axis;

/// Most keys a sweep crosses.
pub const MAX_KEYS: usize = 2;

/// What to sweep, from the command line.
#[derive(Clone, Debug)]
pub struct SweepRequest {
    /// The scene config.
    pub scene: PathBuf,
    /// The keys and their values: at most [`MAX_KEYS`] with several values
    /// (crossed); keys with one value are set in every run.
    pub axes: Vec<Axis>,
    /// Runs per value combination.
    pub runs: usize,
    /// Seed of run 0.
    pub seed: u64,
    /// Generations per run (overrides the scene's `[run]`, as do the next two).
    pub generations: Option<usize>,
    /// Wall-clock budget per run, e.g. "10s".
    pub budget: Option<String>,
    /// Evaluations per run.
    pub evaluations: Option<u64>,
    /// The algorithm's name (a tree algorithm).
    pub algorithm: String,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// Output folder.
    pub out: PathBuf,
}

/// A run that finished, as the progress callback sees it.
pub struct RunDone<'a> {
    /// `key=value …` of its combination.
    pub label: &'a str,
    /// The run.
    pub trace: &'a RunTrace,
    /// Runs finished so far, and in all.
    pub done: usize,
    /// Runs in all.
    pub total: usize,
}

/// One value combination, ready to run.
struct Variant {
    label: String,
    generator: Arc<Loaded>,
    limits: Limits,
    scorer: Arc<dyn Scorer>,
    settings: genform_evolve::Settings,
    horizon: Horizon,
    /// What MAP-Elites bins (other algorithms only read the fitness).
    descriptors: [Descriptor; 2],
    /// What one run of it asks memory for.
    sizes: Vec<Size<'static>>,
}

impl Variant {
    /// The bytes one run of it asks for.
    fn bytes(&self) -> u128 {
        self.sizes.iter().map(|s| s.bytes).fold(0, u128::saturating_add)
    }
}

/// Checks a request's counts and the key count before anything is loaded.
fn check(req: &SweepRequest) -> Result<()> {
    if req.axes.is_empty() {
        bail!("nothing to sweep: give --set KEY=V1,V2,… (e.g. --set ga.population=10,50,100)");
    }
    let varying = req.axes.iter().filter(|a| a.values.len() > 1).count();
    if varying > MAX_KEYS {
        bail!("{varying} --set options have several values; a sweep crosses at most {MAX_KEYS} keys");
    }
    for (i, a) in req.axes.iter().enumerate() {
        if req.axes[..i].iter().any(|b| b.key == a.key) {
            bail!("--set {} is given twice; give all its values in one --set", a.key);
        }
    }
    if let Some(why) = crate::caps::count("--runs", req.runs as u64, crate::caps::MAX_RUNS) {
        bail!(why);
    }
    Ok(())
}

/// Loads every combination: the scene with the values applied and checked,
/// its grammar and its scorer (built once and shared while the settings
/// that make them are the same).
fn load(req: &SweepRequest) -> Result<(genform_evolve::Algorithm, Vec<Vec<String>>, Vec<Variant>)> {
    let text = crate::text::read_text(&req.scene, "scene")?;
    // The scene as written first: its own mistakes keep their positions.
    let written = Scene::from_text(&req.scene, &text, None)?;
    if written.searches != Searches::Trees {
        bail!("{} is a codon scene; genform sweep runs tree scenes (.sg, .ls grammars) for now", req.scene.display());
    }
    let Kind::Tree(algorithm) = super::control::algorithm(Some(&req.algorithm), &written)?.kind else {
        bail!("genform sweep runs tree algorithms");
    };
    let mut combos = Vec::new();
    let mut variants = Vec::new();
    let mut grammars: Vec<(PathBuf, Arc<Loaded>)> = Vec::new();
    let mut scorers: Vec<(String, Arc<dyn Scorer>)> = Vec::new();
    for (values, scene) in Scene::variants(&req.scene, &text, &req.axes)? {
        let shown = |all: bool| -> Vec<String> {
            let pairs = req.axes.iter().zip(&values).filter(|(a, _)| all || a.values.len() > 1);
            pairs.map(|(a, v)| format!("{}={v}", a.key)).collect()
        };
        let label = shown(false).join(" ");
        let at = || format!("--set {}", shown(true).join(" --set "));
        let generator = match grammars.iter().find(|(p, _)| *p == scene.grammar) {
            Some((_, g)) => g.clone(),
            None => {
                let Model::Tree { loaded, .. } = Model::open(&scene, Default::default())? else {
                    bail!("a tree scene makes trees");
                };
                grammars.push((scene.grammar.clone(), loaded.clone()));
                loaded
            }
        };
        let scoring_key = serde_json::to_string(&(
            scene.scoring.to_json(),
            &scene.scoring.fitness,
            scene.optimizers.ga.min_length,
            scene.optimizers.ga.max_length,
        ))?;
        let scorer = match scorers.iter().find(|(k, _)| *k == scoring_key) {
            Some((_, s)) => s.clone(),
            None => {
                let s: Arc<dyn Scorer> = Arc::from(scene.scoring.build(scene.lengths()).with_context(at)?.scorer);
                scorers.push((scoring_key, s.clone()));
                s
            }
        };
        let limits = scene.limits.overrides().apply(generator.limits);
        let horizon =
            super::control::horizon(req.generations, req.budget.as_deref(), req.evaluations, &scene.run, "the runs")
                .with_context(at)?;
        let settings = scene.tree_settings();
        // Fail now, not in the middle of the runs.
        AnyOptimizer::new(algorithm, generator.generator.graph(), &limits, &settings, req.seed, horizon)
            .map_err(|e| anyhow!("{}: {e}", at()))?;
        let descriptors = scene.optimizers.descriptors();
        let sizes = scene.sizes();
        variants.push(Variant { label, generator, limits, scorer, settings, horizon, descriptors, sizes });
        combos.push(req.axes.iter().zip(values).filter(|(a, _)| a.values.len() > 1).map(|(_, v)| v).collect());
    }
    Ok((algorithm, combos, variants))
}

/// Runs the sweep; `on_done` hears of every finished run (in the order
/// they finish). Runs stopped by `cancel` are left out of the result.
pub fn run(req: &SweepRequest, cancel: &AtomicBool, on_done: &(dyn Fn(RunDone) + Sync)) -> Result<SweepResult> {
    check(req)?;
    let _session = crate::gate::session();
    let (algorithm, combinations, variants) = load(req)?;
    crate::gate::refuse_folder("--out", &req.out, super::writes_run_file)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(req.threads.unwrap_or(0))
        .build()
        .context("cannot start worker threads")?;
    let jobs: Vec<(usize, usize)> = (0..variants.len()).flat_map(|v| (0..req.runs).map(move |r| (v, r))).collect();
    let _memory = reserve(&variants, &jobs, pool.current_num_threads())?;
    let done = std::sync::atomic::AtomicUsize::new(0);
    let session = crate::gate::current();
    let results: Vec<Result<Option<RunTrace>>> = pool.install(|| {
        jobs.par_iter()
            .map(|&(v, r)| {
                let trace = crate::gate::within(&session, || one_run(&variants[v], algorithm, req, v, r, cancel))?;
                if let Some(t) = &trace {
                    let k = done.fetch_add(1, std::sync::atomic::Ordering::SeqCst) + 1;
                    on_done(RunDone { label: &variants[v].label, trace: t, done: k, total: jobs.len() });
                }
                Ok(trace)
            })
            .collect()
    });
    let mut runs = Vec::new();
    for r in results {
        runs.extend(r?);
    }
    let keys = req.axes.iter().filter(|a| a.values.len() > 1).map(|a| a.key.clone()).collect();
    Ok(SweepResult { keys, combinations, runs })
}

/// Reserves what the runs that may go at once (one per worker thread, the
/// largest first) ask for together, for the whole sweep.
fn reserve(variants: &[Variant], jobs: &[(usize, usize)], threads: usize) -> Result<Reservation> {
    let mut largest: Vec<&Variant> = jobs.iter().map(|&(v, _)| &variants[v]).collect();
    largest.sort_by_key(|v| std::cmp::Reverse(v.bytes()));
    let at_once = threads.clamp(1, largest.len().max(1));
    let sizes: Vec<Size> = largest.iter().take(at_once).flat_map(|v| v.sizes.iter().cloned()).collect();
    crate::memory::reserve_sizes(&sizes, "sweep")
        .with_context(|| format!("{at_once} runs of the sweep go at once (one per thread; fewer with --threads)"))
}

/// One run of combination `v`; `None` when it was cancelled.
fn one_run(
    variant: &Variant,
    algorithm: genform_evolve::Algorithm,
    req: &SweepRequest,
    v: usize,
    r: usize,
    cancel: &AtomicBool,
) -> Result<Option<RunTrace>> {
    let seed = req.seed + r as u64;
    let Variant { generator, limits, scorer, settings, horizon, descriptors, .. } = variant;
    let mut opt = AnyOptimizer::new(algorithm, generator.generator.graph(), limits, settings, seed, *horizon)
        .map_err(|e| anyhow!("{}: {e}", variant.label))?;
    let objective = TreeObjective {
        generator: generator.generator.as_ref(),
        limits: *limits,
        scorer: scorer.as_ref(),
        descriptors: *descriptors,
    };
    let stop =
        Stop { generations: horizon.generations, budget: horizon.budget, evaluations: horizon.evaluations, cancel };
    let mut points = Vec::new();
    let summary = genform_evolve::run(&mut opt, &objective, &stop, |stats, o| {
        points.push(GenPoint {
            generation: stats.generation,
            evaluations: stats.total_evaluations,
            best: o.best().map_or(f64::NAN, |b| b.fitness),
            max: stats.max,
            mean: stats.avg,
        });
    })?;
    if summary.reason == StopReason::Cancelled {
        return Ok(None);
    }
    Ok(Some(RunTrace { variant: v, run: r, seed, points, seconds: summary.elapsed.as_secs_f64() }))
}

/// Writes `sweep.csv`, `sweep.svg` and `summary.md` into `out`.
pub fn write(result: &SweepResult, scene: &Path, out: &Path) -> Result<()> {
    crate::gate::create_dir(out)?;
    write_atomic(&out.join("sweep.csv"), result.csv().as_bytes())?;
    let title = scene.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    write_atomic(&out.join("sweep.svg"), result.svg(&title).as_bytes())?;
    write_atomic(&out.join("summary.md"), result.summary().as_bytes())
}
