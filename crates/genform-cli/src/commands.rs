//! The verbs: validated settings in, files out. `sample` and `info` reach
//! every formalism through the table (`genform_cli::formalism`); `derive`
//! goes through `grammar::load`, which asks the same table for a generator.

use anyhow::{Result, bail};
use std::path::PathBuf;

use crate::args::{Cli, Command, DeriveArgs, InfoArgs, SampleArgs};
use genform_cli::formalism;
use genform_cli::grammar::{self, express, genome_summary};
use genform_cli::output::{output_format, write_model};

/// Runs one command.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Sample(a) => sample(a),
        Command::Derive(a) => derive(a),
        Command::Info(a) => info(a),
        Command::Evolve(a) => crate::evolve::evolve(a),
        Command::Score(a) => crate::evolve::score(a),
        Command::Compare(a) => crate::evolve::compare(a),
    }
}

fn sample(a: SampleArgs) -> Result<()> {
    let formalism = formalism::for_path(&a.file)?;
    let request = a.request();
    formalism::check_request(formalism, &request)?;
    let sample = formalism.load(&a.file)?.sample(&request)?;
    match &request.out {
        Some(out) => {
            let written = sample.write(out)?;
            eprintln!("{} → {}", sample.summary(), shown(&written));
        }
        None => println!("{}", sample.summary()),
    }
    Ok(())
}

/// The files a sample wrote, for the summary line: one by name, many as
/// the first and last and how many.
fn shown(written: &[PathBuf]) -> String {
    match written {
        [] => "nothing written".to_string(),
        [one] => one.display().to_string(),
        [first, .., last] => format!("{} … {} ({} files)", first.display(), last.display(), written.len()),
    }
}

fn derive(a: DeriveArgs) -> Result<()> {
    output_format(&a.out)?;
    let loaded = grammar::load(&a.file)?;
    let limits = a.limits.overrides().apply(loaded.limits);
    let genome = loaded.read_genome(&a.genome)?;
    if genome.len() > limits.max_genes {
        bail!(
            "the genome has {} genes, more than the gene limit ({}); raise it with --max-genes",
            genome.len(),
            limits.max_genes
        );
    }
    let scene = express(loaded.generator.as_ref(), &genome, &limits)?;
    write_model(&scene, &a.out)?;
    eprintln!("{}: {} → {}", loaded.name, genome_summary(&scene, &genome), a.out.display());
    Ok(())
}

fn info(a: InfoArgs) -> Result<()> {
    print!("{}", formalism::open(&a.file)?.describe());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn written_files_are_shown_by_name_or_as_a_range() {
        let p = |s: &str| PathBuf::from(s);
        assert_eq!(shown(&[p("a.obj")]), "a.obj");
        assert_eq!(shown(&[p("s0.obj"), p("s1.obj"), p("s2.obj")]), "s0.obj … s2.obj (3 files)");
    }
}
