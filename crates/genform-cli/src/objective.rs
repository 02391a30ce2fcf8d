//! The objective `genform evolve` optimizes: express a genome with the
//! scene's generator, score the Scene against every target, combine the
//! counts with the genome length into one fitness.
//!
//! This glue is the only place that knows both a generator and the scorers;
//! the optimizers see an [`Objective`] and genomes, the scorers see Scenes.

use genform_core::{ExpressError, Generator, Genome, Limits, Scene};
use genform_evolve::Objective;
use genform_score::{Counts, Fitness, ImageScorer, ImageScratch, VolumeScorer, VolumeScratch};

/// Every target of a scene, with the fitness constants.
pub struct Scorers {
    /// The voxel target, if any.
    pub volume: Option<VolumeScorer>,
    /// Image targets.
    pub images: Vec<ImageScorer>,
    /// How counts become a fitness.
    pub fitness: Fitness,
}

/// Per-thread working memory of [`Scorers`].
pub struct ScorerScratch {
    volume: Option<VolumeScratch>,
    images: Vec<ImageScratch>,
}

impl Scorers {
    /// Fresh working memory for one thread.
    pub fn scratch(&self) -> ScorerScratch {
        ScorerScratch {
            volume: self.volume.as_ref().map(VolumeScorer::scratch),
            images: self.images.iter().map(ImageScorer::scratch).collect(),
        }
    }

    /// The summed counts of every target.
    pub fn counts(&self, scene: &Scene, scratch: &mut ScorerScratch) -> Counts {
        let mut c = Counts::default();
        if let (Some(v), Some(s)) = (&self.volume, &mut scratch.volume) {
            c += v.counts(scene, s);
        }
        for (img, s) in self.images.iter().zip(&mut scratch.images) {
            c += img.counts(scene, s);
        }
        c
    }
}

/// A generator scored by [`Scorers`]: the function optimizers maximize.
pub struct SceneObjective<'a> {
    /// Expresses genomes.
    pub generator: &'a dyn Generator,
    /// Derivation limits (a genome that exceeds them is invalid).
    pub limits: Limits,
    /// Scores the expressed Scene.
    pub scorers: &'a Scorers,
}

/// Per-thread working memory of [`SceneObjective`]: a reusable Scene and
/// the scorers' scratch.
pub struct EvalScratch {
    scene: Scene,
    scorers: ScorerScratch,
}

impl SceneObjective<'_> {
    /// Expresses `genome` and returns its counts, or why it cannot be
    /// expressed.
    pub fn counts(&self, genome: &Genome, scratch: &mut EvalScratch) -> Result<Counts, ExpressError> {
        scratch.scene.clear();
        self.generator.express(genome, &self.limits, &mut scratch.scene)?;
        Ok(self.scorers.counts(&scratch.scene, &mut scratch.scorers))
    }
}

impl Objective for SceneObjective<'_> {
    type Scratch = EvalScratch;

    fn scratch(&self) -> EvalScratch {
        EvalScratch { scene: Scene::new(), scorers: self.scorers.scratch() }
    }

    fn evaluate(&self, genome: &Genome, scratch: &mut EvalScratch) -> f64 {
        match self.counts(genome, scratch) {
            Ok(c) => self.scorers.fitness.eval(&c, genome.len()),
            Err(_) => f64::NEG_INFINITY,
        }
    }
}
