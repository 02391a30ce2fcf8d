//! Runs of scenes whose genomes are codons (a `.bnf`, `.bsg` or `.gg.yaml`
//! grammar): GE or codon random search, with the same stop rules,
//! checkpoints, Ctrl-C handling and atomic writes as tree scenes.

use anyhow::{Context, Result};
use genform_core::Scene;
use genform_evolve::{AnyCodonOptimizer, CodonAlgorithm, Codons, GeConfig, GenerationStats, Individual, Optimizer};
use genform_export::RenderOptions;
use genform_score::Scorer;
use std::path::Path;

use super::compare::{CompareOutcome, CompareRequest, Contest, race};
use super::control::{Control, EvolveRequest, RunOutcome, ScoreRequest};
use super::session::{ByRef, Common, Ended, Session, drive, stop_at, worker_pool, write_models};
use super::steering::{SteerSet, Steerable};
use crate::files::write_atomic;
use crate::formalism::{Invalid, InvalidCounts, read_codons};
use crate::objective::{CodonObjective, EvalSplit, Expressed, OpenScene};
use crate::report::gallery::{distinct_looks, gallery_png};
use crate::report::stats::{Column, CriteriaRow, Row};

/// Individuals shown in `gallery.png`.
const GALLERY: usize = 16;

/// A fresh codon optimizer: `alg` with `config`.
pub(crate) fn optimizer(alg: CodonAlgorithm, config: &GeConfig, seed: u64) -> Result<AnyCodonOptimizer> {
    AnyCodonOptimizer::new(alg, config, seed).map_err(|e| anyhow::anyhow!("[ge]: {e}"))
}

/// The score of a genome against a codon scene: the fitness and every
/// part of it, one line each.
pub(super) fn score(a: &ScoreRequest, open: &OpenScene) -> Result<Vec<String>> {
    let objective = open.codons()?;
    let codons = read_codons(&a.genome)?;
    let e = objective.express(&codons).map_err(|r| {
        anyhow::anyhow!("{} is an invalid individual of {}: {r}", a.genome.display(), a.scene.display())
    })?;
    let scorer = open.scorer();
    let best = open.max_reachable();
    let form = match scorer.chart() {
        Some(_) => format!("{} form, ", scorer.form()),
        None => String::new(),
    };
    let mut lines = vec![format!(
        "fitness {} ({form}max reachable {best}); {} codons, {} read, {} wraps",
        e.score.fitness,
        codons.len(),
        e.codons_read,
        e.wraps
    )];
    if scorer.chart().is_some() {
        for c in &e.score.components {
            lines.push(format!(
                "  {:<13} measure {} target {} weight {} error {} contribution {}",
                c.name,
                c.measure,
                c.target.unwrap_or(f64::NAN),
                c.weight,
                c.error.unwrap_or(f64::NAN),
                c.value
            ));
        }
    } else {
        let measures: Vec<String> = e.score.measures.iter().map(|(n, v)| format!("{n} {v}")).collect();
        lines.push(format!("  {}", measures.join(" ")));
    }
    Ok(lines)
}

/// Runs a codon scene under `control`.
pub(super) fn evolve(
    a: &EvolveRequest,
    open: &OpenScene,
    alg: CodonAlgorithm,
    horizon: genform_evolve::Horizon,
    mut control: Control,
) -> Result<RunOutcome> {
    let scorer = open.scorer_copy()?;
    let steerable = Steerable::of(scorer.as_ref());
    let objective = open.codon_objective(scorer).context("a codon scene")?;
    let opt = optimizer(alg, &open.scene.optimizers.ge, a.seed)?;
    let pool = worker_pool(a.threads)?;
    let cancel = control.cancel.clone();
    let mut ctx = CodonRun {
        common: Common {
            request: a,
            algorithm: alg.name(),
            scene_path: &open.scene.path,
            threads: pool.current_num_threads(),
        },
        open,
        objective,
        steerable,
        split_before: EvalSplit::default(),
    };
    pool.install(|| drive(&mut ctx, opt, stop_at(horizon, &cancel), &mut control))
}

/// One `evolve` run of a codon scene.
struct CodonRun<'a> {
    common: Common<'a>,
    /// The scene as opened (steering changes `objective` and `steerable` only).
    open: &'a OpenScene,
    /// The objective as steered so far (its scorer replaced at each change).
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

    /// `stats.csv`'s own columns: invalid evaluations of each generation
    /// by reason (children equal to a parent are not evaluated again).
    fn columns(&self) -> Vec<Column> {
        Invalid::ALL
            .iter()
            .map(|r| Column {
                name: format!("invalid_{}", r.name()),
                values: self.invalid.iter().map(|c| c.get(*r)).collect(),
            })
            .collect()
    }
}

impl Session<Codons> for CodonRun<'_> {
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

    fn scorer(&self) -> &dyn Scorer {
        self.objective.scorer()
    }

    fn steerable(&self) -> &Steerable {
        &self.steerable
    }

    fn steer(&mut self, set: &SteerSet) -> Result<()> {
        let (scorer, steerable) = self.steerable.apply(self.objective.scorer(), set)?;
        let objective = self.objective.with_scorer(scorer);
        let old = std::mem::replace(&mut self.objective, objective);
        // Invalid counts were taken by the last generation's record; the time split carries over.
        self.split_before = self.split_before + old.eval_split();
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
        self.objective.scorer().max_reachable(self.open.scene.optimizers.ge.initial_length[0])
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
        let best = opt.best().map(|b| ("best-codons.json", self.codons_json(b)));
        self.common.write_progress(out, rows, &rec.columns(), best)
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
        self.common.write_plot(out, rows, &rec.criteria, self.objective.scorer().chart().unwrap_or(""))?;
        let best = opt.best();
        let expressed =
            match best {
                Some(b) => Some(self.objective.express(&b.genome).map_err(|r| {
                    anyhow::anyhow!("the best individual (fitness {}) cannot be rebuilt: {r}", b.fitness)
                })?),
                None => None,
            };
        if let (Some(e), Some(b)) = (&expressed, best)
            && e.score.fitness.to_bits() != b.fitness.to_bits()
        {
            note(&format!("warning: the best individual re-scores {} instead of {}", e.score.fitness, b.fitness));
        }
        if let Some(e) = &expressed {
            if let Some((ext, text)) = &e.grammar_file {
                write_atomic(&out.join(format!("best.{ext}")), text.as_bytes())?;
            }
            write_models(out, &e.scene)?;
            let png = genform_export::render_png(&self.preview(&e.scene), &RenderOptions::default());
            write_atomic(&out.join("best.png"), &png)?;
            crate::report::pictures::write_silhouettes(out, &self.open.scoring.images, &e.scene)?;
        }
        write_atomic(&out.join("gallery.png"), &self.gallery(opt.population()))?;
        let by_reason = |c: &InvalidCounts| {
            serde_json::Value::Object(c.nonzero().map(|(n, v)| (n.to_string(), serde_json::json!(v))).collect())
        };
        let split = self.split_before + self.objective.eval_split();
        let per = |s: f64| if split.evaluations > 0 { s / split.evaluations as f64 * 1e6 } else { 0.0 };
        let EvalSplit { evaluations: timed, mapping, build, scoring } = split;
        let own = serde_json::json!({
            "kind": self.open.scene.kind(),
            "eval_split": {
                "evaluations": timed,
                "mapping_seconds": mapping, "build_seconds": build, "scoring_seconds": scoring,
                "mapping_us_per_eval": per(mapping), "build_us_per_eval": per(build), "scoring_us_per_eval": per(scoring),
            },
            "best_codons_read": expressed.as_ref().map(|e| e.codons_read),
            "best_components": expressed.as_ref().map(|e| components_json(self.objective.scorer(), e)),
            "best_phenotype": expressed.as_ref().and_then(|e| e.phenotype.clone()),
            "invalid": by_reason(&rec.invalid_totals()),
            "invalid_by_generation": rec.invalid.iter().map(by_reason).collect::<Vec<_>>(),
            "config": self.open.scene.to_json(),
        });
        self.common.write_run_json(out, opt, rows, ended, self.max_reachable(), own)
    }

    fn summary_tail(&self, rec: &Record) -> String {
        format!("; invalid evaluations: {}", rec.invalid_totals())
    }
}

/// `run.json`'s `best_components`: charted criteria as a list of their
/// parts, counting targets as their measures.
fn components_json(scorer: &dyn Scorer, e: &Expressed) -> serde_json::Value {
    if scorer.chart().is_some() {
        serde_json::Value::Array(
            e.score
                .components
                .iter()
                .map(|c| {
                    serde_json::json!({
                        "criterion": c.name, "measure": c.measure, "target": c.target,
                        "weight": c.weight, "error": c.error, "contribution": c.value,
                    })
                })
                .collect(),
        )
    } else {
        serde_json::Value::Object(e.score.measures.iter().map(|(n, v)| (n.to_string(), serde_json::json!(v))).collect())
    }
}

impl CodonRun<'_> {
    /// Scorers that chart their criteria: the best individual's criteria
    /// this generation (re-expressed only when the best changed).
    fn record_criteria(&self, rec: &mut Record, generation: usize, best: Option<&Individual<Codons>>) {
        if self.objective.scorer().chart().is_none() {
            return;
        }
        let Some(best) = best else { return };
        if rec.criteria_of.as_ref() != Some(&best.genome) {
            let Ok(e) = self.objective.express(&best.genome) else { return };
            let contributions = e.score.components.iter().map(|c| (c.name, c.value)).collect();
            rec.criteria.push(CriteriaRow { generation, contributions, total: e.score.fitness });
            rec.criteria_of = Some(best.genome.clone());
        } else if let Some(last) = rec.criteria.last().cloned() {
            rec.criteria.push(CriteriaRow { generation, ..last });
        }
    }

    fn codons_json(&self, best: &Individual<Codons>) -> String {
        let scene = self.open.scene.path.display().to_string();
        codons_json(&best.genome, best.fitness, self.common.algorithm, self.common.request.seed, &scene)
    }

    /// The scene as previews show it: grown surfaces with +z up.
    fn preview(&self, scene: &Scene) -> Scene {
        if scene.surfaces.is_empty() { scene.clone() } else { genform_export::preview_y_up(scene) }
    }

    /// The best individuals that look distinct to the scorer
    /// ([`genform_score::Scorer::look`]), at most [`GALLERY`], each framed
    /// on its own model; fewer when the population holds fewer distinct
    /// looks.
    fn gallery(&self, population: &[Individual<Codons>]) -> Vec<u8> {
        let picks = gallery_picks(&self.objective, population, GALLERY);
        let shown: Vec<(Scene, f64)> = picks.iter().map(|(i, s)| (self.preview(s), population[*i].fitness)).collect();
        gallery_png(&shown)
    }
}

/// The individuals a codon run's `gallery.png` shows: going down
/// `population` (best first), each valid individual whose look is new, at
/// most `n`, as its index in `population` and its model. Individuals that
/// cannot be rebuilt are skipped.
fn gallery_picks(objective: &CodonObjective, population: &[Individual<Codons>], n: usize) -> Vec<(usize, Scene)> {
    let looks = population.iter().enumerate().filter(|(_, ind)| ind.is_valid()).filter_map(|(i, ind)| {
        let e = objective.express(&ind.genome).ok()?;
        Some((objective.scorer().look(&e.scene, &e.score), (i, e.scene)))
    });
    distinct_looks(looks, n)
}

/// `best-codons.json`: the genome with what made and scored it.
pub(crate) fn codons_json(codons: &[u32], fitness: f64, algorithm: &str, seed: u64, scene: &str) -> String {
    let value = serde_json::json!({
        "scene": scene,
        "algorithm": algorithm,
        "seed": seed,
        "fitness": fitness,
        "length": codons.len(),
        "codons": codons,
    });
    serde_json::to_string_pretty(&value).unwrap_or_default() + "\n"
}

/// Runs `compare` on a codon scene.
pub(super) fn compare(
    a: &CompareRequest,
    open: &OpenScene,
    algorithms: &[CodonAlgorithm],
    budget: std::time::Duration,
    control: Control,
) -> Result<CompareOutcome> {
    let config = &open.scene.optimizers.ge;
    optimizer(CodonAlgorithm::Ge, config, a.seed)?;
    let objective = open.codons()?;
    let contest = CodonContest { config, objective: &objective, scene: &open.scene.path, seed: a.seed };
    race(a, &open.scene.path, budget, algorithms, &objective, &contest, control)
}

/// Codon scenes in `compare`.
struct CodonContest<'a> {
    config: &'a GeConfig,
    objective: &'a CodonObjective,
    scene: &'a Path,
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
        let opt = optimizer(alg, self.config, seed)?;
        // Each run's log line counts its own invalid evaluations.
        self.objective.reset_counters();
        Ok(opt)
    }

    fn run_tail(&self) -> String {
        format!("; invalid evaluations: {}", self.objective.take_invalid())
    }

    fn save_best(&self, out: &Path, name: &str, best: &Individual<Codons>) -> Result<()> {
        let scene = self.scene.display().to_string();
        let text = codons_json(&best.genome, best.fitness, name, self.seed, &scene);
        write_atomic(&out.join(format!("best-{name}-codons.json")), text.as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_evolve::{Ge, Objective};

    fn open(path: &Path) -> OpenScene {
        let scene = crate::scene::Scene::load(path, &[]).unwrap();
        OpenScene::open(scene, Default::default()).unwrap()
    }

    fn canopy() -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/genr8_canopy.toml")
    }

    #[test]
    fn a_genr8_gallery_never_shows_one_face_count_and_criteria_twice() {
        let open = open(&canopy());
        let objective = open.codons().unwrap();
        let mut ge = Ge::new(open.scene.optimizers.ge.clone(), 3).unwrap();
        for _ in 0..30 {
            Optimizer::step(&mut ge, &objective);
        }
        let population = ge.population();
        // Face counts and criteria to 4 significant digits.
        let described = |i: usize| {
            let e = objective.express(&population[i].genome).unwrap();
            let faces: Vec<usize> = e.scene.surfaces.iter().map(|s| s.face_count()).collect();
            let criteria: Vec<String> = e.score.components.iter().map(|c| format!("{:.3e}", c.measure)).collect();
            (faces, criteria)
        };
        let valid: Vec<usize> = (0..population.len()).filter(|&i| population[i].is_valid()).collect();
        let surfaces: std::collections::HashSet<_> = valid.iter().map(|&i| described(i)).collect();
        // The population holds one surface more than once (copies, and rule
        // sets that differ only where nothing is drawn).
        assert!(surfaces.len() < valid.len(), "{} surfaces in {} members", surfaces.len(), valid.len());
        let picks = gallery_picks(&objective, population, 16);
        assert_eq!(picks.len(), surfaces.len().min(16), "as many cells as distinct surfaces allow");
        let mut shown = std::collections::HashSet::new();
        for (i, _) in &picks {
            assert!(shown.insert(described(*i)), "#{i} shows a surface already shown");
        }
        assert_eq!(picks[0].0, 0, "the best first");
        assert!(picks.windows(2).all(|w| w[0].0 < w[1].0), "then down the ranks");
    }

    #[test]
    fn phenotype_keys_follow_the_rule_set_and_subtrees_nest_inside_the_read_codons() {
        let open = open(&canopy());
        let objective = open.codons().unwrap();
        let mut s = objective.scratch();
        let mut rng = genform_core::Rng::from_seed(5);
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
        let patch = crate::scene::patch::parse_patch(&["mapper.layout=\"per-choice\"".to_string()]).unwrap();
        let scene = crate::scene::Scene::load(&canopy(), &patch).unwrap();
        let open = OpenScene::open(scene, Default::default()).unwrap();
        let objective = open.codons().unwrap();
        let mut s = objective.scratch();
        let mut rng = genform_core::Rng::from_seed(9);
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
        // What writes or cuts one left-to-right reading is refused, at the layout.
        let both = ["mapper.layout=\"per-choice\"".to_string(), "ge.init=\"sensible\"".to_string()];
        let e = crate::scene::Scene::load(&canopy(), &crate::scene::patch::parse_patch(&both).unwrap()).unwrap_err();
        assert!(e.to_string().contains("per-choice") && e.to_string().contains("sensible"), "{e}");
        let both = ["mapper.layout=\"per-choice\"".to_string(), "ge.subtree_mutation=0.5".to_string()];
        let e = crate::scene::Scene::load(&canopy(), &crate::scene::patch::parse_patch(&both).unwrap()).unwrap_err();
        assert!(e.to_string().contains("subtree_mutation"), "{e}");
    }

    #[test]
    fn invalid_phenotypes_score_minus_infinity_and_are_counted_by_reason() {
        let dir = tempfile::tempdir().unwrap();
        let bnf = "<s> ::= \"Edge0 + Edge0 + Edge0 + Edge0\\nEdge0 -> Edge0\\nAngle 90\\n\" | \"nonsense\\n\"\n";
        std::fs::write(dir.path().join("g.bnf"), bnf).unwrap();
        let scene = "grammar = \"g.bnf\"\nphenotype = \"gr8\"\nsteps = 2\n[mapper]\ngenr8 = false\n\
                     [surface]\nsize = { target = 4.5 }\nsymmetry = { target = 1 }\n";
        std::fs::write(dir.path().join("s.toml"), scene).unwrap();
        let open = open(&dir.path().join("s.toml"));
        let objective = open.codons().unwrap();
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
    fn codons_json_round_trips() {
        let text = codons_json(&[1, 2, 999], 0.25, "ge", 4, "s.toml");
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["codons"], serde_json::json!([1, 2, 999]));
        assert_eq!((v["fitness"].as_f64(), v["seed"].as_u64()), (Some(0.25), Some(4)));
    }
}
