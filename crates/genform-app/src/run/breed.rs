//! Optimizers driven from outside by ask/tell: for a fitness computed by
//! the door's user ([`ask_tell`]: Python callables, Ray workers) and for
//! breeding by eye ([`BreedSession`]: the studio's favourites as the
//! fitness).
//!
//! A breeding session shows a generation; the favourites score 1, the
//! others 0, optionally mixed with the scene's fitness (rescaled to 0..1
//! over the individuals shown) as `(1 − mix)·favourite + mix·scene`. Tree
//! grammars and tree scenes breed with the GA, codon scenes (Genr8
//! surfaces, GE L-systems, codon-driven box-split and graph grammars) with
//! GE; both keep no elites (elitism 0), so every generation shown is new
//! children of the favourites, and the GA never restarts. Same path, seed,
//! size, mix and picks → the same individuals.

use anyhow::{Context, Result, bail};
use genform_core::{Genome, Limits, Scene};
use genform_evolve::ask_tell::{AskTell, Score};
use genform_evolve::{AnyCodonOptimizer, AnyOptimizer, CodonAlgorithm, Codons, Horizon, Objective};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::files::write_atomic;
use crate::formalism::Loaded;
use crate::memory::{Reservation, Size, reserve_sizes};
use crate::objective::{CodonObjective, OpenScene, TreeObjective};
use crate::optimizers::{Kind, Searches, section_sizes};
use crate::scene::Scene as SceneFile;
use crate::scene::patch::{parse_patch, patch_from_json};

/// What an ask/tell optimizer over derivation trees is built from.
pub struct AskTellRequest<'a> {
    /// The grammar its genomes grow over.
    pub generator: &'a Loaded,
    /// Derivation limits.
    pub limits: Limits,
    /// The scene whose settings it starts from (`None`: the defaults).
    pub scene: Option<&'a Path>,
    /// The algorithm's name (a tree algorithm).
    pub algorithm: &'a str,
    /// Seed.
    pub seed: u64,
    /// When the run will stop (the hybrid plans with it).
    pub horizon: Horizon,
    /// Keyword settings: `population=20` sets the algorithm's table,
    /// `mh={…}` any table, as a scene's keys.
    pub settings: serde_json::Map<String, serde_json::Value>,
}

/// An optimizer driven by ask/tell, with its algorithm's name.
pub struct AskTellOptimizer {
    /// The optimizer.
    pub inner: AskTell,
    /// The algorithm's name.
    pub algorithm: &'static str,
    /// Its settings' estimated memory, held in the process's ledger while
    /// it lives.
    memory: Reservation,
}

impl AskTellOptimizer {
    /// The bytes it holds of the memory budget.
    pub fn reserved(&self) -> u64 {
        self.memory.bytes()
    }
}

/// The tree algorithm called `name`.
fn tree_algorithm(name: &str, scene: &Path) -> Result<(genform_evolve::Algorithm, &'static str)> {
    crate::optimizers::check_name(name)?;
    let row = crate::optimizers::find(name, Searches::Trees, scene)
        .map_err(|_| anyhow::anyhow!("ask/tell runs tree algorithms; `{name}` evolves codon genomes"))?;
    match row.kind {
        Kind::Tree(a) => Ok((a, row.section)),
        Kind::Codon(_) => bail!("ask/tell runs tree algorithms; `{name}` evolves codon genomes"),
    }
}

/// An ask/tell optimizer over `request.generator`'s derivation trees, its
/// settings the scene's (or the defaults) with the keyword settings
/// applied as a settings patch, checked as a scene file's are.
pub fn ask_tell(request: AskTellRequest) -> Result<AskTellOptimizer> {
    let (alg, section) = tree_algorithm(request.algorithm, request.scene.unwrap_or(Path::new("(grammar)")))?;
    let patch = parse_patch(&patch_from_json(section, &request.settings)?)?;
    let (settings, sizes) = match request.scene {
        Some(path) => {
            let scene = SceneFile::load(path, &patch)?;
            let mut sizes = crate::optimizers::sizes(Searches::Trees, &scene.optimizers);
            sizes.extend(scene.limit_sizes());
            (scene.tree_settings(), sizes)
        }
        None => {
            let settings = crate::scene::optimizer_settings(None, &patch)?;
            (settings.tree(None), crate::optimizers::sizes(Searches::Trees, &settings))
        }
    };
    let memory = reserve_sizes(&sizes, "ask/tell optimizer")?;
    let graph = request.generator.generator.graph();
    let opt = AnyOptimizer::new(alg, graph, &request.limits, &settings, request.seed, request.horizon)
        .map_err(|e| anyhow::anyhow!("{}: {e}", alg.name()))?;
    Ok(AskTellOptimizer { inner: AskTell::new(opt).map_err(anyhow::Error::msg)?, algorithm: alg.name(), memory })
}

/// What a breeding session starts from.
#[derive(Clone, Debug)]
pub struct BreedRequest {
    /// A grammar with a generator graph, or a scene (`.toml`).
    pub path: PathBuf,
    /// Seed.
    pub seed: u64,
    /// Individuals shown per generation (9..=16).
    pub size: usize,
    /// How much the scene's fitness counts beside the favourites (0..=1).
    pub mix: f64,
}

/// The optimizer and the individuals shown, by genome kind.
enum Pool {
    /// Derivation trees; the scene's objective when its fitness is mixed in.
    Tree { loaded: Arc<Loaded>, limits: Limits, scene: Option<Arc<OpenScene>>, ask: Box<AskTell>, batch: Vec<Genome> },
    /// Codons of a codon scene, scored by the scene.
    Codon { objective: Arc<CodonObjective>, ask: Box<AskTell<Codons, AnyCodonOptimizer>>, batch: Vec<Codons> },
}

/// One breeding session (see the [module](self) docs).
pub struct BreedSession {
    request: BreedRequest,
    pool: Pool,
    /// Picks made so far: the generation shown.
    round: usize,
    /// The scene fitness of the individuals shown (empty without a scene).
    fitness: Vec<Option<f64>>,
    /// Earlier picks: (generation, favourite indices, their genome files).
    history: Vec<(usize, Vec<usize>, Vec<String>)>,
    /// Its estimated memory, held in the process's ledger while it lives.
    memory: Reservation,
}

/// What a breeding session asks memory for: its optimizer at `size`
/// individuals, the scene's scorers where they are built (codon scenes,
/// and tree scenes whose fitness is mixed in) and the scene's `[limits]`.
fn breeding_sizes(scene: Option<&SceneFile>, request: &BreedRequest) -> Vec<Size<'static>> {
    let mut settings = scene.map(|s| s.optimizers.clone()).unwrap_or_default();
    settings.ga.population = request.size;
    settings.ge.population = request.size;
    let Some(scene) = scene else { return section_sizes("ga", &settings) };
    let codons = scene.searches == Searches::Codons;
    let mut sizes = section_sizes(if codons { "ge" } else { "ga" }, &settings);
    if codons || request.mix > 0.0 {
        sizes.extend(scene.scoring.memory());
    }
    sizes.extend(scene.limit_sizes());
    sizes
}

/// What it takes to build one individual's model away from the session.
pub struct ModelJob(Job);

enum Job {
    Tree(Arc<Loaded>, Limits, Genome),
    Codon(Arc<CodonObjective>, Codons),
}

impl ModelJob {
    /// The model, and whether it is a grown surface (previews turn those
    /// +z up).
    pub fn scene(&self) -> Result<(Scene, bool), String> {
        match &self.0 {
            Job::Tree(loaded, limits, genome) => {
                let mut scene = Scene::new();
                loaded.generator.express(genome, limits, &mut scene).map_err(|e| e.to_string())?;
                Ok((scene, false))
            }
            Job::Codon(objective, codons) => {
                let e = objective.express(codons).map_err(|r| r.to_string())?;
                let surface = !e.scene.surfaces.is_empty();
                Ok((e.scene, surface))
            }
        }
    }

    /// A preview picture (PNG) of `width` × `height`; an individual that
    /// builds no model (an invalid codon string) previews as empty.
    pub fn preview_png(&self, width: u32, height: u32) -> Vec<u8> {
        let scene = match self.scene() {
            Ok((scene, true)) => genform_export::preview_y_up(&scene),
            Ok((scene, false)) => scene,
            Err(_) => Scene::new(),
        };
        let options = genform_export::RenderOptions { width, height, ..Default::default() };
        genform_export::render_png(&scene, &options)
    }
}

impl BreedSession {
    /// A session on the grammar or scene of `request`, showing its first
    /// generation.
    pub fn start(request: BreedRequest) -> Result<BreedSession> {
        if !(9..=16).contains(&request.size) {
            bail!("size must be 9..=16, not {}", request.size);
        }
        if !(0.0..=1.0).contains(&request.mix) {
            bail!("mix must be in 0..=1, not {}", request.mix);
        }
        let is_scene = crate::formalism::ends_with_any(&request.path, &[".toml"]);
        let scene = if is_scene { Some(SceneFile::load(&request.path, &[])?) } else { None };
        let memory = reserve_sizes(&breeding_sizes(scene.as_ref(), &request), "breeding session")?;
        let pool = match scene {
            Some(scene) if scene.searches == Searches::Codons => {
                let mut ge = scene.optimizers.ge.clone();
                let open = OpenScene::open(scene, Default::default())?;
                let objective = Arc::new(open.codons()?);
                ge.population = request.size;
                ge.elitism = 0;
                let opt = super::codon::optimizer(CodonAlgorithm::Ge, &ge, request.seed)?;
                let reads = Arc::clone(&objective);
                let ask = AskTell::new(opt)
                    .map_err(anyhow::Error::msg)?
                    .with_expressed(move |c: &Codons| reads.expressed(c, &mut reads.scratch()));
                let keys = Arc::clone(&objective);
                let ask = ask.with_phenotype_key(move |c: &Codons| keys.phenotype_key(c, &mut keys.scratch()));
                Pool::Codon { objective, ask: Box::new(ask), batch: Vec::new() }
            }
            scene => {
                let (loaded, limits, mut settings, scene) = match scene {
                    Some(scene) => {
                        let settings = scene.tree_settings();
                        // The targets are built (voxelized) only when they are mixed in.
                        let (loaded, limits, open) = if request.mix > 0.0 {
                            let open = OpenScene::open(scene, Default::default())?;
                            let (loaded, limits) = open.tree().map(|(l, m)| (l.clone(), m)).context("a tree scene")?;
                            (loaded, limits, Some(Arc::new(open)))
                        } else {
                            match crate::objective::Model::open(&scene, Default::default())? {
                                crate::objective::Model::Tree { loaded, limits } => (loaded, limits, None),
                                crate::objective::Model::Codons(_) => bail!("a tree scene makes trees"),
                            }
                        };
                        (loaded, limits, settings, open)
                    }
                    None => {
                        if request.mix > 0.0 {
                            bail!("mix > 0 mixes in a scene's fitness: breed a scene (.toml)");
                        }
                        let loaded = Arc::new(crate::formalism::load_generator(&request.path)?);
                        let limits = loaded.limits;
                        (loaded, limits, genform_evolve::Settings::default(), None)
                    }
                };
                settings.ga.population = request.size;
                settings.ga.elitism = Some(0);
                settings.ga.restart_after = 0;
                let opt = AnyOptimizer::new(
                    genform_evolve::Algorithm::Ga,
                    loaded.generator.graph(),
                    &limits,
                    &settings,
                    request.seed,
                    Horizon::default(),
                )
                .map_err(|e| anyhow::anyhow!("[ga]: {e}"))?;
                let ask = Box::new(AskTell::new(opt).map_err(anyhow::Error::msg)?);
                Pool::Tree { loaded, limits, scene, ask, batch: Vec::new() }
            }
        };
        let mut session = BreedSession { request, pool, round: 0, fitness: Vec::new(), history: Vec::new(), memory };
        session.next_batch()?;
        Ok(session)
    }

    /// What the session was started with.
    pub fn request(&self) -> &BreedRequest {
        &self.request
    }

    /// The bytes it holds of the memory budget.
    pub fn reserved(&self) -> u64 {
        self.memory.bytes()
    }

    /// Individuals shown.
    pub fn len(&self) -> usize {
        match &self.pool {
            Pool::Tree { batch, .. } => batch.len(),
            Pool::Codon { batch, .. } => batch.len(),
        }
    }

    /// Whether no individual is shown.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The generation shown (picks made so far).
    pub fn round(&self) -> usize {
        self.round
    }

    /// The scene fitness of individual `i` (`None` without a scene, or for
    /// an invalid one).
    pub fn fitness(&self, i: usize) -> Option<f64> {
        self.fitness.get(i).copied().flatten()
    }

    /// Whether a scene's fitness is shown.
    pub fn has_scene_fitness(&self) -> bool {
        !self.fitness.is_empty()
    }

    /// `tree` or `codon`.
    pub fn genomes(&self) -> &'static str {
        if matches!(self.pool, Pool::Tree { .. }) { "tree" } else { "codon" }
    }

    /// Earlier picks: (generation, favourite indices, their genome files).
    pub fn history(&self) -> &[(usize, Vec<usize>, Vec<String>)] {
        &self.history
    }

    /// Asks for the next individuals; their scene fitness where there is one.
    fn next_batch(&mut self) -> Result<()> {
        let finite = |f: f64| Some(f).filter(|f| f.is_finite());
        self.fitness = match &mut self.pool {
            Pool::Tree { loaded, limits, scene, ask, batch } => {
                *batch = ask.ask().map_err(anyhow::Error::msg)?.0.to_vec();
                match scene {
                    None => Vec::new(),
                    Some(open) => {
                        let objective = TreeObjective {
                            generator: loaded.generator.as_ref(),
                            limits: *limits,
                            scorer: open.scorer(),
                            descriptors: open.scene.optimizers.descriptors(),
                        };
                        let mut scratch = objective.scratch();
                        batch.iter().map(|g| finite(objective.evaluate(g, &mut scratch))).collect()
                    }
                }
            }
            Pool::Codon { objective, ask, batch } => {
                *batch = ask.ask().map_err(anyhow::Error::msg)?.0.to_vec();
                let mut scratch = objective.scratch();
                batch.iter().map(|c| finite(objective.evaluate(c, &mut scratch))).collect()
            }
        };
        Ok(())
    }

    /// The scores of the individuals shown: favourites 1, others 0, mixed
    /// with the scene fitness rescaled to 0..1 over them.
    fn scores(&self, favourites: &[usize]) -> Vec<Score> {
        let valid = self.fitness.iter().flatten();
        let lo = valid.clone().fold(f64::INFINITY, |a, b| a.min(*b));
        let hi = valid.fold(f64::NEG_INFINITY, |a, b| a.max(*b));
        let mix = self.request.mix;
        (0..self.len())
            .map(|i| {
                let liked = if favourites.contains(&i) { 1.0 } else { 0.0 };
                let scene = match self.fitness(i) {
                    Some(f) if hi > lo => (f - lo) / (hi - lo),
                    Some(_) => 1.0,
                    None => 0.0,
                };
                ((1.0 - mix) * liked + mix * scene, [f64::NAN; 2])
            })
            .collect()
    }

    /// Breeds the next generation from `favourites` (indices of the
    /// individuals shown; repeats are ignored).
    pub fn pick(&mut self, favourites: &[usize]) -> Result<()> {
        let mut favourites = favourites.to_vec();
        favourites.sort_unstable();
        favourites.dedup();
        if let Some(bad) = favourites.iter().find(|i| **i >= self.len()) {
            bail!("favourite {bad} is not shown: the indices are 0..{}", self.len());
        }
        let scores = self.scores(&favourites);
        match &mut self.pool {
            Pool::Tree { ask, .. } => ask.tell(&scores).map(drop).map_err(anyhow::Error::msg)?,
            Pool::Codon { ask, .. } => ask.tell(&scores).map(drop).map_err(anyhow::Error::msg)?,
        }
        let genomes = favourites.iter().map(|i| self.genome_file(*i)).collect();
        self.history.push((self.round, favourites, genomes));
        self.round += 1;
        self.next_batch()
    }

    /// What building individual `i`'s model takes (built away from the
    /// session, which may be shared).
    pub fn job(&self, i: usize) -> ModelJob {
        ModelJob(match &self.pool {
            Pool::Tree { loaded, limits, batch, .. } => Job::Tree(loaded.clone(), *limits, batch[i].clone()),
            Pool::Codon { objective, batch, .. } => Job::Codon(objective.clone(), batch[i].clone()),
        })
    }

    /// Individual `i` as a file: tree genomes as `genform derive` reads
    /// them (`.json`), codons as a JSON list (`genform score --genome`).
    pub fn genome_file(&self, i: usize) -> String {
        match &self.pool {
            Pool::Tree { loaded, batch, .. } => batch[i].to_json(loaded.generator.graph()),
            Pool::Codon { batch, .. } => serde_json::to_string(&batch[i]).unwrap_or_default(),
        }
    }

    /// Writes the favourites and the individuals shown as genome files
    /// (for `genform derive`) and `favourites.json` (naming the grammar or
    /// scene as `shown`) into `dir`; returns the files written, relative
    /// to it.
    pub fn save(&self, dir: &Path, shown: &str) -> Result<Vec<String>> {
        let mut files = Vec::new();
        let mut write = |rel: String, text: &str| -> Result<()> {
            write_atomic(&dir.join(&rel), text.as_bytes())?;
            files.push(rel);
            Ok(())
        };
        for (g, favs, genomes) in &self.history {
            for (i, genome) in favs.iter().zip(genomes) {
                write(format!("gen-{g}/fav-{i}.json"), genome)?;
            }
        }
        for i in 0..self.len() {
            write(format!("gen-{}/ind-{i}.json", self.round), &self.genome_file(i))?;
        }
        let r = &self.request;
        let summary = serde_json::json!({
            "path": shown, "seed": r.seed, "size": r.size, "mix": r.mix, "generation": self.round,
            "history": self.history.iter().map(|(g, f, _)| serde_json::json!({ "generation": g, "favourites": f })).collect::<Vec<_>>(),
        });
        write("favourites.json".into(), &serde_json::to_string_pretty(&summary).unwrap_or_default())?;
        Ok(files)
    }
}
