//! The run loop ([`drive`]) and what a kind of genome gives it
//! ([`Session`]): the objective as steered so far, the records kept per
//! generation, and the files only that kind writes.

use anyhow::{Context, Result};
use genform_core::Scene;
use genform_evolve::{GenerationStats, Genotype, Horizon, Objective, Optimizer, Rescore, Stop, StopReason};
use genform_export::{ExportOptions, Format};
use genform_score::Scorer;
use std::path::Path;
use std::time::{Duration, Instant};

use super::control::{CHECKPOINT_EVERY, Control, EvolveRequest, RunOutcome, Start, Tick, stop_reason_name};
use super::steering::{SteerEntry, SteerSet, Steerable};
use crate::files::write_atomic;
use crate::report::stats::{Column, CriteriaRow, Row, fitness_svg, stats_csv};

/// What every `evolve` run knows, tree or codon.
pub(super) struct Common<'a> {
    pub request: &'a EvolveRequest,
    /// The algorithm's name.
    pub algorithm: &'static str,
    pub scene_path: &'a Path,
    pub threads: usize,
}

/// How a run ended.
#[derive(Clone, Copy)]
pub(super) struct Ended<'s> {
    /// The `stopped_by` word.
    pub reason: &'static str,
    pub elapsed: Duration,
    /// The changes that took effect, for `run.json`.
    pub steering: &'s [SteerEntry],
}

impl Common<'_> {
    /// Writes `run.json` into `out`: the keys every run has, then `own` (an
    /// object with the kind's own keys).
    pub fn write_run_json<G: Genotype>(
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

    /// `stats.csv` (with the kind's own `columns`) and the best genome
    /// (`best_file`, `best_text`): what a checkpoint writes.
    pub fn write_progress(
        &self,
        out: &Path,
        rows: &[Row],
        columns: &[Column],
        best: Option<(&str, String)>,
    ) -> Result<()> {
        write_atomic(&out.join("stats.csv"), stats_csv(rows, columns).as_bytes())?;
        if let Some((name, text)) = best {
            write_atomic(&out.join(name), text.as_bytes())?;
        }
        Ok(())
    }

    /// `fitness.svg`, with the best model's criteria when its scorer
    /// charts them.
    pub fn write_plot(&self, out: &Path, rows: &[Row], criteria: &[CriteriaRow], formula: &str) -> Result<()> {
        let svg = fitness_svg(&title(self.scene_path), rows, criteria, formula);
        write_atomic(&out.join("fitness.svg"), svg.as_bytes())
    }
}

/// The scene file's name without its ending, for plot titles.
pub(super) fn title(path: &Path) -> String {
    path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default()
}

/// `best.glb`, and `best.obj` with its materials `best.mtl`, of `scene`.
pub(super) fn write_models(out: &Path, scene: &Scene) -> Result<()> {
    crate::files::write_model(scene, &out.join("best.glb"))?;
    crate::files::write_model(scene, &out.join("best.obj"))?;
    Ok(())
}

/// What differs between tree and codon runs of `evolve`; [`drive`] does the rest.
pub(super) trait Session<G> {
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
    /// The scorer as steered so far.
    fn scorer(&self) -> &dyn Scorer;
    /// The weights and targets steering can change, as they are now.
    fn steerable(&self) -> &Steerable;
    /// Applies a change to the objective (nothing changes on error).
    fn steer(&mut self, set: &SteerSet) -> Result<()>;
    /// Scorers that chart their criteria: the best's per-criterion scores
    /// of the last generation.
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
    /// The fitness the shortest genome could reach under the current scorer.
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
pub(super) struct ByRef<'a, O>(pub &'a O);

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

/// [`Stop`] for `horizon`, cancelled by `cancel`.
pub(super) fn stop_at(horizon: Horizon, cancel: &std::sync::atomic::AtomicBool) -> Stop<'_> {
    Stop { generations: horizon.generations, budget: horizon.budget, evaluations: horizon.evaluations, cancel }
}

/// A pool of `threads` workers (`None`: all cores).
pub(super) fn worker_pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new().num_threads(threads.unwrap_or(0)).build().context("cannot start worker threads")
}

/// The run loop: checkpoints, cancellation, steering changes before the
/// generations they take effect at (each followed by re-scoring what the
/// optimizer stores), the watcher, the result files and the outcome.
pub(super) fn drive<G, S: Session<G>, P: Rescore<G>>(
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
    let mut probe = (session.scorer().with_knobs(&[]).map_err(anyhow::Error::msg)?, session.steerable().clone());
    for e in &control.schedule {
        probe = probe
            .1
            .apply(probe.0.as_ref(), &e.set)
            .with_context(|| format!("steering of generation {}", e.generation))?;
    }
    if let Some(out) = &out {
        crate::gate::create_dir(out)?;
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
        generator: None,
        tail: session.summary_tail(&rec),
    })
}
