//! Runs of tree scenes (derivation-tree genomes of `.sg` and `.ls`
//! grammars): `evolve`, `score` and `compare`.

use anyhow::{Context, Result};
use genform_core::{Generator, Genome, Limits, Scene};
use genform_evolve::{AnyOptimizer, GenerationStats, Horizon, Individual, Objective, Optimizer, Settings};
use genform_export::RenderOptions;
use std::path::Path;

use super::compare::{CompareOutcome, CompareRequest, Contest, distinct, race, race_budget};
use super::{
    AlgorithmChoice, Common, Control, Ended, EvolveRequest, RunOutcome, ScoreRequest, Session, SteerSet, Steerable,
    drive, scene_limits, stop_at, stop_rules, title, worker_pool, write_models,
};
use crate::archive::Reports;
use crate::grammar;
use crate::objective::{DescribedObjective, Descriptor, SceneObjective, Scorers};
use crate::output::write_atomic;
use crate::pictures::{self, BestHistory, TargetPicture};
use crate::report::{self, Row};
use crate::scene_config::{LoadedScene, SceneConfig};
use crate::targets;

/// The tree optimizer `alg` names; `ge` is refused with the reason.
pub fn tree_algorithm(alg: AlgorithmChoice, scene: &Path) -> Result<genform_evolve::Algorithm> {
    alg.tree().ok_or_else(|| {
        anyhow::anyhow!(
            "--algorithm ge evolves codon genomes, but {} is a tree scene (its grammar's genomes are derivation \
             trees); use ga, mh, smc, sosmc, hybrid, map-elites or random, or a scene whose grammar is .bnf, .bsg or .gg.yaml",
            scene.display()
        )
    })
}

/// One genome's counts and fitness against a tree scene.
pub(super) fn score(r: &ScoreRequest, scene: LoadedScene) -> Result<Vec<String>> {
    let LoadedScene { mut config, .. } = scene;
    config.fitness.override_form(r.form.as_deref())?;
    let loaded = grammar::load(&config.grammar)?;
    let limits = scene_limits(&config, loaded.limits, r.limits);
    let scorers = targets::build(&config)?;
    let genome = loaded.read_genome(&r.genome)?;
    let objective = SceneObjective { generator: loaded.generator.as_ref(), limits, scorers: &scorers };
    let c = objective.counts(&genome, &mut objective.scratch()).context("cannot build the model")?;
    Ok(vec![format!(
        "fitness {} (form {}, max reachable {}); genes {}; good {} bad {} overlap {} outside {} target {}",
        scorers.fitness.eval(&c, genome.len()),
        scorers.fitness.form.name(),
        scorers.fitness.max_reachable(genome.len()),
        genome.len(),
        c.good,
        c.bad,
        c.overlap,
        c.outside,
        c.target
    )])
}

/// Runs a tree scene under `control`.
pub(super) fn evolve(r: &EvolveRequest, scene: LoadedScene, mut control: Control) -> Result<RunOutcome> {
    let LoadedScene { path: scene_path, mut config } = scene;
    apply_preset(&mut config, r.preset.as_deref());
    let algorithm = tree_algorithm(r.algorithm.unwrap_or(AlgorithmChoice::Ga), &scene_path)?;
    let loaded = grammar::load(&config.grammar)?;
    let limits = scene_limits(&config, loaded.limits, r.limits);
    if config.ga.max_length > limits.max_genes + 1
        && let Some(w) = control.watch.as_deref_mut()
    {
        w.note(&format!(
            "note: [ga] max_length {} is above the gene limit {}; genomes stop at {} genes",
            config.ga.max_length, limits.max_genes, limits.max_genes
        ));
    }
    let scorers = targets::build(&config)?;
    let horizon = stop_rules(r, &config.run)?;
    let pool = worker_pool(r.threads)?;
    let cancel = control.cancel.clone();
    let mut ctx = RunContext {
        common: Common {
            request: r,
            algorithm: algorithm.name(),
            scene_path: &scene_path,
            threads: pool.current_num_threads(),
        },
        config: &config,
        generator: loaded.generator.as_ref(),
        limits,
        scorers,
        steerable: Steerable::Fitness(config.fitness.clone()),
        descriptors: Descriptor::pair(&config.map_elites),
    };
    let opt = AnyOptimizer::new(algorithm, loaded.generator.graph(), &limits, &config.settings(), r.seed, horizon)
        .map_err(|e| anyhow::anyhow!("{}: {e}", section(algorithm)))?;
    pool.install(|| drive(&mut ctx, opt, stop_at(horizon, &cancel), &mut control))
}

/// Sets the scene's GA preset from a preset name (unknown names are left
/// to the door to refuse).
fn apply_preset(config: &mut SceneConfig, preset: Option<&str>) {
    if let Some(p) = preset.and_then(genform_evolve::GaPreset::from_name) {
        config.ga = config.ga.clone().with_preset(p);
    }
}

/// The scene section holding an algorithm's settings, for error messages.
fn section(a: genform_evolve::Algorithm) -> &'static str {
    match a {
        genform_evolve::Algorithm::Ga | genform_evolve::Algorithm::Random => "[ga]",
        genform_evolve::Algorithm::Mh => "[mh]",
        genform_evolve::Algorithm::Smc | genform_evolve::Algorithm::Sosmc => "[smc]",
        genform_evolve::Algorithm::Hybrid => "[hybrid]",
        genform_evolve::Algorithm::MapElites => "[map_elites]",
    }
}

/// Runs `compare` on a tree scene: every algorithm `runs` times with the
/// same wall-clock budget, one run after another on the same worker pool.
pub(super) fn compare(r: &CompareRequest, scene: LoadedScene, control: Control) -> Result<CompareOutcome> {
    let LoadedScene { path: scene_path, mut config } = scene;
    apply_preset(&mut config, r.preset.as_deref());
    let loaded = grammar::load(&config.grammar)?;
    let limits = scene_limits(&config, loaded.limits, r.limits);
    let scorers = targets::build(&config)?;
    let budget = race_budget(r)?;
    let default = [AlgorithmChoice::Ga, AlgorithmChoice::Mh, AlgorithmChoice::Smc, AlgorithmChoice::Sosmc];
    let algorithms = distinct(&r.algorithms, &default, |alg| tree_algorithm(alg, &scene_path))?;
    let contest = TreeContest {
        generator: loaded.generator.as_ref(),
        limits,
        settings: config.settings(),
        horizon: Horizon { budget: Some(budget), ..Horizon::default() },
    };
    for alg in &algorithms {
        contest.start(*alg, r.seed)?;
    }
    let objective = DescribedObjective {
        objective: SceneObjective { generator: loaded.generator.as_ref(), limits, scorers: &scorers },
        descriptors: Descriptor::pair(&config.map_elites),
    };
    race(r, &scene_path, budget, &algorithms, &objective, &contest, control)
}

/// Tree scenes in `compare`.
struct TreeContest<'a> {
    generator: &'a dyn Generator,
    limits: Limits,
    settings: Settings,
    horizon: Horizon,
}

impl Contest<Genome> for TreeContest<'_> {
    type Alg = genform_evolve::Algorithm;
    type Opt = AnyOptimizer;

    fn name(&self, alg: Self::Alg) -> &'static str {
        alg.name()
    }

    fn start(&self, alg: Self::Alg, seed: u64) -> Result<AnyOptimizer> {
        AnyOptimizer::new(alg, self.generator.graph(), &self.limits, &self.settings, seed, self.horizon)
            .map_err(|e| anyhow::anyhow!("{}: {e}", section(alg)))
    }

    fn run_tail(&self) -> String {
        String::new()
    }

    fn save_best(&self, out: &Path, name: &str, best: &Individual<Genome>) -> Result<()> {
        let path = out.join(format!("best-{name}-genome.json"));
        write_atomic(&path, best.genome.to_json(self.generator.graph()).as_bytes())
    }
}
/// One `evolve` run of a tree scene.
struct RunContext<'a> {
    common: Common<'a>,
    /// The scene as written (steering changes `scorers` and `steerable` only).
    config: &'a SceneConfig,
    generator: &'a dyn Generator,
    limits: Limits,
    /// The targets, with the fitness constants as steered so far.
    scorers: Scorers,
    /// The `[fitness]` constants as steered so far.
    steerable: Steerable,
    descriptors: [Descriptor; 2],
}

impl Session<Genome> for RunContext<'_> {
    type Record = BestHistory<Genome>;
    type Objective<'s>
        = DescribedObjective<'s>
    where
        Self: 's;

    fn common(&self) -> &Common<'_> {
        &self.common
    }

    fn objective(&self) -> DescribedObjective<'_> {
        let objective = SceneObjective { generator: self.generator, limits: self.limits, scorers: &self.scorers };
        DescribedObjective { objective, descriptors: self.descriptors }
    }

    fn steerable(&self) -> &Steerable {
        &self.steerable
    }

    fn steer(&mut self, set: &SteerSet) -> Result<()> {
        self.steerable.apply(set)?;
        if let Steerable::Fitness(f) = &self.steerable {
            let mut config = self.config.clone();
            config.fitness = f.clone();
            self.scorers.fitness = config.fitness();
        }
        Ok(())
    }

    fn best_scene(&self, opt: &dyn Optimizer) -> Result<Option<Scene>> {
        opt.best().map(|b| self.express(&b.genome)).transpose()
    }

    fn gallery(&self, opt: &dyn Optimizer) -> Result<Vec<u8>> {
        let reports = self.reports();
        // Earlier epochs' champions compete too: after a restart the best
        // answer so far may no longer be in the population.
        let pool: Vec<Individual> = opt.population().iter().chain(opt.champions()).cloned().collect();
        Ok(reports.gallery_png(&reports.describe(&pool)?))
    }

    fn max_reachable(&self) -> f64 {
        self.scorers.fitness.max_reachable(self.config.ga.min_length)
    }

    fn best_genome(&self, opt: &dyn Optimizer) -> Option<Genome> {
        opt.best().map(|b| b.genome.clone())
    }

    fn record(
        &self,
        rec: &mut BestHistory<Genome>,
        stats: &GenerationStats,
        opt: &dyn Optimizer,
    ) -> (String, Option<String>) {
        rec.record(stats.generation, opt.best().map(|b| (&b.genome, b.fitness)));
        (String::new(), None)
    }

    fn write_progress(&self, out: &Path, opt: &dyn Optimizer, rows: &[Row], _: &BestHistory<Genome>) -> Result<()> {
        write_atomic(&out.join("stats.csv"), report::stats_csv(rows).as_bytes())?;
        if let Some(best) = opt.best() {
            write_atomic(&out.join("best-genome.json"), best.genome.to_json(self.generator.graph()).as_bytes())?;
        }
        Ok(())
    }

    fn write_all(
        &self,
        out: &Path,
        opt: &dyn Optimizer,
        rows: &[Row],
        rec: &BestHistory<Genome>,
        ended: Ended,
        _: &mut dyn FnMut(&str),
    ) -> Result<()> {
        self.write_progress(out, opt, rows, rec)?;
        let title = title(self.common.scene_path);
        write_atomic(&out.join("fitness.svg"), report::fitness_svg(&title, rows).as_bytes())?;
        // The pictures are independent files: made side by side on the run's
        // pool, each written whole, so the folder is the same at any thread count.
        let best = opt.best().map(|b| self.express(&b.genome)).transpose()?;
        let target = match &best {
            Some(_) => Some(TargetPicture::new(self.config, &self.scorers)?),
            None => None,
        };
        let population = opt.population();
        let (pictures, gallery) = rayon::join(
            || -> Result<()> {
                let (Some(scene), Some(target)) = (&best, &target) else { return Ok(()) };
                let (models, evolution) = rayon::join(
                    || -> Result<()> {
                        write_models(out, scene)?;
                        // best-model.png: the model alone in a fitted 3/4 view;
                        // best.png: with its target behind it (see genform_app::pictures).
                        let png = genform_export::render_png(scene, &RenderOptions::default());
                        write_atomic(&out.join("best-model.png"), &png)?;
                        write_atomic(&out.join("best.png"), &target.best_png(scene))?;
                        pictures::write_silhouettes(out, &self.scorers.images, scene)
                    },
                    || self.write_evolution(out, target, rec),
                );
                models.and(evolution)
            },
            || self.write_diversity(out, population),
        );
        pictures?;
        gallery?;
        let l = &self.limits;
        let own = serde_json::json!({
            "limits": { "genes": l.max_genes, "depth": l.max_depth, "primitives": l.max_primitives },
            "config": self.config.as_run(),
        });
        self.common.write_run_json(out, opt, rows, ended, self.max_reachable(), own)
    }

    fn summary_tail(&self, _: &BestHistory<Genome>) -> String {
        String::new()
    }
}

impl RunContext<'_> {
    /// `evolution.png`: the best so far at about [`pictures::FRAMES`]
    /// moments of the run, with the target behind it, as an animated PNG.
    fn write_evolution(&self, out: &Path, target: &TargetPicture, rec: &BestHistory<Genome>) -> Result<()> {
        let frames = rec
            .frames(pictures::FRAMES)
            .into_iter()
            .map(|(g, f, genome)| Ok((g, f, self.express(genome)?)))
            .collect::<Result<Vec<_>>>()?;
        match target.evolution_apng(&frames) {
            Some(apng) => write_atomic(&out.join("evolution.png"), &apng),
            None => Ok(()),
        }
    }

    fn express(&self, genome: &Genome) -> Result<Scene> {
        let mut scene = Scene::new();
        self.generator.express(genome, &self.limits, &mut scene).context("cannot build the best model")?;
        Ok(scene)
    }

    fn reports(&self) -> Reports<'_> {
        Reports { generator: self.generator, limits: self.limits, config: self.config.map_elites() }
    }

    /// `gallery.png` (the best distinct individuals of `population`) and,
    /// for MAP-Elites, whose population is its archive, `archive.csv`,
    /// `archive.png` and `elites/`.
    fn write_diversity(&self, out: &Path, population: &[Individual]) -> Result<()> {
        let reports = self.reports();
        let described = reports.describe(population)?;
        write_atomic(&out.join("gallery.png"), &reports.gallery_png(&described))?;
        if self.common.algorithm == genform_evolve::Algorithm::MapElites.name() {
            reports.write_archive(out, &described)?;
        }
        Ok(())
    }
}
