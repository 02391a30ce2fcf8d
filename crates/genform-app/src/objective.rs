//! The objective `genform evolve` optimizes: express a genome with the
//! scene's generator, score the Scene against every target, combine the
//! counts with the genome length into one fitness.
//!
//! This glue is the only place that knows both a generator and the scorers;
//! the optimizers see an [`Objective`] and genomes, the scorers see Scenes.

use genform_core::{ExpressError, Generator, Genome, Limits, Primitive, Scene};
use genform_evolve::Objective;
use genform_score::{Counts, Fitness, ImageScorer, ImageScratch, VolumeScorer, VolumeScratch};
use glam::Vec3;

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

    /// Empties the caches the scorers keep across evaluations (results
    /// never depend on them; measurements of unrelated models clear them).
    pub fn clear_caches(&self) {
        if let Some(v) = &self.volume {
            v.clear_caches();
        }
        for i in &self.images {
            i.clear_caches();
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

/// A behaviour descriptor of a model: what MAP-Elites spreads its archive
/// over and what the gallery tells individuals apart by. Sizes are along
/// the scene's axes (+y is up in previews).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Descriptor {
    /// Genes of the genome.
    Length,
    /// Bounding box: longest side over shortest side (≥ 1; the shortest
    /// side counts as at least 1 % of the longest, so flat models give 100,
    /// not infinity).
    Aspect,
    /// Bounding box along x.
    Width,
    /// Bounding box along y (up).
    Height,
    /// Bounding box along z.
    Depth,
    /// Instanced primitives, polylines and polygons of the scene.
    Primitives,
}

impl Descriptor {
    /// Every descriptor with its name in scene files.
    pub const ALL: [(&'static str, Descriptor); 6] = [
        ("length", Descriptor::Length),
        ("aspect", Descriptor::Aspect),
        ("width", Descriptor::Width),
        ("height", Descriptor::Height),
        ("depth", Descriptor::Depth),
        ("primitives", Descriptor::Primitives),
    ];

    /// The descriptor called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().find(|(n, _)| *n == name).map(|(_, d)| *d)
    }

    /// The two descriptors `config` names (names are checked when a scene
    /// loads, see [`check_descriptor_names`]; an unknown one reads as `length`).
    pub fn pair(config: &genform_evolve::MapElitesConfig) -> [Descriptor; 2] {
        config.descriptors.each_ref().map(|d| Descriptor::from_name(&d.name).unwrap_or(Descriptor::Length))
    }

    /// Its name in scene files.
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(_, d)| *d == self).map_or("", |(n, _)| n)
    }

    /// Its value for `genome` expressed as `scene`; NaN for a size of an
    /// empty scene.
    pub fn value(self, genome: &Genome, scene: &Scene) -> f64 {
        let size = || extent(scene).unwrap_or([f32::NAN; 3]).map(f64::from);
        match self {
            Descriptor::Length => genome.len() as f64,
            Descriptor::Aspect => {
                let s = size();
                let longest = s[0].max(s[1]).max(s[2]);
                longest / s[0].min(s[1]).min(s[2]).max(0.01 * longest)
            }
            Descriptor::Width => size()[0],
            Descriptor::Height => size()[1],
            Descriptor::Depth => size()[2],
            Descriptor::Primitives => (scene.instances.len() + scene.polylines.len() + scene.polygons.len()) as f64,
        }
    }

    /// The range binned when a scene gives none: `length` the GA's length
    /// bounds `[min_length, max_length]`; `aspect` [1, 6]; a size from 0
    /// to the `[volume]` grid's side along its axis (`box_size`, else 10);
    /// `primitives` [0, max_length].
    pub fn default_range(self, lengths: [usize; 2], box_size: Option<[f64; 3]>) -> [f64; 2] {
        let side = |axis: usize| [0.0, box_size.map_or(10.0, |b| b[axis])];
        match self {
            Descriptor::Length => [lengths[0] as f64, lengths[1] as f64],
            Descriptor::Aspect => [1.0, 6.0],
            Descriptor::Width => side(0),
            Descriptor::Height => side(1),
            Descriptor::Depth => side(2),
            Descriptor::Primitives => [0.0, lengths[1] as f64],
        }
    }
}

/// Checks that `[map_elites]` names only known descriptors. An unknown
/// name is reported at its `file:line:col` in `text` (the scene's text;
/// read from `path` when `None`), with a did-you-mean hint.
pub fn check_descriptor_names(
    path: &std::path::Path,
    text: Option<&str>,
    config: &genform_evolve::MapElitesConfig,
) -> anyhow::Result<()> {
    let Some(bad) = config.descriptors.iter().map(|d| d.name.as_str()).find(|n| Descriptor::from_name(n).is_none())
    else {
        return Ok(());
    };
    let names = Descriptor::ALL.map(|(n, _)| n);
    let hint =
        genform_core::expr::did_you_mean(bad, names).map(|n| format!("did you mean `{n}`? ")).unwrap_or_default();
    let at = match text {
        Some(t) => name_position(t, bad),
        None => std::fs::read_to_string(path).ok().and_then(|t| name_position(&t, bad)),
    };
    anyhow::bail!(
        "{}{}: [map_elites] descriptor `{bad}` is unknown; {hint}the descriptors are {}",
        path.display(),
        at.map(|(l, c)| format!(":{l}:{c}")).unwrap_or_default(),
        names.join(", ")
    )
}

/// `(line, column)` of the `[map_elites]` descriptor name `bad` in the
/// scene text: a second, lenient read that keeps the names' spans.
fn name_position(text: &str, bad: &str) -> Option<(usize, usize)> {
    #[derive(serde::Deserialize)]
    struct Doc {
        map_elites: Option<Section>,
    }
    #[derive(serde::Deserialize)]
    struct Section {
        #[serde(default)]
        descriptors: Vec<Axis>,
    }
    #[derive(serde::Deserialize)]
    struct Axis {
        name: toml::Spanned<String>,
    }
    let doc: Doc = toml::from_str(text).ok()?;
    let span = doc.map_elites?.descriptors.into_iter().find(|a| a.name.get_ref() == bad)?.name.span();
    let before = &text[..span.start.min(text.len())];
    Some((before.matches('\n').count() + 1, span.start - before.rfind('\n').map_or(0, |i| i + 1) + 1))
}

/// Sides of the axis-aligned bounding box of the scene's geometry, or
/// `None` for an empty scene. Each instance counts with its primitive's
/// local box (the unit cube for built-in primitives, the mesh's box for a
/// mesh) carried to world space: exact for boxes, slightly generous for
/// rotated curved ones, and a few operations per instance instead of
/// tessellating — MAP-Elites measures every evaluated model.
fn extent(scene: &Scene) -> Option<[f32; 3]> {
    let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for inst in &scene.instances {
        let (a, b) = match inst.primitive {
            Primitive::Mesh(id) => {
                let mesh = &scene.meshes[id as usize];
                let Some(&first) = mesh.positions.first() else { continue };
                mesh.positions.iter().fold((first, first), |(a, b), p| (a.min(*p), b.max(*p)))
            }
            Primitive::Frustum { top } | Primitive::TaperedBox { top } => {
                let r = 0.5 * top.max(1.0);
                (Vec3::new(-r, -0.5, -r), Vec3::new(r, 0.5, r))
            }
            Primitive::Box | Primitive::Sphere => (Vec3::splat(-0.5), Vec3::splat(0.5)),
        };
        let m = inst.transform.matrix3;
        let centre = inst.transform.transform_point3((a + b) * 0.5);
        let half = (b - a) * 0.5;
        let reach = Vec3::from(m.x_axis.abs() * half.x + m.y_axis.abs() * half.y + m.z_axis.abs() * half.z);
        lo = lo.min(centre - reach);
        hi = hi.max(centre + reach);
    }
    let points = scene.polylines.points().iter().chain(scene.polygons.iter().flat_map(|p| &p.points));
    for p in points.chain(scene.surfaces.iter().flat_map(|s| &s.positions)) {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    (lo.x <= hi.x).then(|| (hi - lo).to_array())
}

/// [`SceneObjective`] that also reports two [`Descriptor`]s, for MAP-Elites.
pub struct DescribedObjective<'a> {
    /// The fitness.
    pub objective: SceneObjective<'a>,
    /// The descriptors, in archive-axis order.
    pub descriptors: [Descriptor; 2],
}

impl Objective for DescribedObjective<'_> {
    type Scratch = EvalScratch;

    fn scratch(&self) -> EvalScratch {
        self.objective.scratch()
    }

    fn evaluate(&self, genome: &Genome, scratch: &mut EvalScratch) -> f64 {
        self.objective.evaluate(genome, scratch)
    }

    fn evaluate_described(&self, genome: &Genome, scratch: &mut EvalScratch, descriptors: &mut [f64; 2]) -> f64 {
        match self.objective.counts(genome, scratch) {
            Ok(c) => {
                *descriptors = self.descriptors.map(|d| d.value(genome, &scratch.scene));
                self.objective.scorers.fitness.eval(&c, genome.len())
            }
            Err(_) => {
                *descriptors = [f64::NAN; 2];
                f64::NEG_INFINITY
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_core::Instance;

    fn boxes(corners: &[[f32; 3]]) -> Scene {
        let mut scene = Scene::new();
        for &c in corners {
            let transform = glam::Affine3A::from_translation(c.into());
            scene.instances.push(Instance { transform, primitive: Primitive::Box, tag: 0 });
        }
        scene
    }

    #[test]
    fn descriptors_measure_the_bounding_box() {
        // Two unit boxes 4 apart along z: a 1 × 1 × 5 box.
        let scene = boxes(&[[0.0, 0.0, 0.0], [0.0, 0.0, 4.0]]);
        let genome = Genome::default();
        let v = |d: Descriptor| d.value(&genome, &scene);
        assert_eq!((v(Descriptor::Width), v(Descriptor::Height), v(Descriptor::Depth)), (1.0, 1.0, 5.0));
        assert_eq!(v(Descriptor::Aspect), 5.0);
        assert_eq!(v(Descriptor::Primitives), 2.0);
        assert_eq!(v(Descriptor::Length), 0.0);
        assert!(Descriptor::Width.value(&genome, &Scene::new()).is_nan());
        for (name, d) in Descriptor::ALL {
            assert_eq!(Descriptor::from_name(name), Some(d));
            assert_eq!(d.name(), name);
        }
        assert_eq!(Descriptor::from_name("lenght"), None);
    }
}
