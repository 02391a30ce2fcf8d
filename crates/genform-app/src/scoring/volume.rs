//! `[volume]`: a voxel grid and the volumes a model should fill or avoid
//! (meshes, or a grammar's model from a fixed genome), scored by
//! [`genform_score::VolumeScorer`].

use anyhow::{Context, Result, bail};
use genform_core::{Mesh, Scene};
use genform_score::{Grid, ScoreError, VolumeScorer, VolumeTarget};
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::row::{Built, Part, ScorerRow, ScorerSection};
use crate::memory::{Size, human};
use crate::toml_doc::{Doc, Value};

/// The `[volume]` row.
pub(crate) struct Volume;

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

fn one() -> f64 {
    1.0
}

/// Bytes per voxel of a volume target: its weight, the model's occupancy
/// and the scorer's per-thread counts.
const VOXEL_BYTES: u128 = 16;

/// A read `[volume]`, with the positions of what can only be refused when
/// it is built.
#[derive(Debug)]
struct VolumeSection {
    config: VolumeConfig,
    /// `file:line:col` of `voxels`.
    voxels_at: String,
    /// `file:line:col` of each `[[volume.target]]`.
    places: Vec<String>,
}

impl ScorerRow for Volume {
    fn section(&self) -> &'static str {
        "volume"
    }

    fn read(&self, doc: &Doc, value: &Value, base: &Path) -> Result<Arc<dyn ScorerSection>> {
        let mut config: VolumeConfig = doc.read(value)?;
        // Too many voxels is left to the memory check, which says how many bytes.
        if let Err(e) = Grid::new(Vec3::from(config.min), Vec3::from(config.max), config.voxels)
            && !matches!(e, ScoreError::TooManyVoxels { .. })
        {
            let key = match &e {
                ScoreError::NonFiniteGrid { min, .. } if min.iter().any(|v| !v.is_finite()) => "min",
                ScoreError::NonFiniteGrid { .. } | ScoreError::EmptyGridAxis { .. } => "max",
                _ => "voxels",
            };
            return Err(doc.refuse(&["volume", key], format!("[volume]: {e}")));
        }
        if config.target.is_empty() {
            return Err(doc.refuse(&["volume"], "[volume] needs at least one [[volume.target]]"));
        }
        let mut places = Vec::new();
        for (i, t) in config.target.iter().enumerate() {
            let index = i.to_string();
            match (&t.mesh, &t.grammar, &t.genome) {
                (Some(_), None, None) | (None, Some(_), Some(_)) => {}
                _ => {
                    return Err(doc.refuse(
                        &["volume", "target", &index],
                        format!(
                            "[[volume.target]] #{}: give either `mesh = \"file.obj\"` or both `grammar` and `genome`",
                            i + 1
                        ),
                    ));
                }
            }
            for (key, v) in [("fill", t.fill), ("avoid", t.avoid)] {
                if !v.is_finite() {
                    return Err(doc.refuse(
                        &["volume", "target", index.as_str(), key],
                        format!("[[volume.target]] #{}: `{key}` must be a finite number, not {v}", i + 1),
                    ));
                }
            }
            places.push(doc.place(&["volume", "target", &index]));
        }
        for (i, t) in config.target.iter_mut().enumerate() {
            let index = i.to_string();
            for (key, p) in [("mesh", &mut t.mesh), ("grammar", &mut t.grammar), ("genome", &mut t.genome)] {
                if let Some(p) = p {
                    *p = base.join(&*p);
                    // A file no process of this kind may read is refused here, at its line.
                    crate::gate::admit_path(p)
                        .map_err(|e| crate::gate::placed(doc.place(&["volume", "target", index.as_str(), key]), e))?;
                }
            }
        }
        let voxels_at = doc.place(&["volume", "voxels"]);
        Ok(Arc::new(VolumeSection { config, voxels_at, places }))
    }
}

impl ScorerSection for VolumeSection {
    fn to_json(&self) -> serde_json::Value {
        serde_json::to_value(&self.config).unwrap_or_default()
    }

    fn memory(&self) -> Vec<Size<'static>> {
        let n = self.config.voxels.iter().fold(1u128, |n, &k| n.saturating_mul(u128::from(k)));
        vec![Size {
            section: "volume",
            key: "voxels",
            value: n,
            bytes: n.saturating_mul(VOXEL_BYTES),
            what: format!("a grid of {n} voxels, {} each", human(VOXEL_BYTES as f64)),
        }]
    }

    fn build(&self) -> Result<Built> {
        let c = &self.config;
        let grid = Grid::new(Vec3::from(c.min), Vec3::from(c.max), c.voxels)
            .with_context(|| format!("{}: [volume]", self.voxels_at))?;
        let mut targets = Vec::new();
        let mut ghosts = Vec::new();
        for (i, t) in c.target.iter().enumerate() {
            let at = || format!("{}: [[volume.target]] #{}", self.places[i], i + 1);
            let (target, ghost) = volume_target(t, &grid).with_context(at)?;
            if target.voxels.count() == 0 {
                bail!(
                    "{}: covers no voxel of the grid; check that it lies inside [volume] min/max and is a closed volume",
                    at()
                );
            }
            targets.push(target);
            ghosts.push(ghost);
        }
        let scorer = VolumeScorer::new(grid, targets)?;
        Ok(Built { part: Part::Counters(vec![Arc::new(scorer)]), ghosts, images: Vec::new() })
    }

    fn target_meshes(&self) -> Result<Vec<Mesh>> {
        self.config
            .target
            .iter()
            .enumerate()
            .map(|(i, t)| target_mesh(t).with_context(|| format!("[[volume.target]] #{}", i + 1)))
            .collect()
    }

    fn has_target_meshes(&self) -> bool {
        true
    }

    fn extent(&self) -> Option<[f64; 3]> {
        let c = &self.config;
        Some([0, 1, 2].map(|k| f64::from(c.max[k] - c.min[k])))
    }
}

/// A target's voxels on `grid` and the mesh pictures draw of it.
fn volume_target(t: &VolumeTargetConfig, grid: &Grid) -> Result<(VolumeTarget, Mesh)> {
    let (voxels, mesh) = match (&t.mesh, &t.grammar, &t.genome) {
        (Some(path), _, _) => {
            let mesh = crate::gate::read_mesh(path)?;
            (genform_score::target::from_mesh(grid, &mesh)?.0, mesh)
        }
        (None, Some(g), Some(genome)) => {
            let scene = fixed_genome_scene(g, genome)?;
            (genform_score::target::from_scene(grid, &scene), flatten(&scene))
        }
        _ => bail!("give either `mesh` or `grammar` and `genome`"),
    };
    Ok((VolumeTarget { voxels, fill: t.fill, avoid: t.avoid }, mesh))
}

/// The mesh a target is: the file, or the fixed genome's model flattened.
fn target_mesh(t: &VolumeTargetConfig) -> Result<Mesh> {
    match (&t.mesh, &t.grammar, &t.genome) {
        (Some(path), _, _) => Ok(crate::gate::read_mesh(path)?),
        (None, Some(g), Some(genome)) => Ok(flatten(&fixed_genome_scene(g, genome)?)),
        _ => bail!("give either `mesh` or `grammar` and `genome`"),
    }
}

/// The Scene a grammar makes from a fixed genome file.
fn fixed_genome_scene(grammar_path: &Path, genome_path: &Path) -> Result<Scene> {
    let loaded = crate::formalism::load_generator(grammar_path)?;
    let genome = loaded.read_genome(genome_path)?;
    let mut scene = Scene::new();
    loaded.generator.express(&genome, &loaded.limits, &mut scene).context("cannot build the target model")?;
    Ok(scene)
}

/// A scene's triangles as one mesh.
fn flatten(scene: &Scene) -> Mesh {
    let mut m = Mesh { name: "target".into(), ..Mesh::default() };
    scene.for_each_triangle(Default::default(), |t, _| {
        let i = m.positions.len() as u32;
        m.positions.extend(t);
        m.triangles.push([i, i + 1, i + 2]);
    });
    m
}
