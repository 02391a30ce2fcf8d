//! `compare`: every algorithm several times with the same wall-clock
//! budget on one scene, with the traces, the best individual of each
//! algorithm, a table and a plot.

use anyhow::Result;
use genform_evolve::{Individual, Objective, Optimizer, Stop, StopReason, run};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use super::control::Control;
use super::session::{title, worker_pool};
use crate::files::write_atomic;
use crate::formalism::LimitOverrides;
use crate::report::comparison::{self, Trace, TracePoint};

/// One `compare`, as a door asks for it.
#[derive(Clone, Debug, Default)]
pub struct CompareRequest {
    /// The scene config (tree or codon scene).
    pub scene: PathBuf,
    /// Wall-clock budget of each run, e.g. `"10s"`.
    pub budget: String,
    /// Runs per algorithm.
    pub runs: usize,
    /// The algorithms by name (empty: those of the optimizer table that
    /// `compare` runs by default for the scene's genomes).
    pub algorithms: Vec<String>,
    /// Seed of each algorithm's first run (run `r` has `seed + r`).
    pub seed: u64,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// Output folder.
    pub out: PathBuf,
    /// A GA preset name (tree scenes).
    pub preset: Option<String>,
    /// Derivation limits over the scene's (tree scenes only).
    pub limits: LimitOverrides,
    /// A settings patch over the scene file (see [`super::EvolveRequest::set`]).
    pub set: Vec<String>,
}

/// What a `compare` found.
#[derive(Clone, Debug)]
pub struct CompareOutcome {
    /// Runs that finished (an interrupted one is left out).
    pub runs: usize,
    /// The budget of each run.
    pub budget: Duration,
    /// The table of results (Markdown).
    pub summary: String,
}

/// What differs between tree and codon runs of `compare`.
pub(super) trait Contest<G> {
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

/// The shared loop of `compare`: every algorithm `r.runs` times for
/// `budget`, with the traces, the best individual of each algorithm, the
/// table and the plot written to `r.out`.
pub(super) fn race<G: Clone + Send, C: Contest<G>, O: Objective<G> + Sync>(
    r: &CompareRequest,
    scene_path: &Path,
    budget: Duration,
    algorithms: &[C::Alg],
    objective: &O,
    contest: &C,
    mut control: Control,
) -> Result<CompareOutcome> {
    crate::gate::create_dir(&r.out)?;
    let pool = worker_pool(r.threads)?;
    let cancel = control.cancel.clone();
    let mut watch = control.watch.take();
    let stop = Stop { generations: None, budget: Some(budget), evaluations: None, cancel: &cancel };
    let spacing = budget.as_secs_f64() / 200.0;
    let mut traces: Vec<Trace> = Vec::new();
    'all: for alg in algorithms {
        let name = contest.name(*alg);
        let mut best: Option<Individual<G>> = None;
        for k in 0..r.runs {
            let seed = r.seed + k as u64;
            let mut opt = contest.start(*alg, seed)?;
            let mut trace = Trace::new(name, k, seed);
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
            let line = format!(
                "{name} run {}/{}: best {:.6} after {} evaluations in {:.1} s{}",
                k + 1,
                r.runs,
                opt.best().map_or(f64::NAN, |b| b.fitness),
                opt.evaluations(),
                summary.elapsed.as_secs_f64(),
                contest.run_tail()
            );
            if let Some(w) = watch.as_deref_mut() {
                w.line(&line);
            }
            let cancelled = summary.reason == StopReason::Cancelled;
            if !cancelled {
                traces.push(trace);
            }
            write_atomic(&r.out.join("comparison.csv"), comparison::csv(&traces).as_bytes())?;
            if cancelled {
                if let Some(w) = watch.as_deref_mut() {
                    w.note("interrupted: the unfinished run is left out");
                }
                break 'all;
            }
        }
        if let Some(b) = best {
            contest.save_best(&r.out, name, &b)?;
        }
    }
    write_atomic(&r.out.join("comparison.csv"), comparison::csv(&traces).as_bytes())?;
    let svg = comparison::svg(&title(scene_path), &traces, budget.as_secs_f64());
    write_atomic(&r.out.join("comparison.svg"), svg.as_bytes())?;
    Ok(CompareOutcome { runs: traces.len(), budget, summary: comparison::summary(&traces) })
}
