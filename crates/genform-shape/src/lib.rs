//! CGA-like shape grammars (`.sg`) compiled to a genform generator graph.
//!
//! A `.sg` file declares rules; each rule (or each instance of a template
//! rule) becomes one symbol of the [`GeneratorGraph`]: its `param`s are the
//! gene's random values, its slots the graph's edges. The rule body compiles
//! to a flat operation program that an interpreter runs over a genome to
//! build a [`Scene`] ([`Generator::express`]), or runs while growing a genome
//! from the prior ([`Generator::sample`]). The language is documented in
//! `docs/shape-grammar.md`.
//!
//! ```
//! use genform_core::{Generator, Limits, Rng, Scene, SourceFile};
//! let file = SourceFile::new("tower.sg", "Tower { param h: uniform(1, 3); size(1, h, 1); box; }");
//! let (grammar, _warnings) = genform_shape::compile(&file, &genform_shape::NoAssets).unwrap();
//! let limits = Limits::default();
//! let sampled = grammar.sample(&mut Rng::from_seed(1), &limits).unwrap();
//! let mut scene = Scene::new();
//! grammar.express(&sampled.genome, &limits, &mut scene).unwrap();
//! assert_eq!(scene.instances.len(), 1);
//! ```

mod ast;
mod codegen;
mod compile;
mod express;
mod fast_expr;
mod footprint;
mod genome_check;
mod geom;
mod interp;
mod lexer;
mod parser;
mod program;
mod sample;
mod scope;
mod scratch;
mod skeleton;

use genform_core::{
    Diagnostics, ExpressError, Generator, GeneratorGraph, Genome, Limits, Mesh, Rng, Sampled, Scene, SourceFile,
};
use std::sync::Arc;

/// Loads the mesh assets a grammar declares with `mesh name = "path";`.
pub trait AssetResolver {
    /// Loads the mesh at `path`, exactly as written in the `.sg` file (the
    /// CLI resolves it relative to the grammar file). The error message is
    /// shown to the user next to the path.
    fn load_mesh(&self, path: &str) -> Result<Mesh, String>;

    /// Loads the footprints at `path` (`footprints "…";`): one list of
    /// world `(x, z)` corners per polygon.
    fn load_footprints(&self, path: &str) -> Result<Vec<Vec<[f64; 2]>>, String> {
        Err(format!("no footprint files are available here (asked for \"{path}\")"))
    }
}

/// A resolver without assets: every `mesh` declaration is an error.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoAssets;

impl AssetResolver for NoAssets {
    fn load_mesh(&self, path: &str) -> Result<Mesh, String> {
        Err(format!("no mesh assets are available here (asked for \"{path}\")"))
    }
}

/// A compiled shape grammar: the generator graph plus one operation program
/// per symbol. Implements [`Generator`].
#[derive(Clone, Debug)]
pub struct ShapeGrammar {
    name: String,
    graph: GeneratorGraph,
    rules: Vec<program::RuleCode>,
    meshes: Vec<Arc<Mesh>>,
    tags: Vec<String>,
    limits: Limits,
    file: SourceFile,
    /// Tables for the fast genome check of `express`, built from `graph`.
    check: genome_check::GenomeCheck,
    /// Some rule asks an occlusion query: runs record what they place.
    occlusion: bool,
    /// The lots of `footprints "…";`.
    footprints: Vec<Arc<[glam::DVec2]>>,
    /// The occluders of `context "…";`.
    context: Arc<[interp::occlusion::Placed]>,
    /// The lot runs start on ([`ShapeGrammar::on_footprint`]).
    start_lot: Option<Arc<[glam::DVec2]>>,
    /// Where the `limits` item sets genes, depth and primitives.
    limits_at: [Option<genform_core::Span>; 3],
    /// Per `color(…)` colour, the tag each tag becomes.
    color_tags: Vec<Vec<u32>>,
    /// Each tag's tag without a colour (kept when occlusion queries ask).
    base_tags: Vec<u32>,
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
    pub fn limit_location(&self, kind: genform_core::LimitKind) -> Option<String> {
        let i = match kind {
            genform_core::LimitKind::Genes => 0,
            genform_core::LimitKind::Depth => 1,
            genform_core::LimitKind::Primitives => 2,
        };
        self.limits_at[i].map(|s| self.file.location(s.start))
    }
}

impl Generator for ShapeGrammar {
    fn graph(&self) -> &GeneratorGraph {
        &self.graph
    }

    fn express(&self, genome: &Genome, limits: &Limits, scene: &mut Scene) -> Result<(), ExpressError> {
        express::express(self, genome, limits, scene)
    }

    /// Execution-driven: runs the grammar and decides each link the first
    /// time the run touches it, so only reachable children are grown.
    fn sample(&self, rng: &mut Rng, limits: &Limits) -> Result<Sampled, ExpressError> {
        sample::sample(self, rng, limits)
    }
}

/// Compiles a `.sg` file. Mesh assets are loaded through `assets`.
///
/// On success returns the grammar and its warnings (e.g. unreachable rules);
/// on failure every error found (and the warnings), each with
/// `file:line:col`, what was expected and hints.
pub fn compile(file: &SourceFile, assets: &dyn AssetResolver) -> Result<(ShapeGrammar, Diagnostics), Diagnostics> {
    compile::compile(file, assets)
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_building;
