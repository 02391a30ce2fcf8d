//! What a row of the scorer registry is: the reader of one scene section
//! ([`ScorerRow`]) and the section it reads ([`ScorerSection`]), which
//! builds a part of the scene's fitness ([`Built`]).

use anyhow::Result;
use genform_core::Mesh;
use genform_score::{Counter, Form, ImageScorer, Scorer};
use std::path::Path;
use std::sync::Arc;

use crate::memory::Size;
use crate::toml_doc::{Doc, Value};

/// A row of the scorer registry: one section of a scene file.
pub(crate) trait ScorerRow: Sync {
    /// The section's name, e.g. `volume` (`[volume]` or `[[volume]]`).
    fn section(&self) -> &'static str;

    /// Reads and checks the section `value` of `doc`, paths resolved
    /// against `base` (the scene's folder); refusals name their position.
    fn read(&self, doc: &Doc, value: &Value, base: &Path) -> Result<Arc<dyn ScorerSection>>;

    /// Whether it scores grown surfaces (Genr8's criteria) rather than
    /// volumes and pictures of a model.
    fn for_surfaces(&self) -> bool {
        false
    }

    /// For counting targets: the `[fitness]` form a scene whose first
    /// counting section this is uses when it names none.
    fn default_form(&self) -> Form {
        Form::Paper
    }
}

/// One scorer's section of a scene, read and checked.
pub(crate) trait ScorerSection: Send + Sync + std::fmt::Debug {
    /// The section as `run.json` echoes it.
    fn to_json(&self) -> serde_json::Value;

    /// The sizes it asks for (grids, pictures), checked against the
    /// memory budget when the scene loads.
    fn memory(&self) -> Vec<Size<'static>> {
        Vec::new()
    }

    /// Builds the scorer (reads its files, voxelizes, …).
    fn build(&self) -> Result<Built>;

    /// The target meshes the studio shows with a model (volume targets).
    fn target_meshes(&self) -> Result<Vec<Mesh>> {
        Ok(Vec::new())
    }

    /// The target pictures (PNG files) the studio shows.
    fn target_pictures(&self) -> Vec<std::path::PathBuf> {
        Vec::new()
    }

    /// Whether it has target meshes ([`ScorerSection::target_meshes`]), without reading them.
    fn has_target_meshes(&self) -> bool {
        false
    }

    /// For sections with weights or targets to steer: a scorer with those
    /// knobs that is cheap to make (no files read), for listing and
    /// checking steering before a run has built the real one.
    fn probe(&self) -> Option<Box<dyn Scorer>> {
        None
    }

    /// The sides of the region its targets lie in, if it has one (the
    /// default ranges of size descriptors).
    fn extent(&self) -> Option<[f64; 3]> {
        None
    }
}

/// What a section builds.
pub(crate) enum Part {
    /// Counting targets, their counts summed (in order) with the scene's
    /// other counting targets' under its `[fitness]` form.
    Counters(Vec<Arc<dyn Counter>>),
    /// A fitness of its own.
    Scorer(Box<dyn Scorer>),
}

/// A built section: its part of the fitness and what pictures show of it.
pub(crate) struct Built {
    /// The scorer.
    pub part: Part,
    /// Meshes drawn behind the best model (`best.png`, `evolution.png`).
    pub ghosts: Vec<Mesh>,
    /// Image targets: pictures show the model over them
    /// (`best-silhouette.png`, the first as `best.png`'s backdrop).
    pub images: Vec<Arc<ImageScorer>>,
}
