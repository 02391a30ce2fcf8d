//! `genform.load_scene` and `Scene`: an evolution scene (grammar, targets,
//! fitness) whose built-in scorers are Python callables.

use anyhow::Result;
use genform_app::OpenScene;
use genform_core::Limits;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::errors::{OrRaise, error};
use crate::grammar::{Grammar, GrammarCore, Model, path_arg};

/// A loaded scene, shared by runs and optimizers: the application
/// library's open scene with its grammar as a handle.
pub struct SceneCore {
    /// The scene file.
    pub path: PathBuf,
    /// The scene, its grammar compiled and its targets built.
    pub open: OpenScene,
    /// Its grammar (which has a generator graph).
    pub grammar: Arc<GrammarCore>,
    /// The grammar's limits overridden by the scene's `[limits]`.
    pub limits: Limits,
}

impl SceneCore {
    /// Loads the tree scene at `path` with its grammar and targets.
    pub fn open(path: &Path) -> Result<Self> {
        let open = OpenScene::open_tree(path)?;
        let grammar = Arc::new(open.grammar()?);
        let limits = open.limits().unwrap_or_default();
        Ok(SceneCore { path: path.to_path_buf(), open, grammar, limits })
    }
}

/// An evolution scene (`genform.load_scene(path)`).
#[pyclass(module = "genform", frozen)]
pub struct Scene {
    /// The scene.
    pub core: Arc<SceneCore>,
}

#[pyfunction]
/// Loads an evolution scene (a TOML scene config) with its grammar and targets.
pub fn load_scene(py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<Scene> {
    let path = path_arg(path)?;
    Ok(Scene { core: Arc::new(py.detach(|| SceneCore::open(&path)).or_raise()?) })
}

/// The genome of `model`, or an error saying it has none.
fn genome_of(model: &Model) -> PyResult<&genform_core::Genome> {
    model.genome.as_ref().ok_or_else(|| error("this model has no genome (its formalism has no generator graph)"))
}

#[pymethods]
impl Scene {
    /// The names of the algorithms that can evolve the scene config at
    /// `path`, tree or codon scene, its default first (`evolve()`'s
    /// `algorithm` values: `ga` … `map-elites`, `random` for tree scenes;
    /// `ge`, `random` for codon scenes).
    #[staticmethod]
    fn algorithms_for(py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<Vec<&'static str>> {
        let path = path_arg(path)?;
        let scene = py.detach(|| genform_app::Scene::load(&path, &[])).or_raise()?;
        let default = scene.algorithm(None).or_raise()?;
        let mut names = scene.algorithms();
        names.sort_by_key(|n| *n != default);
        Ok(names)
    }

    /// The names of the algorithms that can evolve this scene, its default first.
    #[getter]
    fn algorithms(&self, py: Python<'_>) -> PyResult<Vec<&'static str>> {
        Scene::algorithms_for(py, &pyo3::types::PyString::new(py, &self.path()).into_any())
    }

    /// The scene file.
    #[getter]
    fn path(&self) -> String {
        self.core.path.display().to_string()
    }

    /// The scene's grammar.
    #[getter]
    fn grammar(&self) -> Grammar {
        Grammar { core: self.core.grammar.clone() }
    }

    /// The scene's fitness of `model` (its genome expressed under the scene's limits); NaN or -inf: invalid.
    fn fitness(&self, py: Python<'_>, model: &Model) -> PyResult<f64> {
        let genome = genome_of(model)?;
        py.detach(|| self.core.open.fitness(genome)).or_raise()
    }

    fn __call__(&self, py: Python<'_>, model: &Model) -> PyResult<f64> {
        self.fitness(py, model)
    }

    /// The measures behind the fitness (good, bad, overlap, outside, target) and `fitness`.
    fn counts<'py>(&self, py: Python<'py>, model: &Model) -> PyResult<Bound<'py, PyDict>> {
        let genome = genome_of(model)?;
        let s = py.detach(|| self.core.open.score(genome)).or_raise()?;
        let d = PyDict::new(py);
        for (k, v) in &s.measures {
            d.set_item(k, v)?;
        }
        d.set_item("fitness", s.fitness)?;
        Ok(d)
    }

    /// The named parts of the fitness: one dict per component (`name`,
    /// `value`, `weight`, `max`, `measure`, and `target` for criteria).
    fn components<'py>(&self, py: Python<'py>, model: &Model) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let genome = genome_of(model)?;
        let s = py.detach(|| self.core.open.score(genome)).or_raise()?;
        s.components
            .iter()
            .map(|c| {
                let d = PyDict::new(py);
                d.set_item("name", c.name)?;
                d.set_item("value", c.value)?;
                d.set_item("weight", c.weight)?;
                d.set_item("max", c.max)?;
                d.set_item("measure", c.measure)?;
                d.set_item("target", c.target)?;
                Ok(d)
            })
            .collect()
    }

    /// Expresses a genome (dict or JSON text) under the scene's limits.
    fn derive(&self, py: Python<'_>, genome: &Bound<'_, PyAny>) -> PyResult<Model> {
        let text = crate::grammar::genome_text(py, genome)?;
        let genome = self.core.grammar.parse_genome(&text).or_raise()?;
        let (grammar, limits) = (&self.core.grammar, self.core.limits);
        py.detach(|| crate::grammar::derive(grammar, genome, limits)).or_raise()
    }

    /// (fitness, descriptor 0, descriptor 1) per genome JSON text, evaluated in parallel.
    fn score_genomes(&self, py: Python<'_>, genomes: Vec<String>) -> PyResult<Vec<(f64, f64, f64)>> {
        let parsed =
            genomes.iter().map(|g| self.core.grammar.parse_genome(g)).collect::<Result<Vec<_>>>().or_raise()?;
        let scored = py.detach(|| self.core.open.score_genomes(&parsed)).or_raise()?;
        Ok(scored.into_iter().map(|(f, [a, b])| (f, a, b)).collect())
    }

    fn __repr__(&self) -> String {
        format!("<genform.Scene {}>", self.core.path.display())
    }

    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (String,))> {
        Ok((py.import("genform")?.getattr("_cached_scene")?, (self.path(),)))
    }
}
