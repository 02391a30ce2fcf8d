//! Shape grammars (`.sg`): the generator graph is the grammar, so sampling
//! draws a genome from its prior and expresses it.

use anyhow::Result;
use genform_core::Generator;
use genform_shape::ShapeGrammar;
use std::path::Path;

use super::{FileAssets, Formalism, LoadedGrammar, Sample, SampleRequest, SceneSample, compile_file, sample_genome};
use crate::grammar::{Loaded, express, genome_summary};

/// The shape-grammar row of the table.
pub struct ShapeGrammars;

impl Formalism for ShapeGrammars {
    fn name(&self) -> &'static str {
        "shape grammar"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &[".sg"]
    }

    fn sample_options(&self) -> &'static [&'static str] {
        &["--genome-out", "--max-genes", "--max-depth", "--max-primitives"]
    }

    fn genomes(&self) -> super::Genomes {
        super::Genomes::Tree
    }

    fn load(&self, path: &Path) -> Result<Box<dyn LoadedGrammar>> {
        let grammar = compile_file(path, |file| genform_shape::compile(file, &FileAssets::beside(path)))?;
        Ok(Box::new(grammar))
    }
}

impl LoadedGrammar for ShapeGrammar {
    fn sample(&self, request: &SampleRequest) -> Result<Box<dyn Sample>> {
        let limits = request.limits.apply(self.limits());
        let genome = sample_genome(self, request, &limits)?;
        let scene = express(self, &genome, &limits)?;
        let summary = format!("{} seed {}: {}", self.name(), request.seed, genome_summary(&scene, &genome));
        Ok(Box::new(SceneSample { scene, summary }))
    }

    fn describe(&self) -> String {
        let g = self.graph();
        let limits = self.limits();
        let mut out = String::new();
        out.push_str(&format!(
            "grammar {}: {} symbols, start `{}`\n",
            self.name(),
            g.symbols.len(),
            g.symbol(g.root).name
        ));
        out.push_str(&format!(
            "limits: genes {}, depth {}, primitives {}\n",
            limits.max_genes, limits.max_depth, limits.max_primitives
        ));
        for s in &g.symbols {
            out.push_str(&format!("\n{}{}\n", s.name, if s.emits_geometry { "  (emits geometry)" } else { "" }));
            for p in &s.params {
                let dists: Vec<String> = p.components.iter().map(|d| d.describe()).collect();
                let all_same = dists.windows(2).all(|w| w[0] == w[1]);
                let shown = if p.dim() == 1 || all_same {
                    let prefix = if p.dim() > 1 { format!("vec{} ", p.dim()) } else { String::new() };
                    format!("{prefix}{}", dists[0])
                } else {
                    format!("[{}]", dists.join(", "))
                };
                out.push_str(&format!("  param {:<10} {shown}\n", p.name));
            }
            for slot in &s.slots {
                let max = if slot.max_count > 1 { format!(" x {}", slot.max_count) } else { String::new() };
                out.push_str(&format!(
                    "  slot  {:<10} → {} p {}{max}\n",
                    slot.name,
                    g.symbol(slot.target).name,
                    format_prob(slot.prob)
                ));
            }
        }
        out
    }

    fn into_generator(self: Box<Self>) -> Result<Loaded> {
        Ok(Loaded { name: self.name().to_string(), limits: self.limits(), generator: self })
    }
}

fn format_prob(p: f64) -> String {
    let s = format!("{p:.4}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}
