//! The formalisms the CLI knows, behind one interface ([`Formalism`]) and
//! one table ([`FORMALISMS`]) keyed by the grammar file's extension.
//!
//! Every verb reaches every formalism the same way: [`for_path`] picks the
//! row, [`Formalism::load`] compiles the file into a [`LoadedGrammar`], and
//! the verb asks that object to sample ([`LoadedGrammar::sample`]), describe
//! itself (`info`) or hand over its generator graph (`derive`, `evolve`,
//! `score`, `compare`, scene targets; see [`crate::grammar::load`]).

mod boxsplit;
mod graph;
pub(crate) mod hemls;
mod lsystem;
mod shape;

use anyhow::{Context, Result, bail};
use genform_core::{Diagnostics, Generator, Genome, Limits, Rng, Scene, SourceFile};
use std::path::{Path, PathBuf};

use crate::grammar::{LimitOverrides, Loaded};
use crate::output::{unknown_format, write_atomic, write_model_with};
use crate::source_text::{SourceErrors, read_text};
use genform_export::ExportOptions;

/// Every formalism, one row each. A grammar file belongs to the row one of
/// whose [`Formalism::extensions`] its name ends with.
pub static FORMALISMS: &[&dyn Formalism] =
    &[&shape::ShapeGrammars, &lsystem::LSystems, &boxsplit::BoxSplitGrammars, &graph::GraphGrammars, &hemls::Hemls];

/// A grammar formalism: one row of [`FORMALISMS`].
///
/// A new formalism implements this on a unit struct in its own file in this
/// folder and adds that struct to [`FORMALISMS`]; nothing else dispatches on
/// formalisms. It declares which files it reads ([`extensions`]), which
/// `genform sample` options it accepts ([`sample_options`]: the rest are
/// refused with one message built from the table) and which `--out`
/// extensions it writes itself ([`output_extensions`]), and it compiles a
/// file ([`load`], diagnostics through [`compile_file`]) into a
/// [`LoadedGrammar`], which samples models, describes itself for `info`
/// and hands over its generator graph if it has one.
///
/// [`extensions`]: Formalism::extensions
/// [`sample_options`]: Formalism::sample_options
/// [`output_extensions`]: Formalism::output_extensions
/// [`load`]: Formalism::load
pub trait Formalism: Sync {
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
    /// [`COMMON_SAMPLE_OPTIONS`], e.g. `["--steps", "--string-out"]`.
    fn sample_options(&self) -> &'static [&'static str];

    /// `--out` endings (with the dot, lowercase) that this formalism's
    /// samples write themselves, beyond the Scene formats of
    /// `genform-export`, e.g. `[".mca"]`.
    fn output_extensions(&self) -> &'static [&'static str] {
        &[]
    }

    /// Compiles the grammar at `path`; warnings go to stderr, errors become
    /// the returned error with every diagnostic rendered.
    fn load(&self, path: &Path) -> Result<Box<dyn LoadedGrammar>>;

    /// The genomes this formalism's grammars are derived from and evolved
    /// with (`derive`, `evolve`, `score`).
    fn genomes(&self) -> Genomes;
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
}

/// A [`Sample`] that is a Scene and a summary line.
pub struct SceneSample {
    /// The model.
    pub scene: Scene,
    /// The summary line.
    pub summary: String,
}

impl Sample for SceneSample {
    fn scene(&self) -> &Scene {
        &self.scene
    }

    fn summary(&self) -> String {
        self.summary.clone()
    }
}

/// Flags of `genform sample` every formalism accepts.
pub const COMMON_SAMPLE_OPTIONS: &[&str] = &["--seed", "--out", "--granularity"];

/// Stream id of `sample` (so other verbs' streams never coincide with it).
pub(crate) const SAMPLE_STREAM: u64 = 0x5A4D_504C;

/// What `genform sample` asks of a formalism: the common settings and the
/// value of every formalism's options (each formalism reads only those it
/// declares in [`Formalism::sample_options`]; [`check_request`] has refused
/// the others).
#[derive(Clone, Debug)]
pub struct SampleRequest {
    /// Random seed.
    pub seed: u64,
    /// `--out`: the model file.
    pub out: Option<PathBuf>,
    /// The long flags given on the command line (defaults not included).
    pub given: Vec<String>,
    /// `--genome-out`: where to save the genome.
    pub genome_out: Option<PathBuf>,
    /// `--max-genes`, `--max-depth`, `--max-primitives`.
    pub limits: LimitOverrides,
    /// `--steps`: derivation steps.
    pub steps: Option<u32>,
    /// `--max-modules`: longest string (L-systems), most elements (graph grammars).
    pub max_modules: Option<usize>,
    /// `--string-out`: where to write the derived string.
    pub string_out: Option<PathBuf>,
    /// `--box`: the box to derive in, as written.
    pub box_corners: Option<String>,
    /// `--world`: a region file or folder to observe.
    pub world: Option<PathBuf>,
    /// `--trace`: where to write the derivation trace.
    pub trace: Option<PathBuf>,
    /// `--schem-version`: Sponge schematic version.
    pub schem_version: u8,
    /// `--data-version`: Minecraft DataVersion of block files.
    pub data_version: i32,
    /// `--env`: a growth environment file (HEMLS).
    pub env: Option<PathBuf>,
    /// `--every-step`: write every derivation step (HEMLS).
    pub every_step: bool,
    /// `--smooth`: Catmull–Clark steps on the final surface (HEMLS).
    pub smooth: Option<u32>,
    /// `--footprints`: lots to derive a shape grammar on, one derivation
    /// each (GeoJSON).
    pub footprints: Option<PathBuf>,
}

impl SampleRequest {
    /// A request for seed `seed` with every option at the CLI's default
    /// (no files written, Sponge schematic v2, DataVersion 3955 = 1.21.1).
    pub fn new(seed: u64) -> SampleRequest {
        SampleRequest {
            seed,
            out: None,
            given: Vec::new(),
            genome_out: None,
            limits: LimitOverrides::default(),
            steps: None,
            max_modules: None,
            string_out: None,
            box_corners: None,
            world: None,
            trace: None,
            schem_version: 2,
            data_version: 3955,
            env: None,
            every_step: false,
            smooth: None,
            footprints: None,
        }
    }

    /// The random stream of this sample.
    pub fn rng(&self) -> Rng {
        Rng::stream(self.seed, &[SAMPLE_STREAM])
    }
}

/// Whether `path`'s file name ends with one of `endings` (lowercase, with
/// the dot), ignoring case.
pub fn ends_with_any(path: &Path, endings: &[&str]) -> bool {
    let name = path.file_name().map(|n| n.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    endings.iter().any(|e| name.ends_with(e))
}

/// The formalism of the grammar file at `path`, by extension.
pub fn for_path(path: &Path) -> Result<&'static dyn Formalism> {
    if let Some(f) = FORMALISMS.iter().find(|f| ends_with_any(path, f.extensions())) {
        return Ok(*f);
    }
    let ext = match path.extension() {
        Some(e) => format!("extension `.{}`", e.to_string_lossy()),
        None => "no extension".to_string(),
    };
    let supported: Vec<String> =
        FORMALISMS.iter().map(|f| format!("{} ({})", f.extensions().join(" "), f.name())).collect();
    bail!("don't know the grammar format of {} ({ext}); supported: {}", path.display(), supported.join(", "))
}

/// Compiles the grammar at `path` with the formalism its extension names.
pub fn open(path: &Path) -> Result<Box<dyn LoadedGrammar>> {
    for_path(path)?.load(path)
}

/// What `genform info` prints for the grammar at `path`: its own
/// description, then what it is evolved as.
pub fn info(path: &Path) -> Result<String> {
    let f = for_path(path)?;
    Ok(format!("{}\ngenomes: {}\n", f.load(path)?.describe(), f.genomes().describe()))
}

/// Refuses what `formalism` cannot do for `request`, before anything is
/// loaded: an `--out` extension it cannot write, options it does not read.
pub fn check_request(formalism: &dyn Formalism, request: &SampleRequest) -> Result<()> {
    if let Some(out) = &request.out
        && !ends_with_any(out, formalism.output_extensions())
        && genform_export::Format::from_path(out).is_none()
    {
        return Err(unknown_format(out, formalism.output_extensions()));
    }
    check_options(formalism, &request.given)?;
    let l = &request.limits;
    crate::memory::check_flags(&[
        ("--max-genes", l.max_genes, crate::memory::GENE_BYTES, "genes"),
        ("--max-primitives", l.max_primitives, crate::scene_config::PRIMITIVE_BYTES, "primitives"),
        ("--max-modules", request.max_modules, 64, "modules or graph elements"),
    ])
}

/// Refuses the flags in `given` that `formalism` does not read, naming the
/// formalisms they apply to; flags with the same formalisms share a sentence.
fn check_options(formalism: &dyn Formalism, given: &[String]) -> Result<()> {
    let accepted = |f: &dyn Formalism, flag: &str| f.sample_options().contains(&flag);
    // (the formalisms a flag applies to, the refused flags that apply to them)
    let mut groups: Vec<(Vec<String>, Vec<String>)> = Vec::new();
    for flag in given {
        if COMMON_SAMPLE_OPTIONS.contains(&flag.as_str()) || accepted(formalism, flag) {
            continue;
        }
        let owners: Vec<String> = FORMALISMS
            .iter()
            .filter(|f| accepted(**f, flag))
            .map(|f| format!("{} ({})", f.plural(), f.extensions().join(" ")))
            .collect();
        match groups.iter_mut().find(|(o, _)| *o == owners) {
            Some((_, flags)) => flags.push(flag.clone()),
            None => groups.push((owners, vec![flag.clone()])),
        }
    }
    if groups.is_empty() {
        return Ok(());
    }
    let this = format!("{} ({})", formalism.plural(), formalism.extensions().join(" "));
    let sentences: Vec<String> = groups
        .iter()
        .map(|(owners, flags)| {
            let verb = if flags.len() == 1 { "applies" } else { "apply" };
            if owners.is_empty() {
                format!("{} {verb} to no formalism", and_list(flags))
            } else {
                format!("{} {verb} to {} only, not to {this}", and_list(flags), and_list(owners))
            }
        })
        .collect();
    bail!("{}", sentences.join("; "))
}

/// "a", "a and b", "a, b and c".
fn and_list(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
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
        genform_export::read_mesh_file(&self.base.join(path)).map_err(|e| e.to_string())
    }
}

impl genform_shape::AssetResolver for FileAssets {
    fn load_mesh(&self, path: &str) -> Result<genform_core::scene::Mesh, String> {
        self.load(path)
    }

    fn load_footprints(&self, path: &str) -> Result<Vec<Vec<[f64; 2]>>, String> {
        crate::footprints::read_footprints(&self.base.join(path)).map_err(|e| format!("{e:#}"))
    }
}

impl genform_lsystem::SurfaceAssets for FileAssets {
    fn load_mesh(&self, path: &str) -> Result<genform_core::scene::Mesh, String> {
        self.load(path)
    }
}

/// Reads and compiles a grammar file with `compile`: warnings go to the
/// door's [`crate::notes`] sink, errors become one error with every
/// diagnostic rendered.
pub fn compile_file<T>(
    path: &Path,
    compile: impl FnOnce(&SourceFile) -> Result<(T, Diagnostics), Diagnostics>,
) -> Result<T> {
    let text = read_text(path, "grammar")?;
    let file = SourceFile::new(path.display().to_string(), text);
    let color = crate::notes::colour();
    match compile(&file) {
        Ok((value, warnings)) => {
            if !warnings.items.is_empty() {
                crate::notes::warn(&warnings.render(color));
            }
            Ok(value)
        }
        Err(errors) => Err(SourceErrors::new(&errors, color).into()),
    }
}

/// Draws a genome from `generator`'s prior with the request's stream,
/// warning when a limit truncated it, and saves it to `--genome-out`.
pub fn sample_genome(generator: &dyn Generator, request: &SampleRequest, limits: &Limits) -> Result<Genome> {
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

/// The error of [`LoadedGrammar::into_generator`] for a grammar without a
/// generator graph.
pub fn no_generator(path: &Path, why: &str) -> anyhow::Error {
    anyhow::anyhow!("{} cannot be used as a generator: {why}", path.display())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn request(given: &[&str]) -> SampleRequest {
        SampleRequest { given: given.iter().map(|s| s.to_string()).collect(), ..SampleRequest::new(0) }
    }

    fn refusal(file: &str, given: &[&str]) -> String {
        let f = for_path(Path::new(file)).unwrap();
        check_request(f, &request(given)).unwrap_err().to_string()
    }

    #[test]
    fn every_extension_finds_its_row_and_no_extension_hides_another() {
        for f in FORMALISMS {
            for ext in f.extensions() {
                assert_eq!(for_path(Path::new(&format!("dir/x{ext}"))).unwrap().name(), f.name());
                assert_eq!(for_path(Path::new(&format!("X{}", ext.to_uppercase()))).unwrap().name(), f.name());
                let others = FORMALISMS.iter().filter(|g| g.name() != f.name()).flat_map(|g| g.extensions());
                for other in others {
                    assert!(!ext.ends_with(other) && !other.ends_with(ext), "{ext} and {other} overlap");
                }
            }
        }
    }

    #[test]
    fn unknown_extensions_list_the_table() {
        let err = for_path(Path::new("a/house.dae")).err().unwrap().to_string();
        assert!(err.contains("a/house.dae (extension `.dae`)"), "{err}");
        for f in FORMALISMS {
            for ext in f.extensions() {
                assert!(err.contains(&format!("{ext} ({})", f.name())), "{err}");
            }
        }
        let err = for_path(Path::new("Makefile")).err().unwrap().to_string();
        assert!(err.contains("(no extension)"), "{err}");
    }

    #[test]
    fn options_of_other_formalisms_are_refused_with_one_message() {
        assert_eq!(
            refusal("a.sg", &["--seed", "--box", "--world"]),
            "--box and --world apply to box-split grammars (.bsg) only, not to shape grammars (.sg)"
        );
        assert_eq!(
            refusal("a.bsg", &["--steps", "--string-out"]),
            "--steps applies to L-systems (.ls), graph grammars (.gg.yaml) and HEMLS surface grammars (.gr8) only, \
             not to box-split grammars (.bsg); --string-out applies to L-systems (.ls) only, not to box-split \
             grammars (.bsg)"
        );
        assert!(refusal("a.gg.yaml", &["--genome-out"]).starts_with("--genome-out applies to shape grammars (.sg)"));
    }

    #[test]
    fn declared_and_common_options_pass() {
        for f in FORMALISMS {
            let mut given: Vec<&str> = f.sample_options().to_vec();
            given.extend(COMMON_SAMPLE_OPTIONS);
            check_request(*f, &request(&given)).unwrap();
        }
    }

    #[test]
    fn outputs_a_formalism_writes_itself_pass_its_check_only() {
        let mut r = request(&[]);
        r.out = Some(PathBuf::from("g.YAML"));
        check_request(for_path(Path::new("a.gg.yaml")).unwrap(), &r).unwrap();
        let err = check_request(for_path(Path::new("a.sg")).unwrap(), &r).unwrap_err().to_string();
        assert!(err.contains("use one of the extensions: .obj") && !err.contains(".yaml"), "{err}");
        r.out = Some(PathBuf::from("g.dae"));
        let err = check_request(for_path(Path::new("a.gg.yaml")).unwrap(), &r).unwrap_err().to_string();
        assert!(err.ends_with(".vox .yaml .yml"), "{err}");
    }

    #[test]
    fn and_lists() {
        let l = |v: &[&str]| and_list(&v.iter().map(|s| s.to_string()).collect::<Vec<_>>());
        assert_eq!(l(&["a"]), "a");
        assert_eq!(l(&["a", "b"]), "a and b");
        assert_eq!(l(&["a", "b", "c"]), "a, b and c");
    }
}
