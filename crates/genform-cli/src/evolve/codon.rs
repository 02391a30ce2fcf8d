//! `genform evolve`, `score` and `compare` for codon scenes (a `.bnf`,
//! `.bsg` or `.gg.yaml` grammar driven by GE codon genomes): GE or codon
//! random search, with the same stop rules, checkpoints, Ctrl-C handling
//! and atomic writes as tree scenes.

use anyhow::{Context, Result, bail};
use genform_cli::codon_objective::{
    CodonObjective, EvalSplit, Expressed, InvalidCounts, ScoreDetail, Scoring, read_codons,
};
use genform_cli::codon_report::{self, CriteriaRow};
use genform_cli::codon_scene::{CodonKind, CodonSceneConfig, LoadedCodonScene, Phenotype};
use genform_cli::comparison::{self, Trace, TracePoint};
use genform_cli::grammar::LimitOverrides;
use genform_cli::output::write_atomic;
use genform_cli::report::{self, Row};
use genform_cli::scene_config::parse_duration;
use genform_core::Scene;
use genform_evolve::{AnyCodonOptimizer, CodonAlgorithm, Codons, Individual, Optimizer, Stop, StopReason, run};
use genform_export::{Camera, ExportOptions, Format, RenderOptions};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::path::Path;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use super::{CHECKPOINT_EVERY, cancel_on_ctrl_c, worker_pool};
use crate::args::{Algorithm, CompareArgs, EvolveArgs, LimitArgs, ScoreArgs};

/// Individuals shown in `gallery.png`.
const GALLERY: usize = 16;

/// The codon optimizer `alg` names; tree algorithms are refused with the reason.
fn codon_algorithm(alg: Algorithm, scene: &Path) -> Result<CodonAlgorithm> {
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
fn refuse_tree_limits(limits: &LimitArgs) -> Result<()> {
    if limits.overrides() != LimitOverrides::default() {
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

fn title(path: &Path) -> String {
    path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default()
}

/// Runs `genform score` on a codon scene: the genome's fitness and every
/// part of it.
pub fn score(a: ScoreArgs) -> Result<()> {
    refuse_tree_limits(&a.limits)?;
    let scene = CodonSceneConfig::load(&a.scene)?;
    let objective = CodonObjective::new(&scene)?;
    let codons = read_codons(&a.genome)?;
    let e = objective.express(&codons).map_err(|r| {
        anyhow::anyhow!("{} is an invalid individual of {}: {r}", a.genome.display(), a.scene.display())
    })?;
    let best = objective.max_reachable(scene.config.ge.initial_length[0]);
    println!(
        "fitness {} (max reachable {best}); {} codons, {} read, {} wraps",
        e.fitness,
        codons.len(),
        e.codons_read,
        e.wraps
    );
    match &e.detail {
        ScoreDetail::Surface(s) => {
            for c in s.components() {
                println!(
                    "  {:<13} measure {} target {} weight {} error {} contribution {}",
                    c.name(),
                    c.measure,
                    c.target,
                    c.weight,
                    c.error,
                    c.contribution
                );
            }
        }
        ScoreDetail::Counts(c) => {
            println!("  good {} bad {} overlap {} outside {} target {}", c.good, c.bad, c.overlap, c.outside, c.target)
        }
    }
    Ok(())
}

/// Runs `genform evolve` on a codon scene.
pub fn evolve(a: EvolveArgs) -> Result<()> {
    refuse_tree_limits(&a.limits)?;
    let scene = CodonSceneConfig::load(&a.scene)?;
    let algorithm = codon_algorithm(a.algorithm.unwrap_or(Algorithm::Ge), &scene.path)?;
    let config = &scene.config;
    let cli_stops = a.generations.is_some() || a.budget.is_some() || a.evaluations.is_some();
    let (generations, budget, evaluations) = if cli_stops {
        (a.generations, a.budget.clone(), a.evaluations)
    } else {
        (config.run.generations, config.run.budget.clone(), config.run.evaluations)
    };
    let budget = budget.map(|b| parse_duration(&b)).transpose().context("budget")?;
    if generations.is_none() && budget.is_none() && evaluations.is_none() {
        bail!(
            "nothing tells the run when to stop: give --generations, --budget or --evaluations (or [run] in the scene)"
        );
    }
    let objective = CodonObjective::new(&scene)?;
    let opt = AnyCodonOptimizer::new(algorithm, &config.ge, a.seed).map_err(|e| anyhow::anyhow!("[ge]: {e}"))?;
    let pool = worker_pool(a.threads)?;
    let cancel = cancel_on_ctrl_c();
    let ctx = Run {
        args: &a,
        scene: &scene,
        algorithm,
        objective: &objective,
        stop: Stop { generations, budget, evaluations, cancel: &cancel },
        threads: pool.current_num_threads(),
    };
    pool.install(|| ctx.drive(opt))
}

/// One `evolve` run of a codon scene.
struct Run<'a> {
    args: &'a EvolveArgs,
    scene: &'a LoadedCodonScene,
    algorithm: CodonAlgorithm,
    objective: &'a CodonObjective,
    stop: Stop<'a>,
    threads: usize,
}

/// What a run has recorded so far.
#[derive(Default)]
struct Record {
    rows: Vec<Row>,
    invalid: Vec<InvalidCounts>,
    criteria: Vec<CriteriaRow>,
    /// The genome whose criteria the last [`CriteriaRow`] holds.
    criteria_of: Option<Codons>,
}

impl Run<'_> {
    fn progress(&self) -> ProgressBar {
        let bar = match self.stop.generations {
            Some(g) => ProgressBar::new(g as u64),
            None => ProgressBar::new(self.stop.budget.map_or(0, |b| b.as_millis() as u64)),
        };
        if self.args.quiet {
            bar.set_draw_target(ProgressDrawTarget::hidden());
        }
        let template = if self.stop.generations.is_some() {
            "{elapsed_precise} [{bar:30}] gen {pos}/{len} · {msg}"
        } else {
            "{elapsed_precise} [{bar:30}] {msg}"
        };
        bar.set_style(ProgressStyle::with_template(template).expect("valid template").progress_chars("=> "));
        bar
    }

    fn drive(&self, mut opt: AnyCodonOptimizer) -> Result<()> {
        let out = &self.args.out;
        std::fs::create_dir_all(out).with_context(|| format!("cannot create output folder {}", out.display()))?;
        let bar = self.progress();
        let mut rec = Record::default();
        let mut last_checkpoint = Instant::now();
        let mut failed = None;
        let start = Instant::now();
        let summary = run(&mut opt, self.objective, &self.stop, |stats, opt| {
            let secs = start.elapsed().as_secs_f64();
            rec.rows.push((stats.clone(), secs));
            let invalid = self.objective.take_invalid();
            rec.invalid.push(invalid);
            self.record_criteria(&mut rec, stats.generation, opt.best());
            let best = opt.best().map_or(f64::NAN, |b| b.fitness);
            let rate = stats.total_evaluations as f64 / secs.max(1e-9);
            let why = if invalid.total() > 0 { format!(" ({invalid})") } else { String::new() };
            let msg = format!("best {best:.4} · {rate:.0} evals/s · invalid {}{why}", stats.invalid);
            if self.stop.generations.is_some() {
                bar.set_position(stats.generation as u64);
                bar.set_message(msg);
            } else {
                bar.set_position((secs * 1000.0) as u64);
                bar.set_message(format!("gen {} · {msg}", stats.generation));
            }
            if self.args.quiet || !bar.is_hidden() {
                // The bar shows it; a quiet run logs nothing per generation.
            } else if invalid.total() > 0 {
                eprintln!("generation {}: invalid evaluations: {invalid}", stats.generation);
            }
            if failed.is_none() && last_checkpoint.elapsed() >= CHECKPOINT_EVERY {
                if let Err(e) = self.write_progress(opt, &rec) {
                    failed = Some(e);
                    self.stop.cancel.store(true, Ordering::SeqCst);
                }
                last_checkpoint = Instant::now();
            }
        })?;
        if let Some(e) = failed {
            return Err(e);
        }
        bar.finish_and_clear();
        let reason = match summary.reason {
            StopReason::Generations => "generations",
            StopReason::Budget => "budget",
            StopReason::Evaluations => "evaluations",
            StopReason::Cancelled => {
                eprintln!("interrupted: writing the results of generation {}", opt.generation());
                "interrupted"
            }
        };
        self.write_all(&opt, &rec, reason, summary.elapsed)?;
        let mut totals = InvalidCounts::default();
        for c in &rec.invalid {
            totals += *c;
        }
        eprintln!(
            "{}: {} generations, {} evaluations in {:.1} s ({:.0}/s); best fitness {:.6} (max reachable {:.4}); invalid evaluations: {totals} → {}",
            self.scene.path.display(),
            opt.generation(),
            opt.evaluations(),
            summary.elapsed.as_secs_f64(),
            opt.evaluations() as f64 / summary.elapsed.as_secs_f64().max(1e-9),
            opt.best().map_or(f64::NAN, |b| b.fitness),
            self.objective.max_reachable(self.scene.config.ge.initial_length[0]),
            out.display()
        );
        Ok(())
    }

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
        codon_report::codons_json(&best.genome, best.fitness, self.algorithm.name(), self.args.seed, &scene)
    }

    /// Checkpoint: the files that matter if the run dies.
    fn write_progress(&self, opt: &dyn Optimizer<Codons>, rec: &Record) -> Result<()> {
        let out = &self.args.out;
        write_atomic(&out.join("stats.csv"), codon_report::stats_csv(&rec.rows, &rec.invalid).as_bytes())?;
        if let Some(best) = opt.best() {
            write_atomic(&out.join("best-codons.json"), self.codons_json(best).as_bytes())?;
        }
        Ok(())
    }

    /// The scene as previews show it: surfaces with +z up.
    fn preview(&self, scene: &Scene) -> Scene {
        if scene.surfaces.is_empty() { scene.clone() } else { codon_report::z_up(scene) }
    }

    fn write_all(&self, opt: &dyn Optimizer<Codons>, rec: &Record, reason: &str, elapsed: Duration) -> Result<()> {
        let out = &self.args.out;
        self.write_progress(opt, rec)?;
        let name = title(&self.scene.path);
        let svg = codon_report::fitness_svg(&name, &rec.rows, &rec.criteria);
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
            eprintln!("warning: the best individual re-scores {} instead of {}", e.fitness, b.fitness);
        }
        if let Some(e) = &expressed {
            if let Some((ext, text)) = &e.grammar_file {
                write_atomic(&out.join(format!("best.{ext}")), text.as_bytes())?;
            }
            for (file, format) in [("best.glb", Format::Glb), ("best.obj", Format::Obj)] {
                let bytes = genform_export::export(&e.scene, format, &ExportOptions::default())
                    .with_context(|| format!("cannot export {file}"))?;
                write_atomic(&out.join(file), &bytes)?;
            }
            let png = genform_export::render_png(&self.preview(&e.scene), &RenderOptions::default());
            write_atomic(&out.join("best.png"), &png)?;
            if let Scoring::Targets(t) = self.objective.scoring() {
                for (i, img) in t.images.iter().enumerate() {
                    let (rgba, w, h) = img.silhouette(&e.scene);
                    let rgb: Vec<u8> = rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
                    let file = if i == 0 {
                        "best-silhouette.png".to_string()
                    } else {
                        format!("best-silhouette-{}.png", i + 1)
                    };
                    write_atomic(&out.join(file), &genform_export::plot::encode_png_rgb(&rgb, w, h))?;
                }
            }
        }
        write_atomic(&out.join("gallery.png"), &self.gallery(opt.population()))?;
        let mut totals = InvalidCounts::default();
        for c in &rec.invalid {
            totals += *c;
        }
        let by_reason = |c: &InvalidCounts| {
            serde_json::Value::Object(c.nonzero().map(|(n, v)| (n.to_string(), serde_json::json!(v))).collect())
        };
        let split = self.objective.eval_split();
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
        let run = serde_json::json!({
            "genform": env!("CARGO_PKG_VERSION"),
            "scene": self.scene.path.display().to_string(),
            "kind": kind_name(self.scene.kind),
            "algorithm": self.algorithm.name(),
            "seed": self.args.seed,
            "threads": self.threads,
            "stopped_by": reason,
            "generations": opt.generation(),
            "evaluations": opt.evaluations(),
            "seconds": elapsed.as_secs_f64(),
            "evaluations_per_second": opt.evaluations() as f64 / elapsed.as_secs_f64().max(1e-9),
            "eval_seconds": rec.rows.iter().map(|(r, _)| r.eval_time.as_secs_f64()).sum::<f64>(),
            "reproduction_seconds": rec.rows.iter().map(|(r, _)| r.reproduction_time.as_secs_f64()).sum::<f64>(),
            "eval_split": {
                "evaluations": timed,
                "mapping_seconds": mapping, "build_seconds": build, "scoring_seconds": scoring,
                "mapping_us_per_eval": per(mapping), "build_us_per_eval": per(build), "scoring_us_per_eval": per(scoring),
            },
            "best_fitness": best.map(|b| b.fitness),
            "best_length": best.map(|b| b.genome.len()),
            "best_codons_read": expressed.as_ref().map(|e| e.codons_read),
            "best_components": components,
            "best_phenotype": expressed.as_ref().and_then(|e| e.phenotype.clone()),
            "max_reachable_fitness": self.objective.max_reachable(self.scene.config.ge.initial_length[0]),
            "invalid": by_reason(&totals),
            "invalid_by_generation": rec.invalid.iter().map(by_reason).collect::<Vec<_>>(),
            "config": self.scene.config,
        });
        let text = serde_json::to_string_pretty(&run).context("cannot encode run.json")?;
        write_atomic(&out.join("run.json"), text.as_bytes())
    }

    /// The best distinct individuals (distinct models: phenotype text, or
    /// the codons read), rendered with one shared camera.
    fn gallery(&self, population: &[Individual<Codons>]) -> Vec<u8> {
        let mut keys: Vec<String> = Vec::new();
        let mut scenes: Vec<(Scene, f64)> = Vec::new();
        for ind in population.iter().filter(|i| i.is_valid()) {
            if scenes.len() == GALLERY {
                break;
            }
            let Ok(e) = self.objective.express(&ind.genome) else { continue };
            if keys.contains(&e.key) {
                continue;
            }
            keys.push(e.key);
            scenes.push((self.preview(&e.scene), ind.fitness));
        }
        let bounds = scenes.iter().filter_map(|(s, _)| s.bounds(Default::default()));
        let camera = bounds.reduce(|(a, b), (c, d)| (a.min(c), b.max(d))).map(Camera::fit);
        report::gallery_png(&scenes, camera)
    }
}

/// Runs `genform compare` on a codon scene: every codon algorithm `runs`
/// times with the same wall-clock budget.
pub fn compare(a: CompareArgs) -> Result<()> {
    refuse_tree_limits(&a.limits)?;
    let scene = CodonSceneConfig::load(&a.scene)?;
    let budget = parse_duration(&a.budget).context("--budget")?;
    if a.runs == 0 {
        bail!("--runs must be at least 1");
    }
    let given = if a.algorithms.is_empty() { vec![Algorithm::Ge, Algorithm::Random] } else { a.algorithms.clone() };
    let mut algorithms: Vec<CodonAlgorithm> = Vec::new();
    for alg in given {
        let alg = codon_algorithm(alg, &scene.path)?;
        if !algorithms.contains(&alg) {
            algorithms.push(alg);
        }
    }
    let config = &scene.config;
    AnyCodonOptimizer::new(CodonAlgorithm::Ge, &config.ge, a.seed).map_err(|e| anyhow::anyhow!("[ge]: {e}"))?;
    let objective = CodonObjective::new(&scene)?;
    std::fs::create_dir_all(&a.out).with_context(|| format!("cannot create output folder {}", a.out.display()))?;
    let pool = worker_pool(a.threads)?;
    let cancel = cancel_on_ctrl_c();
    let stop = Stop { generations: None, budget: Some(budget), evaluations: None, cancel: &cancel };
    let spacing = budget.as_secs_f64() / 200.0;
    let mut traces: Vec<Trace> = Vec::new();
    'all: for alg in &algorithms {
        let name = alg.name();
        let mut best: Option<Individual<Codons>> = None;
        for r in 0..a.runs {
            let seed = a.seed + r as u64;
            let mut opt = AnyCodonOptimizer::new(*alg, &config.ge, seed).map_err(|e| anyhow::anyhow!("[ge]: {e}"))?;
            objective.reset_counters();
            let mut trace = Trace::new(name, r, seed);
            let start = Instant::now();
            let summary = pool.install(|| {
                run(&mut opt, &objective, &stop, |stats, o| {
                    let point = TracePoint {
                        seconds: start.elapsed().as_secs_f64(),
                        evaluations: stats.total_evaluations,
                        best: o.best().map_or(f64::NAN, |b| b.fitness),
                    };
                    trace.record(point, spacing);
                })
            })?;
            if let Some(b) = opt.best()
                && best.as_ref().is_none_or(|old| b.fitness > old.fitness)
            {
                best = Some(b.clone());
            }
            if !a.quiet {
                eprintln!(
                    "{name} run {}/{}: best {:.6} after {} evaluations in {:.1} s; invalid evaluations: {}",
                    r + 1,
                    a.runs,
                    opt.best().map_or(f64::NAN, |b| b.fitness),
                    opt.evaluations(),
                    summary.elapsed.as_secs_f64(),
                    objective.take_invalid()
                );
            }
            let cancelled = summary.reason == StopReason::Cancelled;
            if !cancelled {
                traces.push(trace);
            }
            write_atomic(&a.out.join("comparison.csv"), comparison::csv(&traces).as_bytes())?;
            if cancelled {
                eprintln!("interrupted: the unfinished run is left out");
                break 'all;
            }
        }
        if let Some(b) = best {
            let text = codon_report::codons_json(&b.genome, b.fitness, name, a.seed, &scene.path.display().to_string());
            write_atomic(&a.out.join(format!("best-{name}-codons.json")), text.as_bytes())?;
        }
    }
    write_atomic(&a.out.join("comparison.csv"), comparison::csv(&traces).as_bytes())?;
    let svg = comparison::svg(&title(&scene.path), &traces, budget.as_secs_f64());
    write_atomic(&a.out.join("comparison.svg"), svg.as_bytes())?;
    print!("{}", comparison::summary(&traces));
    eprintln!(
        "{} runs of {} s each on {} → {}",
        traces.len(),
        budget.as_secs_f64(),
        scene.path.display(),
        a.out.display()
    );
    Ok(())
}
