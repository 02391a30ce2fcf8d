//! Graph grammars (`.gg.yaml`): rewrite the host graph and write the result
//! as a drawing (SVG, PNG) or as a graph (YAML).

use anyhow::{Context, Result};
use genform_core::Scene;
use genform_graph::{DEFAULT_MAX_ELEMENTS, Graph, GraphGrammar};
use std::path::{Path, PathBuf};

use super::{Formalism, LoadedGrammar, Sample, SampleRequest, compile_file, ends_with_any, no_generator};
use crate::grammar::Loaded;
use crate::output::{write_atomic_with, write_model_with};
use genform_export::ExportOptions;

/// The graph-grammar row of the table.
pub struct GraphGrammars;

/// The endings of graph outputs (the derived graph as YAML).
const YAML: &[&str] = &[".yaml", ".yml"];

impl Formalism for GraphGrammars {
    fn name(&self) -> &'static str {
        "graph grammar"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &[".gg.yaml"]
    }

    fn sample_options(&self) -> &'static [&'static str] {
        &["--steps", "--max-modules"]
    }

    fn output_extensions(&self) -> &'static [&'static str] {
        YAML
    }

    fn genomes(&self) -> super::Genomes {
        super::Genomes::Codons
    }

    fn load(&self, path: &Path) -> Result<Box<dyn LoadedGrammar>> {
        let grammar = compile_file(path, genform_graph::compile)?;
        Ok(Box::new(GraphFile { path: path.to_path_buf(), grammar }))
    }
}

/// A compiled graph grammar and the file it came from.
struct GraphFile {
    path: PathBuf,
    grammar: GraphGrammar,
}

impl LoadedGrammar for GraphFile {
    fn sample(&self, request: &SampleRequest) -> Result<Box<dyn Sample>> {
        let grammar = &self.grammar;
        let max_elements = request.max_modules.unwrap_or(DEFAULT_MAX_ELEMENTS);
        let d = grammar
            .derive(&mut request.rng(), request.steps.map(|s| s as usize), max_elements)
            .with_context(|| format!("{}: the derivation stopped", grammar.name()))?;
        let (v, e) = (d.graph.vertex_count(), d.graph.edge_count());
        let summary = format!(
            "{} seed {}: {} steps, {v} vertices, {e} edges, {} elements",
            grammar.name(),
            request.seed,
            d.steps,
            v + e
        );
        Ok(Box::new(GraphSample { scene: std::sync::OnceLock::new(), graph: d.graph, summary }))
    }

    fn describe(&self) -> String {
        let g = &self.grammar;
        let host = g.host();
        let mut out =
            format!("graph grammar {}: host {} vertices, {} edges\n", g.name(), host.vertex_count(), host.edge_count());
        match g.step_limit() {
            Some(n) => out.push_str(&format!("step limit: {n}\n")),
            None => out.push_str("step limit: none (runs until nothing matches)\n"),
        }
        out.push_str(&format!("time limit: {} s per derivation (`time_limit:`)\n", g.time_limit().as_secs_f64()));
        out.push_str(&format!("productions: {}\n", g.production_names().collect::<Vec<_>>().join(", ")));
        out
    }

    fn into_generator(self: Box<Self>) -> Result<Loaded> {
        Err(no_generator(
            &self.path,
            "graph grammars have no derivation-tree genome: each step rewrites a match found in the host graph \
             as it grows. They are evolved with codons that choose the matches and options: write a codon scene \
             (see examples/scenes/ge_graph_tree_sketch.toml) for `genform evolve`, and rebuild a result with \
             `genform derive SCENE.toml --genome best-codons.json`",
        ))
    }
}

/// A derived graph: drawn as a Scene, or written as YAML.
struct GraphSample {
    graph: Graph,
    /// The drawing, made when first asked for (a YAML output needs none).
    scene: std::sync::OnceLock<Scene>,
    summary: String,
}

impl Sample for GraphSample {
    fn scene(&self) -> &Scene {
        self.scene.get_or_init(|| self.graph.to_scene())
    }

    fn summary(&self) -> String {
        self.summary.clone()
    }

    fn write(&self, out: &Path, export: &ExportOptions) -> Result<Vec<PathBuf>> {
        if ends_with_any(out, YAML) {
            write_atomic_with(out, |mut w| self.graph.write_yaml(&mut w))?;
            Ok(vec![out.to_path_buf()])
        } else {
            write_model_with(self.scene(), out, export)
        }
    }
}
