//! What a row of the formalism table is ([`Formalism`]) and what it hands
//! out: a compiled grammar ([`LoadedGrammar`]) that samples models
//! ([`Sample`]), describes itself and gives its generator graph
//! ([`Generator`]-backed [`Loaded`]) or, for codon rows, a decoder.

use anyhow::{Context, Result};
use genform_core::{Generator, Genome, Limits, Scene};
use genform_export::ExportOptions;
use std::path::{Path, PathBuf};

use super::codons::CodonDecoder;
use super::options::SampleRequest;
use super::scene_keys::{ModelSettings, SceneLimits};
use crate::files::{write_atomic, write_model_with};
use crate::toml_doc::Doc;

/// A grammar formalism: one row of [`super::FORMALISMS`].
///
/// A new formalism implements this on a unit struct in its own file in this
/// folder and adds that struct to the table; nothing else dispatches on
/// formalisms. It declares which files it reads ([`Formalism::extensions`]),
/// which `genform sample` options it accepts ([`Formalism::sample_options`]:
/// the rest are refused with one message built from the table), which
/// `--out` extensions it writes itself, which scene settings its scenes
/// may give ([`Formalism::scene_keys`], [`Formalism::limit_keys`]), and it
/// compiles a file ([`Formalism::load`]) into a [`LoadedGrammar`]; a codon
/// row also builds the decoder of its scenes ([`Formalism::decoder`]).
pub(crate) trait Formalism: Sync {
    /// Singular name in messages, e.g. "shape grammar".
    fn name(&self) -> &'static str;

    /// Plural name in messages; the default adds an "s" to [`Formalism::name`].
    fn plural(&self) -> String {
        format!("{}s", self.name())
    }

    /// File-name endings with the leading dot, lowercase, e.g. `[".sg"]` or
    /// `[".gg.yaml"]`; matched case-insensitively against the whole name.
    fn extensions(&self) -> &'static [&'static str];

    /// The long flags of `genform sample` this formalism reads, beyond
    /// [`super::COMMON_SAMPLE_OPTIONS`], e.g. `["--steps", "--string-out"]`.
    fn sample_options(&self) -> &'static [&'static str];

    /// `--out` endings (with the dot, lowercase) that this formalism's
    /// samples write themselves, beyond the Scene formats of
    /// `genform-export`, e.g. `[".mca"]`.
    fn output_extensions(&self) -> &'static [&'static str] {
        &[]
    }

    /// Compiles the grammar at `path`; warnings go to the door's notes,
    /// errors become the returned error with every diagnostic rendered.
    fn load(&self, path: &Path) -> Result<Box<dyn LoadedGrammar>>;

    /// The genomes this formalism's grammars are derived from and evolved
    /// with (`derive`, `evolve`, `score`).
    fn genomes(&self) -> Genomes;

    /// The top-level scene keys of [`super::scene_keys::MODEL_KEYS`] that
    /// scenes of this formalism read, and the `[mapper]` keys as
    /// `mapper.KEY`; the others are refused at their position.
    fn scene_keys(&self) -> &'static [&'static str] {
        &[]
    }

    /// The `[limits]` keys its scenes may set (derivation trees: genes,
    /// depth, primitives).
    fn limit_keys(&self, _model: &ModelSettings) -> &'static [&'static str] {
        &["genes", "depth", "primitives"]
    }

    /// Checks what only this formalism knows about a scene's settings;
    /// refusals name their position through `doc`.
    fn check_scene(&self, _doc: &Doc, _model: &ModelSettings) -> Result<()> {
        Ok(())
    }

    /// Codon formalisms: the decoder of a scene whose grammar is at
    /// `grammar`, with its settings, `[limits]` and codon range.
    fn decoder(
        &self,
        grammar: &Path,
        _model: &ModelSettings,
        _limits: &SceneLimits,
        _codon_range: u32,
    ) -> Result<Box<dyn CodonDecoder>> {
        anyhow::bail!("{}: {} are not evolved with codons", grammar.display(), self.plural())
    }

    /// The scene's kind in `run.json` (`tree`, or a codon scene's
    /// `ge-gr8`, `box-split`, …).
    fn kind(&self, _model: &ModelSettings) -> &'static str {
        "tree"
    }

    /// Whether its grammars draw models of their own (`sample`): a GE
    /// grammar writes another grammar's text from codons instead.
    fn draws_models(&self) -> bool {
        true
    }

    /// Whether the scene's models are grown surfaces (previews turn them
    /// +z up; the `[surface]` criteria apply).
    fn grows_surfaces(&self, _model: &ModelSettings) -> bool {
        false
    }
}

/// What a formalism's models are evolved as: the one contract `derive`,
/// `evolve`, `score` and `info` read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Genomes {
    /// Derivation trees over the grammar's generator graph (tree scenes:
    /// GA, MH, SMC, SOSMC, MAP-Elites; `derive GRAMMAR GENOME`).
    Tree,
    /// Codon lists that make the grammar's choices (codon scenes: GE or
    /// random search; `derive SCENE CODONS`, since the scene's `[mapper]`
    /// settings say how codons choose).
    Codons,
    /// Rule sets written by a GE grammar (`.bnf`) from codons: the grammar
    /// file is a phenotype, evolved through a codon scene of that `.bnf`.
    Phenotype,
}

impl Genomes {
    /// A line for `info` and the docs.
    pub fn describe(self) -> &'static str {
        match self {
            Genomes::Tree => "derivation trees (tree scenes: ga, mh, smc, sosmc, hybrid, map-elites, random)",
            Genomes::Codons => {
                "codon lists (codon scenes: ge, random; derive with the scene: derive SCENE.toml --genome CODONS.json)"
            }
            Genomes::Phenotype => "written by a GE grammar (.bnf) from codons; evolve a codon scene of that .bnf",
        }
    }

    /// A short name (`tree`, `codons`, `phenotype`).
    pub fn name(self) -> &'static str {
        match self {
            Genomes::Tree => "tree",
            Genomes::Codons => "codons",
            Genomes::Phenotype => "phenotype",
        }
    }
}

/// A compiled grammar of some formalism (`Send + Sync`: the Python
/// package shares it between threads).
pub trait LoadedGrammar: Send + Sync {
    /// Draws one model as `request` asks. Side files that options name
    /// (`--genome-out`, `--string-out`, `--trace`) are written here, since
    /// some must be written even when the derivation fails; `--out` is
    /// written afterwards through [`Sample::write`].
    fn sample(&self, request: &SampleRequest) -> Result<Box<dyn Sample>>;

    /// What `genform info` prints: settings, rules, symbols, limits.
    fn describe(&self) -> String;

    /// The generator graph optimizers and `derive` work on, or an error
    /// saying why this grammar has none.
    fn into_generator(self: Box<Self>) -> Result<Loaded>;
}

/// One sampled model, ready to be written.
pub trait Sample: Send + Sync {
    /// The model (for formalisms that grow in steps, the last step's).
    fn scene(&self) -> &Scene;

    /// One line about what was made (name, seed, counts).
    fn summary(&self) -> String;

    /// Writes the model to `out` (the format follows its extension) and
    /// returns the files written: formalisms with their own formats
    /// ([`Formalism::output_extensions`]) or several files (one per growth
    /// step) override it; the default exports [`Sample::scene`] with
    /// `export` (`--granularity`).
    fn write(&self, out: &Path, export: &ExportOptions) -> Result<Vec<PathBuf>> {
        write_model_with(self.scene(), out, export)
    }

    /// The genome the model was derived from, where there is one genome
    /// (not on several footprints) and the request went through the
    /// generator (`--genome-out` or [`SampleRequest::keep_genome`]).
    fn genome(&self) -> Option<&Genome> {
        None
    }
}

/// A [`Sample`] that is a Scene and a summary line.
pub struct SceneSample {
    /// The model.
    pub scene: Scene,
    /// The summary line.
    pub summary: String,
    /// The genome, when it was derived from one.
    pub genome: Option<Genome>,
}

impl Sample for SceneSample {
    fn scene(&self) -> &Scene {
        &self.scene
    }

    fn summary(&self) -> String {
        self.summary.clone()
    }

    fn genome(&self) -> Option<&Genome> {
        self.genome.as_ref()
    }
}

/// A compiled grammar that has a generator graph, whatever its formalism.
pub struct Loaded {
    /// The generator.
    pub generator: Box<dyn Generator>,
    /// Display name of the grammar.
    pub name: String,
    /// Limits declared by the grammar (or defaults), before overrides.
    pub limits: Limits,
}

impl Loaded {
    /// Reads a genome JSON file and checks that it fits this grammar.
    pub fn read_genome(&self, path: &Path) -> Result<Genome> {
        let text = crate::text::read_text(path, "genome")?;
        Genome::from_json(&text, self.generator.graph())
            .with_context(|| format!("{} does not fit grammar `{}`", path.display(), self.name))
    }
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

/// Whether `path`'s file name ends with one of `endings` (lowercase, with
/// the dot), ignoring case.
pub fn ends_with_any(path: &Path, endings: &[&str]) -> bool {
    let name = path.file_name().map(|n| n.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    endings.iter().any(|e| name.ends_with(e))
}

/// Reads mesh assets (shape-grammar `asset`s, L-system `surface`s)
/// relative to the grammar file, through the one mesh-file reader
/// ([`genform_export::read_mesh_file`]: OBJ, STL or GLB by extension).
pub(crate) struct FileAssets {
    base: PathBuf,
}

impl FileAssets {
    /// Assets resolved relative to the folder of `grammar`.
    pub(crate) fn beside(grammar: &Path) -> FileAssets {
        FileAssets { base: grammar.parent().unwrap_or(Path::new(".")).to_path_buf() }
    }

    fn load(&self, path: &str) -> Result<genform_core::scene::Mesh, String> {
        crate::gate::read_mesh(&self.base.join(path)).map_err(|e| format!("{e:#}"))
    }
}

impl genform_shape::AssetResolver for FileAssets {
    fn load_mesh(&self, path: &str) -> Result<genform_core::scene::Mesh, String> {
        self.load(path)
    }

    fn load_footprints(&self, path: &str) -> Result<Vec<Vec<[f64; 2]>>, String> {
        crate::footprints::read_footprints(&self.base.join(path)).map_err(|e| format!("{e:#}"))
    }

    fn load_texture(&self, path: &str) -> Result<Vec<u8>, String> {
        let file = self.base.join(path);
        crate::gate::admit_path(&file).map_err(|e| format!("{e:#}"))?;
        // Checked before reading: every model written embeds or copies it.
        if let Ok(meta) = std::fs::metadata(&file)
            && meta.len() > MAX_TEXTURE_BYTES
        {
            return Err(format!("the file is {} MB, more than a texture may be (64 MB)", meta.len() >> 20));
        }
        crate::gate::read_bytes(&file, "texture").map_err(|e| format!("{e:#}"))
    }
}

/// The largest texture file a grammar may name.
const MAX_TEXTURE_BYTES: u64 = 64 << 20;

impl genform_lsystem::SurfaceAssets for FileAssets {
    fn load_mesh(&self, path: &str) -> Result<genform_core::scene::Mesh, String> {
        self.load(path)
    }
}

/// Draws a genome from `generator`'s prior with the request's stream,
/// warning when a limit truncated it, and saves it to `--genome-out`.
pub(crate) fn sample_genome(generator: &dyn Generator, request: &SampleRequest, limits: &Limits) -> Result<Genome> {
    let sampled = generator.sample(&mut request.rng(), limits).context("cannot sample")?;
    if let Some(kind) = sampled.truncated {
        crate::notes::warn(&format!(
            "warning: growth stopped at the {kind} limit ({}); the model is truncated (raise it with {})",
            kind.value(limits),
            kind.flag()
        ));
    }
    if let Some(path) = &request.genome_out {
        write_atomic(path, sampled.genome.to_json(generator.graph()).as_bytes())?;
    }
    Ok(sampled.genome)
}

/// Shows what the generator left out of `scene`, and why, as warnings
/// (each once, with how often it happened).
pub(crate) fn warn_left_out(scene: &genform_core::Scene) {
    for (text, n) in &scene.notes {
        let times = if *n > 1 { format!(" ({n} times)") } else { String::new() };
        crate::notes::warn(&format!("warning: {text}{times}"));
    }
}

/// The error of [`LoadedGrammar::into_generator`] for a grammar without a
/// generator graph.
pub(crate) fn no_generator(path: &Path, why: &str) -> anyhow::Error {
    anyhow::anyhow!("{} cannot be used as a generator: {why}", path.display())
}
