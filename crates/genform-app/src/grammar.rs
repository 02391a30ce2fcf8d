//! Grammars as generators: the door the genome verbs (`derive`, `evolve`,
//! `score`, `compare`) and scene targets go through. Any formalism in
//! [`crate::formalism::FORMALISMS`] loads here; those without a generator
//! graph say why not.

use anyhow::{Context, Result};
use genform_core::{Generator, Genome, Limits, Scene};
use std::path::Path;

use crate::formalism;

/// A compiled grammar that has a generator graph, whatever its formalism.
pub struct Loaded {
    /// The generator.
    pub generator: Box<dyn Generator>,
    /// Display name of the grammar.
    pub name: String,
    /// Limits declared by the grammar (or defaults), before CLI overrides.
    pub limits: Limits,
}

impl Loaded {
    /// Reads a genome JSON file and checks that it fits this grammar.
    pub fn read_genome(&self, path: &Path) -> Result<Genome> {
        let text = crate::source_text::read_text(path, "genome")?;
        Genome::from_json(&text, self.generator.graph())
            .with_context(|| format!("{} does not fit grammar `{}`", path.display(), self.name))
    }
}

/// Compiles the grammar at `path` (its formalism chosen by extension from
/// the table) into a generator; warnings go to stderr, errors become the
/// returned error with every diagnostic rendered. A formalism without a
/// generator graph is an error that says why.
pub fn load(path: &Path) -> Result<Loaded> {
    formalism::open(path)?.into_generator()
}

/// Expresses `genome` into a fresh Scene.
pub fn express(generator: &dyn Generator, genome: &Genome, limits: &Limits) -> Result<Scene> {
    let mut scene = Scene::new();
    generator.express(genome, limits, &mut scene).context("cannot build the model")?;
    Ok(scene)
}

/// One line about a model expressed from a genome: genes, primitives,
/// triangles.
pub fn genome_summary(scene: &Scene, genome: &Genome) -> String {
    format!(
        "{} genes, {} primitives, {} triangles",
        genome.len(),
        scene.instances.len() + scene.polylines.len() + scene.polygons.len(),
        scene.triangle_count(Default::default())
    )
}

/// Limits given on the command line or in a scene config, each replacing
/// the grammar's own when set.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LimitOverrides {
    /// Most genes.
    pub max_genes: Option<usize>,
    /// Deepest gene.
    pub max_depth: Option<usize>,
    /// Most primitives.
    pub max_primitives: Option<usize>,
}

impl LimitOverrides {
    /// `base` with the set overrides applied.
    pub fn apply(&self, base: Limits) -> Limits {
        Limits {
            max_genes: self.max_genes.unwrap_or(base.max_genes),
            max_depth: self.max_depth.unwrap_or(base.max_depth),
            max_primitives: self.max_primitives.unwrap_or(base.max_primitives),
        }
    }

    /// `self` where set, `other` elsewhere.
    pub fn or(self, other: LimitOverrides) -> LimitOverrides {
        LimitOverrides {
            max_genes: self.max_genes.or(other.max_genes),
            max_depth: self.max_depth.or(other.max_depth),
            max_primitives: self.max_primitives.or(other.max_primitives),
        }
    }
}
