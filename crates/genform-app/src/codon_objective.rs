//! The objective of codon scenes: codons → model → fitness.
//!
//! - GE (`.bnf`): the mapper turns codons into phenotype text; a `.gr8`
//!   phenotype is parsed and grown in the scene's environment, an `.ls`
//!   phenotype is compiled, derived and drawn.
//! - Box-split and graph grammars: codons are the derivation's choices
//!   ([`CodonSource`]).
//!
//! The model is then scored: surfaces by Genr8's criteria
//! ([`SurfaceScorer`]), everything else by the scene's volume and image
//! targets ([`Scorers`]). An individual that cannot become a model is
//! *invalid*: it scores `−∞` (genform-evolve's convention) and its
//! [`Invalid`] reason is counted, so a run reports why individuals fail
//! instead of failing itself.
//!
//! Growth and derivation draw what randomness they need (stochastic `.gr8`
//! rules, random formulas in `.ls`) from the stream `genform sample` uses
//! with seed 0, so an evaluation is deterministic and the written
//! `best.gr8` / `best.ls` re-grows into the same model with
//! `genform sample` (seed 0).

use anyhow::{Context, Result, anyhow, bail};
use genform_boxsplit::{BoxGrammar, DeriveOptions};
use genform_core::scene::{Polygon, Shape2dKind};
use genform_core::{CodonSource, Rng, Scene, SourceFile};
use genform_evolve::{Codons, Objective};
use genform_ge::{Bnf, CodonLayout, MapOptions, Mapper};
use genform_graph::GraphGrammar;
use genform_hemls::{Environment, GrowError, Hemls, Settings};
use genform_score::{Counts, SurfaceScore, SurfaceScorer};
use glam::{IVec3, Vec2, Vec3};
use std::fmt;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use crate::codon_scene::{CodonKind, LoadedCodonScene, Phenotype, box_bounds};
use crate::formalism::{SAMPLE_STREAM, compile_file};
use crate::objective::{ScorerScratch, Scorers};

/// Default `[limits] modules` of `.ls` phenotypes.
pub const DEFAULT_MAX_MODULES: usize = 200_000;
/// Default `[limits] primitives` of `.ls` phenotypes.
pub const DEFAULT_MAX_PRIMITIVES: usize = 20_000;
/// Default `[limits] elements` of graph grammars.
pub const DEFAULT_MAX_ELEMENTS: usize = 20_000;
/// Default wraps of box-split and graph codon sources.
pub const DEFAULT_SOURCE_WRAPS: u32 = 2;
/// Default wraps of the GE mapper without Genr8's extensions.
pub const DEFAULT_GE_WRAPS: u32 = 2;

/// Why an individual is invalid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Invalid {
    /// The mapper needed a codon after its last wrap.
    WrapLimit,
    /// The derivation tree passed `[mapper] max_depth` (standard GE).
    DepthLimit,
    /// The genome has no codons.
    EmptyGenome,
    /// Genr8's repair needed too many rules.
    RepairLimit,
    /// The phenotype text does not parse (`.gr8` or `.ls` errors).
    Parse,
    /// Growth or drawing failed (a rule that cannot apply, a non-finite
    /// coordinate).
    Growth,
    /// The model grew past a `[limits]` element limit.
    ElementLimit,
    /// Box-split and graph grammars: the codons ran out (after the wraps).
    Exhausted,
    /// Box-split and graph grammars: the derivation itself failed.
    Derivation,
}

impl Invalid {
    /// Every reason, in report order.
    pub const ALL: [Invalid; 9] = [
        Invalid::WrapLimit,
        Invalid::DepthLimit,
        Invalid::EmptyGenome,
        Invalid::RepairLimit,
        Invalid::Parse,
        Invalid::Growth,
        Invalid::ElementLimit,
        Invalid::Exhausted,
        Invalid::Derivation,
    ];

    /// The name in logs, `stats.csv` and `run.json`, e.g. `wrap_limit`.
    pub fn name(self) -> &'static str {
        match self {
            Invalid::WrapLimit => "wrap_limit",
            Invalid::DepthLimit => "depth_limit",
            Invalid::EmptyGenome => "empty_genome",
            Invalid::RepairLimit => "repair_limit",
            Invalid::Parse => "parse",
            Invalid::Growth => "growth",
            Invalid::ElementLimit => "element_limit",
            Invalid::Exhausted => "exhausted",
            Invalid::Derivation => "derivation",
        }
    }

    fn index(self) -> usize {
        Invalid::ALL.iter().position(|r| *r == self).unwrap_or(0)
    }

    fn of_mapping(f: genform_ge::Failure) -> Invalid {
        match f {
            genform_ge::Failure::WrapLimit => Invalid::WrapLimit,
            genform_ge::Failure::DepthLimit => Invalid::DepthLimit,
            genform_ge::Failure::EmptyGenome => Invalid::EmptyGenome,
            genform_ge::Failure::RepairLimit => Invalid::RepairLimit,
        }
    }
}

/// An invalid individual: the reason and, when asked for, what exactly
/// went wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct Rejection {
    /// Why.
    pub reason: Invalid,
    /// The error in words (empty on the fast evaluation path).
    pub message: String,
}

impl fmt::Display for Rejection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.message.is_empty() {
            f.write_str(self.reason.name())
        } else {
            write!(f, "{}: {}", self.reason.name(), self.message)
        }
    }
}

/// Counts of invalid evaluations by [`Invalid`] reason.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct InvalidCounts(pub [u64; 9]);

impl InvalidCounts {
    /// The count of `reason`.
    pub fn get(&self, reason: Invalid) -> u64 {
        self.0[reason.index()]
    }

    /// All of them.
    pub fn total(&self) -> u64 {
        self.0.iter().sum()
    }

    /// `(name, count)` of the reasons that occurred, in report order.
    pub fn nonzero(&self) -> impl Iterator<Item = (&'static str, u64)> + '_ {
        Invalid::ALL.iter().map(|r| (r.name(), self.get(*r))).filter(|(_, n)| *n > 0)
    }
}

impl std::ops::AddAssign for InvalidCounts {
    fn add_assign(&mut self, o: InvalidCounts) {
        for (a, b) in self.0.iter_mut().zip(o.0) {
            *a += b;
        }
    }
}

impl fmt::Display for InvalidCounts {
    /// `parse 3, element_limit 2`, or `none`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let parts: Vec<String> = self.nonzero().map(|(n, c)| format!("{n} {c}")).collect();
        if parts.is_empty() { f.write_str("none") } else { f.write_str(&parts.join(", ")) }
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

/// A fitness with what it is made of.
#[derive(Clone, Debug, PartialEq)]
pub enum ScoreDetail {
    /// Genr8's criteria.
    Surface(Box<SurfaceScore>),
    /// Volume and image target counts.
    Counts(Counts),
}

/// A scored model, with its parts.
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
    /// The fitness.
    pub fitness: f64,
    /// What it is made of.
    pub detail: ScoreDetail,
    /// Codon reads (re-reads after wrapping included).
    pub codons_read: usize,
    /// Times reading wrapped to the first codon.
    pub wraps: u32,
    /// Tells distinct models apart: the phenotype text (GE) or the codons
    /// read (box-split, graph).
    pub key: String,
}

/// How a model is scored.
pub enum Scoring {
    /// Genr8's six surface criteria.
    Surface(SurfaceScorer),
    /// Volume and image targets.
    Targets(Scorers),
}

/// The language a GE phenotype is grown in.
enum Language {
    Gr8 { settings: Settings, env: Environment },
    Ls { max_modules: usize, max_primitives: usize },
}

/// What turns codons into a model.
enum Decoder {
    Ge { bnf: Bnf, options: MapOptions, language: Language },
    BoxSplit { grammar: BoxGrammar, min: IVec3, max: IVec3, range: u32, wraps: u32 },
    // Boxed: a compiled graph grammar is several times larger than the other variants.
    Graph { grammar: Box<GraphGrammar>, steps: Option<usize>, max_elements: usize, range: u32, wraps: u32 },
}

/// The objective of a codon scene (see the [module](self) docs).
pub struct CodonObjective {
    decoder: Decoder,
    scoring: Scoring,
    invalid: [AtomicU64; 9],
    /// Nanoseconds: mapping, build, scoring; then the evaluation count.
    timing: [AtomicU64; 4],
}

/// Per-thread working memory of [`CodonObjective`].
pub struct CodonScratch {
    mapper: Option<Mapper>,
    scene: Scene,
    scorers: Option<ScorerScratch>,
    /// Graph grammars: the last derived graph, whose allocations the next
    /// derivation reuses.
    graph: Option<genform_graph::Graph>,
}

/// What decoding read and made, beyond the scene.
struct Decoded {
    codons_read: usize,
    wraps: u32,
    /// gr8: the grown system.
    hemls: Option<Hemls>,
}

fn reject(reason: Invalid, detail: bool, message: impl FnOnce() -> String) -> Rejection {
    Rejection { reason, message: if detail { message() } else { String::new() } }
}

impl CodonObjective {
    /// Builds the objective of a loaded codon scene: compiles the grammar,
    /// reads the environment and the targets.
    pub fn new(scene: &LoadedCodonScene) -> Result<CodonObjective> {
        let c = &scene.config;
        let range = c.ge.codon_range;
        let wraps = c.mapper.max_wraps.unwrap_or(DEFAULT_SOURCE_WRAPS);
        let decoder = match scene.kind {
            CodonKind::Ge(phenotype) => {
                let bnf = compile_file(&c.grammar, genform_ge::compile)?;
                let genr8 = c.mapper.genr8.unwrap_or(phenotype == Phenotype::Gr8);
                let mut options = if genr8 {
                    MapOptions::genr8()
                } else {
                    MapOptions { spaced: false, ..MapOptions::standard(DEFAULT_GE_WRAPS, None) }
                };
                if let Some(w) = c.mapper.max_wraps {
                    options.max_wraps = w;
                }
                options.layout = c.mapper.layout.unwrap_or_default();
                if options.layout == CodonLayout::PerChoice {
                    // Both write or cut genomes as one left-to-right reading.
                    if c.ge.init == genform_evolve::Init::Sensible {
                        bail!(
                            "[mapper] layout = \"per-choice\" cannot be combined with [ge] init = \"sensible\"; use init = \"random\" or layout = \"sequential\""
                        );
                    }
                    if c.ge.subtree_mutation > 0.0 {
                        bail!(
                            "[mapper] layout = \"per-choice\" cannot be combined with [ge] subtree_mutation (subtrees are not contiguous codon spans there); set subtree_mutation = 0 or layout = \"sequential\""
                        );
                    }
                }
                if let Some(d) = c.mapper.max_depth {
                    match &mut options.genr8 {
                        Some(g) => g.max_depth = Some(d),
                        None => options.max_tree_depth = Some(d),
                    }
                }
                Mapper::new(&bnf, options.clone())
                    .map_err(|e| anyhow!("[mapper]: {e} (grammar {})", c.grammar.display()))?;
                let language = match phenotype {
                    Phenotype::Gr8 => {
                        let (mut settings, env) = match &c.environment {
                            Some(path) => crate::formalism::hemls::load_environment(path)?,
                            None => (Settings::default(), Environment::default()),
                        };
                        if let Some(s) = c.steps {
                            settings.steps = s;
                        }
                        let l = &c.limits;
                        let lim = &mut settings.limits;
                        lim.max_vertices = l.vertices.unwrap_or(lim.max_vertices);
                        lim.max_edges = l.edges.unwrap_or(lim.max_edges);
                        lim.max_faces = l.faces.unwrap_or(lim.max_faces);
                        Language::Gr8 { settings, env }
                    }
                    Phenotype::Ls => Language::Ls {
                        max_modules: c.limits.modules.unwrap_or(DEFAULT_MAX_MODULES),
                        max_primitives: c.limits.primitives.unwrap_or(DEFAULT_MAX_PRIMITIVES),
                    },
                };
                Decoder::Ge { bnf, options, language }
            }
            CodonKind::BoxSplit => {
                let grammar = compile_file(&c.grammar, genform_boxsplit::compile)?;
                let (min, max) = box_bounds(c.box_corners.context("a box-split scene needs `box`")?);
                Decoder::BoxSplit { grammar, min, max, range, wraps }
            }
            CodonKind::Graph => {
                let grammar = compile_file(&c.grammar, genform_graph::compile)?;
                Decoder::Graph {
                    grammar: Box::new(grammar),
                    steps: c.steps.map(|s| s as usize),
                    max_elements: c.limits.elements.unwrap_or(DEFAULT_MAX_ELEMENTS),
                    range,
                    wraps,
                }
            }
        };
        let scoring = match (&c.surface, scene.kind) {
            (Some(s), CodonKind::Ge(Phenotype::Gr8)) => Scoring::Surface(SurfaceScorer::new(*s)?),
            _ => Scoring::Targets(crate::targets::build(&c.targets_view())?),
        };
        Ok(CodonObjective { decoder, scoring, invalid: Default::default(), timing: Default::default() })
    }

    /// How models are scored.
    pub fn scoring(&self) -> &Scoring {
        &self.scoring
    }

    /// The best fitness a model can reach: Σ weights for surfaces, the
    /// targets' maximum (with the shortest initial genome) otherwise.
    pub fn max_reachable(&self, shortest: usize) -> f64 {
        match &self.scoring {
            Scoring::Surface(s) => s.best(),
            Scoring::Targets(t) => t.fitness.max_reachable(shortest),
        }
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

    /// Resets the time split (between runs of `compare`).
    pub fn reset_counters(&self) {
        for a in self.timing.iter().chain(&self.invalid) {
            a.store(0, Ordering::Relaxed);
        }
    }

    /// Adds the time since `since` to split `i`, unless `untimed` (the
    /// detailed path of [`CodonObjective::express`], which is no evaluation).
    fn add_time(&self, i: usize, since: Instant, untimed: bool) -> Instant {
        let now = Instant::now();
        if !untimed {
            self.timing[i].fetch_add((now - since).as_nanos() as u64, Ordering::Relaxed);
        }
        now
    }

    /// Decodes `codons` into `s.scene` (cleared first). `detail` fills the
    /// rejection's message.
    fn decode(&self, codons: &[u32], s: &mut CodonScratch, detail: bool) -> Result<Decoded, Rejection> {
        s.scene.clear();
        let start = Instant::now();
        match &self.decoder {
            Decoder::Ge { language, .. } => {
                let mapper = s.mapper.as_mut().expect("GE scratch has a mapper");
                let out = mapper.map(codons);
                let mapped = self.add_time(0, start, detail);
                if let Some(f) = out.fail {
                    return Err(reject(Invalid::of_mapping(f), detail, || format!("mapping failed ({f})")));
                }
                let text = mapper.phenotype().unwrap_or_default();
                let (codons_read, wraps) = (out.used_codons, out.wraps);
                let result = match language {
                    Language::Gr8 { settings, env } => grow_gr8(text, settings, env, &mut s.scene, detail),
                    Language::Ls { max_modules, max_primitives } => {
                        draw_ls(text, *max_modules, *max_primitives, &mut s.scene, detail).map(|()| None)
                    }
                };
                self.add_time(1, mapped, detail);
                Ok(Decoded { codons_read, wraps, hemls: result? })
            }
            Decoder::BoxSplit { grammar, min, max, range, wraps } => {
                let mut source = CodonSource::new(codons, *range, *wraps);
                let d = grammar.derive(None, *min, *max, &mut source, &DeriveOptions::default());
                self.add_time(0, start, detail);
                if source.exhausted() {
                    return Err(reject(Invalid::Exhausted, detail, || {
                        format!("the {} codons ran out after {} wraps", codons.len(), source.wraps())
                    }));
                }
                let d = d.map_err(|f| reject(Invalid::Derivation, detail, || f.message.clone()))?;
                s.scene.blocks.push(d.blocks);
                Ok(Decoded { codons_read: source.used(), wraps: source.wraps(), hemls: None })
            }
            Decoder::Graph { grammar, steps, max_elements, range, wraps } => {
                let mut source = CodonSource::new(codons, *range, *wraps);
                let d = grammar.derive_reusing(&mut source, *steps, *max_elements, s.graph.take());
                self.add_time(0, start, detail);
                if source.exhausted() {
                    return Err(reject(Invalid::Exhausted, detail, || {
                        format!("the {} codons ran out after {} wraps", codons.len(), source.wraps())
                    }));
                }
                let d = d.map_err(|e| {
                    let reason = match e {
                        genform_graph::DeriveError::TooManyElements { .. } => Invalid::ElementLimit,
                        _ => Invalid::Derivation,
                    };
                    reject(reason, detail, || e.to_string())
                })?;
                s.scene = d.graph.to_scene();
                s.graph = Some(d.graph);
                drawing_as_polygons(&mut s.scene);
                Ok(Decoded { codons_read: source.used(), wraps: source.wraps(), hemls: None })
            }
        }
    }

    /// Scores the model in `s.scene`.
    fn score(&self, s: &mut CodonScratch, codons: usize, untimed: bool) -> (f64, ScoreDetail) {
        let start = Instant::now();
        let out = match &self.scoring {
            Scoring::Surface(scorer) => {
                let score = scorer.score_scene(&s.scene);
                (score.fitness(), ScoreDetail::Surface(Box::new(score)))
            }
            Scoring::Targets(t) => {
                let scratch = s.scorers.get_or_insert_with(|| t.scratch());
                let c = t.counts(&s.scene, scratch);
                (t.fitness.eval(&c, codons), ScoreDetail::Counts(c))
            }
        };
        self.add_time(2, start, untimed);
        out
    }

    /// The model `codons` make, scored, with its parts; or why it is invalid
    /// (with the error in words).
    pub fn express(&self, codons: &[u32]) -> Result<Expressed, Rejection> {
        let mut s = self.scratch();
        let decoded = self.decode(codons, &mut s, true)?;
        let (fitness, detail) = self.score(&mut s, codons.len(), true);
        let phenotype = s.mapper.as_ref().and_then(|m| m.phenotype()).map(str::to_string);
        let mut scene = std::mem::take(&mut s.scene);
        let grammar_file = match &self.decoder {
            Decoder::Ge { language: Language::Gr8 { env, .. }, .. } => {
                env.guides(&mut scene);
                decoded.hemls.as_ref().map(|h| ("gr8", h.to_string()))
            }
            Decoder::Ge { language: Language::Ls { .. }, .. } => phenotype.clone().map(|p| ("ls", p)),
            _ => None,
        };
        let key = match &phenotype {
            Some(p) => p.clone(),
            None => format!("{:?}", &codons[..decoded.codons_read.min(codons.len())]),
        };
        Ok(Expressed {
            scene,
            phenotype,
            grammar_file,
            fitness,
            detail,
            codons_read: decoded.codons_read,
            wraps: decoded.wraps,
            key,
        })
    }
}

/// The name phenotypes are parsed under: its stem names the surface tag and
/// the L-system, as `genform sample best.gr8` / `best.ls` would.
const PHENOTYPE_STEM: &str = "best";

/// Parses and grows a `.gr8` phenotype into `scene`; counts the vertices
/// outside soft boundaries for the soft-boundary criterion.
fn grow_gr8(
    text: &str,
    settings: &Settings,
    env: &Environment,
    scene: &mut Scene,
    detail: bool,
) -> Result<Option<Hemls>, Rejection> {
    let name = format!("{PHENOTYPE_STEM}.gr8");
    let hemls = genform_hemls::parse_str(&name, text).map_err(|d| {
        reject(Invalid::Parse, detail, || format!("the phenotype does not parse:\n{}", d.render(false)))
    })?;
    let mut rng = Rng::stream(0, &[SAMPLE_STREAM]);
    let growth = genform_hemls::grow(&hemls, settings, env, &mut rng).map_err(|e| {
        let reason = if matches!(e, GrowError::Limit { .. }) { Invalid::ElementLimit } else { Invalid::Growth };
        reject(reason, detail, || e.to_string())
    })?;
    let tag = scene.tag(&hemls.name);
    let mut surface = growth.map.to_surface(tag);
    if env.has_soft_boundaries() {
        surface.outside_soft = growth.map.positions().iter().filter(|p| env.is_outside_soft(**p)).count() as u32;
    }
    scene.surfaces.push(surface);
    Ok(Some(hemls))
}

/// Compiles, derives and draws an `.ls` phenotype into `scene` as
/// `genform sample` does (seed 0).
fn draw_ls(
    text: &str,
    max_modules: usize,
    max_primitives: usize,
    scene: &mut Scene,
    detail: bool,
) -> Result<(), Rejection> {
    let file = SourceFile::new(format!("{PHENOTYPE_STEM}.ls"), text.to_string());
    let (system, _) = genform_lsystem::compile(&file).map_err(|d| {
        reject(Invalid::Parse, detail, || format!("the phenotype does not compile:\n{}", d.render(false)))
    })?;
    let mut rng = Rng::stream(0, &[SAMPLE_STREAM]);
    let steps = system.settings.derivation;
    let max_modules = max_modules.min(system.settings.max_modules);
    let string = system
        .derive_limited(steps, &mut rng, max_modules, |_, _| {})
        .map_err(|e| reject(Invalid::ElementLimit, detail, || e.to_string()))?;
    system.interpret(&string, &mut rng, max_primitives, scene).map_err(|e| {
        let genform_lsystem::TurtleError::TooManyPrimitives { .. } = e;
        reject(Invalid::ElementLimit, detail, || e.to_string())
    })?;
    Ok(())
}

/// Segments of circles drawn as polygons.
const CIRCLE_SEGMENTS: usize = 16;

/// Adds a polygon (z = 0) for every filled 2D shape and stroked line of a
/// graph drawing, so the image and volume scorers, which see polygons but
/// not SVG shapes, see the drawing: rectangles as quads, circles as
/// 16-gons, lines as quads as wide as their stroke. Paths and images are
/// left out.
pub fn drawing_as_polygons(scene: &mut Scene) {
    let at = |p: Vec2| Vec3::new(p.x, p.y, 0.0);
    let mut polygons = Vec::new();
    for shape in &scene.shapes2d {
        let points: Vec<Vec3> = match &shape.kind {
            Shape2dKind::Rect { min, size } => {
                let (a, b) = (*min, *min + *size);
                vec![at(a), at(Vec2::new(b.x, a.y)), at(b), at(Vec2::new(a.x, b.y))]
            }
            Shape2dKind::Circle { center, radius } => (0..CIRCLE_SEGMENTS)
                .map(|i| {
                    let t = std::f32::consts::TAU * i as f32 / CIRCLE_SEGMENTS as f32;
                    at(*center + *radius * Vec2::new(t.cos(), t.sin()))
                })
                .collect(),
            Shape2dKind::Line { from, to } => {
                let width = shape
                    .attributes
                    .iter()
                    .find(|(k, _)| k == "stroke-width")
                    .and_then(|(_, v)| v.parse::<f32>().ok())
                    .unwrap_or(genform_graph::DEFAULT_STROKE_WIDTH as f32);
                let d = *to - *from;
                if d.length_squared() == 0.0 || width.is_nan() || width <= 0.0 {
                    continue;
                }
                let n = Vec2::new(-d.y, d.x).normalize() * (0.5 * width);
                vec![at(*from + n), at(*to + n), at(*to - n), at(*from - n)]
            }
            Shape2dKind::Path { .. } | Shape2dKind::Image { .. } => continue,
        };
        polygons.push(Polygon { points, tag: shape.tag });
    }
    scene.polygons.extend(polygons);
}

impl Objective<Codons> for CodonObjective {
    type Scratch = CodonScratch;

    fn scratch(&self) -> CodonScratch {
        let mapper = match &self.decoder {
            Decoder::Ge { bnf, options, .. } => {
                Some(Mapper::new(bnf, options.clone()).expect("the options were checked when the objective was built"))
            }
            _ => None,
        };
        CodonScratch { mapper, scene: Scene::new(), scorers: None, graph: None }
    }

    fn evaluate(&self, codons: &Codons, s: &mut CodonScratch) -> f64 {
        self.timing[3].fetch_add(1, Ordering::Relaxed);
        match self.decode(codons, s, false) {
            Ok(_) => self.score(s, codons.len(), false).0,
            Err(r) => {
                self.invalid[r.reason.index()].fetch_add(1, Ordering::Relaxed);
                f64::NEG_INFINITY
            }
        }
    }

    /// GE scenes: the codons the mapper reads (mapping only); the other
    /// decoders read codons during derivation, so they do not say.
    fn expressed(&self, codons: &Codons, s: &mut CodonScratch) -> Option<usize> {
        let mapper = s.mapper.as_mut()?;
        let out = mapper.map(codons);
        Some(out.extent.min(codons.len()))
    }

    /// GE scenes: a hash of the phenotype text (mapping only), which with
    /// the scene's fixed environment, steps and limits decides the model;
    /// `None` when mapping fails or for the other decoders.
    fn phenotype_key(&self, codons: &Codons, s: &mut CodonScratch) -> Option<u64> {
        use std::hash::{Hash, Hasher};
        let mapper = s.mapper.as_mut()?;
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
        if let Some(mapper) = s.mapper.as_mut() {
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
        let mapper = s.mapper.as_mut()?;
        mapper.ramped(index, plan.max_depth, plan.codon_range, plan.max_length, rng)
    }
}

/// Reads a codon genome: `best-codons.json` (an object with `codons`) or a
/// bare JSON array of codons.
pub fn read_codons(path: &std::path::Path) -> Result<Codons> {
    let text = crate::source_text::read_text(path, "genome")?;
    let value: serde_json::Value =
        serde_json::from_str(&text).with_context(|| format!("{} is not JSON", path.display()))?;
    let list = match &value {
        serde_json::Value::Array(_) => &value,
        serde_json::Value::Object(o) => o.get("codons").ok_or_else(|| {
            anyhow!("{} has no `codons` list (is it a best-codons.json of a codon scene?)", path.display())
        })?,
        _ => return Err(anyhow!("{}: expected a list of codons or an object with `codons`", path.display())),
    };
    serde_json::from_value(list.clone())
        .with_context(|| format!("{}: `codons` must be a list of non-negative integers below 2³²", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_core::scene::Shape2d;

    #[test]
    fn invalid_counts_add_and_print() {
        let mut a = InvalidCounts::default();
        assert_eq!(a.to_string(), "none");
        a.0[Invalid::Parse.index()] = 3;
        let mut b = InvalidCounts::default();
        b.0[Invalid::WrapLimit.index()] = 2;
        b.0[Invalid::Parse.index()] = 1;
        a += b;
        assert_eq!((a.total(), a.get(Invalid::Parse)), (6, 4));
        assert_eq!(a.to_string(), "wrap_limit 2, parse 4");
        let names: Vec<&str> = Invalid::ALL.iter().map(|r| r.name()).collect();
        assert_eq!(names.len(), 9);
        assert!(names.iter().all(|n| names.iter().filter(|m| *m == n).count() == 1));
    }

    #[test]
    fn invalid_phenotypes_score_minus_infinity_and_are_counted_by_reason() {
        let dir = tempfile::tempdir().unwrap();
        let bnf = "<s> ::= \"Edge0 + Edge0 + Edge0 + Edge0\\nEdge0 -> Edge0\\nAngle 90\\n\" | \"nonsense\\n\"\n";
        std::fs::write(dir.path().join("g.bnf"), bnf).unwrap();
        let scene = "grammar = \"g.bnf\"\nphenotype = \"gr8\"\nsteps = 2\n[mapper]\ngenr8 = false\n\
                     [surface]\nsize = { target = 4.5 }\nsymmetry = { target = 1 }\n";
        std::fs::write(dir.path().join("s.toml"), scene).unwrap();
        let loaded = crate::codon_scene::CodonSceneConfig::load(&dir.path().join("s.toml")).unwrap();
        let objective = CodonObjective::new(&loaded).unwrap();
        let mut scratch = objective.scratch();
        // A unit square grown 2 steps by 1.5: 2.25 + 2.25 across, symmetric.
        assert_eq!(objective.evaluate(&vec![0], &mut scratch), 2.0);
        assert_eq!(objective.evaluate(&vec![1], &mut scratch), f64::NEG_INFINITY);
        assert_eq!(objective.evaluate(&vec![], &mut scratch), f64::NEG_INFINITY);
        let counts = objective.take_invalid();
        assert_eq!((counts.get(Invalid::Parse), counts.get(Invalid::EmptyGenome), counts.total()), (1, 1, 2));
        assert_eq!(objective.take_invalid().total(), 0, "taking resets");
        assert_eq!(objective.eval_split().evaluations, 3);
        let e = objective.express(&[2]).unwrap();
        let (ext, text) = e.grammar_file.unwrap();
        assert_eq!((ext, text.as_str()), ("gr8", "Edge0 + Edge0 + Edge0 + Edge0\nEdge0 -> Edge0\nAngle 90\n"));
        assert_eq!(e.scene.surfaces.len(), 1);
        let r = objective.express(&[3]).unwrap_err();
        assert_eq!(r.reason, Invalid::Parse);
        assert!(r.to_string().starts_with("parse: the phenotype does not parse"), "{r}");
        assert_eq!(objective.eval_split().evaluations, 3, "express is no evaluation");
    }

    #[test]
    fn phenotype_keys_follow_the_rule_set_and_subtrees_nest_inside_the_read_codons() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/genr8_canopy.toml");
        let loaded = crate::codon_scene::CodonSceneConfig::load(&path).unwrap();
        let objective = CodonObjective::new(&loaded).unwrap();
        let mut s = objective.scratch();
        let mut rng = Rng::from_seed(5);
        let mut by_key: std::collections::HashMap<u64, String> = std::collections::HashMap::new();
        let (mut spans, mut with_spans, mut twins) = (Vec::new(), 0, 0);
        for _ in 0..200 {
            let mut codons: Codons = (0..rng.int_inclusive(50, 200)).map(|_| rng.below(1000) as u32).collect();
            let mut first = None;
            for twin in 0..2 {
                if twin == 1 {
                    // The same choices from other codons: every read codon
                    // moved by a multiple of every choice count (≤ 10).
                    let read = objective.expressed(&codons, &mut s).unwrap();
                    codons[..read].iter_mut().for_each(|c| *c = (*c + 2520) % 5040);
                }
                let Some(key) = objective.phenotype_key(&codons, &mut s) else { continue };
                twins += usize::from(twin == 1 && first == Some(key));
                first = Some(key);
                let text = objective.express(&codons).map(|e| e.phenotype.unwrap()).unwrap_or_default();
                let known = by_key.entry(key).or_insert_with(|| text.clone());
                assert_eq!(*known, text, "one key, two rule sets");
            }
            objective.subtrees(&codons, &mut s, &mut spans);
            let read = objective.expressed(&codons, &mut s).unwrap();
            with_spans += usize::from(!spans.is_empty());
            for (i, a) in spans.iter().enumerate() {
                assert!(a.start < a.end && a.end <= read, "{a:?} outside the {read} read codons");
                for b in &spans[i + 1..] {
                    assert!(b.start > a.start && (b.end <= a.end || b.start >= a.end), "{a:?} {b:?} overlap");
                }
            }
        }
        // Codons shifted by 2520 keep every choice up to 10 alternatives
        // (most of them), so most twins share their original's key.
        assert!(twins > 100 && by_key.len() > 100, "{twins} twins, {} keys", by_key.len());
        // Measured 145: the rest wrapped (positions repeat, no subtrees).
        assert!(with_spans > 100, "{with_spans} of 200 genomes with subtrees");
    }

    #[test]
    fn per_choice_codons_past_the_read_prefix_never_change_the_rule_set() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/genr8_canopy.toml");
        let mut loaded = crate::codon_scene::CodonSceneConfig::load(&path).unwrap();
        loaded.config.mapper.layout = Some(CodonLayout::PerChoice);
        let objective = CodonObjective::new(&loaded).unwrap();
        let mut s = objective.scratch();
        let mut rng = Rng::from_seed(9);
        let (mut valid, mut short) = (0, 0);
        for _ in 0..200 {
            let mut codons: Codons = (0..rng.int_inclusive(50, 400)).map(|_| rng.below(1000) as u32).collect();
            let read = objective.expressed(&codons, &mut s).unwrap();
            let Some(key) = objective.phenotype_key(&codons, &mut s) else { continue };
            valid += 1;
            if read < codons.len() {
                short += 1;
                codons[read..].iter_mut().for_each(|c| *c = (*c + 1) % 1000);
                assert_eq!(objective.phenotype_key(&codons, &mut s), Some(key), "a codon past {read} was read");
            }
        }
        assert!(valid > 100 && short > 50, "{valid} valid, {short} read a proper prefix");
        // What writes or cuts one left-to-right reading is refused.
        loaded.config.ge.init = genform_evolve::Init::Sensible;
        let e = CodonObjective::new(&loaded).err().unwrap().to_string();
        assert!(e.contains("per-choice") && e.contains("sensible"), "{e}");
        loaded.config.ge.init = genform_evolve::Init::Random;
        loaded.config.ge.subtree_mutation = 0.5;
        let e = CodonObjective::new(&loaded).err().unwrap().to_string();
        assert!(e.contains("subtree_mutation"), "{e}");
    }

    #[test]
    fn drawings_become_polygons_the_scorers_see() {
        let mut scene = Scene::new();
        let shape = |kind, attributes: Vec<(String, String)>| Shape2d { kind, attributes: attributes.into(), tag: 0 };
        scene.shapes2d.push(shape(Shape2dKind::Rect { min: Vec2::ZERO, size: Vec2::new(2.0, 1.0) }, vec![]));
        scene.shapes2d.push(shape(Shape2dKind::Circle { center: Vec2::ONE, radius: 0.5 }, vec![]));
        let wide = vec![("stroke-width".to_string(), "0.4".to_string())];
        scene.shapes2d.push(shape(Shape2dKind::Line { from: Vec2::ZERO, to: Vec2::new(0.0, 3.0) }, wide));
        scene.shapes2d.push(shape(Shape2dKind::Path { d: "M 0 0".into() }, vec![]));
        drawing_as_polygons(&mut scene);
        assert_eq!(scene.polygons.len(), 3);
        assert_eq!(scene.polygons[0].points[2], Vec3::new(2.0, 1.0, 0.0));
        assert_eq!(scene.polygons[1].points.len(), CIRCLE_SEGMENTS);
        let line = &scene.polygons[2].points;
        assert!((line[0].x - -0.2).abs() < 1e-6 && (line[3].x - 0.2).abs() < 1e-6, "{line:?}");
    }

    #[test]
    fn codons_are_read_from_an_object_or_a_list() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("c.json");
        std::fs::write(&p, r#"{"fitness": 1.5, "codons": [3, 999, 0]}"#).unwrap();
        assert_eq!(read_codons(&p).unwrap(), vec![3, 999, 0]);
        std::fs::write(&p, "[7, 8]").unwrap();
        assert_eq!(read_codons(&p).unwrap(), vec![7, 8]);
        std::fs::write(&p, r#"{"genome": []}"#).unwrap();
        assert!(read_codons(&p).unwrap_err().to_string().contains("no `codons`"));
        std::fs::write(&p, "[-1]").unwrap();
        assert!(format!("{:#}", read_codons(&p).unwrap_err()).contains("non-negative"));
    }
}
