//! `[surface]`: Genr8's six surface criteria, each with a target and a
//! weight ([`genform_score::SurfaceScorer`]).

use anyhow::Result;
use genform_score::{SurfaceError, SurfaceObjective, SurfaceScorer};
use std::path::Path;
use std::sync::Arc;

use super::row::{Built, Part, ScorerRow, ScorerSection};
use crate::toml_doc::{Doc, Value};

/// The `[surface]` row.
pub(crate) struct Surface;

/// A read `[surface]`.
#[derive(Debug)]
struct SurfaceSection(SurfaceObjective);

impl ScorerRow for Surface {
    fn section(&self) -> &'static str {
        "surface"
    }

    fn read(&self, doc: &Doc, value: &Value, _base: &Path) -> Result<Arc<dyn ScorerSection>> {
        let objective: SurfaceObjective = doc.read(value)?;
        if let Err(e) = SurfaceScorer::new(objective) {
            let criterion = match &e {
                SurfaceError::BadTarget { criterion, .. }
                | SurfaceError::BadWeight { criterion, .. }
                | SurfaceError::BadFloor { criterion, .. } => Some(*criterion),
                _ => None,
            };
            let path: Vec<&str> = ["surface"].into_iter().chain(criterion).collect();
            return Err(doc.refuse(&path, format!("[surface]: {e}")));
        }
        Ok(Arc::new(SurfaceSection(objective)))
    }

    fn for_surfaces(&self) -> bool {
        true
    }
}

impl ScorerSection for SurfaceSection {
    fn to_json(&self) -> serde_json::Value {
        serde_json::to_value(self.0).unwrap_or_default()
    }

    fn probe(&self) -> Option<Box<dyn genform_score::Scorer>> {
        SurfaceScorer::new(self.0).ok().map(|s| Box::new(s) as Box<dyn genform_score::Scorer>)
    }

    fn build(&self) -> Result<Built> {
        let scorer = SurfaceScorer::new(self.0)?;
        Ok(Built { part: Part::Scorer(Box::new(scorer)), ghosts: Vec::new(), images: Vec::new() })
    }
}
