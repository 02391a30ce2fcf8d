//! `genform.load_scene` and `Scene`: an evolution scene (grammar, targets,
//! fitness) whose built-in scorers are Python callables.

use anyhow::{Result, bail};
use genform_app::objective::{DescribedObjective, Descriptor, SceneObjective, Scorers};
use genform_app::scene_config::{LoadedScene, SceneConfig};
use genform_app::scene_file::SceneFile;
use genform_core::Limits;
use genform_evolve::Objective;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::errors::{OrRaise, error};
use crate::grammar::{Grammar, GrammarCore, Model, path_arg};

/// A loaded scene, shared by runs and optimizers.
pub struct SceneCore {
    /// The scene file.
    pub path: PathBuf,
    /// Its settings.
    pub config: SceneConfig,
    /// Its grammar (which has a generator graph).
    pub grammar: Arc<GrammarCore>,
    /// Its targets and fitness.
    pub scorers: Scorers,
    /// The grammar's limits overridden by the scene's `[limits]`.
    pub limits: Limits,
}

impl SceneCore {
    /// Loads the scene at `path` with its grammar and targets.
    pub fn open(path: &Path) -> Result<Self> {
        let LoadedScene { path, config } = match SceneFile::load(path, &[])? {
            SceneFile::Tree(scene) => scene,
            SceneFile::Codon(_) => bail!(
                "{} is a codon scene (grammatical evolution): run it with genform.evolve(path); load_scene's \
                 scorers as callables and ask/tell work on tree scenes",
                path.display()
            ),
        };
        let grammar = Arc::new(GrammarCore::open(&config.grammar)?);
        let limits = config.limits.overrides().apply(grammar.generator()?.limits);
        let scorers = genform_app::targets::build(&config)?;
        Ok(SceneCore { path, config, grammar, scorers, limits })
    }

    /// The fitness with the scene's `[map_elites]` descriptors, as `genform evolve` evaluates.
    pub fn objective(&self) -> DescribedObjective<'_> {
        let generator = self.grammar.generator.as_ref().expect("scenes load grammars with a generator");
        DescribedObjective {
            objective: SceneObjective {
                generator: generator.generator.as_ref(),
                limits: self.limits,
                scorers: &self.scorers,
            },
            descriptors: Descriptor::pair(&self.config.map_elites),
        }
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
        let objective = self.core.objective();
        Ok(py.detach(|| objective.evaluate(genome, &mut objective.scratch())))
    }

    fn __call__(&self, py: Python<'_>, model: &Model) -> PyResult<f64> {
        self.fitness(py, model)
    }

    /// The counts behind the fitness (good, bad, overlap, outside, target) and `fitness`.
    fn counts<'py>(&self, py: Python<'py>, model: &Model) -> PyResult<Bound<'py, PyDict>> {
        let genome = genome_of(model)?;
        let objective = self.core.objective();
        let o = &objective.objective;
        let c = py
            .detach(|| o.counts(genome, &mut o.scratch()))
            .map_err(|e| error(format!("cannot build the model: {e}")))?;
        let d = PyDict::new(py);
        for (k, v) in [("good", c.good), ("bad", c.bad), ("overlap", c.overlap), ("outside", c.outside)] {
            d.set_item(k, v)?;
        }
        d.set_item("target", c.target)?;
        d.set_item("fitness", self.core.scorers.fitness.eval(&c, genome.len()))?;
        Ok(d)
    }

    /// Expresses a genome (dict or JSON text) under the scene's limits.
    fn derive(&self, py: Python<'_>, genome: &Bound<'_, PyAny>) -> PyResult<Model> {
        let text = crate::grammar::genome_text(py, genome)?;
        let genome = self.core.grammar.parse_genome(&text).or_raise()?;
        let (grammar, limits) = (&self.core.grammar, self.core.limits);
        py.detach(|| grammar.derive(genome, limits)).or_raise()
    }

    /// (fitness, descriptor 0, descriptor 1) per genome JSON text, evaluated in parallel.
    fn score_genomes(&self, py: Python<'_>, genomes: Vec<String>) -> PyResult<Vec<(f64, f64, f64)>> {
        let parsed =
            genomes.iter().map(|g| self.core.grammar.parse_genome(g)).collect::<Result<Vec<_>>>().or_raise()?;
        let objective = self.core.objective();
        Ok(py.detach(|| {
            parsed
                .par_iter()
                .map_init(
                    || objective.scratch(),
                    |scratch, g| {
                        let mut d = [f64::NAN; 2];
                        let f = objective.evaluate_described(g, scratch, &mut d);
                        (f, d[0], d[1])
                    },
                )
                .collect()
        }))
    }

    fn __repr__(&self) -> String {
        format!("<genform.Scene {}>", self.core.path.display())
    }

    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (String,))> {
        Ok((py.import("genform")?.getattr("_cached_scene")?, (self.path(),)))
    }
}
