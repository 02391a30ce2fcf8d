//! A scene opened for evolution ([`OpenScene`]: its grammar compiled, its
//! scorers built) and the objectives optimizers maximize: a genome
//! expressed into a Scene — a derivation tree by the grammar's generator
//! ([`TreeObjective`]), codons by the formalism row's decoder
//! ([`CodonObjective`]) — scored by the scene's scorer.
//!
//! This glue is the only place that knows both a model maker and the
//! scorers; optimizers see an [`Objective`] and genomes, scorers see
//! Scenes.

use anyhow::Result;
use genform_core::{ExpressError, Generator, Genome, Limits, Scene};
use genform_evolve::{Codons, Objective};
use genform_score::{Descriptor, Score, Scorer, Scratch};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use crate::formalism::{CodonDecoder, DecodeScratch, InvalidCounts, LimitOverrides, Loaded, Phase, Rejection};
use crate::optimizers::Searches;
use crate::scene::Scene as SceneFile;
use crate::scoring::BuiltScoring;

/// What turns a scene's genomes into models.
pub(crate) enum Model {
    /// The grammar's generator, with the scene's limits.
    Tree {
        /// The compiled grammar.
        loaded: Arc<Loaded>,
        /// Its limits with the scene's `[limits]` and the door's overrides.
        limits: Limits,
    },
    /// The formalism row's decoder.
    Codons(Arc<dyn CodonDecoder>),
}

/// A scene ready to evolve: the file, its grammar compiled into a model
/// maker, its scorers built.
pub struct OpenScene {
    /// The scene file, read.
    pub scene: SceneFile,
    pub(crate) model: Model,
    pub(crate) scoring: BuiltScoring,
}

impl Model {
    /// Compiles the scene's grammar into its model maker; `flags` are the
    /// door's derivation limits over the scene's (derivation trees only).
    pub(crate) fn open(scene: &SceneFile, flags: LimitOverrides) -> Result<Model> {
        Ok(match scene.searches {
            Searches::Trees => {
                let loaded = crate::formalism::load_generator(&scene.grammar)?;
                let limits = flags.or(scene.limits.overrides()).apply(loaded.limits);
                Model::Tree { loaded: Arc::new(loaded), limits }
            }
            Searches::Codons => {
                if flags != LimitOverrides::default() {
                    anyhow::bail!(
                        "--max-genes, --max-depth and --max-primitives limit derivation trees; a codon scene sets its \
                         limits in its [limits] table (vertices, edges, faces, modules, primitives, elements)"
                    );
                }
                let codon_range = scene.optimizers.ge.codon_range;
                Model::Codons(Arc::from(scene.formalism.decoder(
                    &scene.grammar,
                    &scene.model,
                    &scene.limits,
                    codon_range,
                )?))
            }
        })
    }
}

impl OpenScene {
    /// Compiles the scene's grammar and builds its scorers; `flags` are the
    /// door's derivation limits over the scene's (derivation trees only).
    pub fn open(scene: SceneFile, flags: LimitOverrides) -> Result<OpenScene> {
        let model = Model::open(&scene, flags)?;
        let scoring = scene.scoring.build(scene.lengths())?;
        Ok(OpenScene { scene, model, scoring })
    }

    /// A tree scene at `path` opened for a door that scores genomes
    /// itself (Python's `load_scene`); codon scenes are refused with the
    /// way to run them.
    pub fn open_tree(path: &std::path::Path) -> Result<OpenScene> {
        let scene = SceneFile::load(path, &[])?;
        if scene.searches != Searches::Trees {
            anyhow::bail!(
                "{} is a codon scene (grammatical evolution): run it with genform.evolve(path); load_scene's \
                 scorers as callables and ask/tell work on tree scenes",
                path.display()
            );
        }
        OpenScene::open(scene, LimitOverrides::default())
    }

    /// The scorer.
    pub fn scorer(&self) -> &dyn Scorer {
        self.scoring.scorer.as_ref()
    }

    /// A tree scene's grammar as a handle (its generator shared, not
    /// compiled again).
    pub fn grammar(&self) -> Result<crate::grammar::GrammarHandle> {
        let (loaded, _) = self.tree().ok_or_else(|| anyhow::anyhow!("a codon scene has no grammar handle"))?;
        crate::grammar::GrammarHandle::with_generator(&self.scene.grammar, loaded.clone())
    }

    /// A tree scene's derivation limits.
    pub fn limits(&self) -> Option<Limits> {
        self.tree().map(|(_, l)| l)
    }

    /// The objective of a tree scene, as its runs evaluate it.
    pub fn objective(&self) -> Option<TreeObjective<'_>> {
        self.tree_objective(self.scorer())
    }

    /// A tree genome's fitness (`−∞` when it cannot be expressed).
    pub fn fitness(&self, genome: &Genome) -> Result<f64> {
        let o = self.tree_objective(self.scorer()).ok_or_else(|| anyhow::anyhow!("a codon scene scores codons"))?;
        Ok(o.evaluate(genome, &mut o.scratch()))
    }

    /// A tree genome's score with its parts.
    pub fn score(&self, genome: &Genome) -> Result<Score> {
        let o = self.tree_objective(self.scorer()).ok_or_else(|| anyhow::anyhow!("a codon scene scores codons"))?;
        o.score(genome, &mut o.scratch()).map_err(|e| anyhow::anyhow!("cannot build the model: {e}"))
    }

    /// Fitness and the two `[map_elites]` descriptors of each genome,
    /// evaluated in parallel, in order.
    pub fn score_genomes(&self, genomes: &[Genome]) -> Result<Vec<(f64, [f64; 2])>> {
        use rayon::prelude::*;
        let o = self.tree_objective(self.scorer()).ok_or_else(|| anyhow::anyhow!("a codon scene scores codons"))?;
        Ok(genomes
            .par_iter()
            .map_init(
                || o.scratch(),
                |scratch, g| {
                    let mut d = [f64::NAN; 2];
                    let f = o.evaluate_described(g, scratch, &mut d);
                    (f, d)
                },
            )
            .collect())
    }

    /// The best fitness the scene's shortest genome can reach.
    pub fn max_reachable(&self) -> f64 {
        self.scorer().max_reachable(self.scene.optimizers.shortest(self.scene.searches))
    }

    /// The generator and limits of a tree scene.
    pub fn tree(&self) -> Option<(&Arc<Loaded>, Limits)> {
        match &self.model {
            Model::Tree { loaded, limits } => Some((loaded, *limits)),
            Model::Codons(_) => None,
        }
    }

    /// The tree objective of this scene, scored by `scorer`.
    pub(crate) fn tree_objective<'a>(&'a self, scorer: &'a dyn Scorer) -> Option<TreeObjective<'a>> {
        let (loaded, limits) = self.tree()?;
        Some(TreeObjective {
            generator: loaded.generator.as_ref(),
            limits,
            scorer,
            descriptors: self.scene.optimizers.descriptors(),
        })
    }

    /// The codon objective of this scene, scored by `scorer`.
    pub(crate) fn codon_objective(&self, scorer: Box<dyn Scorer>) -> Option<CodonObjective> {
        match &self.model {
            Model::Codons(decoder) => Some(CodonObjective::new(decoder.clone(), scorer)),
            Model::Tree { .. } => None,
        }
    }

    /// A copy of the scene's scorer (to steer, or to count apart).
    pub(crate) fn scorer_copy(&self) -> Result<Box<dyn Scorer>> {
        self.scorer().with_knobs(&[]).map_err(anyhow::Error::msg)
    }

    /// The codon objective of a codon scene, with its own copy of the
    /// scorer (and its own invalid counts and time split).
    pub(crate) fn codons(&self) -> Result<CodonObjective> {
        self.codon_objective(self.scorer_copy()?).ok_or_else(|| anyhow::anyhow!("a tree scene has no codon objective"))
    }
}

/// A generator scored by a scorer, with two descriptors for MAP-Elites:
/// the function tree optimizers maximize.
pub struct TreeObjective<'a> {
    /// Expresses genomes.
    pub generator: &'a dyn Generator,
    /// Derivation limits (a genome that exceeds them is invalid).
    pub limits: Limits,
    /// Scores the expressed Scene.
    pub scorer: &'a dyn Scorer,
    /// The descriptors, in archive-axis order.
    pub descriptors: [Descriptor; 2],
}

/// Per-thread working memory of [`TreeObjective`]: a reusable Scene and
/// the scorer's scratch.
pub struct EvalScratch {
    scene: Scene,
    scorer: Scratch,
}

impl TreeObjective<'_> {
    /// Expresses `genome` into the scratch's scene.
    fn express_into(&self, genome: &Genome, scratch: &mut EvalScratch) -> Result<(), ExpressError> {
        scratch.scene.clear();
        self.generator.express(genome, &self.limits, &mut scratch.scene)
    }

    /// Expresses `genome` and scores it with every part, or says why it
    /// cannot be expressed.
    pub fn score(&self, genome: &Genome, scratch: &mut EvalScratch) -> Result<Score, ExpressError> {
        self.express_into(genome, scratch)?;
        Ok(self.scorer.score(&scratch.scene, genome.len(), &mut scratch.scorer))
    }
}

impl Objective for TreeObjective<'_> {
    type Scratch = EvalScratch;

    fn scratch(&self) -> EvalScratch {
        EvalScratch { scene: Scene::new(), scorer: self.scorer.scratch() }
    }

    fn evaluate(&self, genome: &Genome, scratch: &mut EvalScratch) -> f64 {
        match self.express_into(genome, scratch) {
            Ok(()) => self.scorer.fitness(&scratch.scene, genome.len(), &mut scratch.scorer),
            Err(_) => f64::NEG_INFINITY,
        }
    }

    fn evaluate_described(&self, genome: &Genome, scratch: &mut EvalScratch, descriptors: &mut [f64; 2]) -> f64 {
        match self.express_into(genome, scratch) {
            Ok(()) => {
                *descriptors = self.descriptors.map(|d| d.value(genome.len(), &scratch.scene));
                self.scorer.fitness(&scratch.scene, genome.len(), &mut scratch.scorer)
            }
            Err(_) => {
                *descriptors = [f64::NAN; 2];
                f64::NEG_INFINITY
            }
        }
    }
}

/// Where evaluation time went, summed over evaluations and threads.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EvalSplit {
    /// Evaluations timed.
    pub evaluations: u64,
    /// Seconds mapping codons (GE) or deriving with codon choices (box-split, graph).
    pub mapping: f64,
    /// Seconds parsing and growing (gr8) or compiling, deriving and drawing (ls).
    pub build: f64,
    /// Seconds scoring the model.
    pub scoring: f64,
}

impl std::ops::Add for EvalSplit {
    type Output = EvalSplit;

    fn add(self, b: EvalSplit) -> EvalSplit {
        EvalSplit {
            evaluations: self.evaluations + b.evaluations,
            mapping: self.mapping + b.mapping,
            build: self.build + b.build,
            scoring: self.scoring + b.scoring,
        }
    }
}

/// A scored model of a codon genome, with its parts.
#[derive(Clone, Debug)]
pub struct Expressed {
    /// The model, with the environment's guides (for files and pictures).
    pub scene: Scene,
    /// GE: the mapped phenotype text.
    pub phenotype: Option<String>,
    /// The grammar file to write: `best.gr8` (the grown rewrite system in
    /// canonical form) or `best.ls` (the phenotype); `None` for box-split
    /// and graph grammars. `(extension, text)`.
    pub grammar_file: Option<(&'static str, String)>,
    /// The fitness and what it is made of.
    pub score: Score,
    /// Codon reads (re-reads after wrapping included).
    pub codons_read: usize,
    /// Times reading wrapped to the first codon.
    pub wraps: u32,
}

/// The objective of a codon scene: codons → model (the formalism row's
/// decoder) → fitness. An individual that cannot become a model scores
/// `−∞` and its reason is counted.
pub struct CodonObjective {
    decoder: Arc<dyn CodonDecoder>,
    scorer: Box<dyn Scorer>,
    invalid: [AtomicU64; 9],
    /// Nanoseconds: mapping, build, scoring; then the evaluation count.
    timing: [AtomicU64; 4],
}

/// Per-thread working memory of [`CodonObjective`].
pub struct CodonScratch {
    decoder: DecodeScratch,
    scene: Scene,
    scorer: Option<Scratch>,
}

impl CodonObjective {
    /// `decoder`'s models scored by `scorer`.
    pub(crate) fn new(decoder: Arc<dyn CodonDecoder>, scorer: Box<dyn Scorer>) -> CodonObjective {
        CodonObjective { decoder, scorer, invalid: Default::default(), timing: Default::default() }
    }

    /// The same decoder with another scorer (a steered one); the counters
    /// start again.
    pub(crate) fn with_scorer(&self, scorer: Box<dyn Scorer>) -> CodonObjective {
        CodonObjective::new(self.decoder.clone(), scorer)
    }

    /// The scorer.
    pub fn scorer(&self) -> &dyn Scorer {
        self.scorer.as_ref()
    }

    /// The invalid evaluations counted since the last call, by reason.
    pub fn take_invalid(&self) -> InvalidCounts {
        let mut out = InvalidCounts::default();
        for (o, a) in out.0.iter_mut().zip(&self.invalid) {
            *o = a.swap(0, Ordering::Relaxed);
        }
        out
    }

    /// Where evaluation time went so far.
    pub fn eval_split(&self) -> EvalSplit {
        let s = |i: usize| self.timing[i].load(Ordering::Relaxed) as f64 * 1e-9;
        EvalSplit { evaluations: self.timing[3].load(Ordering::Relaxed), mapping: s(0), build: s(1), scoring: s(2) }
    }

    /// Resets the time split and the invalid counts (between runs of `compare`).
    pub fn reset_counters(&self) {
        for a in self.timing.iter().chain(&self.invalid) {
            a.store(0, Ordering::Relaxed);
        }
    }

    /// Decodes `codons` into `s.scene` (cleared first); `detail` fills the
    /// rejection's message and the grammar file and keeps the time out of
    /// the split (the detailed path is no evaluation).
    fn decode(
        &self,
        codons: &[u32],
        s: &mut CodonScratch,
        detail: bool,
    ) -> Result<crate::formalism::Decoded, Rejection> {
        s.scene.clear();
        let mut last = Instant::now();
        let timing = &self.timing;
        let mut lap = |phase: Phase| {
            let now = Instant::now();
            if !detail {
                let i = if phase == Phase::Mapping { 0 } else { 1 };
                timing[i].fetch_add((now - last).as_nanos() as u64, Ordering::Relaxed);
            }
            last = now;
        };
        self.decoder.decode(codons, &mut s.decoder, &mut s.scene, detail, &mut lap)
    }

    /// Scores the model in `s.scene`.
    fn score(&self, s: &mut CodonScratch, codons: usize, untimed: bool) -> Score {
        let start = Instant::now();
        let scratch = s.scorer.get_or_insert_with(|| self.scorer.scratch());
        let score = self.scorer.score(&s.scene, codons, scratch);
        if !untimed {
            self.timing[2].fetch_add(start.elapsed().as_nanos() as u64, Ordering::Relaxed);
        }
        score
    }

    /// The model `codons` make, scored, with its parts; or why it is invalid
    /// (with the error in words).
    pub fn express(&self, codons: &[u32]) -> Result<Expressed, Rejection> {
        let mut s = self.scratch();
        let decoded = self.decode(codons, &mut s, true)?;
        let score = self.score(&mut s, codons.len(), true);
        let phenotype = self.decoder.phenotype(&s.decoder).map(str::to_string);
        let mut scene = std::mem::take(&mut s.scene);
        self.decoder.dress(&mut scene);
        Ok(Expressed {
            scene,
            phenotype,
            grammar_file: decoded.grammar_file,
            score,
            codons_read: decoded.codons_read,
            wraps: decoded.wraps,
        })
    }
}

impl Objective<Codons> for CodonObjective {
    type Scratch = CodonScratch;

    fn scratch(&self) -> CodonScratch {
        CodonScratch { decoder: self.decoder.scratch(), scene: Scene::new(), scorer: None }
    }

    fn evaluate(&self, codons: &Codons, s: &mut CodonScratch) -> f64 {
        self.timing[3].fetch_add(1, Ordering::Relaxed);
        match self.decode(codons, s, false) {
            Ok(_) => {
                let start = Instant::now();
                let scratch = s.scorer.get_or_insert_with(|| self.scorer.scratch());
                let fitness = self.scorer.fitness(&s.scene, codons.len(), scratch);
                self.timing[2].fetch_add(start.elapsed().as_nanos() as u64, Ordering::Relaxed);
                fitness
            }
            Err(r) => {
                self.invalid[r.reason.index()].fetch_add(1, Ordering::Relaxed);
                f64::NEG_INFINITY
            }
        }
    }

    /// GE scenes: the codons the mapper reads (mapping only); the other
    /// decoders read codons during derivation, so they do not say.
    fn expressed(&self, codons: &Codons, s: &mut CodonScratch) -> Option<usize> {
        let mapper = self.decoder.mapper(&mut s.decoder)?;
        let out = mapper.map(codons);
        Some(out.extent.min(codons.len()))
    }

    /// GE scenes: a hash of the phenotype text (mapping only), which with
    /// the scene's fixed environment, steps and limits decides the model;
    /// `None` when mapping fails or for the other decoders.
    fn phenotype_key(&self, codons: &Codons, s: &mut CodonScratch) -> Option<u64> {
        use std::hash::{Hash, Hasher};
        let mapper = self.decoder.mapper(&mut s.decoder)?;
        mapper.map(codons).fail.is_none().then_some(())?;
        // SipHash with fixed keys: the same hash in every run and thread.
        let mut h = std::collections::hash_map::DefaultHasher::new();
        mapper.phenotype()?.hash(&mut h);
        Some(h.finish())
    }

    /// GE scenes: the subtrees of the mapping's trace
    /// ([`genform_ge::Mapping::subtrees`]).
    fn subtrees(&self, codons: &Codons, s: &mut CodonScratch, out: &mut Vec<genform_evolve::CodonSpan>) {
        out.clear();
        if let Some(mapper) = self.decoder.mapper(&mut s.decoder) {
            let trace = mapper.trace(codons);
            out.extend(trace.subtrees().iter().map(|t| genform_evolve::CodonSpan { start: t.start, end: t.end }));
        }
    }

    /// GE scenes: [`genform_ge::Mapper::ramped`] over the scene's grammar
    /// and mapping options; the other decoders have no grammar to unmap.
    fn sensible_genome(
        &self,
        index: usize,
        plan: genform_evolve::SensiblePlan,
        rng: &mut genform_core::Rng,
        s: &mut CodonScratch,
    ) -> Option<Codons> {
        let mapper = self.decoder.mapper(&mut s.decoder)?;
        mapper.ramped(index, plan.max_depth, plan.codon_range, plan.max_length, rng)
    }
}
