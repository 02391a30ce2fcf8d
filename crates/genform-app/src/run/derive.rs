//! `derive`: a model rebuilt from a genome — a tree genome with its grammar
//! (or the tree scene it was evolved in, under the scene's limits), or
//! codons with the codon scene they were evolved in.

use anyhow::{Result, bail};
use genform_core::Scene;
use std::path::{Path, PathBuf};

use crate::formalism::{self, Genomes, LimitOverrides, Loaded, express, genome_summary, read_codons};
use crate::objective::{Model, OpenScene};
use crate::optimizers::Searches;

/// One `derive`, as a door asks for it.
#[derive(Clone, Debug, Default)]
pub struct DeriveRequest {
    /// A grammar with a generator graph, or a scene config (`.toml`).
    pub file: PathBuf,
    /// The genome: tree genome JSON, or codons for a codon scene.
    pub genome: PathBuf,
    /// Derivation limits over the grammar's or scene's (tree genomes).
    pub limits: LimitOverrides,
    /// A settings patch over the scene file (see [`super::EvolveRequest::set`]).
    pub set: Vec<String>,
}

/// A derived model and one line about it.
pub struct Derived {
    /// The model.
    pub scene: Scene,
    /// `name: genes, primitives, triangles` (or codons read).
    pub summary: String,
}

/// Rebuilds the model `request` names.
pub fn derive(r: &DeriveRequest) -> Result<Derived> {
    if r.file.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml")) {
        let scene = super::control::load_scene(&r.file, &r.set, None)?;
        return match scene.searches {
            // Trees need no scorer: the targets are not built.
            Searches::Trees => match Model::open(&scene, r.limits)? {
                Model::Tree { loaded, limits } => tree(&loaded, limits, &r.genome),
                Model::Codons(_) => bail!("a tree scene makes trees"),
            },
            Searches::Codons => codon(r, &OpenScene::open(scene, r.limits)?),
        };
    }
    if let Ok(f) = formalism::for_path(&r.file)
        && f.genomes() == Genomes::Codons
    {
        bail!(
            "{} is evolved with codons, and how codons choose depends on the codon scene's [mapper] settings: \
             give the scene the codons came from (genform derive SCENE.toml --genome {})",
            r.file.display(),
            r.genome.display()
        );
    }
    let loaded = formalism::load_generator(&r.file)?;
    tree(&loaded, r.limits.apply(loaded.limits), &r.genome)
}

/// A tree genome under `limits`.
fn tree(loaded: &Loaded, limits: genform_core::Limits, genome: &Path) -> Result<Derived> {
    let genome = loaded.read_genome(genome)?;
    if genome.len() > limits.max_genes {
        bail!(
            "the genome has {} genes, more than the gene limit ({}); raise it with --max-genes",
            genome.len(),
            limits.max_genes
        );
    }
    let scene = express(loaded.generator.as_ref(), &genome, &limits)?;
    let summary = format!("{}: {}", loaded.name, genome_summary(&scene, &genome));
    Ok(Derived { scene, summary })
}

/// Codons with their codon scene's decoder.
fn codon(r: &DeriveRequest, open: &OpenScene) -> Result<Derived> {
    let objective = open.codons()?;
    let codons = read_codons(&r.genome)?;
    let e = objective.express(&codons).map_err(|why| {
        anyhow::anyhow!("{} is an invalid individual of {}: {why}", r.genome.display(), r.file.display())
    })?;
    let summary =
        format!("{}: {} codons, {} read, fitness {}", r.file.display(), codons.len(), e.codons_read, e.score.fitness);
    Ok(Derived { scene: e.scene, summary })
}
