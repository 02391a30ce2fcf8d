//! GE grammars (`.bnf`): grammatical evolution. A codon genome is mapped
//! through the BNF (`genform-ge`) into phenotype text in the language the
//! scene's `phenotype` names — `"gr8"` (a HEMLS rewrite system, grown in
//! `environment` for `steps` steps) or `"ls"` (an L-system, derived and
//! drawn) — and that text is the model's grammar.
//!
//! Growth and drawing take what randomness they need (stochastic `.gr8`
//! rules, random formulas in `.ls`) from the stream `genform sample` uses
//! with seed 0, so an evaluation is deterministic and the written
//! `best.gr8` / `best.ls` re-grows into the same model with
//! `genform sample` (seed 0).

use anyhow::{Result, anyhow, bail};
use genform_core::{Scene, SourceFile};
use genform_ge::{Bnf, MapOptions, Mapper};
use genform_hemls::{Environment, GrowError, Hemls, Settings};
use std::path::{Path, PathBuf};

use super::codons::{CodonDecoder, DecodeScratch, Decoded, Invalid, PHENOTYPE_STEM, Phase, Rejection, reject};
use super::hemls::load_environment;
use super::options::{SampleRequest, sample_rng};
use super::row::{Formalism, Genomes, Loaded, LoadedGrammar, Sample, no_generator};
use super::scene_keys::{ModelSettings, Phenotype, SceneLimits};
use crate::text::compile_file;
use crate::toml_doc::Doc;

/// Default `[limits] modules` of `.ls` phenotypes.
pub const DEFAULT_MAX_MODULES: usize = 200_000;
/// Default `[limits] primitives` of `.ls` phenotypes.
pub const DEFAULT_MAX_PRIMITIVES: usize = 20_000;
/// Default wraps of the GE mapper without Genr8's extensions.
pub const DEFAULT_GE_WRAPS: u32 = 2;

/// The GE row of the table.
pub struct GeGrammars;

impl Formalism for GeGrammars {
    fn name(&self) -> &'static str {
        "GE grammar"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &[".bnf"]
    }

    fn sample_options(&self) -> &'static [&'static str] {
        &[]
    }

    fn genomes(&self) -> Genomes {
        Genomes::Codons
    }

    fn load(&self, path: &Path) -> Result<Box<dyn LoadedGrammar>> {
        let bnf = compile_file(path, genform_ge::compile)?;
        Ok(Box::new(BnfFile { path: path.to_path_buf(), bnf }))
    }

    fn scene_keys(&self) -> &'static [&'static str] {
        &["phenotype", "environment", "steps", "mapper.max_wraps", "mapper.max_depth", "mapper.genr8", "mapper.layout"]
    }

    fn limit_keys(&self, model: &ModelSettings) -> &'static [&'static str] {
        match model.phenotype {
            Some(Phenotype::Gr8) => &["vertices", "edges", "faces"],
            Some(Phenotype::Ls) => &["modules", "primitives"],
            None => &[],
        }
    }

    fn check_scene(&self, doc: &Doc, model: &ModelSettings) -> Result<()> {
        let Some(phenotype) = model.phenotype else {
            return Err(doc.refuse(
                &["grammar"],
                "a .bnf grammar needs `phenotype = \"gr8\"` or `phenotype = \"ls\"`: the language it writes",
            ));
        };
        if phenotype == Phenotype::Ls {
            for key in ["environment", "steps"] {
                if doc.get(key).is_some() {
                    return Err(doc.refuse(
                        &[key],
                        format!(
                            "`{key}` applies to phenotype = \"gr8\" scenes (an .ls phenotype sets its own `derivation:`)"
                        ),
                    ));
                }
            }
        }
        if let Some(s) = model.steps
            && s > genform_hemls::envfile::MAX_STEPS
        {
            return Err(doc.refuse(
                &["steps"],
                format!("steps = {s} is more than {} (growth is exponential)", genform_hemls::envfile::MAX_STEPS),
            ));
        }
        Ok(())
    }

    fn decoder(
        &self,
        grammar: &Path,
        model: &ModelSettings,
        limits: &SceneLimits,
        _codon_range: u32,
    ) -> Result<Box<dyn CodonDecoder>> {
        let phenotype = model.phenotype.ok_or_else(|| anyhow!("a .bnf grammar needs `phenotype`"))?;
        let bnf = compile_file(grammar, genform_ge::compile)?;
        let m = &model.mapper;
        let genr8 = m.genr8.unwrap_or(phenotype == Phenotype::Gr8);
        let mut options = if genr8 {
            MapOptions::genr8()
        } else {
            MapOptions { spaced: false, ..MapOptions::standard(DEFAULT_GE_WRAPS, None) }
        };
        if let Some(w) = m.max_wraps {
            options.max_wraps = w;
        }
        options.layout = m.layout.unwrap_or_default();
        if let Some(d) = m.max_depth {
            match &mut options.genr8 {
                Some(g) => g.max_depth = Some(d),
                None => options.max_tree_depth = Some(d),
            }
        }
        Mapper::new(&bnf, options.clone()).map_err(|e| anyhow!("[mapper]: {e} (grammar {})", grammar.display()))?;
        let language = match phenotype {
            Phenotype::Gr8 => {
                let (mut settings, env) = match &model.environment {
                    Some(path) => load_environment(path)?,
                    None => (Settings::default(), Environment::default()),
                };
                if let Some(s) = model.steps {
                    settings.steps = s;
                }
                let lim = &mut settings.limits;
                lim.max_vertices = limits.vertices.unwrap_or(lim.max_vertices);
                lim.max_edges = limits.edges.unwrap_or(lim.max_edges);
                lim.max_faces = limits.faces.unwrap_or(lim.max_faces);
                Language::Gr8 { settings, env }
            }
            Phenotype::Ls => Language::Ls {
                max_modules: limits.modules.unwrap_or(DEFAULT_MAX_MODULES),
                max_primitives: limits.primitives.unwrap_or(DEFAULT_MAX_PRIMITIVES),
            },
        };
        Ok(Box::new(GeDecoder { bnf, options, language }))
    }

    fn draws_models(&self) -> bool {
        false
    }

    fn kind(&self, model: &ModelSettings) -> &'static str {
        match model.phenotype {
            Some(Phenotype::Ls) => "ge-ls",
            _ => "ge-gr8",
        }
    }

    fn grows_surfaces(&self, model: &ModelSettings) -> bool {
        model.phenotype == Some(Phenotype::Gr8)
    }
}

/// A compiled BNF grammar and the file it came from.
struct BnfFile {
    path: PathBuf,
    bnf: Bnf,
}

impl LoadedGrammar for BnfFile {
    fn sample(&self, _request: &SampleRequest) -> Result<Box<dyn Sample>> {
        bail!(
            "{} is a GE grammar: it maps codons into a grammar, so it has no model of its own to sample; \
             show a mapping with `genform map {} --genome C1,C2,…`, or evolve a codon scene of it \
             (see examples/scenes/genr8_canopy.toml)",
            self.path.display(),
            self.path.display()
        )
    }

    fn describe(&self) -> String {
        let b = &self.bnf;
        let alternatives: usize = b.rules.iter().map(|r| r.alternatives.len()).sum();
        let groups = if b.has_groups() { ", with { } and [ ] groups (Genr8's mapping)" } else { "" };
        format!(
            "GE grammar: {} rules, {alternatives} productions, start {}{groups}\n{b}",
            b.rules.len(),
            b.rule(b.start()).name
        )
    }

    fn into_generator(self: Box<Self>) -> Result<Loaded> {
        Err(no_generator(
            &self.path,
            "a GE grammar maps codons into another grammar's text, with no derivation tree of its own: evolve a \
             codon scene of it (`phenotype = \"gr8\"` or `\"ls\"`, see docs/hemls.md)",
        ))
    }
}

/// The language a GE phenotype is grown in.
enum Language {
    Gr8 { settings: Settings, env: Environment },
    Ls { max_modules: usize, max_primitives: usize },
}

/// Codons → phenotype text → model.
struct GeDecoder {
    bnf: Bnf,
    options: MapOptions,
    language: Language,
}

impl CodonDecoder for GeDecoder {
    fn scratch(&self) -> DecodeScratch {
        Box::new(
            Mapper::new(&self.bnf, self.options.clone()).expect("the options were checked when the decoder was built"),
        )
    }

    fn decode(
        &self,
        codons: &[u32],
        scratch: &mut DecodeScratch,
        scene: &mut Scene,
        detail: bool,
        lap: &mut dyn FnMut(Phase),
    ) -> Result<Decoded, Rejection> {
        let mapper = scratch.downcast_mut::<Mapper>().expect("a GE scratch holds its mapper");
        let out = mapper.map(codons);
        lap(Phase::Mapping);
        if let Some(f) = out.fail {
            return Err(reject(Invalid::of_mapping(f), detail, || format!("mapping failed ({f})")));
        }
        let text = mapper.phenotype().unwrap_or_default();
        let (codons_read, wraps) = (out.used_codons, out.wraps);
        let grown = match &self.language {
            Language::Gr8 { settings, env } => grow_gr8(text, settings, env, scene, detail)
                .map(|h| if detail { Some(("gr8", h.to_string())) } else { None }),
            Language::Ls { max_modules, max_primitives } => draw_ls(text, *max_modules, *max_primitives, scene, detail)
                .map(|()| if detail { Some(("ls", text.to_string())) } else { None }),
        };
        lap(Phase::Build);
        Ok(Decoded { codons_read, wraps, grammar_file: grown? })
    }

    fn dress(&self, scene: &mut Scene) {
        if let Language::Gr8 { env, .. } = &self.language {
            env.guides(scene);
        }
    }

    fn phenotype<'s>(&self, scratch: &'s DecodeScratch) -> Option<&'s str> {
        scratch.downcast_ref::<Mapper>()?.phenotype()
    }

    fn mapper<'s>(&self, scratch: &'s mut DecodeScratch) -> Option<&'s mut Mapper> {
        scratch.downcast_mut::<Mapper>()
    }
}

/// Parses and grows a `.gr8` phenotype into `scene`; counts the vertices
/// outside soft boundaries for the soft-boundary criterion.
fn grow_gr8(
    text: &str,
    settings: &Settings,
    env: &Environment,
    scene: &mut Scene,
    detail: bool,
) -> Result<Hemls, Rejection> {
    let name = format!("{PHENOTYPE_STEM}.gr8");
    let hemls = genform_hemls::parse_str(&name, text).map_err(|d| {
        reject(Invalid::Parse, detail, || format!("the phenotype does not parse:\n{}", d.render(false)))
    })?;
    let mut rng = sample_rng(0);
    let growth = genform_hemls::grow(&hemls, settings, env, &mut rng).map_err(|e| {
        let reason = if matches!(e, GrowError::Limit { .. }) { Invalid::ElementLimit } else { Invalid::Growth };
        reject(reason, detail, || e.to_string())
    })?;
    let tag = scene.tag(&hemls.name);
    let mut surface = growth.map.to_surface(tag);
    if env.has_soft_boundaries() {
        surface.outside_soft = growth.map.positions().iter().filter(|p| env.is_outside_soft(**p)).count() as u32;
    }
    scene.surfaces.push(surface);
    Ok(hemls)
}

/// Compiles, derives and draws an `.ls` phenotype into `scene` as
/// `genform sample` does (seed 0).
fn draw_ls(
    text: &str,
    max_modules: usize,
    max_primitives: usize,
    scene: &mut Scene,
    detail: bool,
) -> Result<(), Rejection> {
    let file = SourceFile::new(format!("{PHENOTYPE_STEM}.ls"), text.to_string());
    let (system, _) = genform_lsystem::compile(&file).map_err(|d| {
        reject(Invalid::Parse, detail, || format!("the phenotype does not compile:\n{}", d.render(false)))
    })?;
    let mut rng = sample_rng(0);
    let steps = system.settings.derivation;
    let max_modules = max_modules.min(system.settings.max_modules);
    let string = system
        .derive_limited(steps, &mut rng, max_modules, |_, _| {})
        .map_err(|e| reject(Invalid::ElementLimit, detail, || e.to_string()))?;
    system.interpret(&string, &mut rng, max_primitives, scene).map_err(|e| {
        let genform_lsystem::TurtleError::TooManyPrimitives { .. } = e;
        reject(Invalid::ElementLimit, detail, || e.to_string())
    })?;
    Ok(())
}
