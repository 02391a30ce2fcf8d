//! `genform.Optimizer`: ask/tell for a fitness computed in Python (or on
//! Ray workers), over [`genform_evolve::ask_tell::AskTell`].

use genform_app::AskTellRequest;
use genform_core::Limits;
use genform_evolve::ask_tell::{AskTell, Score};
use genform_evolve::{Horizon, Optimizer as _};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use rayon::prelude::*;
use std::sync::Arc;
use std::time::Duration;

use crate::errors::{OrRaise, Whole, error};
use crate::grammar::{Grammar, GrammarCore, Model, path_arg};
use crate::scene::{Scene, SceneCore};

/// Ask/tell over any algorithm.
#[pyclass(module = "genform")]
pub struct Optimizer {
    inner: AskTell,
    grammar: Arc<GrammarCore>,
    limits: Limits,
    algorithm: &'static str,
    stats: Vec<Py<PyDict>>,
}

/// A grammar or a scene, from a `Grammar`, a `Scene` or a path (`.toml`: a scene).
pub enum Target {
    /// A bare grammar: default settings, its own limits.
    Grammar(Arc<GrammarCore>),
    /// A scene: its settings and limits.
    Scene(Arc<SceneCore>),
}

impl Target {
    /// Reads the `target` argument.
    pub fn from_py(target: &Bound<'_, PyAny>) -> PyResult<Target> {
        if let Ok(s) = target.cast::<Scene>() {
            return Ok(Target::Scene(s.get().core.clone()));
        }
        if let Ok(g) = target.cast::<Grammar>() {
            return Ok(Target::Grammar(g.get().core.clone()));
        }
        let path = path_arg(target)?;
        let is_scene = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml"));
        let py = target.py();
        Ok(if is_scene {
            Target::Scene(Arc::new(py.detach(|| SceneCore::open(&path)).or_raise()?))
        } else {
            Target::Grammar(Arc::new(py.detach(|| GrammarCore::open(&path)).or_raise()?))
        })
    }
}

/// A time budget: seconds, or text such as "30s", "2m".
pub fn budget_arg(budget: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Duration>> {
    let Some(b) = budget.filter(|b| !b.is_none()) else { return Ok(None) };
    if let Ok(secs) = b.extract::<f64>() {
        return Duration::try_from_secs_f64(secs).map(Some).map_err(|_| error(format!("budget: {secs} seconds")));
    }
    let text: String = b.extract()?;
    genform_app::parse_duration(&text).map(Some).or_raise()
}

#[pymethods]
impl Optimizer {
    #[new]
    #[pyo3(signature = (target, algorithm = "ga", seed = Whole(0), generations = None, evaluations = None, budget = None, **settings))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        target: &Bound<'_, PyAny>,
        algorithm: &str,
        seed: Whole<u64>,
        generations: Option<Whole<usize>>,
        evaluations: Option<Whole<u64>>,
        budget: Option<&Bound<'_, PyAny>>,
        settings: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let target = Target::from_py(target)?;
        let (grammar, limits, scene) = match &target {
            Target::Grammar(g) => (g.clone(), g.generator().or_raise()?.limits, None),
            Target::Scene(s) => (s.grammar.clone(), s.limits, Some(s.path.as_path())),
        };
        let settings = crate::settings::keywords(settings)?;
        let (seed, generations, evaluations) = (seed.0, generations.map(|g| g.0), evaluations.map(|e| e.0));
        let horizon = Horizon { generations, budget: budget_arg(budget)?, evaluations };
        let generator = grammar.generator().or_raise()?.clone();
        let request = AskTellRequest { generator: &generator, limits, scene, algorithm, seed, horizon, settings };
        let opt = py.detach(|| genform_app::ask_tell(request)).or_raise()?;
        Ok(Optimizer { inner: opt.inner, grammar, limits, algorithm: opt.algorithm, stats: Vec::new() })
    }

    /// The models to score next (the same list until `tell`).
    fn ask(&mut self, py: Python<'_>) -> PyResult<Vec<Model>> {
        let (genomes, completed) = self.inner.ask().map_err(error)?;
        let genomes = genomes.to_vec();
        for s in completed {
            self.record(py, &s)?;
        }
        let (grammar, limits) = (&self.grammar, self.limits);
        let models: anyhow::Result<Vec<Model>> =
            py.detach(|| genomes.into_par_iter().map(|g| crate::grammar::derive(grammar, g, limits)).collect());
        models.or_raise()
    }

    /// The genomes of `ask` as JSON texts, without deriving the models
    /// (for scorers that derive them elsewhere, e.g. Ray workers).
    fn ask_genomes(&mut self, py: Python<'_>) -> PyResult<Vec<String>> {
        let (genomes, completed) = self.inner.ask().map_err(error)?;
        let genomes = genomes.to_vec();
        for s in completed {
            self.record(py, &s)?;
        }
        let graph = self.grammar.generator().or_raise()?.generator.graph();
        Ok(genomes.iter().map(|g| g.to_json(graph)).collect())
    }

    /// Scores for the models of `ask`, in order (a fitness, or (fitness,
    /// descriptor 0, descriptor 1)); the generation's statistics once it
    /// completed, None when the algorithm needs another batch.
    fn tell<'py>(&mut self, py: Python<'py>, scores: Vec<Bound<'py, PyAny>>) -> PyResult<Option<Py<PyDict>>> {
        let scores = scores.iter().map(score_arg).collect::<PyResult<Vec<Score>>>()?;
        match self.inner.tell(&scores).map_err(error)? {
            Some(s) => Ok(Some(self.record(py, &s)?)),
            None => Ok(None),
        }
    }

    /// The algorithm's name.
    #[getter]
    fn algorithm(&self) -> &'static str {
        self.algorithm
    }

    /// Index of the last completed generation (0 = the initial one).
    #[getter]
    fn generation(&self) -> usize {
        self.inner.optimizer().generation()
    }

    /// Whether generation 0 is complete.
    #[getter]
    fn is_initialized(&self) -> bool {
        self.inner.optimizer().is_initialized()
    }

    /// Scores told so far that the optimizer used.
    #[getter]
    fn evaluations(&self) -> u64 {
        self.inner.optimizer().evaluations()
    }

    /// The best fitness so far (NaN before any valid one).
    #[getter]
    fn best_fitness(&self) -> f64 {
        self.inner.optimizer().best().map_or(f64::NAN, |b| b.fitness)
    }

    /// The best model so far.
    #[getter]
    fn best(&self, py: Python<'_>) -> PyResult<Option<Model>> {
        let Some(b) = self.inner.optimizer().best() else { return Ok(None) };
        let genome = b.genome.clone();
        py.detach(|| crate::grammar::derive(&self.grammar, genome, self.limits)).map(Some).or_raise()
    }

    /// The best genome so far as JSON text.
    #[getter]
    fn best_genome_json(&self) -> Option<String> {
        let b = self.inner.optimizer().best()?;
        Some(b.genome.to_json(self.grammar.generator.as_ref()?.generator.graph()))
    }

    /// One dict per completed generation.
    #[getter]
    fn stats(&self, py: Python<'_>) -> Vec<Py<PyDict>> {
        self.stats.iter().map(|d| d.clone_ref(py)).collect()
    }
}

impl Optimizer {
    fn record(&mut self, py: Python<'_>, s: &genform_evolve::GenerationStats) -> PyResult<Py<PyDict>> {
        let best = self.inner.optimizer().best().map(|b| b.fitness);
        let row = crate::stats::row(py, s, best, None)?.unbind();
        self.stats.push(row.clone_ref(py));
        Ok(row)
    }
}

/// A score: a number, or (fitness, descriptor 0, descriptor 1).
fn score_arg(s: &Bound<'_, PyAny>) -> PyResult<Score> {
    if let Ok(f) = s.extract::<f64>() {
        return Ok((f, [f64::NAN; 2]));
    }
    if let Ok(t) = s.cast::<PyTuple>()
        && let Ok((f, a, b)) = t.extract::<(f64, f64, f64)>()
    {
        return Ok((f, [a, b]));
    }
    Err(error(format!("a score is a number or (fitness, descriptor, descriptor), not {s}")))
}
