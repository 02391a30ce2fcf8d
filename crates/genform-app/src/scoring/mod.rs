//! The scorer registry: every section of a scene that scores its models is
//! one row of [`SCORERS`], in a file of its own that reads the section
//! (with positions), sizes it against the memory budget and builds a
//! scorer of `genform-score`'s contract ([`genform_score::Scorer`]).
//!
//! Counting targets (volume grids, image silhouettes) are summed and turned
//! into one fitness by the scene's `[fitness]` form
//! ([`genform_score::Targets`]); criteria scorers (Genr8's surface
//! criteria) give a fitness of their own; a scene with both adds them up.
//! Everything downstream — statistics, plots, steering, the studio, Python
//! — reads the result through the contract: named components with weights
//! and reachable maxima, and knobs by name.
//!
//! Adding a scorer is a file in this folder and one line in [`SCORERS`].

mod fitness;
mod image;
mod row;
mod silhouettes;
mod surface;
mod volume;

use anyhow::Result;
use genform_core::Mesh;
use genform_score::{Counter, Form, ImageScorer, Scorer};
use std::sync::Arc;

pub use fitness::FitnessConfig;
pub(crate) use row::{Part, ScorerRow, ScorerSection};

use crate::memory::Size;

/// Every scorer, one row each, in the order their fitness parts are
/// summed: a scene's section of a row's name is read by that row.
pub(crate) static SCORERS: &[&dyn ScorerRow] =
    &[&volume::Volume, &image::Images, &silhouettes::Silhouettes, &surface::Surface];

/// The section of the counting targets' formula.
pub(crate) const FITNESS: &str = "fitness";

/// A scene's scorers as read from its file.
#[derive(Clone, Debug, Default)]
pub struct Scoring {
    /// The sections given, by index into [`SCORERS`], in registry order.
    pub(crate) sections: Vec<(usize, Arc<dyn ScorerSection>)>,
    /// `[fitness]`, as written (or its defaults).
    pub fitness: FitnessConfig,
}

/// A scene's scorer, built, with what pictures show of its targets.
pub(crate) struct BuiltScoring {
    /// The scorer.
    pub scorer: Box<dyn Scorer>,
    /// Meshes drawn behind the best model.
    pub ghosts: Vec<Mesh>,
    /// Image targets the model is shown over.
    pub images: Vec<Arc<ImageScorer>>,
}

impl Scoring {
    /// The rows of the sections given.
    pub(crate) fn rows(&self) -> impl Iterator<Item = &'static dyn ScorerRow> + '_ {
        self.sections.iter().map(|(i, _)| SCORERS[*i])
    }

    /// Whether any counting target is given (the `[fitness]` form applies).
    pub(crate) fn counts(&self) -> bool {
        self.rows().any(|r| !r.for_surfaces())
    }

    /// Whether a section named `name` is given.
    pub fn has(&self, name: &str) -> bool {
        self.rows().any(|r| r.section() == name)
    }

    /// The form of the first counting section (the form `[fitness]` uses
    /// when it names none).
    pub(crate) fn default_form(&self) -> Form {
        self.rows().find(|r| !r.for_surfaces()).map_or(Form::Paper, |r| r.default_form())
    }

    /// The fitness of the counting targets: `[fitness]` with the length
    /// range defaulting to `lengths`.
    pub(crate) fn fitness(&self, lengths: [f64; 2]) -> genform_score::Fitness {
        self.fitness.fitness(self.default_form(), lengths)
    }

    /// The sides of the region the first section with one lies in (the
    /// default ranges of size descriptors).
    pub(crate) fn extent(&self) -> Option<[f64; 3]> {
        self.sections.iter().find_map(|(_, s)| s.extent())
    }

    /// A scorer with the knobs of the real one, cheap to make (no target
    /// read): the `[fitness]` weights when counting targets are given,
    /// then each section's own.
    pub(crate) fn probe(&self) -> Box<dyn Scorer> {
        let mut parts: Vec<Box<dyn Scorer>> = Vec::new();
        if self.counts() {
            parts.push(Box::new(genform_score::Targets::new(Vec::new(), self.fitness([0.0, 1.0]))));
        }
        parts.extend(self.sections.iter().filter_map(|(_, s)| s.probe()));
        if parts.len() == 1 { parts.remove(0) } else { Box::new(genform_score::Sum(parts)) }
    }

    /// The sizes the sections ask for.
    pub(crate) fn memory(&self) -> Vec<Size<'static>> {
        self.sections.iter().flat_map(|(_, s)| s.memory()).collect()
    }

    /// The sections as `run.json` echoes them, by name.
    pub(crate) fn to_json(&self) -> Vec<(&'static str, serde_json::Value)> {
        self.sections.iter().map(|(i, s)| (SCORERS[*i].section(), s.to_json())).collect()
    }

    /// The sections, for what the studio shows of their targets.
    pub(crate) fn sections(&self) -> impl Iterator<Item = &Arc<dyn ScorerSection>> {
        self.sections.iter().map(|(_, s)| s)
    }

    /// Builds every section into one scorer: counting targets summed under
    /// `[fitness]` (its length range defaulting to `lengths`), criteria
    /// scorers added.
    pub(crate) fn build(&self, lengths: [f64; 2]) -> Result<BuiltScoring> {
        let mut counters: Vec<Arc<dyn Counter>> = Vec::new();
        let mut scorers: Vec<Box<dyn Scorer>> = Vec::new();
        let (mut ghosts, mut images) = (Vec::new(), Vec::new());
        for (_, section) in &self.sections {
            let built = section.build()?;
            match built.part {
                Part::Counters(c) => counters.extend(c),
                Part::Scorer(s) => scorers.push(s),
            }
            ghosts.extend(built.ghosts);
            images.extend(built.images);
        }
        if !counters.is_empty() {
            scorers.insert(0, Box::new(genform_score::Targets::new(counters, self.fitness(lengths))));
        }
        let scorer: Box<dyn Scorer> =
            if scorers.len() == 1 { scorers.remove(0) } else { Box::new(genform_score::Sum(scorers)) };
        Ok(BuiltScoring { scorer, ghosts, images })
    }
}
