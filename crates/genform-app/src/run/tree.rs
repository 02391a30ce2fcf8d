//! Runs of scenes whose genomes are derivation trees (`.sg`, `.ls`
//! grammars): `evolve`, `score` and `compare`.

use anyhow::{Context, Result};
use genform_core::{Generator, Genome, Limits, Scene};
use genform_evolve::{AnyOptimizer, GenerationStats, Horizon, Individual, Optimizer, Settings};
use genform_export::RenderOptions;
use genform_score::Scorer;
use std::path::Path;

use super::compare::{CompareOutcome, CompareRequest, Contest, race};
use super::control::{Control, EvolveRequest, RunOutcome, ScoreRequest};
use super::session::{Common, Ended, Session, drive, stop_at, worker_pool, write_models};
use super::steering::{SteerSet, Steerable};
use crate::files::write_atomic;
use crate::objective::{OpenScene, TreeObjective};
use crate::report::archive::Reports;
use crate::report::pictures::{self, BestHistory, TargetPicture};
use crate::report::stats::Row;

/// The scene section holding an algorithm's settings, for error messages.
fn section(a: genform_evolve::Algorithm) -> &'static str {
    crate::optimizers::OPTIMIZERS
        .iter()
        .find(|r| r.kind == crate::optimizers::Kind::Tree(a))
        .map_or("ga", |r| r.section)
}

/// A fresh tree optimizer: `alg` with the scene's settings.
pub(crate) fn optimizer(
    alg: genform_evolve::Algorithm,
    open: &OpenScene,
    settings: &Settings,
    seed: u64,
    horizon: Horizon,
) -> Result<AnyOptimizer> {
    let (loaded, limits) = open.tree().context("a tree optimizer needs a tree scene")?;
    AnyOptimizer::new(alg, loaded.generator.graph(), &limits, settings, seed, horizon)
        .map_err(|e| anyhow::anyhow!("[{}]: {e}", section(alg)))
}

/// One genome's counts and fitness against a tree scene.
pub(super) fn score(r: &ScoreRequest, open: &OpenScene) -> Result<Vec<String>> {
    let (loaded, _) = open.tree().context("a tree scene")?;
    let genome = loaded.read_genome(&r.genome)?;
    let objective = open.tree_objective(open.scorer()).context("a tree scene")?;
    let s = objective
        .score(&genome, &mut genform_evolve::Objective::scratch(&objective))
        .context("cannot build the model")?;
    let measures: Vec<String> = s.measures.iter().map(|(n, v)| format!("{n} {v}")).collect();
    Ok(vec![format!(
        "fitness {} (form {}, max reachable {}); genes {}; {}",
        s.fitness,
        open.scorer().form(),
        open.scorer().max_reachable(genome.len()),
        genome.len(),
        measures.join(" ")
    )])
}

/// Runs a tree scene under `control`.
pub(super) fn evolve(
    r: &EvolveRequest,
    open: &OpenScene,
    alg: genform_evolve::Algorithm,
    horizon: Horizon,
    mut control: Control,
) -> Result<RunOutcome> {
    let (loaded, limits) = open.tree().context("a tree scene")?;
    let ga = &open.scene.optimizers.ga;
    if ga.max_length > limits.max_genes + 1
        && let Some(w) = control.watch.as_deref_mut()
    {
        w.note(&format!(
            "note: [ga] max_length {} is above the gene limit {}; genomes stop at {} genes",
            ga.max_length, limits.max_genes, limits.max_genes
        ));
    }
    let pool = worker_pool(r.threads)?;
    let cancel = control.cancel.clone();
    let scorer = open.scorer_copy()?;
    let mut ctx = TreeRun {
        common: Common {
            request: r,
            algorithm: alg.name(),
            scene_path: &open.scene.path,
            threads: pool.current_num_threads(),
        },
        open,
        generator: loaded.generator.as_ref(),
        limits,
        steerable: Steerable::of(scorer.as_ref()),
        scorer,
    };
    let opt = optimizer(alg, open, &open.scene.tree_settings(), r.seed, horizon)?;
    let mut outcome = pool.install(|| drive(&mut ctx, opt, stop_at(horizon, &cancel), &mut control))?;
    outcome.generator = Some((open.scene.grammar.clone(), loaded.clone(), limits));
    Ok(outcome)
}

/// Runs `compare` on a tree scene.
pub(super) fn compare(
    r: &CompareRequest,
    open: &OpenScene,
    algorithms: &[genform_evolve::Algorithm],
    budget: std::time::Duration,
    control: Control,
) -> Result<CompareOutcome> {
    let (loaded, _) = open.tree().context("a tree scene")?;
    let contest = TreeContest {
        open,
        graph_of: loaded.generator.as_ref(),
        settings: open.scene.tree_settings(),
        horizon: Horizon { budget: Some(budget), ..Horizon::default() },
    };
    for alg in algorithms {
        contest.start(*alg, r.seed)?;
    }
    let objective = open.tree_objective(open.scorer()).context("a tree scene")?;
    race(r, &open.scene.path, budget, algorithms, &objective, &contest, control)
}

/// Tree scenes in `compare`.
struct TreeContest<'a> {
    open: &'a OpenScene,
    graph_of: &'a dyn Generator,
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
        optimizer(alg, self.open, &self.settings, seed, self.horizon)
    }

    fn run_tail(&self) -> String {
        String::new()
    }

    fn save_best(&self, out: &Path, name: &str, best: &Individual<Genome>) -> Result<()> {
        let path = out.join(format!("best-{name}-genome.json"));
        write_atomic(&path, best.genome.to_json(self.graph_of.graph()).as_bytes())
    }
}

/// One `evolve` run of a tree scene.
struct TreeRun<'a> {
    common: Common<'a>,
    /// The scene as opened (steering changes `scorer` and `steerable` only).
    open: &'a OpenScene,
    generator: &'a dyn Generator,
    limits: Limits,
    /// The scorer as steered so far.
    scorer: Box<dyn Scorer>,
    /// Its knobs.
    steerable: Steerable,
}

impl Session<Genome> for TreeRun<'_> {
    type Record = BestHistory<Genome>;
    type Objective<'s>
        = TreeObjective<'s>
    where
        Self: 's;

    fn common(&self) -> &Common<'_> {
        &self.common
    }

    fn objective(&self) -> TreeObjective<'_> {
        TreeObjective {
            generator: self.generator,
            limits: self.limits,
            scorer: self.scorer.as_ref(),
            descriptors: self.open.scene.optimizers.descriptors(),
        }
    }

    fn scorer(&self) -> &dyn Scorer {
        self.scorer.as_ref()
    }

    fn steerable(&self) -> &Steerable {
        &self.steerable
    }

    fn steer(&mut self, set: &SteerSet) -> Result<()> {
        let (scorer, steerable) = self.steerable.apply(self.scorer.as_ref(), set)?;
        self.scorer = scorer;
        self.steerable = steerable;
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
        self.scorer.max_reachable(self.open.scene.optimizers.ga.min_length)
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
        let best = opt.best().map(|b| ("best-genome.json", b.genome.to_json(self.generator.graph())));
        self.common.write_progress(out, rows, &[], best)
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
        self.common.write_plot(out, rows, &[], "")?;
        // The pictures are independent files: made side by side on the run's
        // pool, each written whole, so the folder is the same at any thread count.
        let best = opt.best().map(|b| self.express(&b.genome)).transpose()?;
        let scoring = &self.open.scoring;
        let target = best.as_ref().map(|_| TargetPicture::new(&scoring.ghosts, &scoring.images));
        let population = opt.population();
        let (pictures, gallery) = rayon::join(
            || -> Result<()> {
                let (Some(scene), Some(target)) = (&best, &target) else { return Ok(()) };
                let (models, evolution) = rayon::join(
                    || -> Result<()> {
                        write_models(out, scene)?;
                        // best-model.png: the model alone in a fitted 3/4 view;
                        // best.png: with its target behind it (see report::pictures).
                        let png = genform_export::render_png(scene, &RenderOptions::default());
                        write_atomic(&out.join("best-model.png"), &png)?;
                        write_atomic(&out.join("best.png"), &target.best_png(scene))?;
                        pictures::write_silhouettes(out, &scoring.images, scene)
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
            "config": self.open.scene.to_json(),
        });
        self.common.write_run_json(out, opt, rows, ended, self.max_reachable(), own)
    }

    fn summary_tail(&self, _: &BestHistory<Genome>) -> String {
        String::new()
    }
}

impl TreeRun<'_> {
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
        Reports {
            generator: self.generator,
            limits: self.limits,
            config: self.open.scene.optimizers.map_elites(self.open.scene.scoring.extent()),
        }
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

#[cfg(test)]
mod tests {
    use super::*;
    use genform_evolve::{Algorithm, Stop, run};
    use std::sync::atomic::AtomicBool;

    /// Best fitness, evaluations and the cells of the archive grid the
    /// final population covers, for one run of `algorithm` on `open`.
    fn race(open: &OpenScene, algorithm: Algorithm, seed: u64, stop: &Stop) -> (f64, u64, usize) {
        let horizon = Horizon { generations: stop.generations, evaluations: stop.evaluations, budget: None };
        let mut opt = optimizer(algorithm, open, &open.scene.tree_settings(), seed, horizon).unwrap();
        let objective = open.tree_objective(open.scorer()).unwrap();
        run(&mut opt, &objective, stop, |_, _| {}).unwrap();
        let (loaded, limits) = open.tree().unwrap();
        let config = open.scene.optimizers.map_elites(open.scene.scoring.extent());
        let reports = Reports { generator: loaded.generator.as_ref(), limits, config };
        let described = reports.describe(opt.population()).unwrap();
        let mut cells: Vec<[usize; 2]> = described.iter().map(|(_, d)| reports.config.cell(d.descriptors)).collect();
        cells.sort();
        cells.dedup();
        (opt.best().unwrap().fitness, opt.evaluations(), cells.len())
    }

    /// Issue #18: on spaceship_volume MAP-Elites fills more cells than the
    /// GA's final population covers, and its best is within 5 % of the
    /// GA's at equal evaluations (the GA's 130 generations, 15 750
    /// evaluations), on the mean of three seeds. About a minute with the
    /// test profile; the numbers are in docs/evolve.md.
    #[test]
    fn map_elites_covers_more_than_the_ga_and_matches_its_best() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/spaceship_volume.toml");
        let open = OpenScene::open(crate::scene::Scene::load(&path, &[]).unwrap(), Default::default()).unwrap();
        let cancel = AtomicBool::new(false);
        let (mut ga_sum, mut me_sum) = (0.0, 0.0);
        for seed in 1..=3 {
            let ga_stop = Stop { generations: Some(130), budget: None, evaluations: None, cancel: &cancel };
            let (ga_best, evaluations, ga_cells) = race(&open, Algorithm::Ga, seed, &ga_stop);
            let me_stop = Stop { generations: None, budget: None, evaluations: Some(evaluations), cancel: &cancel };
            let (me_best, me_evaluations, me_cells) = race(&open, Algorithm::MapElites, seed, &me_stop);
            eprintln!(
                "seed {seed}: GA best {ga_best:.4} in {ga_cells} cells; MAP-Elites best {me_best:.4} in {me_cells} cells"
            );
            assert_eq!(me_evaluations, evaluations, "equal evaluations");
            assert!(
                me_cells > ga_cells,
                "seed {seed}: MAP-Elites fills {me_cells} cells, the GA's population {ga_cells}"
            );
            ga_sum += ga_best;
            me_sum += me_best;
        }
        let (ga, me) = (ga_sum / 3.0, me_sum / 3.0);
        assert!(me >= ga - 0.05 * ga.abs(), "mean best: MAP-Elites {me:.4} vs GA {ga:.4}");
    }
}
