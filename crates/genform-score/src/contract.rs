//! The scorer contract: what every scorer of a scene gives the rest of
//! genform, whatever it measures.
//!
//! A [`Scorer`] turns a Scene (and the length of the genome that made it)
//! into one fitness on the hot path ([`Scorer::fitness`]), and into a
//! [`Score`] for reports: the fitness, its named [`Component`]s (what each
//! term adds, with its weight and the most it can add) and the raw
//! measures behind them. Its steerable weights and targets are
//! [`Knob`]s, read and changed by name ([`Scorer::knobs`],
//! [`Scorer::with_knobs`]), so steering, statistics, plots, the studio's
//! criteria panels and Python read every scorer the same way.
//!
//! Two shapes implement it here:
//!
//! - **Counting targets** ([`Counter`]: volume grids, image silhouettes,
//!   multi-view silhouettes) each reduce the Scene to [`Counts`]; the
//!   counts of all of a scene's targets are summed and one [`Fitness`]
//!   form turns them into a fitness ([`Targets`]). A new counting target
//!   is a [`Counter`].
//! - **Criteria scorers** (Genr8's surface criteria, [`SurfaceScorer`])
//!   score the Scene themselves; their components are criteria charted per
//!   generation ([`Scorer::chart`]).

use crate::fitness::{Counts, Fitness};
use crate::surface::{SurfaceCriterion, SurfaceScorer};
use genform_core::scene::Scene;
use std::any::Any;

pub use crate::component::{Component, Score};

/// Per-thread working memory of a scorer (each scorer knows its own type).
pub type Scratch = Box<dyn Any + Send>;

/// A weight (and, for criteria, a target) that steering may change.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Knob {
    /// The name steering uses.
    pub name: &'static str,
    /// What it is, in messages: `[fitness] weight`, `[surface] criterion`.
    pub kind: &'static str,
    /// The weight now.
    pub weight: f64,
    /// The target now, for criteria with one.
    pub target: Option<f64>,
    /// Whether the weight may be negative (a target to stay away from).
    pub signed: bool,
}

/// A scorer of Scenes (see the [module](self) docs).
pub trait Scorer: Send + Sync {
    /// Fresh working memory for one thread.
    fn scratch(&self) -> Scratch;

    /// The fitness of `scene`, made from a genome of `genome_len` genes or
    /// codons (for length terms). The hot path: allocation-free once the
    /// scratch has seen a scene of this kind.
    fn fitness(&self, scene: &Scene, genome_len: usize, scratch: &mut Scratch) -> f64;

    /// [`Scorer::fitness`] with its components and measures.
    fn score(&self, scene: &Scene, genome_len: usize, scratch: &mut Scratch) -> Score;

    /// The best fitness a model of `shortest` genes can reach.
    fn max_reachable(&self, shortest: usize) -> f64;

    /// The weights and targets steering can change, as they are now.
    fn knobs(&self) -> Vec<Knob>;

    /// This scorer with `knobs` (a subset of [`Scorer::knobs`] by name,
    /// with new values) applied; an error says why the values cannot be
    /// scored with, and nothing changes.
    fn with_knobs(&self, knobs: &[Knob]) -> Result<Box<dyn Scorer>, String>;

    /// For scorers whose components are criteria to follow generation by
    /// generation (charted in `fitness.svg`, the studio's criteria panel):
    /// what one criterion adds, in words (`w/(1+e)`). `None`: the
    /// components are terms of one formula, reported for the best model.
    fn chart(&self) -> Option<&'static str> {
        None
    }

    /// The name of the formula that makes the fitness (`paper`, `bounded`).
    fn form(&self) -> &'static str;

    /// What `scene` looks like to this scorer, as text: two models with one
    /// look show the same thing in a gallery. By default the scene's
    /// counts, its bounds and the score's measures.
    fn look(&self, scene: &Scene, score: &Score) -> String {
        crate::look::look(scene, &score.measures.iter().map(|(_, v)| *v).collect::<Vec<_>>())
    }

    /// Empties caches kept across evaluations (results never depend on them).
    fn clear_caches(&self) {}
}

/// A counting target: reduces a Scene to [`Counts`] (see [`Targets`]).
pub trait Counter: Send + Sync {
    /// Fresh working memory for one thread.
    fn scratch(&self) -> Scratch;
    /// What `scene` covers of this target.
    fn counts(&self, scene: &Scene, scratch: &mut Scratch) -> Counts;
    /// Empties caches kept across evaluations.
    fn clear_caches(&self) {}
}

impl Counter for crate::volume::VolumeScorer {
    fn scratch(&self) -> Scratch {
        Box::new(crate::volume::VolumeScorer::scratch(self))
    }

    fn counts(&self, scene: &Scene, scratch: &mut Scratch) -> Counts {
        crate::volume::VolumeScorer::counts(self, scene, downcast(scratch))
    }

    fn clear_caches(&self) {
        crate::volume::VolumeScorer::clear_caches(self)
    }
}

impl Counter for crate::image::ImageScorer {
    fn scratch(&self) -> Scratch {
        Box::new(crate::image::ImageScorer::scratch(self))
    }

    fn counts(&self, scene: &Scene, scratch: &mut Scratch) -> Counts {
        crate::image::ImageScorer::counts(self, scene, downcast(scratch))
    }

    fn clear_caches(&self) {
        crate::image::ImageScorer::clear_caches(self)
    }
}

/// The scratch of type `T` a scorer made; another type is a bug in the
/// scorer that made it.
pub fn downcast<T: 'static>(scratch: &mut Scratch) -> &mut T {
    scratch.downcast_mut::<T>().expect("a scorer is given the scratch it made")
}

/// Counting targets whose counts are summed (in order) and turned into a
/// fitness by one [`Fitness`]: a scene's volume and image targets under
/// its `[fitness]` constants.
pub struct Targets {
    counters: Vec<std::sync::Arc<dyn Counter>>,
    fitness: Fitness,
}

impl Targets {
    /// `counters` (at least one) under `fitness`.
    pub fn new(counters: Vec<std::sync::Arc<dyn Counter>>, fitness: Fitness) -> Targets {
        Targets { counters, fitness }
    }

    /// The fitness constants.
    pub fn constants(&self) -> &Fitness {
        &self.fitness
    }

    /// The counting targets, in order.
    pub fn counters(&self) -> &[std::sync::Arc<dyn Counter>] {
        &self.counters
    }

    /// The summed counts of every target.
    pub fn counts(&self, scene: &Scene, scratch: &mut Scratch) -> Counts {
        let scratches = downcast::<Vec<Scratch>>(scratch);
        let mut c = Counts::default();
        for (t, s) in self.counters.iter().zip(scratches) {
            c += t.counts(scene, s);
        }
        c
    }
}

/// The names `[fitness]` weights go by, in order.
pub const FITNESS_WEIGHTS: [&str; 4] = ["good", "bad", "overlap", "length"];

impl Scorer for Targets {
    fn scratch(&self) -> Scratch {
        Box::new(self.counters.iter().map(|c| c.scratch()).collect::<Vec<Scratch>>())
    }

    fn fitness(&self, scene: &Scene, genome_len: usize, scratch: &mut Scratch) -> f64 {
        self.fitness.eval(&self.counts(scene, scratch), genome_len)
    }

    fn score(&self, scene: &Scene, genome_len: usize, scratch: &mut Scratch) -> Score {
        let c = self.counts(scene, scratch);
        Score {
            fitness: self.fitness.eval(&c, genome_len),
            components: self.fitness.components(&c, genome_len),
            measures: vec![
                ("good", c.good),
                ("bad", c.bad),
                ("overlap", c.overlap),
                ("outside", c.outside),
                ("target", c.target),
            ],
        }
    }

    fn max_reachable(&self, shortest: usize) -> f64 {
        self.fitness.max_reachable(shortest)
    }

    fn knobs(&self) -> Vec<Knob> {
        let f = &self.fitness;
        FITNESS_WEIGHTS
            .iter()
            .zip([f.good, f.bad, f.overlap, f.length])
            .map(|(name, weight)| Knob { name, kind: "[fitness] weight", weight, target: None, signed: true })
            .collect()
    }

    fn with_knobs(&self, knobs: &[Knob]) -> Result<Box<dyn Scorer>, String> {
        let mut fitness = self.fitness;
        for k in knobs {
            let slot = match k.name {
                "good" => &mut fitness.good,
                "bad" => &mut fitness.bad,
                "overlap" => &mut fitness.overlap,
                "length" => &mut fitness.length,
                other => return Err(format!("[fitness] has no weight `{other}`")),
            };
            if !k.weight.is_finite() {
                return Err(format!("`{}` must be a finite number, not {}", k.name, k.weight));
            }
            *slot = k.weight;
        }
        Ok(Box::new(Targets { counters: self.counters.clone(), fitness }))
    }

    fn form(&self) -> &'static str {
        self.fitness.form.name()
    }

    fn clear_caches(&self) {
        for c in &self.counters {
            c.clear_caches();
        }
    }
}

/// Several scorers whose fitness values add up (a scene scored by
/// criteria and by counting targets at once).
pub struct Sum(pub Vec<Box<dyn Scorer>>);

impl Scorer for Sum {
    fn scratch(&self) -> Scratch {
        Box::new(self.0.iter().map(|s| s.scratch()).collect::<Vec<Scratch>>())
    }

    fn fitness(&self, scene: &Scene, genome_len: usize, scratch: &mut Scratch) -> f64 {
        let scratches = downcast::<Vec<Scratch>>(scratch);
        self.0.iter().zip(scratches).map(|(s, x)| s.fitness(scene, genome_len, x)).sum()
    }

    fn score(&self, scene: &Scene, genome_len: usize, scratch: &mut Scratch) -> Score {
        let scratches = downcast::<Vec<Scratch>>(scratch);
        let mut out = Score { fitness: 0.0, components: Vec::new(), measures: Vec::new() };
        for (s, x) in self.0.iter().zip(scratches) {
            let part = s.score(scene, genome_len, x);
            out.fitness += part.fitness;
            out.components.extend(part.components);
            out.measures.extend(part.measures);
        }
        out
    }

    fn max_reachable(&self, shortest: usize) -> f64 {
        self.0.iter().map(|s| s.max_reachable(shortest)).sum()
    }

    fn knobs(&self) -> Vec<Knob> {
        self.0.iter().flat_map(|s| s.knobs()).collect()
    }

    fn with_knobs(&self, knobs: &[Knob]) -> Result<Box<dyn Scorer>, String> {
        let parts = self
            .0
            .iter()
            .map(|s| {
                let own: Vec<Knob> =
                    knobs.iter().filter(|k| s.knobs().iter().any(|m| m.name == k.name)).copied().collect();
                s.with_knobs(&own)
            })
            .collect::<Result<Vec<_>, String>>()?;
        Ok(Box::new(Sum(parts)))
    }

    fn chart(&self) -> Option<&'static str> {
        self.0.iter().find_map(|s| s.chart())
    }

    fn form(&self) -> &'static str {
        self.0.first().map_or("", |s| s.form())
    }

    fn clear_caches(&self) {
        for s in &self.0 {
            s.clear_caches();
        }
    }
}

impl Scorer for SurfaceScorer {
    fn scratch(&self) -> Scratch {
        Box::new(())
    }

    fn fitness(&self, scene: &Scene, _: usize, _: &mut Scratch) -> f64 {
        self.score_scene(scene).fitness()
    }

    fn score(&self, scene: &Scene, _: usize, _: &mut Scratch) -> Score {
        let s = self.score_scene(scene);
        let bounded = self.objective().form.is_bounded();
        let components: Vec<Component> = s
            .components()
            .iter()
            .map(|c| Component {
                name: c.name(),
                measure: c.measure,
                target: Some(c.target),
                weight: c.weight,
                error: Some(c.error),
                value: c.contribution,
                max: if bounded { c.weight } else { 0.0 },
            })
            .collect();
        let measures = components.iter().map(|c| (c.name, c.measure)).collect();
        Score { fitness: s.fitness(), components, measures }
    }

    fn max_reachable(&self, _: usize) -> f64 {
        self.best()
    }

    fn knobs(&self) -> Vec<Knob> {
        SurfaceCriterion::ALL
            .iter()
            .map(|c| {
                let g = self.objective().goal(*c);
                Knob {
                    name: c.name(),
                    kind: "[surface] criterion",
                    weight: g.weight,
                    target: Some(g.target),
                    signed: false,
                }
            })
            .collect()
    }

    fn with_knobs(&self, knobs: &[Knob]) -> Result<Box<dyn Scorer>, String> {
        let mut objective = *self.objective();
        for k in knobs {
            let c = SurfaceCriterion::from_name(k.name).ok_or_else(|| format!("[surface] has no `{}`", k.name))?;
            let goal = objective.goal_mut(c);
            goal.weight = k.weight;
            if let Some(t) = k.target {
                goal.target = t;
            }
        }
        SurfaceScorer::new(objective).map(|s| Box::new(s) as Box<dyn Scorer>).map_err(|e| format!("[surface]: {e}"))
    }

    fn chart(&self) -> Option<&'static str> {
        Some(self.objective().form.contribution_formula())
    }

    fn form(&self) -> &'static str {
        self.objective().form.name()
    }

    /// Surfaces by face count and criteria values, not bounds: a surface and
    /// its mirror image (GE finds many) score and look alike.
    fn look(&self, scene: &Scene, score: &Score) -> String {
        crate::look::surface_look(scene, &score.measures.iter().map(|(_, v)| *v).collect::<Vec<_>>())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Form, SurfaceObjective};

    struct Fixed(Counts);

    impl Counter for Fixed {
        fn scratch(&self) -> Scratch {
            Box::new(0u32)
        }
        fn counts(&self, _: &Scene, scratch: &mut Scratch) -> Counts {
            *downcast::<u32>(scratch) += 1;
            self.0
        }
    }

    #[test]
    fn targets_sum_counts_and_components_add_up_to_the_fitness() {
        let a = Counts { good: 30.0, bad: 5.0, overlap: 2.0, outside: 1.0, target: 60.0 };
        let b = Counts { good: 10.0, bad: 7.0, overlap: 0.0, outside: 0.0, target: 20.0 };
        for form in Form::NAMES.map(|(_, f)| f) {
            let fitness = Fitness { form, length: 0.3, ..Fitness::default() };
            let t = Targets::new(vec![std::sync::Arc::new(Fixed(a)), std::sync::Arc::new(Fixed(b))], fitness);
            let mut s = Scorer::scratch(&t);
            let scene = Scene::new();
            let mut sum = a;
            sum += b;
            assert_eq!(t.fitness(&scene, 40, &mut s), fitness.eval(&sum, 40));
            let score = t.score(&scene, 40, &mut s);
            let total: f64 = score.components.iter().map(|c| c.value).sum();
            assert!((total - score.fitness).abs() < 1e-12, "{form:?}: {total} vs {}", score.fitness);
            assert_eq!(score.measure("good"), Some(40.0));
            assert!(score.components.iter().all(|c| c.value <= c.max + 1e-12), "{score:?}");
        }
    }

    #[test]
    fn knobs_change_weights_by_name() {
        let t = Targets::new(vec![std::sync::Arc::new(Fixed(Counts::default()))], Fitness::default());
        let mut knobs = t.knobs();
        assert_eq!(knobs.iter().map(|k| k.name).collect::<Vec<_>>(), FITNESS_WEIGHTS);
        knobs[0].weight = 5.0;
        let steered = t.with_knobs(&knobs[..1]).unwrap();
        assert_eq!(steered.knobs()[0].weight, 5.0);
        assert_eq!(t.knobs()[0].weight, 2.0, "the original is unchanged");
        let s = SurfaceScorer::new(SurfaceObjective::default().with(SurfaceCriterion::Size, 10.0, 1.0)).unwrap();
        let mut k = s.knobs();
        assert_eq!(k.len(), 6);
        k[0].weight = 0.0;
        assert!(s.with_knobs(&k[..1]).err().unwrap().starts_with("[surface]"));
        k[0].weight = 2.0;
        k[0].target = Some(4.0);
        let steered = s.with_knobs(&k[..1]).unwrap();
        assert_eq!((steered.knobs()[0].weight, steered.knobs()[0].target), (2.0, Some(4.0)));
        assert_eq!(steered.chart(), Some("w/(1+e)"));
    }
}
