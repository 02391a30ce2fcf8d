//! A scene file, tree or codon, loaded through one door: every verb and
//! front door asks [`SceneFile::load`] and matches on what it found.

use anyhow::Result;
use std::path::Path;

use crate::codon_scene::{CodonSceneConfig, LoadedCodonScene, is_codon_scene};
use crate::run::Steerable;
use crate::scene_config::{LoadedScene, SceneConfig};
use crate::sweep::set::Axis;

/// A loaded, checked scene file.
#[derive(Clone, Debug)]
pub enum SceneFile {
    /// A tree scene (`.sg`, `.ls` grammars: derivation-tree genomes).
    Tree(LoadedScene),
    /// A codon scene (`.bnf`, `.bsg`, `.gg.yaml` grammars: codon genomes).
    Codon(LoadedCodonScene),
}

impl SceneFile {
    /// Loads the scene at `path` with `patch` (a settings patch, possibly
    /// empty) applied; its grammar's extension says which kind it is.
    pub fn load(path: &Path, patch: &[Axis]) -> Result<SceneFile> {
        Ok(if is_codon_scene(path) {
            SceneFile::Codon(CodonSceneConfig::load_patched(path, patch)?)
        } else {
            SceneFile::Tree(SceneConfig::load_patched(path, patch)?)
        })
    }

    /// The scene file.
    pub fn path(&self) -> &Path {
        match self {
            SceneFile::Tree(s) => &s.path,
            SceneFile::Codon(s) => &s.path,
        }
    }

    /// What steering can change in this scene.
    pub fn steerable(&self) -> Steerable {
        match self {
            SceneFile::Tree(s) => Steerable::Fitness(s.config.fitness.clone()),
            SceneFile::Codon(s) => Steerable::of_codon_scene(&s.config),
        }
    }

    /// The algorithms this kind of scene runs, by name.
    pub fn algorithms(&self) -> &'static [&'static str] {
        match self {
            SceneFile::Tree(_) => &["ga", "mh", "smc", "sosmc", "hybrid", "map-elites", "random"],
            SceneFile::Codon(_) => &["ge", "random"],
        }
    }

    /// The volume and image targets as a tree scene's config (a codon
    /// scene's seen as one); `None` for surface scenes, which have none.
    pub fn targets(&self) -> Option<SceneConfig> {
        match self {
            SceneFile::Tree(s) => Some(s.config.clone()),
            SceneFile::Codon(s) if s.config.surface.is_some() => None,
            SceneFile::Codon(s) => Some(s.config.targets_view()),
        }
    }
}
