//! The compiled grammar itself, apart from what runs it (`express`,
//! `sample`) and what builds it (`compile`), so that those can all name it
//! without naming one another.

use crate::genome_check::GenomeCheck;
use crate::interp::occlusion::Placed;
use crate::program::RuleCode;
use genform_core::{GeneratorGraph, LimitKind, Limits, Mesh, SourceFile, Span};
use glam::DVec2;
use std::sync::Arc;

/// A compiled shape grammar: the generator graph plus one operation program
/// per symbol. Implements [`Generator`](genform_core::Generator).
#[derive(Clone, Debug)]
pub struct ShapeGrammar {
    pub(crate) name: String,
    pub(crate) graph: GeneratorGraph,
    pub(crate) rules: Vec<RuleCode>,
    pub(crate) meshes: Vec<Arc<Mesh>>,
    pub(crate) tags: Vec<String>,
    pub(crate) limits: Limits,
    pub(crate) file: SourceFile,
    /// Tables for the fast genome check of `express`, built from `graph`.
    pub(crate) check: GenomeCheck,
    /// Some rule asks an occlusion query: runs record what they place.
    pub(crate) occlusion: bool,
    /// The lots of `footprints "…";`.
    pub(crate) footprints: Vec<Arc<[DVec2]>>,
    /// The occluders of `context "…";`.
    pub(crate) context: Arc<[Placed]>,
    /// What the file says of each of `footprints`.
    pub(crate) footprint_props: Vec<crate::lot_props::LotProps>,
    /// Where the local origin of `footprints` lies, in the file's terms.
    pub(crate) footprint_origin: Option<String>,
    /// The lot runs start on ([`ShapeGrammar::on_footprint`]).
    pub(crate) start_lot: Option<Arc<[DVec2]>>,
    /// The `lot.*` values of runs (all 0 without a footprint).
    pub(crate) start_props: crate::lot_props::LotProps,
    /// Where the `limits` item sets genes, depth and primitives.
    pub(crate) limits_at: [Option<Span>; 3],
    /// Per `color(…)` colour, the tag each tag becomes.
    pub(crate) color_tags: Vec<Vec<u32>>,
    /// Each tag's tag without a colour (kept when occlusion queries ask).
    pub(crate) base_tags: Vec<u32>,
    /// The images of `texture(…)`.
    pub(crate) textures: Vec<Arc<genform_core::scene::Texture>>,
    /// Per texture, the tag each tag becomes under `texture(…)`.
    pub(crate) texture_tags: Vec<Vec<u32>>,
    /// Each tag's texture (empty when there are no textures).
    pub(crate) tag_textures: Vec<Option<u32>>,
}

impl ShapeGrammar {
    /// The grammar's name: `grammar "name";`, else the file stem.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The limits of the `limits` header, defaults for those not given.
    pub fn limits(&self) -> Limits {
        self.limits
    }

    /// `file:line:col` of the value the `limits` header gives `kind`, if it
    /// gives one.
    pub fn limit_location(&self, kind: LimitKind) -> Option<String> {
        let i = match kind {
            LimitKind::Genes => 0,
            LimitKind::Depth => 1,
            LimitKind::Primitives => 2,
        };
        self.limits_at[i].map(|s| self.file.location(s.start))
    }
}
