//! `genform.evolve`: a scene run as `genform evolve` does it, with
//! per-generation statistics for Python, a progress callable, Ctrl-C
//! handled by Python, and the run folder written when `out` is given.
//!
//! The optimizer runs on a worker thread (its rayon pool does the
//! evaluations); the calling thread waits with the GIL released, runs the
//! progress callable and checks for Ctrl-C, which sets the run's cancel
//! flag, so the run stops after the current generation.

use anyhow::{Context, Result};
use genform_app::archive::Reports;
use genform_app::output::write_atomic;
use genform_app::pictures::{self, BestHistory, TargetPicture};
use genform_app::report::{self, Row};
use genform_core::{Genome, Scene};
use genform_evolve::{AnyOptimizer, GenerationStats, Horizon, Optimizer as _, Stop, StopReason, run};
use genform_export::{ExportOptions, Format, RenderOptions};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use crate::errors::{OrRaise, error};
use crate::grammar::{Model, path_arg};
use crate::optimizer::{Target, budget_arg};
use crate::scene::SceneCore;
use crate::settings;

/// What `evolve` returns.
#[pyclass(module = "genform", get_all, set_all)]
pub struct RunResult {
    /// The best model found.
    pub best: Option<Py<Model>>,
    /// Its fitness (NaN when none was valid).
    pub best_fitness: f64,
    /// One dict per generation.
    pub stats: Py<PyAny>,
    /// The run folder, when one was written.
    pub out: Option<String>,
    /// Generations run (index of the last).
    pub generations: usize,
    /// Objective evaluations.
    pub evaluations: u64,
    /// Why the run stopped: generations, budget, evaluations or interrupted.
    pub stopped_by: String,
    /// Wall time.
    pub seconds: f64,
}

#[pymethods]
impl RunResult {
    #[new]
    #[pyo3(signature = (best, best_fitness, stats, out, generations, evaluations, stopped_by, seconds))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        best: Option<Py<Model>>,
        best_fitness: f64,
        stats: Py<PyAny>,
        out: Option<String>,
        generations: usize,
        evaluations: u64,
        stopped_by: String,
        seconds: f64,
    ) -> Self {
        RunResult { best, best_fitness, stats, out, generations, evaluations, stopped_by, seconds }
    }

    fn __repr__(&self) -> String {
        format!(
            "<genform.RunResult best {:.6} after {} generations, {} evaluations ({})>",
            self.best_fitness, self.generations, self.evaluations, self.stopped_by
        )
    }
}

/// A message from the run thread.
enum Event {
    // Both payloads are boxed: they are large and unequal (clippy's large_enum_variant).
    Generation(Box<GenerationStats>, Option<f64>, f64),
    Done(Result<genform_evolve::RunSummary, genform_evolve::Unbounded>, Box<AnyOptimizer>, BestHistory<Genome>),
}

/// The `stopped_by` word of `run.json`.
fn reason_name(r: StopReason) -> &'static str {
    match r {
        StopReason::Generations => "generations",
        StopReason::Budget => "budget",
        StopReason::Evaluations => "evaluations",
        StopReason::Cancelled => "interrupted",
    }
}

#[pyfunction]
#[pyo3(signature = (scene, algorithm = "ga", seed = 0, budget = None, generations = None, evaluations = None,
                    threads = None, out = None, progress = None, **settings))]
#[allow(clippy::too_many_arguments)]
/// Runs an optimizer on a scene, as `genform evolve` does.
pub fn evolve(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    algorithm: &str,
    seed: u64,
    budget: Option<&Bound<'_, PyAny>>,
    generations: Option<usize>,
    evaluations: Option<u64>,
    threads: Option<usize>,
    out: Option<&Bound<'_, PyAny>>,
    progress: Option<Bound<'_, PyAny>>,
    settings: Option<&Bound<'_, PyDict>>,
) -> PyResult<RunResult> {
    let Target::Scene(core) = Target::from_py(scene)? else {
        return Err(error("evolve() needs a scene (a .toml scene config or genform.Scene), not a grammar"));
    };
    let alg = settings::algorithm(algorithm).or_raise()?;
    let config_settings = settings::apply(core.config.settings(), alg, settings)?;
    let budget = budget_arg(budget)?;
    let horizon = if generations.is_some() || budget.is_some() || evaluations.is_some() {
        Horizon { generations, budget, evaluations }
    } else {
        let r = &core.config.run;
        let b = r.budget.as_deref().map(genform_app::scene_config::parse_duration).transpose().or_raise()?;
        Horizon { generations: r.generations, budget: b, evaluations: r.evaluations }
    };
    if horizon.generations.is_none() && horizon.budget.is_none() && horizon.evaluations.is_none() {
        return Err(error("nothing tells the run when to stop: give generations, budget or evaluations"));
    }
    let out: Option<PathBuf> = out.filter(|o| !o.is_none()).map(path_arg).transpose()?;
    let graph = core.grammar.generator().or_raise()?.generator.graph();
    let opt = AnyOptimizer::new(alg, graph, &core.limits, &config_settings, seed, horizon)
        .map_err(|e| error(format!("{}: {e}", alg.name())))?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| error(format!("cannot start worker threads: {e}")))?;
    let threads = pool.current_num_threads();

    let cancel = AtomicBool::new(false);
    let (tx, rx) = mpsc::channel::<Event>();
    // A Mutex makes the receiver Sync, as waiting without the GIL requires.
    let rx = std::sync::Mutex::new(rx);
    let mut rows: Vec<Row> = Vec::new();
    let mut dicts: Vec<Py<PyDict>> = Vec::new();
    let mut failure: Option<PyErr> = None;
    let mut interrupted = false;
    let (summary, opt, history) = std::thread::scope(|s| -> PyResult<_> {
        let (core, cancel) = (&core, &cancel);
        s.spawn(move || {
            let mut opt = opt;
            let mut history = BestHistory::default();
            let stop = Stop {
                generations: horizon.generations,
                budget: horizon.budget,
                evaluations: horizon.evaluations,
                cancel,
            };
            let objective = core.objective();
            let start = Instant::now();
            let summary = pool.install(|| {
                run(&mut opt, &objective, &stop, |stats, o| {
                    history.record(stats.generation, o.best().map(|b| (&b.genome, b.fitness)));
                    let best = o.best().map(|b| b.fitness);
                    let _ = tx.send(Event::Generation(Box::new(stats.clone()), best, start.elapsed().as_secs_f64()));
                })
            });
            let _ = tx.send(Event::Done(summary, Box::new(opt), history));
        });
        loop {
            match py.detach(|| rx.lock().expect("not poisoned").recv_timeout(Duration::from_millis(50))) {
                Ok(Event::Generation(stats, best, secs)) => {
                    let row = crate::stats::row(py, &stats, best, Some(secs))?;
                    if let Some(cb) = &progress
                        && failure.is_none()
                        && let Err(e) = cb.call1((row.clone(),))
                    {
                        failure = Some(e);
                        cancel.store(true, Ordering::SeqCst);
                    }
                    dicts.push(row.unbind());
                    rows.push((*stats, secs));
                }
                Ok(Event::Done(summary, opt, history)) => return Ok((summary, *opt, history)),
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                Err(mpsc::RecvTimeoutError::Disconnected) => return Err(error("the run thread stopped unexpectedly")),
            }
            // Python's SIGINT handler runs here and raises KeyboardInterrupt.
            if let Err(e) = py.check_signals() {
                if e.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) {
                    interrupted = true;
                } else if failure.is_none() {
                    failure = Some(e);
                }
                cancel.store(true, Ordering::SeqCst);
            }
        }
    })?;
    if let Some(e) = failure {
        return Err(e);
    }
    let summary = summary.map_err(|e| error(e.to_string()))?;
    let stopped_by = if interrupted { "interrupted" } else { reason_name(summary.reason) };
    let best_genome = opt.best().map(|b| b.genome.clone());
    if let Some(dir) = &out {
        let folder = Folder { core: &core, out: dir, seed, threads, algorithm: alg.name(), settings: &config_settings };
        py.detach(|| folder.write(&opt, &rows, &history, stopped_by, summary.elapsed)).or_raise()?;
    }
    let best = match best_genome {
        Some(g) => Some(Py::new(py, py.detach(|| core.grammar.derive(g, core.limits)).or_raise()?)?),
        None => None,
    };
    Ok(RunResult {
        best,
        best_fitness: opt.best().map_or(f64::NAN, |b| b.fitness),
        stats: pyo3::types::PyList::new(py, dicts)?.into_any().unbind(),
        out: out.map(|o| o.display().to_string()),
        generations: opt.generation(),
        evaluations: opt.evaluations(),
        stopped_by: stopped_by.to_string(),
        seconds: summary.elapsed.as_secs_f64(),
    })
}

/// The run folder: the files `genform evolve --out` writes for a tree
/// scene (stats.csv, best-genome.json, fitness.svg, best.glb, best.obj,
/// best-model.png, best.png, best-silhouette.png for image targets,
/// evolution.png, gallery.png, MAP-Elites' archive files, run.json).
struct Folder<'a> {
    core: &'a Arc<SceneCore>,
    out: &'a Path,
    seed: u64,
    threads: usize,
    algorithm: &'static str,
    settings: &'a genform_evolve::Settings,
}

impl Folder<'_> {
    fn write(
        &self,
        opt: &AnyOptimizer,
        rows: &[Row],
        history: &BestHistory<Genome>,
        stopped_by: &str,
        elapsed: Duration,
    ) -> Result<()> {
        let (out, core) = (self.out, self.core);
        std::fs::create_dir_all(out).with_context(|| format!("cannot create output folder {}", out.display()))?;
        let generator = core.grammar.generator()?;
        write_atomic(&out.join("stats.csv"), report::stats_csv(rows).as_bytes())?;
        let title = core.path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        write_atomic(&out.join("fitness.svg"), report::fitness_svg(&title, rows).as_bytes())?;
        if let Some(best) = opt.best() {
            write_atomic(&out.join("best-genome.json"), best.genome.to_json(generator.generator.graph()).as_bytes())?;
            let mut scene = Scene::new();
            generator
                .generator
                .express(&best.genome, &core.limits, &mut scene)
                .context("cannot build the best model")?;
            for (name, format) in [("best.glb", Format::Glb), ("best.obj", Format::Obj)] {
                let bytes = genform_export::export(&scene, format, &ExportOptions::default())
                    .with_context(|| format!("cannot export {name}"))?;
                write_atomic(&out.join(name), &bytes)?;
            }
            write_atomic(&out.join("best-model.png"), &genform_export::render_png(&scene, &RenderOptions::default()))?;
            let target = TargetPicture::new(&core.config, &core.scorers)?;
            write_atomic(&out.join("best.png"), &target.best_png(&scene))?;
            pictures::write_silhouettes(out, &core.scorers.images, &scene)?;
            let frames = history
                .frames(pictures::FRAMES)
                .into_iter()
                .map(|(g, f, genome)| {
                    let mut scene = Scene::new();
                    generator.generator.express(genome, &core.limits, &mut scene).context("cannot build a frame")?;
                    Ok((g, f, scene))
                })
                .collect::<Result<Vec<_>>>()?;
            if let Some(apng) = target.evolution_apng(&frames) {
                write_atomic(&out.join("evolution.png"), &apng)?;
            }
        }
        let reports =
            Reports { generator: generator.generator.as_ref(), limits: core.limits, config: core.config.map_elites() };
        let described = reports.describe(opt.population())?;
        write_atomic(&out.join("gallery.png"), &reports.gallery_png(&described))?;
        if self.algorithm == genform_evolve::Algorithm::MapElites.name() {
            reports.write_archive(out, &described)?;
        }
        let secs = elapsed.as_secs_f64();
        let best = opt.best();
        let l = &core.limits;
        let mut run = serde_json::json!({
            "genform": env!("CARGO_PKG_VERSION"),
            "scene": core.path.display().to_string(),
            "algorithm": self.algorithm,
            "seed": self.seed,
            "threads": self.threads,
            "stopped_by": stopped_by,
            "generations": opt.generation(),
            "evaluations": opt.evaluations(),
            "seconds": secs,
            "evaluations_per_second": opt.evaluations() as f64 / secs.max(1e-9),
            "eval_seconds": rows.iter().map(|(r, _)| r.eval_time.as_secs_f64()).sum::<f64>(),
            "reproduction_seconds": rows.iter().map(|(r, _)| r.reproduction_time.as_secs_f64()).sum::<f64>(),
            "best_fitness": best.map(|b| b.fitness),
            "best_length": best.map(|b| b.genome.len()),
            "max_reachable_fitness": core.scorers.fitness.max_reachable(core.config.ga.min_length),
            "limits": { "genes": l.max_genes, "depth": l.max_depth, "primitives": l.max_primitives },
            "config": core.config,
        });
        // The settings that ran, keyword arguments included.
        let s = self.settings;
        if let Some(config) = run.get_mut("config").and_then(|c| c.as_object_mut()) {
            config.insert("ga".into(), serde_json::to_value(&s.ga)?);
            config.insert("mh".into(), serde_json::to_value(&s.mh)?);
            config.insert("smc".into(), serde_json::to_value(&s.smc)?);
            config.insert("hybrid".into(), serde_json::to_value(&s.hybrid)?);
            config.insert("map_elites".into(), serde_json::to_value(&s.map_elites)?);
        }
        let text = serde_json::to_string_pretty(&run).context("cannot encode run.json")?;
        write_atomic(&out.join("run.json"), text.as_bytes())
    }
}
