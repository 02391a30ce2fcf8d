//! Shape grammars (`.sg`): the generator graph is the grammar, so sampling
//! draws a genome from its prior and expresses it.

use anyhow::{Context, Result};
use genform_core::Generator;
use genform_shape::ShapeGrammar;
use std::path::Path;

use super::options::SampleRequest;
use super::row::{
    FileAssets, Formalism, Genomes, Loaded, LoadedGrammar, Sample, SceneSample, express, genome_summary, sample_genome,
};
use super::scene_keys::PRIMITIVE_BYTES;
use crate::text::compile_file;

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
        &["--genome-out", "--max-genes", "--max-depth", "--max-primitives", "--footprints"]
    }

    fn genomes(&self) -> Genomes {
        Genomes::Tree
    }

    fn load(&self, path: &Path) -> Result<Box<dyn LoadedGrammar>> {
        let grammar = compile_file(path, |file| genform_shape::compile(file, &FileAssets::beside(path)))?;
        Ok(Box::new(grammar))
    }
}

/// The grammar set on each footprint of `--footprints`, else on each it
/// declares; empty when there are none.
fn on_lots(g: &ShapeGrammar, request: &SampleRequest) -> Result<Vec<ShapeGrammar>> {
    match &request.footprints {
        Some(path) => {
            let lots = crate::footprints::read_footprints(path)?;
            if lots.is_empty() {
                anyhow::bail!(
                    "{} holds no footprint (a GeoJSON Polygon or MultiPolygon, or an OBJ face facing up)",
                    path.display()
                );
            }
            let on = |(k, c): (usize, &Vec<[f64; 2]>)| {
                g.on_footprint(c).map_err(|why| anyhow::anyhow!("{}: footprint {} {why}", path.display(), k + 1))
            };
            lots.iter().enumerate().map(on).collect()
        }
        None => Ok((0..g.footprints().len()).filter_map(|k| g.on_declared_footprint(k)).collect()),
    }
}

/// Refuses limits of the grammar's `limits` header (those no flag
/// overrides) that would let one derivation exhaust the memory budget.
fn check_file_limits(g: &ShapeGrammar, request: &SampleRequest) -> Result<()> {
    use genform_core::LimitKind;
    let l = g.limits();
    let given = [
        (
            LimitKind::Genes,
            "genes",
            request.limits.max_genes,
            l.max_genes,
            crate::memory::GENE_BYTES,
            "genes",
            "--max-genes",
        ),
        (
            LimitKind::Primitives,
            "primitives",
            request.limits.max_primitives,
            l.max_primitives,
            PRIMITIVE_BYTES,
            "primitives",
            "--max-primitives",
        ),
    ];
    for (kind, key, flag_value, n, each, what, flag) in given {
        let Some(at) = g.limit_location(kind).filter(|_| flag_value.is_none()) else { continue };
        crate::memory::check_limit(
            &format!("`limits {key} = {n}` ({at})"),
            &format!("`{key}` in the grammar's `limits`, or give {flag}"),
            n,
            each,
            what,
        )?;
    }
    Ok(())
}

impl LoadedGrammar for ShapeGrammar {
    fn sample(&self, request: &SampleRequest) -> Result<Box<dyn Sample>> {
        check_file_limits(self, request)?;
        let lots = on_lots(self, request)?;
        if !lots.is_empty() {
            return sample_on_lots(self, &lots, request);
        }
        let limits = request.limits.apply(self.limits());
        let genome = sample_genome(self, request, &limits)?;
        let scene = express(self, &genome, &limits)?;
        let summary = format!("{} seed {}: {}", self.name(), request.seed, genome_summary(&scene, &genome));
        Ok(Box::new(SceneSample { scene, summary, genome: Some(genome) }))
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

/// One derivation per lot, lot `k` with seed `seed + k`, into one scene.
fn sample_on_lots(g: &ShapeGrammar, lots: &[ShapeGrammar], request: &SampleRequest) -> Result<Box<dyn Sample>> {
    if request.genome_out.is_some() {
        anyhow::bail!(
            "--genome-out saves one genome, and each of the {} footprints has its own: sample one lot (a grammar \
             without footprints) to save its genome",
            lots.len()
        );
    }
    let limits = request.limits.apply(g.limits());
    let mut scene = genform_core::Scene::new();
    let mut genes = 0;
    for (k, lot) in lots.iter().enumerate() {
        let one = SampleRequest { seed: request.seed.wrapping_add(k as u64), ..request.clone() };
        let genome = sample_genome(lot, &one, &limits).with_context(|| format!("footprint {}", k + 1))?;
        lot.express(&genome, &limits, &mut scene)
            .with_context(|| format!("footprint {}: cannot build the model", k + 1))?;
        genes += genome.len();
    }
    let (n, seed) = (lots.len(), request.seed);
    let primitives = scene.instances.len() + scene.polygons.len();
    let summary = format!(
        "{} seed {seed}: {n} footprints (seeds {seed}–{}), {genes} genes, {primitives} primitives",
        g.name(),
        seed.wrapping_add(n as u64 - 1)
    );
    Ok(Box::new(SceneSample { scene, summary, genome: None }))
}

fn format_prob(p: f64) -> String {
    let s = format!("{p:.4}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}
