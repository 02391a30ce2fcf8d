//! `genform evolve`, `score` and `compare` for codon scenes (a `.bnf`,
//! `.bsg` or `.gg.yaml` grammar driven by GE codon genomes): GE or codon
//! random search, with the same stop rules, checkpoints, Ctrl-C handling
//! and atomic writes as tree scenes.

use crate::codon_objective::{CodonObjective, EvalSplit, Expressed, InvalidCounts, ScoreDetail, Scoring, read_codons};
use crate::codon_report::{self, CriteriaRow};
use crate::codon_scene::{CodonKind, LoadedCodonScene, Phenotype};
use crate::grammar::LimitOverrides;
use crate::output::write_atomic;
use crate::report::{self, Row};
use anyhow::{Result, bail};
use genform_core::Scene;
use genform_evolve::{AnyCodonOptimizer, CodonAlgorithm, Codons, GenerationStats, Individual, Optimizer};
use genform_export::RenderOptions;
use std::path::Path;

use super::compare::{CompareOutcome, CompareRequest, Contest, distinct, race, race_budget};
use super::{
    AlgorithmChoice, ByRef, Common, Control, Ended, EvolveRequest, RunOutcome, ScoreRequest, Session, SteerSet,
    Steerable, drive, stop_at, stop_rules, title, worker_pool, write_models,
};

/// Individuals shown in `gallery.png`.
const GALLERY: usize = 16;

/// The codon optimizer `alg` names; tree algorithms are refused with the reason.
fn codon_algorithm(alg: AlgorithmChoice, scene: &Path) -> Result<CodonAlgorithm> {
    alg.codon().ok_or_else(|| {
        anyhow::anyhow!(
            "--algorithm {} searches derivation trees, but {} is a codon scene (its genomes are codon lists); \
             use --algorithm ge or random",
            alg.name(),
            scene.display()
        )
    })
}

/// Refuses the tree scenes' derivation-limit flags.
fn refuse_tree_limits(limits: &LimitOverrides) -> Result<()> {
    if *limits != LimitOverrides::default() {
        bail!(
            "--max-genes, --max-depth and --max-primitives limit derivation trees; a codon scene sets its limits in \
             its [limits] table (vertices, edges, faces, modules, primitives, elements)"
        );
    }
    Ok(())
}

/// A one-word name of the scene's kind, for logs and `run.json`.
fn kind_name(kind: CodonKind) -> &'static str {
    match kind {
        CodonKind::Ge(Phenotype::Gr8) => "ge-gr8",
        CodonKind::Ge(Phenotype::Ls) => "ge-ls",
        CodonKind::BoxSplit => "box-split",
        CodonKind::Graph => "graph",
    }
}

/// The score of a genome against a codon scene: the fitness and every
/// part of it, one line each.
pub(super) fn score(a: &ScoreRequest, mut scene: LoadedCodonScene) -> Result<Vec<String>> {
    refuse_tree_limits(&a.limits)?;
    if a.form.is_some() && scene.config.surface.is_some() {
        bail!("--form chooses how volume and image targets count; {} scores a surface", a.scene.display());
    }
    scene.config.fitness.override_form(a.form.as_deref())?;
    let objective = CodonObjective::new(&scene)?;
    let codons = read_codons(&a.genome)?;
    let e = objective.express(&codons).map_err(|r| {
        anyhow::anyhow!("{} is an invalid individual of {}: {r}", a.genome.display(), a.scene.display())
    })?;
    let best = objective.max_reachable(scene.config.ge.initial_length[0]);
    let form = match objective.scoring() {
        Scoring::Surface(s) => format!("{} form, ", s.objective().form.name()),
        Scoring::Targets(_) => String::new(),
    };
    let mut lines = vec![format!(
        "fitness {} ({form}max reachable {best}); {} codons, {} read, {} wraps",
        e.fitness,
        codons.len(),
        e.codons_read,
        e.wraps
    )];
    match &e.detail {
        ScoreDetail::Surface(s) => {
            for c in s.components() {
                lines.push(format!(
                    "  {:<13} measure {} target {} weight {} error {} contribution {}",
                    c.name(),
                    c.measure,
                    c.target,
                    c.weight,
                    c.error,
                    c.contribution
                ));
            }
        }
        ScoreDetail::Counts(c) => lines.push(format!(
            "  good {} bad {} overlap {} outside {} target {}",
            c.good, c.bad, c.overlap, c.outside, c.target
        )),
    }
    Ok(lines)
}

/// Runs a codon scene under `control`.
pub(super) fn evolve(a: &EvolveRequest, scene: LoadedCodonScene, mut control: Control) -> Result<RunOutcome> {
    refuse_tree_limits(&a.limits)?;
    let algorithm = codon_algorithm(a.algorithm.unwrap_or(AlgorithmChoice::Ge), &scene.path)?;
    let config = &scene.config;
    let horizon = stop_rules(a, &config.run)?;
    let objective = CodonObjective::new(&scene)?;
    let opt = AnyCodonOptimizer::new(algorithm, &config.ge, a.seed).map_err(|e| anyhow::anyhow!("[ge]: {e}"))?;
    let pool = worker_pool(a.threads)?;
    let cancel = control.cancel.clone();
    let mut ctx = Run {
        common: Common {
            request: a,
            algorithm: algorithm.name(),
            scene_path: &scene.path,
            threads: pool.current_num_threads(),
        },
        scene: &scene,
        objective,
        steerable: Steerable::of_codon_scene(config),
        split_before: EvalSplit::default(),
    };
    pool.install(|| drive(&mut ctx, opt, stop_at(horizon, &cancel), &mut control))
}

/// One `evolve` run of a codon scene.
struct Run<'a> {
    common: Common<'a>,
    /// The scene as written (steering changes `objective` and `steerable` only).
    scene: &'a LoadedCodonScene,
    /// The objective as steered so far (rebuilt at each change).
    objective: CodonObjective,
    steerable: Steerable,
    /// The time split of the objectives that steering replaced.
    split_before: EvalSplit,
}

/// What a codon run records per generation beside the statistics rows.
#[derive(Default)]
struct Record {
    invalid: Vec<InvalidCounts>,
    criteria: Vec<CriteriaRow>,
    /// The genome whose criteria the last [`CriteriaRow`] holds.
    criteria_of: Option<Codons>,
}

impl Record {
    /// Invalid evaluations of the whole run, by reason.
    fn invalid_totals(&self) -> InvalidCounts {
        let mut totals = InvalidCounts::default();
        for c in &self.invalid {
            totals += *c;
        }
        totals
    }
}

impl Session<Codons> for Run<'_> {
    type Record = Record;
    type Objective<'s>
        = ByRef<'s, CodonObjective>
    where
        Self: 's;

    fn common(&self) -> &Common<'_> {
        &self.common
    }

    fn objective(&self) -> ByRef<'_, CodonObjective> {
        ByRef(&self.objective)
    }

    fn steerable(&self) -> &Steerable {
        &self.steerable
    }

    fn steer(&mut self, set: &SteerSet) -> Result<()> {
        let mut steerable = self.steerable.clone();
        steerable.apply(set)?;
        let mut scene = self.scene.clone();
        match &steerable {
            Steerable::Surface(s) => scene.config.surface = Some(*s),
            Steerable::Fitness(f) => scene.config.fitness = f.clone(),
        }
        let objective = CodonObjective::new(&scene)?;
        let old = std::mem::replace(&mut self.objective, objective);
        // Invalid counts were taken by the last generation's record; the time split carries over.
        self.split_before = add_split(self.split_before, old.eval_split());
        self.steerable = steerable;
        Ok(())
    }

    fn criteria(&self, rec: &Record) -> Vec<(&'static str, f64)> {
        rec.criteria.last().map(|r| r.contributions.clone()).unwrap_or_default()
    }

    fn gallery(&self, opt: &dyn Optimizer<Codons>) -> Result<Vec<u8>> {
        Ok(self.gallery(opt.population()))
    }

    fn best_scene(&self, opt: &dyn Optimizer<Codons>) -> Result<Option<Scene>> {
        let Some(b) = opt.best() else { return Ok(None) };
        let e = self.objective.express(&b.genome).map_err(|r| anyhow::anyhow!("cannot rebuild the best: {r}"))?;
        Ok(Some(e.scene))
    }

    fn max_reachable(&self) -> f64 {
        self.objective.max_reachable(self.scene.config.ge.initial_length[0])
    }

    fn record(
        &self,
        rec: &mut Record,
        stats: &GenerationStats,
        opt: &dyn Optimizer<Codons>,
    ) -> (String, Option<String>) {
        let invalid = self.objective.take_invalid();
        rec.invalid.push(invalid);
        self.record_criteria(rec, stats.generation, opt.best());
        let log =
            (invalid.total() > 0).then(|| format!("generation {}: invalid evaluations: {invalid}", stats.generation));
        let why = if invalid.total() > 0 { format!(" ({invalid})") } else { String::new() };
        (format!(" · invalid {}{why}", stats.invalid), log)
    }

    fn write_progress(&self, out: &Path, opt: &dyn Optimizer<Codons>, rows: &[Row], rec: &Record) -> Result<()> {
        write_atomic(&out.join("stats.csv"), codon_report::stats_csv(rows, &rec.invalid).as_bytes())?;
        if let Some(best) = opt.best() {
            write_atomic(&out.join("best-codons.json"), self.codons_json(best).as_bytes())?;
        }
        Ok(())
    }

    fn write_all(
        &self,
        out: &Path,
        opt: &dyn Optimizer<Codons>,
        rows: &[Row],
        rec: &Record,
        ended: Ended,
        note: &mut dyn FnMut(&str),
    ) -> Result<()> {
        self.write_progress(out, opt, rows, rec)?;
        let formula = match self.objective.scoring() {
            Scoring::Surface(s) => s.objective().form.contribution_formula(),
            Scoring::Targets(_) => "",
        };
        let svg = codon_report::fitness_svg(&title(&self.scene.path), rows, &rec.criteria, formula);
        write_atomic(&out.join("fitness.svg"), svg.as_bytes())?;
        let best = opt.best();
        let expressed =
            match best {
                Some(b) => Some(self.objective.express(&b.genome).map_err(|r| {
                    anyhow::anyhow!("the best individual (fitness {}) cannot be rebuilt: {r}", b.fitness)
                })?),
                None => None,
            };
        if let (Some(e), Some(b)) = (&expressed, best)
            && e.fitness.to_bits() != b.fitness.to_bits()
        {
            note(&format!("warning: the best individual re-scores {} instead of {}", e.fitness, b.fitness));
        }
        if let Some(e) = &expressed {
            if let Some((ext, text)) = &e.grammar_file {
                write_atomic(&out.join(format!("best.{ext}")), text.as_bytes())?;
            }
            write_models(out, &e.scene)?;
            let png = genform_export::render_png(&self.preview(&e.scene), &RenderOptions::default());
            write_atomic(&out.join("best.png"), &png)?;
            if let Scoring::Targets(t) = self.objective.scoring() {
                crate::pictures::write_silhouettes(out, &t.images, &e.scene)?;
            }
        }
        write_atomic(&out.join("gallery.png"), &self.gallery(opt.population()))?;
        let by_reason = |c: &InvalidCounts| {
            serde_json::Value::Object(c.nonzero().map(|(n, v)| (n.to_string(), serde_json::json!(v))).collect())
        };
        let split = add_split(self.split_before, self.objective.eval_split());
        let per = |s: f64| if split.evaluations > 0 { s / split.evaluations as f64 * 1e6 } else { 0.0 };
        let EvalSplit { evaluations: timed, mapping, build, scoring } = split;
        let components = expressed.as_ref().map(|e| match &e.detail {
            ScoreDetail::Surface(s) => serde_json::Value::Array(
                s.components()
                    .iter()
                    .map(|c| {
                        serde_json::json!({
                            "criterion": c.name(), "measure": c.measure, "target": c.target,
                            "weight": c.weight, "error": c.error, "contribution": c.contribution,
                        })
                    })
                    .collect(),
            ),
            ScoreDetail::Counts(c) => serde_json::json!({
                "good": c.good, "bad": c.bad, "overlap": c.overlap, "outside": c.outside, "target": c.target,
            }),
        });
        let own = serde_json::json!({
            "kind": kind_name(self.scene.kind),
            "eval_split": {
                "evaluations": timed,
                "mapping_seconds": mapping, "build_seconds": build, "scoring_seconds": scoring,
                "mapping_us_per_eval": per(mapping), "build_us_per_eval": per(build), "scoring_us_per_eval": per(scoring),
            },
            "best_codons_read": expressed.as_ref().map(|e| e.codons_read),
            "best_components": components,
            "best_phenotype": expressed.as_ref().and_then(|e| e.phenotype.clone()),
            "invalid": by_reason(&rec.invalid_totals()),
            "invalid_by_generation": rec.invalid.iter().map(by_reason).collect::<Vec<_>>(),
            "config": self.scene.config,
        });
        self.common.write_run_json(out, opt, rows, ended, self.max_reachable(), own)
    }

    fn summary_tail(&self, rec: &Record) -> String {
        format!("; invalid evaluations: {}", rec.invalid_totals())
    }
}

/// The sum of two time splits.
fn add_split(a: EvalSplit, b: EvalSplit) -> EvalSplit {
    EvalSplit {
        evaluations: a.evaluations + b.evaluations,
        mapping: a.mapping + b.mapping,
        build: a.build + b.build,
        scoring: a.scoring + b.scoring,
    }
}

impl Run<'_> {
    /// Surface scenes: the best individual's criteria this generation
    /// (re-expressed only when the best changed).
    fn record_criteria(&self, rec: &mut Record, generation: usize, best: Option<&Individual<Codons>>) {
        if !matches!(self.objective.scoring(), Scoring::Surface(_)) {
            return;
        }
        let Some(best) = best else { return };
        if rec.criteria_of.as_ref() != Some(&best.genome) {
            let Ok(Expressed { detail: ScoreDetail::Surface(s), .. }) = self.objective.express(&best.genome) else {
                return;
            };
            let contributions = s.components().iter().map(|c| (c.name(), c.contribution)).collect();
            rec.criteria.push(CriteriaRow { generation, contributions, total: s.fitness() });
            rec.criteria_of = Some(best.genome.clone());
        } else if let Some(last) = rec.criteria.last().cloned() {
            rec.criteria.push(CriteriaRow { generation, ..last });
        }
    }

    fn codons_json(&self, best: &Individual<Codons>) -> String {
        let scene = self.scene.path.display().to_string();
        codon_report::codons_json(&best.genome, best.fitness, self.common.algorithm, self.common.request.seed, &scene)
    }

    /// The scene as previews show it: surfaces with +z up.
    fn preview(&self, scene: &Scene) -> Scene {
        if scene.surfaces.is_empty() { scene.clone() } else { codon_report::z_up(scene) }
    }

    /// The best individuals that look distinct
    /// ([`codon_report::gallery_picks`]: surfaces by face count and
    /// criteria values, other models by bounds and counts), at most
    /// [`GALLERY`], each framed on its own model; fewer when the population
    /// holds fewer distinct looks.
    fn gallery(&self, population: &[Individual<Codons>]) -> Vec<u8> {
        let picks = codon_report::gallery_picks(&self.objective, population, GALLERY);
        let shown: Vec<(Scene, f64)> = picks.iter().map(|(i, s)| (self.preview(s), population[*i].fitness)).collect();
        report::gallery_png(&shown)
    }
}

/// Runs `compare` on a codon scene: every codon algorithm `runs` times
/// with the same wall-clock budget.
pub(super) fn compare(a: &CompareRequest, scene: LoadedCodonScene, control: Control) -> Result<CompareOutcome> {
    refuse_tree_limits(&a.limits)?;
    let budget = race_budget(a)?;
    let default = [AlgorithmChoice::Ge, AlgorithmChoice::Random];
    let algorithms = distinct(&a.algorithms, &default, |alg| codon_algorithm(alg, &scene.path))?;
    let config = &scene.config;
    AnyCodonOptimizer::new(CodonAlgorithm::Ge, &config.ge, a.seed).map_err(|e| anyhow::anyhow!("[ge]: {e}"))?;
    let objective = CodonObjective::new(&scene)?;
    let contest = CodonContest { scene: &scene, objective: &objective, seed: a.seed };
    race(a, &scene.path, budget, &algorithms, &objective, &contest, control)
}

/// Codon scenes in `compare`.
struct CodonContest<'a> {
    scene: &'a LoadedCodonScene,
    objective: &'a CodonObjective,
    /// The first run's seed, as `best-<algorithm>-codons.json` records it.
    seed: u64,
}

impl Contest<Codons> for CodonContest<'_> {
    type Alg = CodonAlgorithm;
    type Opt = AnyCodonOptimizer;

    fn name(&self, alg: CodonAlgorithm) -> &'static str {
        alg.name()
    }

    fn start(&self, alg: CodonAlgorithm, seed: u64) -> Result<AnyCodonOptimizer> {
        let opt = AnyCodonOptimizer::new(alg, &self.scene.config.ge, seed).map_err(|e| anyhow::anyhow!("[ge]: {e}"))?;
        // Each run's log line counts its own invalid evaluations.
        self.objective.reset_counters();
        Ok(opt)
    }

    fn run_tail(&self) -> String {
        format!("; invalid evaluations: {}", self.objective.take_invalid())
    }

    fn save_best(&self, out: &Path, name: &str, best: &Individual<Codons>) -> Result<()> {
        let scene = self.scene.path.display().to_string();
        let text = codon_report::codons_json(&best.genome, best.fitness, name, self.seed, &scene);
        write_atomic(&out.join(format!("best-{name}-codons.json")), text.as_bytes())
    }
}
