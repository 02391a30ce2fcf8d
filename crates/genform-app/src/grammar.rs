//! A grammar opened for a door that keeps it ([`GrammarHandle`]: the
//! Python package's `Grammar`): compiled once for sampling and `info`, with
//! its generator graph when its formalism has one.

use anyhow::{Context, Result};
use genform_core::{Genome, Limits, Scene};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::formalism::{self, FormalismRef, Loaded, LoadedGrammar, express, genome_summary};

/// A compiled grammar of any formalism.
pub struct GrammarHandle {
    /// The file it was compiled from.
    pub path: PathBuf,
    /// Its row of the formalism table.
    pub formalism: FormalismRef,
    /// The grammar as the verbs see it.
    pub loaded: Box<dyn LoadedGrammar>,
    /// Its generator graph, if the formalism has one.
    pub generator: Option<Arc<Loaded>>,
    /// Why there is no generator graph (when there is none).
    no_generator: String,
    /// What compiling it read (the grammar, its meshes, context,
    /// footprints) and what its samples read: files no model of it may be
    /// saved over ([`GrammarHandle::guarded`]).
    inputs: Arc<crate::gate::Session>,
}

impl GrammarHandle {
    /// Compiles `path` with the formalism its extension names.
    pub fn open(path: &Path) -> Result<GrammarHandle> {
        let session = crate::gate::fresh_session();
        let formalism = formalism::formalism_of(path)?;
        let loaded = formalism.load(path)?;
        // A second compile for the generator: `into_generator` consumes the grammar.
        let (generator, no_generator) = match formalism.load(path)?.into_generator() {
            Ok(g) => (Some(Arc::new(g)), String::new()),
            Err(e) => (None, format!("{e:#}")),
        };
        let inputs = session.session().clone();
        Ok(GrammarHandle { path: path.to_path_buf(), formalism, loaded, generator, no_generator, inputs })
    }

    /// Runs `f` (a sample, a save) with this grammar's inputs in force:
    /// what `f` reads joins them, and a file `f` writes may not be one.
    pub fn guarded<T>(&self, f: impl FnOnce() -> T) -> T {
        crate::gate::within(&Some(self.inputs.clone()), f)
    }

    /// A handle on a scene's grammar whose generator is already compiled.
    pub fn with_generator(path: &Path, generator: Arc<Loaded>) -> Result<GrammarHandle> {
        let session = crate::gate::fresh_session();
        let formalism = formalism::formalism_of(path)?;
        let loaded = formalism.load(path)?;
        Ok(GrammarHandle {
            path: path.to_path_buf(),
            formalism,
            loaded,
            generator: Some(generator),
            no_generator: String::new(),
            inputs: session.session().clone(),
        })
    }

    /// The generator, or the error saying why there is none.
    pub fn generator(&self) -> Result<&Arc<Loaded>> {
        self.generator.as_ref().ok_or_else(|| anyhow::anyhow!("{}", self.no_generator))
    }

    /// Parses a genome's JSON text against the generator graph.
    pub fn parse_genome(&self, text: &str) -> Result<Genome> {
        let g = self.generator()?;
        Genome::from_json(text, g.generator.graph())
            .with_context(|| format!("the genome does not fit grammar `{}`", g.name))
    }

    /// Expresses `genome` under `limits`: the model and one line about it.
    pub fn derive(&self, genome: &Genome, limits: Limits) -> Result<(Scene, String)> {
        let g = self.generator()?;
        let scene = express(g.generator.as_ref(), genome, &limits)?;
        let summary = format!("{}: {}", g.name, genome_summary(&scene, genome));
        Ok((scene, summary))
    }
}
