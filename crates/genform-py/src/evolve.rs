//! `genform.evolve`: a scene run through the same run loop as `genform
//! evolve` ([`genform_app::run`]): tree and codon scenes, the same run
//! folder, per-generation statistics for Python, a progress callable and
//! Ctrl-C handled by Python.
//!
//! The run goes on a worker thread (its rayon pool does the evaluations);
//! the calling thread waits with the GIL released, runs the progress
//! callable and checks for Ctrl-C, which sets the run's cancel flag, so the
//! run stops after the current generation.

use genform_app::{Control, EvolveRequest, RunOutcome, SteerSet, Tick, Watch};
use genform_evolve::GenerationStats;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use crate::errors::{OrRaise, Whole, error};
use crate::grammar::{Model, path_arg};
use crate::optimizer::budget_arg;
use crate::scene::Scene;
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
    Generation(Box<GenerationStats>, Option<f64>, f64),
    Note(String),
    Done(Box<anyhow::Result<RunOutcome>>),
}

/// The run loop's watcher: hands each generation and note to the calling thread.
struct Relay(mpsc::Sender<Event>);

impl Watch for Relay {
    fn generation(&mut self, tick: &Tick) -> Option<SteerSet> {
        let _ = self.0.send(Event::Generation(Box::new(tick.stats.clone()), tick.best, tick.seconds));
        None
    }

    fn note(&mut self, text: &str) {
        let _ = self.0.send(Event::Note(text.to_string()));
    }
}

#[pyfunction]
#[pyo3(signature = (scene, algorithm = None, seed = Whole(0), budget = None, generations = None, evaluations = None,
                    threads = None, out = None, progress = None, **settings))]
#[allow(clippy::too_many_arguments)]
/// Runs an optimizer on a scene, as `genform evolve` does.
pub fn evolve(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    algorithm: Option<&str>,
    seed: Whole<u64>,
    budget: Option<&Bound<'_, PyAny>>,
    generations: Option<Whole<usize>>,
    evaluations: Option<Whole<u64>>,
    threads: Option<Whole<usize>>,
    out: Option<&Bound<'_, PyAny>>,
    progress: Option<Bound<'_, PyAny>>,
    settings: Option<&Bound<'_, PyDict>>,
) -> PyResult<RunResult> {
    let path: PathBuf = match scene.cast::<Scene>() {
        Ok(s) => s.get().core.path.clone(),
        Err(_) => path_arg(scene)?,
    };
    if !path.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml")) {
        return Err(error("evolve() needs a scene (a .toml scene config or genform.Scene), not a grammar"));
    }
    if let Some(name) = algorithm {
        genform_app::check_algorithm(name).or_raise()?;
    }
    let keywords = crate::settings::keywords(settings)?;
    let set = if keywords.is_empty() {
        Vec::new()
    } else {
        genform_app::settings_patch(&path, algorithm, &keywords).or_raise()?
    };
    let request = EvolveRequest {
        scene: path,
        seed: seed.0,
        generations: generations.map(|g| g.0),
        budget: budget_arg(budget)?.map(|d| format!("{}", d.as_secs_f64())),
        evaluations: evaluations.map(|e| e.0),
        threads: threads.map(|t| t.0),
        out: out.filter(|o| !o.is_none()).map(path_arg).transpose()?,
        algorithm: algorithm.map(str::to_string),
        set,
        ..EvolveRequest::default()
    };
    let cancel = Arc::new(AtomicBool::new(false));
    let (tx, rx) = mpsc::channel::<Event>();
    // A Mutex makes the receiver Sync, as waiting without the GIL requires.
    let rx = std::sync::Mutex::new(rx);
    let mut dicts: Vec<Py<PyDict>> = Vec::new();
    let mut failure: Option<PyErr> = None;
    let mut interrupted = false;
    let outcome = std::thread::scope(|s| -> PyResult<_> {
        let (request, flag) = (&request, cancel.clone());
        s.spawn(move || {
            let mut relay = Relay(tx.clone());
            let control = Control { cancel: flag, schedule: Vec::new(), watch: Some(&mut relay) };
            let _ = tx.send(Event::Done(Box::new(genform_app::evolve(request, control))));
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
                }
                Ok(Event::Note(text)) => {
                    let warning = py.get_type::<pyo3::exceptions::PyUserWarning>();
                    PyErr::warn(py, &warning, &std::ffi::CString::new(text).unwrap_or_default(), 1)?;
                }
                Ok(Event::Done(outcome)) => return Ok(*outcome),
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
    let outcome = outcome.or_raise()?;
    let stopped_by = if interrupted { "interrupted" } else { genform_app::stop_reason_name(outcome.stopped_by) };
    let best = best_model(py, &outcome)?;
    Ok(RunResult {
        best,
        best_fitness: outcome.best_fitness.unwrap_or(f64::NAN),
        stats: pyo3::types::PyList::new(py, dicts)?.into_any().unbind(),
        out: outcome.out.as_ref().map(|o| o.display().to_string()),
        generations: outcome.generations,
        evaluations: outcome.evaluations,
        stopped_by: stopped_by.to_string(),
        seconds: outcome.elapsed.as_secs_f64(),
    })
}

/// The run's best as a model: a tree scene's genome with the run's own
/// generator (so the model has its genome; nothing is compiled or
/// voxelized again), a codon scene's phenotype as built.
fn best_model(py: Python<'_>, outcome: &RunOutcome) -> PyResult<Option<Py<Model>>> {
    let Some(scene) = &outcome.best_scene else { return Ok(None) };
    let model = match (&outcome.generator, &outcome.best_genome) {
        (Some((path, loaded, limits)), Some(genome)) => {
            let core =
                Arc::new(py.detach(|| genform_app::GrammarHandle::with_generator(path, loaded.clone())).or_raise()?);
            let genome = genome.clone();
            py.detach(|| crate::grammar::derive(&core, genome, *limits)).or_raise()?
        }
        _ => Model::of_scene(scene.clone(), format!("{}: the best of the run", outcome.scene.display())),
    };
    Ok(Some(Py::new(py, model)?))
}
