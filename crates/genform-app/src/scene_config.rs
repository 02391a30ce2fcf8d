//! Scene configs: the TOML files `genform evolve` reads (a grammar, the
//! targets to steer it towards, the fitness constants and the optimizer's
//! settings). Parsing is declarative (serde, unknown keys rejected);
//! [`SceneConfig::load`] then resolves paths against the file's folder and
//! checks values, so every mistake is reported with the file name and the
//! key that is wrong.

use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// The whole file, as written.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SceneConfig {
    /// Grammar file, relative to the config.
    pub grammar: PathBuf,
    /// A one-line description, shown in `run.json` and the plots.
    #[serde(default)]
    pub description: String,
    /// The voxel target, if any.
    #[serde(default)]
    pub volume: Option<VolumeConfig>,
    /// Image targets (any number, each with its camera).
    #[serde(default)]
    pub image: Vec<ImageConfig>,
    /// Fitness constants.
    #[serde(default)]
    pub fitness: FitnessConfig,
    /// Genetic-algorithm settings (see `genform_evolve::GaConfig`).
    #[serde(default)]
    pub ga: genform_evolve::GaConfig,
    /// MCMC settings (see `genform_evolve::MhConfig`); when the section is
    /// absent, the chains take their lengths from `[ga]`.
    #[serde(default)]
    pub mh: Option<genform_evolve::MhConfig>,
    /// SMC/SOSMC settings (see `genform_evolve::SmcConfig`); when absent,
    /// `max_length` follows `[ga]`.
    #[serde(default)]
    pub smc: Option<genform_evolve::SmcConfig>,
    /// The hybrid's switching rules (see `genform_evolve::HybridConfig`).
    #[serde(default)]
    pub hybrid: genform_evolve::HybridConfig,
    /// MAP-Elites settings (see `genform_evolve::MapElitesConfig`);
    /// descriptor ranges left out take each descriptor's default.
    #[serde(default)]
    pub map_elites: genform_evolve::MapElitesConfig,
    /// When to stop (command-line flags override it).
    #[serde(default)]
    pub run: RunConfig,
    /// Derivation limits overriding the grammar's own.
    #[serde(default)]
    pub limits: LimitsConfig,
}

/// `[volume]`: a voxel grid and the volumes to fill or avoid.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct VolumeConfig {
    /// Grid corner with the smallest coordinates.
    pub min: [f32; 3],
    /// Grid corner with the largest coordinates.
    pub max: [f32; 3],
    /// Voxels along x, y and z.
    pub voxels: [u32; 3],
    /// The target volumes (at least one).
    pub target: Vec<VolumeTargetConfig>,
}

/// `[[volume.target]]`: one volume, from a mesh or a grammar with a fixed genome.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct VolumeTargetConfig {
    /// A mesh file (.obj, .stl, .glb), voxelized robustly.
    #[serde(default)]
    pub mesh: Option<PathBuf>,
    /// A grammar whose fixed genome (`genome`) makes the target.
    #[serde(default)]
    pub grammar: Option<PathBuf>,
    /// The genome for `grammar` (JSON, as `genform sample --genome-out` writes).
    #[serde(default)]
    pub genome: Option<PathBuf>,
    /// Weight of each covered target voxel (w_i; negative = stay out).
    #[serde(default = "one")]
    pub fill: f64,
    /// Weight of each model voxel outside this target (w̃_i).
    #[serde(default = "one")]
    pub avoid: f64,
}

/// `[[image]]`: a silhouette target seen through a camera.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ImageConfig {
    /// Target picture: a PNG (dark = target) or a PFM float weight image.
    pub target: PathBuf,
    /// How a PNG is read: "dark" (dark = target, rest = avoid) or "signed"
    /// (grey 128 = don't care, white = +1, black = −1).
    #[serde(default = "dark")]
    pub mode: String,
    /// Rendering width in pixels (must match the target).
    #[serde(default = "width")]
    pub width: u32,
    /// Rendering height in pixels (must match the target).
    #[serde(default = "height")]
    pub height: u32,
    /// The orbit camera.
    pub camera: CameraConfig,
}

/// An orbit camera: eye = look_at + radius·(cosθ cosφ, sinθ, cosθ sinφ).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CameraConfig {
    /// Vertical field of view in degrees.
    #[serde(default = "fov")]
    pub fov: f32,
    /// Azimuth in radians.
    pub phi: f32,
    /// Elevation in radians.
    pub theta: f32,
    /// Distance from the look-at point.
    pub radius: f32,
    /// The point at the image centre.
    pub look_at: [f32; 3],
}

/// `[fitness]`: the constants of the fitness formula.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FitnessConfig {
    /// "paper", "separate-overlap", "image", "linear" or "reference-cpu";
    /// an unknown name is an error at its line:col.
    #[serde(default, deserialize_with = "known_form")]
    pub form: Option<String>,
    /// Weight of covered target (α).
    #[serde(default = "two")]
    pub good: f64,
    /// Weight of covered non-target (β).
    #[serde(default = "fifteen")]
    pub bad: f64,
    /// Weight of self-overlap.
    #[serde(default = "one")]
    pub overlap: f64,
    /// Weight of the genome-length penalty (γ).
    #[serde(default = "tenth")]
    pub length: f64,
    /// Lengths over which the penalty rises from 0 to full; defaults to
    /// the GA's length bounds.
    #[serde(default)]
    pub length_range: Option<[f64; 2]>,
}

impl FitnessConfig {
    /// Replaces the form with `form` (e.g. `genform score --form`) after
    /// checking its name.
    pub fn override_form(&mut self, form: Option<&str>) -> Result<()> {
        if let Some(form) = form {
            check_form(form).map_err(anyhow::Error::msg)?;
            self.form = Some(form.to_string());
        }
        Ok(())
    }
}

/// Reads a `form` value, refusing names that are not a fitness form (the
/// TOML reader adds the value's position). Every scene's `[fitness]` is
/// read through here, so a loaded form is always a known one.
fn known_form<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Option<String>, D::Error> {
    let name = String::deserialize(d)?;
    check_form(&name).map_err(serde::de::Error::custom)?;
    Ok(Some(name))
}

/// Whether `name` is a fitness form; the error lists the forms.
fn check_form(name: &str) -> std::result::Result<(), String> {
    match genform_score::Form::from_name(name) {
        Some(_) => Ok(()),
        None => {
            let names: Vec<&str> = genform_score::Form::NAMES.iter().map(|(n, _)| *n).collect();
            Err(format!("form `{name}` is unknown; use one of: {}", names.join(", ")))
        }
    }
}

impl Default for FitnessConfig {
    fn default() -> Self {
        FitnessConfig { form: None, good: 2.0, bad: 15.0, overlap: 1.0, length: 0.1, length_range: None }
    }
}

/// `[run]`: stopping rules.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RunConfig {
    /// Stop after this many generations.
    #[serde(default)]
    pub generations: Option<usize>,
    /// Stop after this wall-clock time, e.g. "30s", "2m", "1h".
    #[serde(default)]
    pub budget: Option<String>,
    /// Stop after this many evaluations.
    #[serde(default)]
    pub evaluations: Option<u64>,
}

impl RunConfig {
    /// Checks that the budget, if any, is a duration.
    pub fn check(&self) -> Result<()> {
        if let Some(b) = &self.budget {
            parse_duration(b).context("[run] budget")?;
        }
        Ok(())
    }
}

/// `[limits]`: derivation limits overriding the grammar's.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LimitsConfig {
    /// Most genes.
    #[serde(default)]
    pub genes: Option<usize>,
    /// Deepest gene.
    #[serde(default)]
    pub depth: Option<usize>,
    /// Most primitives.
    #[serde(default)]
    pub primitives: Option<usize>,
}

impl LimitsConfig {
    /// The `[limits]` as overrides of a grammar's limits.
    pub fn overrides(&self) -> crate::grammar::LimitOverrides {
        crate::grammar::LimitOverrides { max_genes: self.genes, max_depth: self.depth, max_primitives: self.primitives }
    }
}

fn one() -> f64 {
    1.0
}
fn two() -> f64 {
    2.0
}
fn fifteen() -> f64 {
    15.0
}
fn tenth() -> f64 {
    0.1
}
fn fov() -> f32 {
    60.0
}
fn width() -> u32 {
    800
}
fn height() -> u32 {
    600
}
fn dark() -> String {
    "dark".into()
}

/// A loaded config with every path resolved against its folder.
#[derive(Clone, Debug)]
pub struct LoadedScene {
    /// The config file.
    pub path: PathBuf,
    /// Its contents (paths absolute or relative to the working folder).
    pub config: SceneConfig,
}

impl SceneConfig {
    /// Reads, parses and checks the config at `path`.
    pub fn load(path: &Path) -> Result<LoadedScene> {
        let (mut config, base) = read_scene::<SceneConfig>(path)?;
        crate::objective::check_descriptor_names(path, None, &config.map_elites)?;
        config.resolve(base);
        config.check().with_context(|| format!("in scene {}", path.display()))?;
        crate::memory::check_sizes(path, None, &config.memory_sizes())?;
        Ok(LoadedScene { path: path.to_path_buf(), config })
    }

    /// [`SceneConfig::load`] with a settings patch applied first (the
    /// scene as written is checked first, so its own mistakes keep their
    /// positions).
    pub fn load_patched(path: &Path, patch: &[crate::sweep::set::Axis]) -> Result<LoadedScene> {
        if patch.is_empty() {
            return SceneConfig::load(path);
        }
        let text = crate::source_text::read_text(path, "scene")?;
        SceneConfig::load_text(path, &text)?;
        let text = crate::sweep::set::patched_text::<SceneConfig>(path, &text, patch)?;
        SceneConfig::load_text(path, &text)
    }

    /// [`SceneConfig::load`] of `text` standing for the file at `path` (its
    /// folder resolves relative paths): `genform sweep` loads edited copies.
    pub fn load_text(path: &Path, text: &str) -> Result<LoadedScene> {
        let mut config: SceneConfig = parse_toml(path, text)?;
        crate::objective::check_descriptor_names(path, Some(text), &config.map_elites)?;
        config.resolve(path.parent().unwrap_or(Path::new(".")));
        config.check().with_context(|| format!("in scene {}", path.display()))?;
        crate::memory::check_sizes(path, Some(text), &config.memory_sizes())?;
        Ok(LoadedScene { path: path.to_path_buf(), config })
    }

    /// The sizes this scene asks for, checked against the memory budget
    /// (see [`crate::memory`]): the GA's population, the MCMC chains, the
    /// SMC particles, the MAP-Elites archive and batches, and the targets.
    /// Each optimizer holds about two genomes per member (parents and
    /// children, current and proposal, particles and their resampling).
    pub fn memory_sizes(&self) -> Vec<crate::memory::Size<'static>> {
        use crate::memory::{GENE_BYTES, INDIVIDUAL_BYTES, Size, estimate, human};
        let genome = |genes: usize| INDIVIDUAL_BYTES.saturating_add((genes as u64).saturating_mul(GENE_BYTES));
        let members = |section: &'static str, key: &'static str, n: usize, genes: usize| {
            let each = genome(genes);
            Size {
                section,
                key,
                value: n as u128,
                bytes: estimate(n as u64, each).saturating_mul(2),
                what: format!("2 × {n} genomes of up to {genes} genes, about {} each", human(each as f64)),
            }
        };
        let mut sizes = vec![members("ga", "population", self.ga.population, self.ga.initial_length[1])];
        if let Some(mh) = &self.mh {
            sizes.push(members("mh", "chains", mh.chains, mh.initial_length[1]));
        }
        if let Some(smc) = &self.smc {
            sizes.push(members("smc", "particles", smc.particles, smc.max_length));
        }
        let me = &self.map_elites;
        let cells = me.descriptors.iter().fold(1u128, |n, d| n.saturating_mul(d.bins as u128));
        let cell_bytes = u128::from(genome(self.ga.max_length));
        sizes.push(Size {
            section: "map_elites",
            key: "descriptors",
            value: cells,
            bytes: cells.saturating_mul(cell_bytes),
            what: format!("an archive of {cells} cells, each up to a genome of {}", human(cell_bytes as f64)),
        });
        sizes.push(members("map_elites", "initial", me.initial, self.ga.initial_length[1]));
        sizes.push(members("map_elites", "batch", me.batch, self.ga.max_length));
        sizes.extend(target_sizes(self.volume.as_ref(), &self.image));
        let l = &self.limits;
        sizes.extend(crate::memory::limit_sizes(&[
            ("genes", l.genes, GENE_BYTES, "genes"),
            ("primitives", l.primitives, PRIMITIVE_BYTES, "primitives"),
        ]));
        sizes
    }

    /// Makes every path absolute against `base` (the scene's folder).
    pub(crate) fn resolve(&mut self, base: &Path) {
        let fix = |p: &mut PathBuf| *p = base.join(&*p);
        fix(&mut self.grammar);
        if let Some(v) = &mut self.volume {
            for t in &mut v.target {
                for p in [&mut t.mesh, &mut t.grammar, &mut t.genome].into_iter().flatten() {
                    fix(p);
                }
            }
        }
        for i in &mut self.image {
            fix(&mut i.target);
        }
    }

    /// Checks the targets, fitness constants, stop rules and algorithm settings.
    pub(crate) fn check(&self) -> Result<()> {
        if self.volume.is_none() && self.image.is_empty() {
            bail!("no target: add a [volume] section or an [[image]] section");
        }
        if let Some(v) = &self.volume {
            if v.target.is_empty() {
                bail!("[volume] needs at least one [[volume.target]]");
            }
            for (i, t) in v.target.iter().enumerate() {
                match (&t.mesh, &t.grammar, &t.genome) {
                    (Some(_), None, None) | (None, Some(_), Some(_)) => {}
                    _ => bail!(
                        "[[volume.target]] #{}: give either `mesh = \"file.obj\"` or both `grammar` and `genome`",
                        i + 1
                    ),
                }
                if !t.fill.is_finite() || !t.avoid.is_finite() {
                    bail!("[[volume.target]] #{}: `fill` and `avoid` must be finite numbers", i + 1);
                }
            }
        }
        for (i, img) in self.image.iter().enumerate() {
            if genform_score::PngMode::from_name(&img.mode).is_none() {
                bail!("[[image]] #{}: mode `{}` is unknown; use \"dark\" or \"signed\"", i + 1, img.mode);
            }
        }
        for (k, v) in [
            ("good", self.fitness.good),
            ("bad", self.fitness.bad),
            ("overlap", self.fitness.overlap),
            ("length", self.fitness.length),
        ] {
            if !v.is_finite() {
                bail!("[fitness] `{k}` must be a finite number");
            }
        }
        self.run.check()?;
        self.ga.validate().map_err(|e| anyhow::anyhow!("[ga]: {e}"))?;
        let settings = self.settings();
        settings.mh.validate().map_err(|e| anyhow::anyhow!("[mh]: {e}"))?;
        settings.smc.validate().map_err(|e| anyhow::anyhow!("[smc]: {e}"))?;
        settings.hybrid.validate().map_err(|e| anyhow::anyhow!("[hybrid]: {e}"))?;
        settings.map_elites.validate_ranges().map_err(|e| anyhow::anyhow!("[map_elites]: {e}"))?;
        Ok(())
    }

    /// This config as a run ran it, for `run.json`: defaults that depend on
    /// other keys written out (`[ga] elitism`, a fifth of the population
    /// when left out).
    pub fn as_run(&self) -> SceneConfig {
        let mut c = self.clone();
        c.ga.elitism = Some(c.ga.elites());
        c
    }

    /// The settings of every algorithm; absent `[mh]` and `[smc]` sections
    /// take their defaults with the genome lengths of `[ga]`, unset
    /// `[map_elites]` ranges their descriptor's default.
    pub fn settings(&self) -> genform_evolve::Settings {
        let ga = &self.ga;
        let mh = self.mh.clone().unwrap_or_else(|| genform_evolve::MhConfig {
            initial_length: ga.initial_length,
            min_length: ga.min_length,
            max_length: ga.max_length,
            ..Default::default()
        });
        let smc = self
            .smc
            .clone()
            .unwrap_or_else(|| genform_evolve::SmcConfig { max_length: ga.max_length, ..Default::default() });
        genform_evolve::Settings { ga: ga.clone(), mh, smc, hybrid: self.hybrid.clone(), map_elites: self.map_elites() }
    }

    /// `[map_elites]` with every unset descriptor range filled in by
    /// [`Descriptor::default_range`](crate::objective::Descriptor::default_range).
    pub fn map_elites(&self) -> genform_evolve::MapElitesConfig {
        let mut config = self.map_elites.clone();
        let box_size = self.volume.as_ref().map(|v| [0, 1, 2].map(|k| f64::from(v.max[k] - v.min[k])));
        for axis in &mut config.descriptors {
            if let (None, Some(d)) = (axis.range, crate::objective::Descriptor::from_name(&axis.name)) {
                axis.range = Some(d.default_range([self.ga.min_length, self.ga.max_length], box_size));
            }
        }
        config
    }

    /// The fitness function: the configured form, or "image" for image-only
    /// scenes and "paper" otherwise; the length range defaults to the GA's
    /// length bounds.
    pub fn fitness(&self) -> genform_score::Fitness {
        let f = &self.fitness;
        let form = f.form.as_deref().and_then(genform_score::Form::from_name).unwrap_or(if self.volume.is_none() {
            genform_score::Form::Image
        } else {
            genform_score::Form::Paper
        });
        let [from, to] = f.length_range.unwrap_or([self.ga.min_length as f64, self.ga.max_length as f64]);
        genform_score::Fitness {
            form,
            good: f.good,
            bad: f.bad,
            overlap: f.overlap,
            length: f.length,
            length_from: from,
            length_to: to,
        }
    }
}

/// Bytes per voxel of a volume target: its weight, the model's occupancy
/// and the scorer's per-thread counts.
const VOXEL_BYTES: u128 = 16;
/// Bytes per drawn primitive of a scene (an affine transform, a primitive
/// id and a tag), with the voxelizer's share.
pub(crate) const PRIMITIVE_BYTES: u64 = 96;
/// Bytes per pixel of an image target: its weight and the rendering.
const PIXEL_BYTES: u128 = 16;

/// The sizes of the target grids (`[volume] voxels`, `[[image]]`
/// `width` × `height`), checked against the memory budget.
pub(crate) fn target_sizes(volume: Option<&VolumeConfig>, image: &[ImageConfig]) -> Vec<crate::memory::Size<'static>> {
    use crate::memory::{Size, human};
    let mut sizes = Vec::new();
    if let Some(v) = volume {
        let n = v.voxels.iter().fold(1u128, |n, &k| n.saturating_mul(u128::from(k)));
        sizes.push(Size {
            section: "volume",
            key: "voxels",
            value: n,
            bytes: n.saturating_mul(VOXEL_BYTES),
            what: format!("a grid of {n} voxels, {} each", human(VOXEL_BYTES as f64)),
        });
    }
    for img in image {
        let n = u128::from(img.width) * u128::from(img.height);
        sizes.push(Size {
            section: "image",
            key: "width",
            value: n,
            bytes: n.saturating_mul(PIXEL_BYTES),
            what: format!("a {} × {} picture, {} a pixel", img.width, img.height, human(PIXEL_BYTES as f64)),
        });
    }
    sizes
}

/// Reads and parses the scene file at `path`; returns it with the folder
/// its relative paths start from.
pub(crate) fn read_scene<T: serde::de::DeserializeOwned>(path: &Path) -> Result<(T, &Path)> {
    let text = crate::source_text::read_text(path, "scene")?;
    let config = parse_toml(path, &text)?;
    Ok((config, path.parent().unwrap_or(Path::new("."))))
}

/// Parses scene TOML `text` read from `path`; errors (unknown keys, wrong
/// types) name the file and the `line:col` of the offending key.
pub fn parse_toml<T: serde::de::DeserializeOwned>(path: &Path, text: &str) -> Result<T> {
    toml::from_str(text).map_err(|e| {
        let at = e
            .span()
            .map(|s| {
                let line = text[..s.start.min(text.len())].matches('\n').count() + 1;
                let col = s.start - text[..s.start.min(text.len())].rfind('\n').map_or(0, |i| i + 1) + 1;
                format!(":{line}:{col}")
            })
            .unwrap_or_default();
        anyhow::anyhow!("{}{at}: {}", path.display(), e.message())
    })
}

/// Parses "30s", "2m", "1.5h", "500ms" or a bare number of seconds.
pub fn parse_duration(s: &str) -> Result<Duration> {
    let s = s.trim();
    let split = s.find(|c: char| c.is_ascii_alphabetic()).unwrap_or(s.len());
    let (num, unit) = s.split_at(split);
    let v: f64 = num.trim().parse().with_context(|| format!("`{s}` is not a duration such as 30s, 5m or 1h"))?;
    let secs = match unit.trim() {
        "" | "s" | "sec" => v,
        "ms" => v / 1000.0,
        "m" | "min" => v * 60.0,
        "h" => v * 3600.0,
        u => bail!("unknown time unit `{u}` in `{s}`; use ms, s, m or h"),
    };
    if !(secs.is_finite() && secs > 0.0) {
        bail!("duration `{s}` must be positive");
    }
    if secs >= 1e9 {
        bail!("duration `{s}` is too long: at most 999,999,999 s (about 31 years)");
    }
    Ok(Duration::from_secs_f64(secs))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations() {
        assert_eq!(parse_duration("30s").unwrap(), Duration::from_secs(30));
        assert_eq!(parse_duration("2m").unwrap(), Duration::from_secs(120));
        assert_eq!(parse_duration("1.5h").unwrap(), Duration::from_secs(5400));
        assert_eq!(parse_duration("250ms").unwrap(), Duration::from_millis(250));
        assert_eq!(parse_duration("12").unwrap(), Duration::from_secs(12));
        assert!(parse_duration("-3s").unwrap_err().to_string().contains("positive"));
        let err = parse_duration("99999999999999999999h").unwrap_err().to_string();
        assert!(err.contains("too long"), "{err}");
        assert!(parse_duration("3 fortnights").is_err());
        assert!(parse_duration("fast").is_err());
    }
}
