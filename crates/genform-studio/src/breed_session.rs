//! Breeding sessions: the optimizer behind each, the individuals shown,
//! their scene fitness and the picks made so far.

use genform_app::codon_objective::CodonObjective;
use genform_app::objective::{SceneObjective, Scorers};
use genform_core::{Generator, Genome, Limits, Scene};
use genform_evolve::ask_tell::{AskTell, Score};
use genform_evolve::{AnyCodonOptimizer, Codons, Objective};
use serde_json::{Value, json};
use std::collections::HashMap;
use std::sync::{Arc, Mutex, MutexGuard};

use super::api::{ApiError, Table};

/// Every breeding session of this server.
#[derive(Default)]
pub struct Breeds {
    pub(crate) inner: Table<Mutex<Breed>>,
}

impl Breeds {
    pub(crate) fn get(&self, id: &str) -> Result<Arc<Mutex<Breed>>, ApiError> {
        let n = id.strip_prefix('b').and_then(|n| n.parse::<u64>().ok());
        let guard = self.inner.lock().unwrap_or_else(|p| p.into_inner());
        n.and_then(|n| guard.1.get(&n).cloned())
            .ok_or_else(|| ApiError::not_found(format!("no breeding session `{id}`")))
    }
}

pub(crate) fn lock(b: &Mutex<Breed>) -> MutexGuard<'_, Breed> {
    b.lock().unwrap_or_else(|p| p.into_inner())
}

/// The optimizer and the individuals shown, by genome kind.
pub(crate) enum Pool {
    /// Derivation trees of a grammar; `scorers` when a scene's fitness is mixed in.
    Tree {
        generator: Arc<dyn Generator>,
        limits: Limits,
        scorers: Option<Box<Scorers>>,
        ask: Box<AskTell>,
        batch: Vec<Genome>,
    },
    /// Codons of a codon scene, scored by the scene.
    Codon { objective: Arc<CodonObjective>, ask: Box<AskTell<Codons, AnyCodonOptimizer>>, batch: Vec<Codons> },
}

/// What it takes to build one individual's model away from the session's lock.
pub(crate) enum Job {
    Tree(Arc<dyn Generator>, Limits, Genome),
    Codon(Arc<CodonObjective>, Codons),
}

impl Job {
    /// The model, and whether it is a surface (previews turn those +z up).
    pub(crate) fn scene(&self) -> Result<(Scene, bool), String> {
        match self {
            Job::Tree(generator, limits, genome) => {
                let mut scene = Scene::new();
                generator.express(genome, limits, &mut scene).map_err(|e| e.to_string())?;
                Ok((scene, false))
            }
            Job::Codon(objective, codons) => {
                let e = objective.express(codons).map_err(|r| r.to_string())?;
                let surface = !e.scene.surfaces.is_empty();
                Ok((e.scene, surface))
            }
        }
    }
}

impl Pool {
    pub(crate) fn len(&self) -> usize {
        match self {
            Pool::Tree { batch, .. } => batch.len(),
            Pool::Codon { batch, .. } => batch.len(),
        }
    }

    /// Asks for the next individuals; their scene fitness where there is one.
    pub(crate) fn next_batch(&mut self) -> Result<Vec<Option<f64>>, ApiError> {
        let finite = |f: f64| Some(f).filter(|f| f.is_finite());
        match self {
            Pool::Tree { generator, limits, scorers, ask, batch } => {
                *batch = ask.ask().map_err(ApiError::internal)?.0.to_vec();
                let Some(scorers) = scorers else { return Ok(Vec::new()) };
                let objective = SceneObjective { generator: generator.as_ref(), limits: *limits, scorers };
                let mut scratch = objective.scratch();
                Ok(batch.iter().map(|g| finite(objective.evaluate(g, &mut scratch))).collect())
            }
            Pool::Codon { objective, ask, batch } => {
                *batch = ask.ask().map_err(ApiError::internal)?.0.to_vec();
                let mut scratch = objective.scratch();
                Ok(batch.iter().map(|c| finite(objective.evaluate(c, &mut scratch))).collect())
            }
        }
    }

    pub(crate) fn tell(&mut self, scores: &[Score]) -> Result<(), ApiError> {
        match self {
            Pool::Tree { ask, .. } => ask.tell(scores).map(drop).map_err(ApiError::internal),
            Pool::Codon { ask, .. } => ask.tell(scores).map(drop).map_err(ApiError::internal),
        }
    }

    pub(crate) fn job(&self, i: usize) -> Job {
        match self {
            Pool::Tree { generator, limits, batch, .. } => Job::Tree(generator.clone(), *limits, batch[i].clone()),
            Pool::Codon { objective, batch, .. } => Job::Codon(objective.clone(), batch[i].clone()),
        }
    }

    /// Individual `i` as a file: tree genomes as `genform derive` reads
    /// them (`.json`), codons as a JSON list (`genform score --genome`).
    pub(crate) fn genome_file(&self, i: usize) -> String {
        match self {
            Pool::Tree { generator, batch, .. } => batch[i].to_json(generator.graph()),
            Pool::Codon { batch, .. } => serde_json::to_string(&batch[i]).unwrap_or_default(),
        }
    }
}

/// One breeding session.
pub(crate) struct Breed {
    pub(crate) id: String,
    pub(crate) path: String,
    pub(crate) seed: u64,
    pub(crate) size: usize,
    pub(crate) mix: f64,
    pub(crate) pool: Pool,
    /// Picks made so far: the generation shown.
    pub(crate) round: usize,
    /// The scene fitness of the individuals shown (empty without a scene).
    pub(crate) fitness: Vec<Option<f64>>,
    /// Earlier picks: (generation, favourite indices, their genome files).
    pub(crate) history: Vec<(usize, Vec<usize>, Vec<String>)>,
    pub(crate) previews: HashMap<(usize, String), Arc<Vec<u8>>>,
}

impl Breed {
    pub(crate) fn json(&self) -> Value {
        let individuals: Vec<Value> = (0..self.pool.len())
            .map(|i| {
                json!({
                    "index": i,
                    "preview": format!("/api/breed/{}/{}/{i}.png", self.id, self.round),
                    "model": format!("/api/breed/{}/{}/{i}.glb", self.id, self.round),
                    "fitness": self.fitness.get(i).copied().flatten(),
                })
            })
            .collect();
        let history: Vec<Value> =
            self.history.iter().map(|(g, f, _)| json!({ "generation": g, "favourites": f })).collect();
        let kind = if matches!(self.pool, Pool::Tree { .. }) { "tree" } else { "codon" };
        json!({
            "id": self.id, "path": self.path, "seed": self.seed, "generation": self.round, "size": self.size,
            "mix": self.mix, "scene": !self.fitness.is_empty(), "genomes": kind, "individuals": individuals,
            "history": history,
        })
    }

    /// Asks for the next individuals to show.
    pub(crate) fn next_batch(&mut self) -> Result<(), ApiError> {
        self.fitness = self.pool.next_batch()?;
        self.previews.clear();
        Ok(())
    }

    /// The scores of the individuals shown: favourites 1, others 0, mixed
    /// with the scene fitness rescaled to 0..1 over them.
    pub(crate) fn scores(&self, favourites: &[usize]) -> Vec<Score> {
        let valid = self.fitness.iter().flatten();
        let lo = valid.clone().fold(f64::INFINITY, |a, b| a.min(*b));
        let hi = valid.fold(f64::NEG_INFINITY, |a, b| a.max(*b));
        (0..self.pool.len())
            .map(|i| {
                let liked = if favourites.contains(&i) { 1.0 } else { 0.0 };
                let scene = match self.fitness.get(i).copied().flatten() {
                    Some(f) if hi > lo => (f - lo) / (hi - lo),
                    Some(_) => 1.0,
                    None => 0.0,
                };
                ((1.0 - self.mix) * liked + self.mix * scene, [f64::NAN; 2])
            })
            .collect()
    }
}
