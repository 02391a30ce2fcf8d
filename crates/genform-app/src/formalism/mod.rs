//! The formalisms the CLI knows, behind one interface ([`Formalism`]) and
//! one table ([`FORMALISMS`]) keyed by the grammar file's extension.
//!
//! Every verb reaches every formalism the same way: [`for_path`] picks the
//! row, [`Formalism::load`] compiles the file into a [`LoadedGrammar`], and
//! the verb asks that object to sample ([`LoadedGrammar::sample`]), describe
//! itself (`info`) or hand over its generator graph (`derive`, `evolve`,
//! `score`, `compare`, scene targets; see [`load_generator`]). Doors see
//! the rows as [`FormalismRef`]s; scenes read their scene hooks (which
//! keys a scene may set, the decoder of a codon scene).

mod boxsplit;
mod codons;
mod ge;
mod graph;
mod hemls;
mod lsystem;
mod options;
mod row;
mod scene_keys;
mod shape;

use anyhow::{Result, bail};
use std::path::Path;

pub(crate) use codons::{CodonDecoder, DecodeScratch, Decoded, Phase};
pub use codons::{Invalid, InvalidCounts, Rejection, read_codons};
pub use options::{COMMON_SAMPLE_OPTIONS, SAMPLE_OPTIONS, SampleOption, SampleRequest, ValueKind, sample_option};
pub(crate) use row::Formalism;
pub use row::{Genomes, Loaded, LoadedGrammar, Sample, ends_with_any, express, genome_summary};
pub use scene_keys::{LIMIT_KEYS, LimitOverrides, MODEL_KEYS, ModelSettings, PRIMITIVE_BYTES, SceneLimits};

/// A row of the formalism table, as the doors see it.
#[derive(Clone, Copy)]
pub struct FormalismRef(&'static dyn Formalism);

impl FormalismRef {
    /// Singular name in messages, e.g. "shape grammar".
    pub fn name(self) -> &'static str {
        self.0.name()
    }

    /// Plural name in messages.
    pub fn plural(self) -> String {
        self.0.plural()
    }

    /// File-name endings with the leading dot, lowercase.
    pub fn extensions(self) -> &'static [&'static str] {
        self.0.extensions()
    }

    /// The `genform sample` flags it reads beyond [`COMMON_SAMPLE_OPTIONS`].
    pub fn sample_options(self) -> &'static [&'static str] {
        self.0.sample_options()
    }

    /// Whether it reads the sample option `name` (common ones included).
    pub fn reads(self, name: &str) -> bool {
        let flag = format!("--{}", name.trim_start_matches("--").replace('_', "-"));
        COMMON_SAMPLE_OPTIONS.contains(&flag.as_str()) || self.0.sample_options().contains(&flag.as_str())
    }

    /// `--out` endings its samples write themselves.
    pub fn output_extensions(self) -> &'static [&'static str] {
        self.0.output_extensions()
    }

    /// Whether its grammars draw models of their own (`sample`; a GE
    /// grammar maps codons into another grammar instead).
    pub fn draws_models(self) -> bool {
        self.0.draws_models()
    }

    /// What its grammars are evolved as.
    pub fn genomes(self) -> Genomes {
        self.0.genomes()
    }

    /// Compiles the grammar at `path`.
    pub fn load(self, path: &Path) -> Result<Box<dyn LoadedGrammar>> {
        self.0.load(path)
    }

    /// Refuses what it cannot do for `request`, before anything is loaded
    /// (see [`check_request`]).
    pub fn check(self, request: &SampleRequest) -> Result<()> {
        check_request(self.0, request)
    }
}

/// Every row of the formalism table.
pub fn formalisms() -> Vec<FormalismRef> {
    FORMALISMS.iter().map(|f| FormalismRef(*f)).collect()
}

/// The grammar files the table reads, for help texts: "(.sg shape grammar,
/// .ls L-system, …)".
pub fn grammar_files_help() -> String {
    let rows: Vec<String> = FORMALISMS.iter().map(|f| format!("{} {}", f.extensions().join(" "), f.name())).collect();
    format!("Grammar file ({})", rows.join(", "))
}

/// The formalism of the grammar file at `path`, by extension.
pub fn formalism_of(path: &Path) -> Result<FormalismRef> {
    for_path(path).map(FormalismRef)
}

/// Every formalism, one row each. A grammar file belongs to the row one of
/// whose [`Formalism::extensions`] its name ends with.
pub(crate) static FORMALISMS: &[&dyn Formalism] = &[
    &shape::ShapeGrammars,
    &lsystem::LSystems,
    &boxsplit::BoxSplitGrammars,
    &graph::GraphGrammars,
    &hemls::Hemls,
    &ge::GeGrammars,
];

/// The row of the grammar file at `path`, by extension.
pub(crate) fn for_path(path: &Path) -> Result<&'static dyn Formalism> {
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
pub(crate) fn open(path: &Path) -> Result<Box<dyn LoadedGrammar>> {
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
fn check_request(formalism: &dyn Formalism, request: &SampleRequest) -> Result<()> {
    if let Some(out) = &request.out
        && !ends_with_any(out, formalism.output_extensions())
        && genform_export::Format::from_path(out).is_none()
    {
        return Err(crate::files::unknown_format(out, formalism.output_extensions()));
    }
    check_options(formalism, &request.given)?;
    let l = &request.limits;
    crate::memory::check_flags(&[
        ("--max-genes", l.max_genes, crate::memory::GENE_BYTES, "genes"),
        ("--max-primitives", l.max_primitives, PRIMITIVE_BYTES, "primitives"),
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

/// Compiles the grammar at `path` into a generator; a formalism without a
/// generator graph is an error that says why.
pub(crate) fn load_generator(path: &Path) -> Result<Loaded> {
    open(path)?.into_generator()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

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
            assert!(err.contains(&format!("{} ({})", f.extensions().join(" "), f.name())), "{err}");
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
            "--steps applies to L-systems (.ls .lpy), graph grammars (.gg.yaml) and HEMLS surface grammars (.gr8) only, \
             not to box-split grammars (.bsg); --string-out applies to L-systems (.ls .lpy) only, not to box-split \
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
    fn every_option_of_the_table_is_read_and_every_declared_one_is_in_it() {
        for o in SAMPLE_OPTIONS {
            let flag = format!("--{}", o.name);
            let read = FORMALISMS.iter().any(|f| f.sample_options().contains(&flag.as_str()));
            assert!(COMMON_SAMPLE_OPTIONS.contains(&flag.as_str()) || read, "no formalism reads {flag}");
        }
        for f in FORMALISMS {
            for flag in f.sample_options().iter().chain(COMMON_SAMPLE_OPTIONS) {
                assert!(sample_option(flag).is_some(), "{} declares {flag}, which the table lacks", f.name());
            }
        }
    }

    #[test]
    fn and_lists() {
        let l = |v: &[&str]| and_list(&v.iter().map(|s| s.to_string()).collect::<Vec<_>>());
        assert_eq!(l(&["a"]), "a");
        assert_eq!(l(&["a", "b"]), "a and b");
        assert_eq!(l(&["a", "b", "c"]), "a, b and c");
    }
}
