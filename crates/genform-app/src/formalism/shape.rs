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
        let assets = ShapeAssets(FileAssets::beside(path), path.parent().unwrap_or(Path::new(".")).to_path_buf());
        let grammar = compile_file(path, |file| genform_shape::compile(file, &assets))?;
        Ok(Box::new(grammar))
    }
}

/// The grammar file's assets, its footprints read with their properties,
/// their local origin and the lots skipped ([`crate::footprints::read_lots`]).
struct ShapeAssets(FileAssets, std::path::PathBuf);

impl genform_shape::AssetResolver for ShapeAssets {
    fn load_mesh(&self, path: &str) -> Result<genform_core::scene::Mesh, String> {
        genform_shape::AssetResolver::load_mesh(&self.0, path)
    }

    fn load_footprints(&self, path: &str) -> Result<Vec<Vec<[f64; 2]>>, String> {
        genform_shape::AssetResolver::load_footprints(&self.0, path)
    }

    fn load_texture(&self, path: &str) -> Result<Vec<u8>, String> {
        genform_shape::AssetResolver::load_texture(&self.0, path)
    }

    fn load_footprint_set(&self, path: &str) -> Result<genform_shape::FootprintSet, String> {
        crate::footprints::read_lots(&self.1.join(path)).map_err(|e| format!("{e:#}"))
    }
}

/// The lots a sample derives on, and where their origin lies.
struct Lots {
    grammars: Vec<ShapeGrammar>,
    origin: Option<String>,
}

/// The grammar set on each footprint of `--footprints`, else on each it
/// declares; empty when there are none. A lot the grammar cannot stand on
/// is skipped with a warning naming it; a file with no usable lot is an
/// error.
fn on_lots(g: &ShapeGrammar, request: &SampleRequest) -> Result<Lots> {
    match &request.footprints {
        Some(path) => {
            let set = crate::footprints::read_lots(path)?;
            let mut skipped = set.skipped;
            let mut grammars = Vec::with_capacity(set.lots.len());
            for lot in &set.lots {
                match g.on_footprint_with(&lot.corners, lot.props) {
                    Ok(on) => grammars.push(on),
                    Err(why) => skipped.push(format!("{} {why}", lot.label)),
                }
            }
            if grammars.is_empty() {
                match skipped.first() {
                    Some(why) => {
                        anyhow::bail!("{} holds no usable footprint ({} skipped; {why})", path.display(), skipped.len())
                    }
                    None => anyhow::bail!(
                        "{} holds no footprint (a GeoJSON or GeoPackage Polygon or MultiPolygon, or an OBJ face facing up)",
                        path.display()
                    ),
                }
            }
            for why in &skipped {
                crate::notes::warn(&format!("warning: {}: {why}; the lot is skipped", path.display()));
            }
            Ok(Lots { grammars, origin: set.origin })
        }
        None => Ok(Lots {
            grammars: (0..g.footprints().len()).filter_map(|k| g.on_declared_footprint(k)).collect(),
            origin: g.footprint_origin().map(str::to_string),
        }),
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
        if !lots.grammars.is_empty() {
            return sample_on_lots(self, &lots, request);
        }
        let limits = request.limits.apply(self.limits());
        let genome = sample_genome(self, request, &limits)?;
        let scene = express(self, &genome, &limits)?;
        super::row::warn_left_out(&scene);
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
/// When the footprints were moved to a local origin, the summary names it
/// and so does the scene (GLB `asset.extras`, OBJ and PLY comments).
fn sample_on_lots(g: &ShapeGrammar, on: &Lots, request: &SampleRequest) -> Result<Box<dyn Sample>> {
    let lots = &on.grammars;
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
    super::row::warn_left_out(&scene);
    let (n, seed) = (lots.len(), request.seed);
    let primitives = scene.instances.len() + scene.polygons.len();
    scene.origin = on.origin.clone();
    let origin = on.origin.as_ref().map_or(String::new(), |o| format!(", origin at {o}"));
    let summary = format!(
        "{} seed {seed}: {n} footprints (seeds {seed}–{}), {genes} genes, {primitives} primitives{origin}",
        g.name(),
        seed.wrapping_add(n as u64 - 1)
    );
    Ok(Box::new(SceneSample { scene, summary, genome: None }))
}

fn format_prob(p: f64) -> String {
    let s = format!("{p:.4}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}
