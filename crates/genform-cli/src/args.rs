//! Raw command-line arguments (clap). Validation into settings happens in
//! `commands` and the formalism table, so parsing stays declarative.

use clap::parser::ValueSource;
use clap::{ArgMatches, Args, CommandFactory, FromArgMatches, Parser, Subcommand};
use genform_app::formalism::SampleRequest;
use genform_app::run::{AlgorithmChoice, CompareRequest, EvolveRequest, ScoreRequest};
use std::path::PathBuf;

/// Grammar-based procedural modeling and evolutionary control.
#[derive(Debug, Parser)]
#[command(name = "genform", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
    /// Memory budget that the sizes a scene asks for (population, chains,
    /// particles, archive, voxel grid, pictures, L-system drawings) are checked against before
    /// anything is allocated, e.g. `8G` or `512M` (default: half of the
    /// machine's memory, or of a smaller cgroup or `ulimit -v` limit).
    #[arg(long, global = true, value_name = "SIZE", value_parser = genform_app::memory::parse_size)]
    pub max_memory: Option<u64>,
}

/// Parses the process's command line (exiting with clap's message on
/// errors and for `--help`), noting which `sample` options were given.
pub fn parse() -> Cli {
    parse_from(std::env::args_os()).unwrap_or_else(|e| e.exit())
}

/// Parses `args` (the program name first) like [`parse`].
fn parse_from<I, T>(args: I) -> Result<Cli, clap::Error>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let matches = Cli::command().try_get_matches_from(args)?;
    let mut cli = Cli::from_arg_matches(&matches)?;
    if let (Command::Sample(a), Some(("sample", sub))) = (&mut cli.command, matches.subcommand()) {
        a.given = given_flags("sample", sub);
    }
    Ok(cli)
}

/// The long flags of subcommand `verb` given on the command line, in
/// declaration order (values that only come from defaults are left out).
fn given_flags(verb: &str, matches: &ArgMatches) -> Vec<String> {
    let command = Cli::command();
    let Some(sub) = command.find_subcommand(verb) else { return Vec::new() };
    sub.get_arguments()
        .filter(|arg| matches.value_source(arg.get_id().as_str()) == Some(ValueSource::CommandLine))
        .filter_map(|arg| arg.get_long().map(|l| format!("--{l}")))
        .collect()
}

/// The verbs. The formalism is chosen by the grammar file's extension.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Draw a model from the grammar's prior and write it.
    Sample(SampleArgs),
    /// Replay a saved genome and write the model it describes.
    Derive(DeriveArgs),
    /// Show the generator graph: symbols, parameters, slots and limits.
    Info(InfoArgs),
    /// Steer a grammar towards the targets of a scene config (TOML) by evolution.
    Evolve(EvolveArgs),
    /// Score a saved genome against the targets of a scene config.
    Score(ScoreArgs),
    /// Run several algorithms on a scene with equal time budgets and compare them.
    Compare(CompareArgs),
    /// Vary one or two scene settings, run each value several times, and
    /// plot the best fitness per generation (a parameter study).
    Sweep(SweepArgs),
    /// Map a codon genome through a BNF grammar (grammatical evolution) and
    /// show the phenotype and every codon read.
    Map(MapArgs),
    /// Start the studio: a local web page to explore grammars, watch and
    /// steer runs, and breed models by eye.
    Serve(ServeArgs),
    /// Print a shell completion script, e.g. `genform completions bash >
    /// ~/.local/share/bash-completion/completions/genform`.
    Completions(CompletionsArgs),
}

/// Arguments of `genform completions`.
#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// The shell to complete in.
    #[arg(value_enum)]
    pub shell: clap_complete::Shell,
}

/// The command line's definition, for completion scripts.
pub fn command() -> clap::Command {
    Cli::command()
}

/// Most worker threads a run may ask for: each has its own stack and
/// scratch buffers, and no machine this runs on has more cores.
pub const MAX_THREADS: usize = 1024;

/// Parses `--threads`: 1 to [`MAX_THREADS`].
fn thread_count(text: &str) -> Result<usize, String> {
    match text.parse::<usize>() {
        Ok(n) if (1..=MAX_THREADS).contains(&n) => Ok(n),
        Ok(_) => Err(format!("must be 1 to {MAX_THREADS} (the default uses every core)")),
        Err(_) => Err(format!("`{text}` is not a whole number of threads")),
    }
}

/// Arguments of `genform serve`.
#[derive(Debug, Args)]
pub struct ServeArgs {
    /// A scene config (.toml) or grammar to open first; its folder is
    /// served too (as `scene/…`).
    pub file: Option<PathBuf>,
    /// Port to listen on; 0 picks a free one.
    #[arg(long, default_value_t = 8150)]
    pub port: u16,
    /// Address to listen on (default 127.0.0.1, this machine only). Any
    /// other address lets other machines start runs and read results.
    #[arg(long, value_name = "ADDR")]
    pub host: Option<String>,
    /// Folder for run folders, breeding saves and sampled models.
    #[arg(long, short, default_value = "studio-runs")]
    pub out: PathBuf,
    /// Folder of example grammars and scenes (default: ./examples if it exists).
    #[arg(long, value_name = "DIR")]
    pub examples: Option<PathBuf>,
}

/// Arguments of `genform map`.
#[derive(Debug, Args)]
pub struct MapArgs {
    /// BNF grammar (.bnf).
    pub grammar: PathBuf,
    /// The codons, comma-separated (e.g. `12,7,200`).
    #[arg(long, value_name = "C1,C2,…", value_delimiter = ',', required = true, num_args = 1..)]
    pub genome: Vec<u32>,
    /// How often reading may wrap back to the first codon (default 0; 4 with --genr8).
    #[arg(long, value_name = "N")]
    pub max_wraps: Option<u32>,
    /// Derivation-tree depth limit (root = 1); deeper is invalid. With --genr8:
    /// the depth from which only productions without non-terminals are chosen.
    #[arg(long, value_name = "D")]
    pub max_depth: Option<u32>,
    /// Genr8's extensions: `{ }` repetition and `[ ]` options decided by
    /// codons, Edge IDs, EdgeX/Y/Z binding, depth-limited choice, repair of
    /// edge types without a rule, spaced tokens (for examples/ge/genr8*.bnf).
    #[arg(long)]
    pub genr8: bool,
    /// Which codon each decision reads: `sequential` (standard GE) or
    /// `per-choice` (one interleaved codon stream per non-terminal, group
    /// and edge IDs, as a scene's `[mapper] layout`).
    #[arg(long, value_name = "LAYOUT", value_parser = ["sequential", "per-choice"], default_value = "sequential")]
    pub layout: String,
    /// Print the whole trace as JSON (fields `valid`, `fail`, `phenotype`,
    /// `used_codons`, `wraps`, `choices`, `steps`).
    #[arg(long)]
    pub json: bool,
}

/// Overrides of the grammar's derivation limits.
#[derive(Debug, Args, Clone, Default)]
pub struct LimitArgs {
    /// Most genes (rule applications) in a derivation.
    #[arg(long, value_name = "N")]
    pub max_genes: Option<usize>,
    /// Deepest derivation.
    #[arg(long, value_name = "N")]
    pub max_depth: Option<usize>,
    /// Most primitives in the model.
    #[arg(long, value_name = "N")]
    pub max_primitives: Option<usize>,
}

impl LimitArgs {
    /// The overrides these flags set.
    pub fn overrides(&self) -> genform_app::grammar::LimitOverrides {
        genform_app::grammar::LimitOverrides {
            max_genes: self.max_genes,
            max_depth: self.max_depth,
            max_primitives: self.max_primitives,
        }
    }
}

/// Arguments of `genform sample`.
#[derive(Debug, Args)]
pub struct SampleArgs {
    /// Grammar file (.sg shape grammar, .ls L-system, .bsg box-split grammar, .gg.yaml graph grammar,
    /// .gr8 HEMLS surface grammar).
    pub file: PathBuf,
    /// Random seed; the same seed gives the same model.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Output file; the format follows the extension (.glb .obj .ply .stl .png .svg;
    /// block grammars also .schem .litematic .vox .mca; graph grammars .yaml). Without it
    /// nothing is written: the model's summary goes to stdout.
    #[arg(long, short)]
    pub out: Option<PathBuf>,
    /// L-systems, graph grammars and HEMLS: derivation steps (default: the
    /// file's `derivation:`; HEMLS: the environment's `steps`, else 4).
    #[arg(long, value_name = "N")]
    pub steps: Option<u32>,
    /// L-systems: longest string a derivation may produce (default: the
    /// file's `max_modules:`, else 5,000,000); graph grammars: most
    /// elements (vertices + edges, default 1,000,000).
    #[arg(long, value_name = "N")]
    pub max_modules: Option<usize>,
    /// L-systems: also write the derived module string to this text file.
    #[arg(long, value_name = "FILE")]
    pub string_out: Option<PathBuf>,
    /// Box-split grammars: the box to derive in, two opposite corners
    /// (inclusive) `x0,y0,z0,x1,y1,z1`.
    #[arg(long = "box", value_name = "X0,Y0,Z0,X1,Y1,Z1", allow_hyphen_values = true)]
    pub r#box: Option<String>,
    /// Box-split grammars: observe this Minecraft region file (r.X.Z.mca) or
    /// folder of region files; `--out x.mca` writes into a copy of it.
    #[arg(long, value_name = "REGION")]
    pub world: Option<PathBuf>,
    /// Box-split grammars: write the derivation trace (choices, failures,
    /// backtracks) as JSON.
    #[arg(long, value_name = "FILE.json")]
    pub trace: Option<PathBuf>,
    /// Box-split grammars: Sponge schematic version of `.schem` output.
    #[arg(long, value_name = "2|3", default_value_t = 2, value_parser = clap::value_parser!(u8).range(2..=3))]
    pub schem_version: u8,
    /// Box-split grammars: Minecraft DataVersion written into `.schem` and
    /// `.litematic` files (3955 = 1.21.1; 3337 = 1.19.4).
    #[arg(long, value_name = "N", default_value_t = 3955)]
    pub data_version: i32,
    /// Also save the derivation tree (genome) as JSON, for `genform derive`.
    #[arg(long, value_name = "G.json")]
    pub genome_out: Option<PathBuf>,
    /// .glb/.obj: how the model is split into nodes/objects: `merged` (one mesh, a part per
    /// material), `tag` (one per tag), `instanced` (one per primitive; GLB nodes share meshes);
    /// `auto`: merged above 32 primitives, else instanced.
    #[arg(long, value_name = "MODE", default_value_t = genform_export::Granularity::Auto)]
    pub granularity: genform_export::Granularity,
    /// HEMLS (.gr8): the environment file (TOML: growth settings, charges,
    /// gravity, boundaries); without it the surface grows with Genr8's defaults.
    #[arg(long, value_name = "ENV.toml")]
    pub env: Option<PathBuf>,
    /// HEMLS (.gr8): write every derivation step, one mesh per step
    /// (`name-step0.obj` …) and, for .png/.svg, one picture with a labelled
    /// panel per step, all at one scale.
    #[arg(long)]
    pub every_step: bool,
    /// HEMLS (.gr8): apply K Catmull–Clark subdivision steps to the final surface (at most 6).
    #[arg(long, value_name = "K")]
    pub smooth: Option<u32>,
    /// Shape grammars (.sg): derive once per lot of this GeoJSON file
    /// (Polygon and MultiPolygon features, metres) or OBJ file (faces facing
    /// up), lot k with seed SEED + k, instead of the `footprints` the
    /// grammar declares.
    #[arg(long, value_name = "LOTS.geojson|LOTS.obj")]
    pub footprints: Option<PathBuf>,
    #[command(flatten)]
    pub limits: LimitArgs,
    /// The long flags given on the command line (filled by [`parse`], not
    /// by clap), for the formalism table's option check.
    #[arg(skip)]
    pub given: Vec<String>,
}

impl SampleArgs {
    /// What these arguments ask of the grammar's formalism.
    pub fn request(&self) -> SampleRequest {
        SampleRequest {
            seed: self.seed,
            out: self.out.clone(),
            given: self.given.clone(),
            genome_out: self.genome_out.clone(),
            limits: self.limits.overrides(),
            steps: self.steps,
            max_modules: self.max_modules,
            string_out: self.string_out.clone(),
            box_corners: self.r#box.clone(),
            world: self.world.clone(),
            trace: self.trace.clone(),
            schem_version: self.schem_version,
            data_version: self.data_version,
            env: self.env.clone(),
            every_step: self.every_step,
            smooth: self.smooth,
            footprints: self.footprints.clone(),
        }
    }
}

/// Arguments of `genform derive`.
#[derive(Debug, Args)]
pub struct DeriveArgs {
    /// Grammar file with derivation-tree genomes (.sg, a context-free .ls),
    /// or the scene (.toml) a genome was evolved in: tree scenes derive
    /// under their limits, codon scenes (.bnf, .bsg, .gg.yaml grammars)
    /// decode codons with their [mapper] settings.
    pub file: PathBuf,
    /// Genome JSON written by `sample --genome-out` or an optimizer
    /// (`best-genome.json`), or codons (`best-codons.json`).
    #[arg(long, value_name = "G.json")]
    pub genome: PathBuf,
    /// Output file; the format follows the extension (.glb .obj .ply .stl .png).
    #[arg(long, short)]
    pub out: PathBuf,
    /// Overrides a scene setting (with a scene file), as for `evolve`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    #[command(flatten)]
    pub limits: LimitArgs,
}

/// Arguments of `genform info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// Grammar file (.sg shape grammar, .ls L-system, .bsg box-split grammar, .gg.yaml graph grammar,
    /// .gr8 HEMLS surface grammar).
    pub file: PathBuf,
}

/// A search algorithm on the command line: the app's [`AlgorithmChoice`],
/// with its names and help texts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Algorithm(pub AlgorithmChoice);

impl clap::ValueEnum for Algorithm {
    fn value_variants<'a>() -> &'a [Self] {
        const ALL: [Algorithm; 8] = {
            let all = AlgorithmChoice::ALL;
            [
                Algorithm(all[0]),
                Algorithm(all[1]),
                Algorithm(all[2]),
                Algorithm(all[3]),
                Algorithm(all[4]),
                Algorithm(all[5]),
                Algorithm(all[6]),
                Algorithm(all[7]),
            ]
        };
        &ALL
    }

    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        Some(clap::builder::PossibleValue::new(self.0.name()).help(self.0.about()))
    }
}

impl From<Algorithm> for AlgorithmChoice {
    fn from(a: Algorithm) -> AlgorithmChoice {
        a.0
    }
}

/// Arguments of `genform evolve`.
#[derive(Debug, Args)]
pub struct EvolveArgs {
    /// Scene config (.toml): grammar, targets, fitness and optimizer settings.
    pub scene: PathBuf,
    /// Random seed; the same seed gives the same results at any thread count.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Stop after N generations (overrides the scene's `[run]`).
    #[arg(long, value_name = "N")]
    pub generations: Option<usize>,
    /// Stop after this much wall-clock time, e.g. 30s, 5m, 1h.
    #[arg(long, value_name = "TIME")]
    pub budget: Option<String>,
    /// Stop after N objective evaluations.
    #[arg(long, value_name = "N")]
    pub evaluations: Option<u64>,
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(long, value_name = "N", value_parser = thread_count)]
    pub threads: Option<usize>,
    /// Output folder for the best model, genome, statistics and plots.
    #[arg(long, short, default_value = "evolve-out")]
    pub out: PathBuf,
    /// Search algorithm (default: ga for tree scenes, ge for codon scenes).
    #[arg(long, value_enum)]
    pub algorithm: Option<Algorithm>,
    /// GA preset, overriding the scene's `[ga] preset`: `thesis` runs the
    /// thesis' exact operators (no drift, no duplicate avoidance).
    #[arg(long, value_name = "NAME", value_parser = ["default", "thesis"])]
    pub preset: Option<String>,
    /// No progress bar.
    #[arg(long, short)]
    pub quiet: bool,
    /// Replay the steering of an earlier run: its `run.json` (or a JSON list
    /// of `{"generation": N, "set": {"weights": {…}, "targets": {…}}}`);
    /// each change takes effect at the same generation as before.
    #[arg(long, value_name = "FILE")]
    pub steering: Option<PathBuf>,
    /// Overrides a scene setting, e.g. `ga.population=20` or
    /// `surface.weights.symmetry=2` (a TOML value; a bare word is a
    /// string); repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    #[command(flatten)]
    pub limits: LimitArgs,
}

/// Arguments of `genform compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// Scene config (.toml).
    pub scene: PathBuf,
    /// Wall-clock budget of every run, e.g. 10s, 1m.
    #[arg(long, value_name = "TIME", default_value = "30s")]
    pub budget: String,
    /// Runs per algorithm; run r uses seed `--seed` + r.
    #[arg(long, value_name = "N", default_value_t = 5)]
    pub runs: usize,
    /// Algorithms to compare, comma-separated (default: ga,mh,smc,sosmc for
    /// tree scenes, ge,random for codon scenes).
    #[arg(long, value_enum, value_delimiter = ',')]
    pub algorithms: Vec<Algorithm>,
    /// Seed of the first run.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads of each run (default: all cores); runs go one after another.
    #[arg(long, value_name = "N", value_parser = thread_count)]
    pub threads: Option<usize>,
    /// Output folder for comparison.csv, comparison.svg and each algorithm's best genome.
    #[arg(long, short, default_value = "compare-out")]
    pub out: PathBuf,
    /// GA preset of the `ga` and `hybrid` runs, overriding the scene's
    /// `[ga] preset`: `thesis` runs the thesis' exact operators.
    #[arg(long, value_name = "NAME", value_parser = ["default", "thesis"])]
    pub preset: Option<String>,
    /// No progress output.
    #[arg(long, short)]
    pub quiet: bool,
    /// Overrides a scene setting, e.g. `ga.population=20` or
    /// `surface.weights.symmetry=2` (a TOML value; a bare word is a
    /// string); repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    #[command(flatten)]
    pub limits: LimitArgs,
}

/// Arguments of `genform sweep`.
#[derive(Debug, Args)]
pub struct SweepArgs {
    /// Scene config (.toml) of a tree grammar.
    pub scene: PathBuf,
    /// A scene key and its values, e.g. `ga.population=10,50,100` or
    /// `ga.initial_length=[10,10],[50,50]`: TOML values separated by `,` or
    /// `;` outside brackets, braces and quotes; a bare word is a string.
    /// Give it twice to cross two keys; more `--set`s with one value each
    /// fix other settings for every run.
    #[arg(long = "set", value_name = "KEY=V1,V2,…", required = true)]
    pub set: Vec<String>,
    /// Runs per value (combination); run r uses seed `--seed` + r.
    #[arg(long, value_name = "N", default_value_t = 5)]
    pub runs: usize,
    /// Seed of the first run.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Stop each run after N generations (overrides the scene's `[run]`).
    #[arg(long, value_name = "N")]
    pub generations: Option<usize>,
    /// Stop each run after this much wall-clock time, e.g. 10s (results then
    /// depend on the machine and its load).
    #[arg(long, value_name = "TIME")]
    pub budget: Option<String>,
    /// Stop each run after N objective evaluations.
    #[arg(long, value_name = "N")]
    pub evaluations: Option<u64>,
    /// Search algorithm (default ga).
    #[arg(long, value_enum, default_value = "ga")]
    pub algorithm: Algorithm,
    /// Worker threads shared by all runs (default: all cores). Results do not depend on it.
    #[arg(long, value_name = "N", value_parser = thread_count)]
    pub threads: Option<usize>,
    /// Output folder for sweep.csv, sweep.svg and summary.md.
    #[arg(long, short, default_value = "sweep-out")]
    pub out: PathBuf,
    /// No progress output.
    #[arg(long, short)]
    pub quiet: bool,
}

/// Arguments of `genform score`.
#[derive(Debug, Args)]
pub struct ScoreArgs {
    /// Scene config (.toml).
    pub scene: PathBuf,
    /// Genome JSON (e.g. `best-genome.json` of an evolve run; for codon
    /// scenes `best-codons.json` or a JSON list of codons).
    #[arg(long, value_name = "G.json")]
    pub genome: PathBuf,
    /// Score under this `[fitness] form` instead of the scene's (volume and
    /// image targets): `paper`, `separate-overlap`, `image`, `linear` or
    /// `reference-cpu` (the reference implementation's CPU counting).
    #[arg(long, value_name = "NAME")]
    pub form: Option<String>,
    /// Overrides a scene setting, e.g. `ga.population=20` or
    /// `surface.weights.symmetry=2` (a TOML value; a bare word is a
    /// string); repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    #[command(flatten)]
    pub limits: LimitArgs,
}

impl EvolveArgs {
    /// The run these arguments ask for.
    pub fn request(&self) -> EvolveRequest {
        EvolveRequest {
            scene: self.scene.clone(),
            seed: self.seed,
            generations: self.generations,
            budget: self.budget.clone(),
            evaluations: self.evaluations,
            threads: self.threads,
            out: Some(self.out.clone()),
            algorithm: self.algorithm.map(AlgorithmChoice::from),
            preset: self.preset.clone(),
            limits: self.limits.overrides(),
            set: self.set.clone(),
        }
    }
}

impl CompareArgs {
    /// The comparison these arguments ask for.
    pub fn request(&self) -> CompareRequest {
        CompareRequest {
            scene: self.scene.clone(),
            budget: self.budget.clone(),
            runs: self.runs,
            algorithms: self.algorithms.iter().map(|a| AlgorithmChoice::from(*a)).collect(),
            seed: self.seed,
            threads: self.threads,
            out: self.out.clone(),
            preset: self.preset.clone(),
            limits: self.limits.overrides(),
            set: self.set.clone(),
        }
    }
}

impl ScoreArgs {
    /// The score these arguments ask for.
    pub fn request(&self) -> ScoreRequest {
        ScoreRequest {
            scene: self.scene.clone(),
            genome: self.genome.clone(),
            form: self.form.clone(),
            limits: self.limits.overrides(),
            set: self.set.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_app::formalism::{COMMON_SAMPLE_OPTIONS, FORMALISMS};

    fn sample_flags() -> Vec<String> {
        let command = Cli::command();
        let sample = command.find_subcommand("sample").unwrap();
        sample.get_arguments().filter_map(|a| a.get_long().map(|l| format!("--{l}"))).collect()
    }

    #[test]
    fn every_sample_flag_is_common_or_read_by_a_formalism_and_every_declared_one_exists() {
        let flags = sample_flags();
        for flag in &flags {
            let read = FORMALISMS.iter().any(|f| f.sample_options().contains(&flag.as_str()));
            assert!(COMMON_SAMPLE_OPTIONS.contains(&flag.as_str()) || read, "no formalism reads {flag}");
        }
        for f in FORMALISMS {
            for opt in f.sample_options().iter().chain(COMMON_SAMPLE_OPTIONS) {
                assert!(flags.iter().any(|fl| fl == opt), "{} declares {opt}, which `sample` lacks", f.name());
            }
        }
    }

    #[test]
    fn given_lists_the_flags_on_the_command_line_only() {
        let args = ["genform", "sample", "c.bsg", "--box", "0,0,0,1,1,1", "-o", "c.schem", "--schem-version", "2"];
        let Command::Sample(a) = parse_from(args).unwrap().command else { panic!("not sample") };
        assert_eq!(a.given, ["--out", "--box", "--schem-version"]);
        let r = a.request();
        assert_eq!((r.schem_version, r.data_version, r.box_corners.as_deref()), (2, 3955, Some("0,0,0,1,1,1")));
        let Command::Sample(a) = parse_from(["genform", "sample", "a.sg"]).unwrap().command else { panic!() };
        assert!(a.given.is_empty());
    }
}
