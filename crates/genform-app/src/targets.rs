//! Building the scorers of a scene config: reading target meshes, genomes
//! and pictures, voxelizing and checking them.

use anyhow::{Context, Result, bail};
use genform_core::Scene;
use genform_core::camera::Camera;
use genform_score::{Grid, ImageScorer, ImageTarget, PngMode, VolumeScorer, VolumeTarget};
use glam::Vec3;
use std::path::Path;

use crate::grammar;
use crate::objective::Scorers;
use crate::scene_config::{ImageConfig, SceneConfig, VolumeConfig, VolumeTargetConfig};

/// The scorers `config` describes.
pub fn build(config: &SceneConfig) -> Result<Scorers> {
    let volume = config.volume.as_ref().map(volume).transpose()?;
    let images = config
        .image
        .iter()
        .enumerate()
        .map(|(i, c)| image(c).with_context(|| format!("[[image]] #{}", i + 1)))
        .collect::<Result<_>>()?;
    Ok(Scorers { volume, images, fitness: config.fitness() })
}

fn volume(c: &VolumeConfig) -> Result<VolumeScorer> {
    let grid = Grid::new(Vec3::from(c.min), Vec3::from(c.max), c.voxels).context("[volume]")?;
    let targets = c
        .target
        .iter()
        .enumerate()
        .map(|(i, t)| volume_target(t, &grid).with_context(|| format!("[[volume.target]] #{}", i + 1)))
        .collect::<Result<Vec<_>>>()?;
    for (i, t) in targets.iter().enumerate() {
        if t.voxels.count() == 0 {
            bail!(
                "[[volume.target]] #{} covers no voxel of the grid; check that it lies inside [volume] min/max and is a closed volume",
                i + 1
            );
        }
    }
    Ok(VolumeScorer::new(grid, targets)?)
}

fn volume_target(t: &VolumeTargetConfig, grid: &Grid) -> Result<VolumeTarget> {
    let voxels = match (&t.mesh, &t.grammar, &t.genome) {
        (Some(mesh), _, _) => {
            let mesh = read_mesh(mesh)?;
            genform_score::target::from_mesh(grid, &mesh)?.0
        }
        (None, Some(g), Some(genome)) => {
            let scene = fixed_genome_scene(g, genome)?;
            genform_score::target::from_scene(grid, &scene)
        }
        _ => bail!("give either `mesh` or `grammar` and `genome`"),
    };
    Ok(VolumeTarget { voxels, fill: t.fill, avoid: t.avoid })
}

/// Reads a target mesh file, its format from the extension
/// ([`genform_export::read_mesh_file`], the one mesh-file reader).
pub fn read_mesh(path: &Path) -> Result<genform_core::Mesh> {
    Ok(genform_export::read_mesh_file(path)?)
}

/// The Scene a grammar makes from a fixed genome file.
pub fn fixed_genome_scene(grammar_path: &Path, genome_path: &Path) -> Result<Scene> {
    let loaded = grammar::load(grammar_path)?;
    let genome = loaded.read_genome(genome_path)?;
    let mut scene = Scene::new();
    loaded.generator.express(&genome, &loaded.limits, &mut scene).context("cannot build the target model")?;
    Ok(scene)
}

/// The camera an image config describes.
pub fn camera(c: &ImageConfig) -> Camera {
    Camera {
        fov_deg: c.camera.fov,
        phi: c.camera.phi,
        theta: c.camera.theta,
        radius: c.camera.radius,
        look_at: Vec3::from(c.camera.look_at),
    }
}

fn image(c: &ImageConfig) -> Result<ImageScorer> {
    let bytes = std::fs::read(&c.target).with_context(|| format!("cannot read target image {}", c.target.display()))?;
    let is_pfm = c.target.extension().is_some_and(|e| e.eq_ignore_ascii_case("pfm"));
    let target = if is_pfm {
        ImageTarget::from_pfm(&bytes)
    } else {
        ImageTarget::from_png(&bytes, PngMode::from_name(&c.mode).unwrap_or_default())
    }
    .with_context(|| format!("cannot read target image {}", c.target.display()))?;
    Ok(ImageScorer::new(camera(c), c.width, c.height, target)?)
}
