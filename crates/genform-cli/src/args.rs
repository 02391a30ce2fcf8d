//! Raw command-line arguments (clap). Validation into settings happens in
//! `commands` and the formalism table, so parsing stays declarative.

use clap::builder::{PossibleValue, PossibleValuesParser};
use clap::parser::ValueSource;
use clap::{Arg, ArgAction, ArgMatches, Args, CommandFactory, FromArgMatches, Parser, Subcommand};
use genform_app::{
    CompareRequest, EvolveRequest, LimitOverrides, MapRequest, SAMPLE_OPTIONS, SampleRequest, ScoreRequest, ValueKind,
};
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
    #[arg(long, global = true, value_name = "SIZE", value_parser = genform_app::parse_size)]
    pub max_memory: Option<u64>,
}

/// Parses the process's command line (exiting with clap's message on
/// errors and for `--help`).
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
    Cli::from_arg_matches(&matches)
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
    #[cfg(feature = "studio")]
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
#[cfg(feature = "studio")]
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

impl MapArgs {
    /// The mapping these arguments ask for.
    pub fn request(&self) -> MapRequest {
        MapRequest {
            grammar: self.grammar.clone(),
            genome: self.genome.clone(),
            max_wraps: self.max_wraps,
            max_depth: self.max_depth,
            genr8: self.genr8,
            per_choice: self.layout == "per-choice",
            json: self.json,
        }
    }
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
    pub fn overrides(&self) -> LimitOverrides {
        LimitOverrides { max_genes: self.max_genes, max_depth: self.max_depth, max_primitives: self.max_primitives }
    }
}

/// Arguments of `genform sample`: the grammar, and the options of the
/// application's one table of them ([`SAMPLE_OPTIONS`]), each a flag.
#[derive(Debug, Clone)]
pub struct SampleArgs {
    /// Grammar file.
    pub file: PathBuf,
    /// The options given on the command line, in the table's order, each
    /// with its value as written (flags as `true`).
    pub options: Vec<(&'static str, serde_json::Value)>,
}

/// The value parser of an option: its value checked early, as text.
fn option_parser(kind: ValueKind) -> clap::builder::ValueParser {
    match kind {
        ValueKind::Count { max } => clap::builder::ValueParser::new(move |s: &str| -> Result<String, String> {
            match s.trim().parse::<u64>() {
                Ok(n) if n <= max => Ok(s.trim().to_string()),
                _ => Err(format!("`{s}` is not a whole number 0..={max}")),
            }
        }),
        ValueKind::Integer { min, max } => clap::builder::ValueParser::new(move |s: &str| -> Result<String, String> {
            match s.trim().parse::<i64>() {
                Ok(n) if (min..=max).contains(&n) => Ok(s.trim().to_string()),
                _ => Err(format!("`{s}` is not a whole number {min}..={max}")),
            }
        }),
        ValueKind::Choice(names) => PossibleValuesParser::new(names.iter().copied()).into(),
        _ => clap::builder::ValueParser::string(),
    }
}

impl Args for SampleArgs {
    fn augment_args(cmd: clap::Command) -> clap::Command {
        let file = Arg::new("file")
            .value_parser(clap::value_parser!(PathBuf))
            .required(true)
            .help(genform_app::grammar_files_help());
        SAMPLE_OPTIONS.iter().fold(cmd.arg(file), |cmd, o| {
            let mut arg = Arg::new(o.name).long(o.name).help(o.help);
            if let Some(c) = o.short {
                arg = arg.short(c);
            }
            arg = match o.kind {
                ValueKind::Flag => arg.action(ArgAction::SetTrue),
                kind => arg
                    .value_name(o.value_name)
                    .value_parser(option_parser(kind))
                    .allow_hyphen_values(kind == ValueKind::Text),
            };
            if let Some(d) = o.default {
                arg = arg.help(format!("{} [default: {d}]", o.help));
            }
            cmd.arg(arg)
        })
    }

    fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
        Self::augment_args(cmd)
    }
}

impl FromArgMatches for SampleArgs {
    fn from_arg_matches(m: &ArgMatches) -> Result<Self, clap::Error> {
        let file = m.get_one::<PathBuf>("file").cloned().unwrap_or_default();
        let options = SAMPLE_OPTIONS
            .iter()
            .filter(|o| m.value_source(o.name) == Some(ValueSource::CommandLine))
            .map(|o| {
                let value = match o.kind {
                    ValueKind::Flag => serde_json::Value::Bool(m.get_flag(o.name)),
                    _ => serde_json::Value::String(m.get_one::<String>(o.name).cloned().unwrap_or_default()),
                };
                (o.name, value)
            })
            .collect();
        Ok(SampleArgs { file, options })
    }

    fn update_from_arg_matches(&mut self, m: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}

impl SampleArgs {
    /// What these arguments ask of the grammar's formalism (files as
    /// given, relative to the working folder).
    pub fn request(&self) -> anyhow::Result<SampleRequest> {
        let mut r = SampleRequest::new(0);
        for (name, value) in &self.options {
            r.set(name, value, &|s| Ok(PathBuf::from(s)))?;
        }
        Ok(r)
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
    /// Grammar file (every formalism of the table).
    #[arg(help = genform_app::grammar_files_help())]
    pub file: PathBuf,
}

/// The `--algorithm` values: the optimizer table's names with what each is.
fn algorithms() -> PossibleValuesParser {
    PossibleValuesParser::new(
        genform_app::algorithm_names().into_iter().map(|(n, about)| PossibleValue::new(n).help(about)),
    )
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
    #[arg(long, value_parser = algorithms())]
    pub algorithm: Option<String>,
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
    #[arg(long, value_parser = algorithms(), value_delimiter = ',')]
    pub algorithms: Vec<String>,
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
    #[arg(long, value_parser = algorithms(), default_value = "ga")]
    pub algorithm: String,
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
            algorithm: self.algorithm.clone(),
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
            algorithms: self.algorithms.clone(),
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

    fn sample_flags() -> Vec<String> {
        let command = Cli::command();
        let sample = command.find_subcommand("sample").unwrap();
        sample.get_arguments().filter_map(|a| a.get_long().map(|l| format!("--{l}"))).collect()
    }

    #[test]
    fn every_option_of_the_table_is_a_sample_flag() {
        let flags = sample_flags();
        assert_eq!(flags.len(), SAMPLE_OPTIONS.len());
        for o in SAMPLE_OPTIONS {
            assert!(flags.contains(&format!("--{}", o.name)), "{} is no flag", o.name);
        }
    }

    #[test]
    fn given_lists_the_flags_on_the_command_line_only() {
        let args = ["genform", "sample", "c.bsg", "--box", "0,0,0,1,1,1", "-o", "c.schem", "--schem-version", "2"];
        let Command::Sample(a) = parse_from(args).unwrap().command else { panic!("not sample") };
        let r = a.request().unwrap();
        assert_eq!(r.given, ["--out", "--box", "--schem-version"]);
        assert_eq!((r.schem_version, r.data_version, r.box_corners.as_deref()), (2, 3955, Some("0,0,0,1,1,1")));
        let Command::Sample(a) = parse_from(["genform", "sample", "a.sg"]).unwrap().command else { panic!() };
        assert!(a.request().unwrap().given.is_empty());
        let args = ["genform", "sample", "c.bsg", "--box", "-3,0,0,1,1,1", "--every-step", "--steps", "x"];
        let e = parse_from(args).unwrap_err().to_string();
        assert!(e.contains("--steps") && e.contains("not a whole number"), "{e}");
    }
}
