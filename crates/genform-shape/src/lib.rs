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

mod assets;
mod ast;
mod builtins;
mod codegen;
mod compile;
mod express;
mod fast_expr;
mod footprint;
mod genome_check;
mod geom;
mod grammar;
mod interp;
mod lexer;
mod lot_props;
mod parser;
mod polygon;
mod program;
mod sample;
mod scope;
mod scratch;
mod setback;
mod skeleton;
mod solid_faces;

use genform_core::{
    Diagnostics, ExpressError, Generator, GeneratorGraph, Genome, Limits, Rng, Sampled, Scene, SourceFile,
};

pub use assets::{AssetResolver, NoAssets};
pub use footprint::{FootprintLot, FootprintSet, LotProps};
pub use grammar::ShapeGrammar;

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
#[cfg(test)]
mod tests_links;
#[cfg(test)]
mod tests_texture;
