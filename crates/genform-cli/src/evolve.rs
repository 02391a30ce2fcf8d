//! `genform evolve`: run an optimizer on a scene config and write the
//! results (best model, genome, statistics, plots) to a folder.

use anyhow::{Context, Result, bail};
use genform_cli::comparison::{self, Trace, TracePoint};
use genform_cli::grammar::{self, LimitOverrides};
use genform_cli::objective::{SceneObjective, Scorers};
use genform_cli::output::write_atomic;
use genform_cli::report::{self, Row};
use genform_cli::scene_config::{LoadedScene, SceneConfig, parse_duration};
use genform_cli::targets;
use genform_core::{Generator, Genome, Limits, Scene};
use genform_evolve::{AnyOptimizer, Horizon, Individual, Objective, Optimizer, Stop, StopReason, run};
use genform_export::{Camera, ExportOptions, Format, RenderOptions};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::args::{Algorithm, CompareArgs, EvolveArgs, ScoreArgs};

mod codon;

/// How often results are written during a run, so a crash loses little.
const CHECKPOINT_EVERY: Duration = Duration::from_secs(10);

/// The grammar's limits overridden by the scene's `[limits]`, then by flags.
fn scene_limits(config: &SceneConfig, grammar: Limits, flags: LimitOverrides) -> Limits {
    let scene = LimitOverrides {
        max_genes: config.limits.genes,
        max_depth: config.limits.depth,
        max_primitives: config.limits.primitives,
    };
    flags.or(scene).apply(grammar)
}

/// The tree optimizer `alg` names; `ge` is refused with the reason.
fn tree_algorithm(alg: Algorithm, scene: &Path) -> Result<genform_evolve::Algorithm> {
    alg.tree().ok_or_else(|| {
        anyhow::anyhow!(
            "--algorithm ge evolves codon genomes, but {} is a tree scene (its grammar's genomes are derivation \
             trees); use ga, mh, smc, sosmc, hybrid or random, or a scene whose grammar is .bnf, .bsg or .gg.yaml",
            scene.display()
        )
    })
}

/// Runs `genform score`: one genome's counts and fitness against a scene.
pub fn score(a: ScoreArgs) -> Result<()> {
    if genform_cli::codon_scene::is_codon_scene(&a.scene) {
        return codon::score(a);
    }
    let LoadedScene { config, .. } = SceneConfig::load(&a.scene)?;
    let loaded = grammar::load(&config.grammar)?;
    let limits = scene_limits(&config, loaded.limits, a.limits.overrides());
    let scorers = targets::build(&config)?;
    let genome = loaded.read_genome(&a.genome)?;
    let objective = SceneObjective { generator: loaded.generator.as_ref(), limits, scorers: &scorers };
    let c = objective.counts(&genome, &mut objective.scratch()).context("cannot build the model")?;
    println!(
        "fitness {} (max reachable {}); genes {}; good {} bad {} overlap {} outside {} target {}",
        scorers.fitness.eval(&c, genome.len()),
        scorers.fitness.max_reachable(genome.len()),
        genome.len(),
        c.good,
        c.bad,
        c.overlap,
        c.outside,
        c.target
    );
    Ok(())
}

/// Runs `genform evolve`.
pub fn evolve(a: EvolveArgs) -> Result<()> {
    if genform_cli::codon_scene::is_codon_scene(&a.scene) {
        return codon::evolve(a);
    }
    let LoadedScene { path: scene_path, config } = SceneConfig::load(&a.scene)?;
    let algorithm = tree_algorithm(a.algorithm.unwrap_or(Algorithm::Ga), &scene_path)?;
    let loaded = grammar::load(&config.grammar)?;
    let limits = scene_limits(&config, loaded.limits, a.limits.overrides());
    if config.ga.max_length > limits.max_genes + 1 {
        eprintln!(
            "note: [ga] max_length {} is above the gene limit {}; genomes stop at {} genes",
            config.ga.max_length, limits.max_genes, limits.max_genes
        );
    }
    let scorers = targets::build(&config)?;
    // Command-line stop rules replace the scene's [run] as a whole.
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
    let pool = worker_pool(a.threads)?;
    let cancel = cancel_on_ctrl_c();
    let objective = SceneObjective { generator: loaded.generator.as_ref(), limits, scorers: &scorers };
    let ctx = RunContext {
        args: &a,
        algorithm,
        scene_path: &scene_path,
        config: &config,
        generator: loaded.generator.as_ref(),
        limits,
        scorers: &scorers,
        stop: Stop { generations, budget, evaluations, cancel: &cancel },
        threads: pool.current_num_threads(),
    };
    let horizon = Horizon { generations, budget, evaluations };
    let opt = AnyOptimizer::new(algorithm, loaded.generator.graph(), &limits, &config.settings(), a.seed, horizon)
        .map_err(|e| anyhow::anyhow!("{}: {e}", section(algorithm)))?;
    pool.install(|| ctx.drive(opt, &objective))
}

/// The scene section holding an algorithm's settings, for error messages.
fn section(a: genform_evolve::Algorithm) -> &'static str {
    match a {
        genform_evolve::Algorithm::Ga | genform_evolve::Algorithm::Random => "[ga]",
        genform_evolve::Algorithm::Mh => "[mh]",
        genform_evolve::Algorithm::Smc | genform_evolve::Algorithm::Sosmc => "[smc]",
        genform_evolve::Algorithm::Hybrid => "[hybrid]",
    }
}

fn worker_pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new().num_threads(threads.unwrap_or(0)).build().context("cannot start worker threads")
}

/// A flag set by Ctrl-C; a second Ctrl-C quits at once.
fn cancel_on_ctrl_c() -> Arc<AtomicBool> {
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    let _ = ctrlc::set_handler(move || {
        if flag.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
    });
    cancel
}

/// Runs `genform compare`: every algorithm `runs` times with the same
/// wall-clock budget, one run after another on the same worker pool.
pub fn compare(a: CompareArgs) -> Result<()> {
    if genform_cli::codon_scene::is_codon_scene(&a.scene) {
        return codon::compare(a);
    }
    let LoadedScene { path: scene_path, config } = SceneConfig::load(&a.scene)?;
    let loaded = grammar::load(&config.grammar)?;
    let limits = scene_limits(&config, loaded.limits, a.limits.overrides());
    let scorers = targets::build(&config)?;
    let budget = parse_duration(&a.budget).context("--budget")?;
    if a.runs == 0 {
        bail!("--runs must be at least 1");
    }
    let given = if a.algorithms.is_empty() {
        vec![Algorithm::Ga, Algorithm::Mh, Algorithm::Smc, Algorithm::Sosmc]
    } else {
        a.algorithms.clone()
    };
    let mut algorithms: Vec<genform_evolve::Algorithm> = Vec::new();
    for alg in given {
        let alg = tree_algorithm(alg, &scene_path)?;
        if !algorithms.contains(&alg) {
            algorithms.push(alg);
        }
    }
    let settings = config.settings();
    let horizon = Horizon { budget: Some(budget), ..Horizon::default() };
    for alg in &algorithms {
        AnyOptimizer::new(*alg, loaded.generator.graph(), &limits, &settings, a.seed, horizon)
            .map_err(|e| anyhow::anyhow!("{}: {e}", section(*alg)))?;
    }
    std::fs::create_dir_all(&a.out).with_context(|| format!("cannot create output folder {}", a.out.display()))?;
    let pool = worker_pool(a.threads)?;
    let cancel = cancel_on_ctrl_c();
    let objective = SceneObjective { generator: loaded.generator.as_ref(), limits, scorers: &scorers };
    let stop = Stop { generations: None, budget: Some(budget), evaluations: None, cancel: &cancel };
    let title = scene_path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let spacing = budget.as_secs_f64() / 200.0;
    let mut traces: Vec<Trace> = Vec::new();
    'all: for alg in &algorithms {
        let name = alg.name();
        let mut best: Option<Individual> = None;
        for r in 0..a.runs {
            let seed = a.seed + r as u64;
            let mut opt = AnyOptimizer::new(*alg, loaded.generator.graph(), &limits, &settings, seed, horizon)
                .map_err(|e| anyhow::anyhow!("{}: {e}", section(*alg)))?;
            let mut trace = Trace::new(name, r, seed);
            let start = Instant::now();
            let summary = pool.install(|| {
                run(&mut opt, &objective, &stop, |stats, o| {
                    let best = o.best().map_or(f64::NAN, |b| b.fitness);
                    let point = TracePoint {
                        seconds: start.elapsed().as_secs_f64(),
                        evaluations: stats.total_evaluations,
                        best,
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
                    "{name} run {}/{}: best {:.6} after {} evaluations in {:.1} s",
                    r + 1,
                    a.runs,
                    opt.best().map_or(f64::NAN, |b| b.fitness),
                    opt.evaluations(),
                    summary.elapsed.as_secs_f64()
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
            let path = a.out.join(format!("best-{name}-genome.json"));
            write_atomic(&path, b.genome.to_json(loaded.generator.graph()).as_bytes())?;
        }
    }
    write_atomic(&a.out.join("comparison.csv"), comparison::csv(&traces).as_bytes())?;
    let svg = comparison::svg(&title, &traces, budget.as_secs_f64());
    write_atomic(&a.out.join("comparison.svg"), svg.as_bytes())?;
    print!("{}", comparison::summary(&traces));
    eprintln!(
        "{} runs of {} s each on {} → {}",
        traces.len(),
        budget.as_secs_f64(),
        scene_path.display(),
        a.out.display()
    );
    Ok(())
}

struct RunContext<'a> {
    args: &'a EvolveArgs,
    algorithm: genform_evolve::Algorithm,
    scene_path: &'a Path,
    config: &'a SceneConfig,
    generator: &'a dyn Generator,
    limits: Limits,
    scorers: &'a Scorers,
    stop: Stop<'a>,
    threads: usize,
}

impl RunContext<'_> {
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

    fn drive<Opt: Optimizer, O: Objective>(&self, mut opt: Opt, objective: &O) -> Result<()> {
        let out = &self.args.out;
        std::fs::create_dir_all(out).with_context(|| format!("cannot create output folder {}", out.display()))?;
        let bar = self.progress();
        let mut rows: Vec<Row> = Vec::new();
        let mut last_checkpoint = Instant::now();
        let mut failed = None;
        let start = Instant::now();
        let summary = run(&mut opt, objective, &self.stop, |stats, opt| {
            let secs = start.elapsed().as_secs_f64();
            rows.push((stats.clone(), secs));
            let best = opt.best().map_or(f64::NAN, |b| b.fitness);
            let rate = stats.total_evaluations as f64 / secs.max(1e-9);
            if self.stop.generations.is_some() {
                bar.set_position(stats.generation as u64);
                bar.set_message(format!("best {best:.4} · {rate:.0} evals/s"));
            } else {
                bar.set_position((secs * 1000.0) as u64);
                bar.set_message(format!("gen {} · best {best:.4} · {rate:.0} evals/s", stats.generation));
            }
            if failed.is_none() && last_checkpoint.elapsed() >= CHECKPOINT_EVERY {
                if let Err(e) = self.write_progress(opt, &rows) {
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
        self.write_all(&opt, &rows, reason, summary.elapsed)?;
        let best = opt.best().map_or(f64::NAN, |b| b.fitness);
        eprintln!(
            "{}: {} generations, {} evaluations in {:.1} s ({:.0}/s); best fitness {best:.6} (max reachable {:.4}) → {}",
            self.scene_path.display(),
            opt.generation(),
            opt.evaluations(),
            summary.elapsed.as_secs_f64(),
            opt.evaluations() as f64 / summary.elapsed.as_secs_f64().max(1e-9),
            self.scorers.fitness.max_reachable(self.config.ga.min_length),
            out.display()
        );
        Ok(())
    }

    /// Checkpoint: the files that matter if the run dies.
    fn write_progress(&self, opt: &dyn Optimizer, rows: &[Row]) -> Result<()> {
        let out = &self.args.out;
        write_atomic(&out.join("stats.csv"), report::stats_csv(rows).as_bytes())?;
        if let Some(best) = opt.best() {
            write_atomic(&out.join("best-genome.json"), best.genome.to_json(self.generator.graph()).as_bytes())?;
        }
        Ok(())
    }

    fn express(&self, genome: &Genome) -> Result<Scene> {
        let mut scene = Scene::new();
        self.generator.express(genome, &self.limits, &mut scene).context("cannot build the best model")?;
        Ok(scene)
    }

    fn write_all(&self, opt: &dyn Optimizer, rows: &[Row], reason: &str, elapsed: Duration) -> Result<()> {
        let out = &self.args.out;
        self.write_progress(opt, rows)?;
        let title = self.scene_path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        write_atomic(&out.join("fitness.svg"), report::fitness_svg(&title, rows).as_bytes())?;
        if let Some(best) = opt.best() {
            let scene = self.express(&best.genome)?;
            for (name, format) in [("best.glb", Format::Glb), ("best.obj", Format::Obj)] {
                let bytes = genform_export::export(&scene, format, &ExportOptions::default())
                    .with_context(|| format!("cannot export {name}"))?;
                write_atomic(&out.join(name), &bytes)?;
            }
            // A fitted 3/4 view: the reference's image frame is mirrored
            // (see genform_core::camera), so previews through a target's
            // camera would show the model flipped against the target picture;
            // best-silhouette.png shows the true overlay.
            write_atomic(&out.join("best.png"), &genform_export::render_png(&scene, &RenderOptions::default()))?;
            for (i, img) in self.scorers.images.iter().enumerate() {
                let (rgba, w, h) = img.silhouette(&scene);
                let rgb: Vec<u8> = rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
                let name =
                    if i == 0 { "best-silhouette.png".to_string() } else { format!("best-silhouette-{}.png", i + 1) };
                write_atomic(&out.join(name), &genform_export::plot::encode_png_rgb(&rgb, w, h))?;
            }
        }
        write_atomic(&out.join("gallery.png"), &self.gallery(opt.population())?)?;
        let best = opt.best();
        let run = serde_json::json!({
            "genform": env!("CARGO_PKG_VERSION"),
            "scene": self.scene_path.display().to_string(),
            "algorithm": self.algorithm.name(),
            "seed": self.args.seed,
            "threads": self.threads,
            "stopped_by": reason,
            "generations": opt.generation(),
            "evaluations": opt.evaluations(),
            "seconds": elapsed.as_secs_f64(),
            "evaluations_per_second": opt.evaluations() as f64 / elapsed.as_secs_f64().max(1e-9),
            "eval_seconds": rows.iter().map(|(r, _)| r.eval_time.as_secs_f64()).sum::<f64>(),
            "reproduction_seconds": rows.iter().map(|(r, _)| r.reproduction_time.as_secs_f64()).sum::<f64>(),
            "best_fitness": best.map(|b| b.fitness),
            "best_length": best.map(|b| b.genome.len()),
            "max_reachable_fitness": self.scorers.fitness.max_reachable(self.config.ga.min_length),
            "limits": { "genes": self.limits.max_genes, "depth": self.limits.max_depth, "primitives": self.limits.max_primitives },
            "config": self.config,
        });
        let text = serde_json::to_string_pretty(&run).context("cannot encode run.json")?;
        write_atomic(&out.join("run.json"), text.as_bytes())
    }

    /// The 16 best distinct individuals, rendered with one shared camera.
    fn gallery(&self, population: &[Individual]) -> Result<Vec<u8>> {
        let mut picked: Vec<&Individual> = Vec::new();
        for ind in population.iter().filter(|i| i.is_valid()) {
            if picked.len() == 16 {
                break;
            }
            if !picked.iter().any(|p| p.genome == ind.genome) {
                picked.push(ind);
            }
        }
        let scenes: Vec<(Scene, f64)> =
            picked.iter().map(|i| Ok((self.express(&i.genome)?, i.fitness))).collect::<Result<_>>()?;
        let bounds = scenes.iter().filter_map(|(s, _)| s.bounds(Default::default()));
        let camera = bounds.reduce(|(a, b), (c, d)| (a.min(c), b.max(d))).map(Camera::fit);
        Ok(report::gallery_png(&scenes, camera))
    }
}
