//! The verbs: validated settings in, files out. `sample` and `info` reach
//! every formalism through the table (`genform_app::formalism`); `derive`
//! goes through `grammar::load`, which asks the same table for a generator.

use anyhow::Result;
use std::path::PathBuf;

use crate::args::{Cli, Command, DeriveArgs, InfoArgs, MapArgs, SampleArgs, ServeArgs};
use genform_app::formalism;
use genform_app::output::{output_format, write_model};

/// Runs one command.
pub fn run(cli: Cli) -> Result<()> {
    if let Some(bytes) = cli.max_memory {
        genform_app::memory::set_budget(bytes);
    }
    match cli.command {
        Command::Sample(a) => sample(a),
        Command::Derive(a) => derive(a),
        Command::Info(a) => info(a),
        Command::Evolve(a) => crate::evolve::evolve(a),
        Command::Score(a) => crate::evolve::score(a),
        Command::Compare(a) => crate::evolve::compare(a),
        Command::Sweep(a) => crate::sweep::sweep(a),
        Command::Map(a) => map(a),
        Command::Serve(a) => serve(a),
        Command::Completions(a) => {
            let mut command = crate::args::command();
            let mut script = Vec::new();
            clap_complete::generate(a.shell, &mut command, "genform", &mut script);
            print_all(&String::from_utf8_lossy(&script))
        }
    }
}

fn sample(a: SampleArgs) -> Result<()> {
    let inputs: Vec<&std::path::Path> =
        [Some(a.file.as_path()), a.env.as_deref(), a.footprints.as_deref()].into_iter().flatten().collect();
    genform_app::output::refuse_overwriting_inputs(
        &inputs,
        &[
            ("--out", a.out.as_deref()),
            ("--string-out", a.string_out.as_deref()),
            ("--trace", a.trace.as_deref()),
            ("--genome-out", a.genome_out.as_deref()),
        ],
    )?;
    let formalism = formalism::for_path(&a.file)?;
    let request = a.request();
    formalism::check_request(formalism, &request)?;
    let sample = formalism.load(&a.file)?.sample(&request)?;
    match &request.out {
        Some(out) => {
            let export = genform_export::ExportOptions { granularity: a.granularity, ..Default::default() };
            let written = sample.write(out, &export)?;
            eprintln!("{} → {}", sample.summary(), shown(&written));
        }
        None => {
            println!("{}", sample.summary());
            eprintln!(
                "no model file written: add --out FILE to save it (e.g. --out {}.glb; .obj .ply .stl .png .svg too)",
                a.file.file_stem().map_or("model".into(), |s| s.to_string_lossy().replace(".gg", ""))
            );
        }
    }
    // The process ends here, and the kernel takes its memory back at once:
    // freeing a model of a million elements piece by piece first took
    // 4 % of a whole run.
    std::mem::forget(sample);
    Ok(())
}

/// The files a sample wrote, for the summary line: one or two by name
/// (an OBJ and its material library), more as the first and last and how
/// many.
fn shown(written: &[PathBuf]) -> String {
    match written {
        [] => "nothing written".to_string(),
        [one] => one.display().to_string(),
        [a, b] => format!("{} and {}", a.display(), b.display()),
        [first, .., last] => format!("{} … {} ({} files)", first.display(), last.display(), written.len()),
    }
}

fn derive(a: DeriveArgs) -> Result<()> {
    genform_app::output::refuse_overwriting_inputs(&[&a.file, &a.genome], &[("--out", Some(&a.out))])?;
    output_format(&a.out)?;
    let request = genform_app::run::DeriveRequest {
        file: a.file.clone(),
        genome: a.genome.clone(),
        limits: a.limits.overrides(),
        set: a.set.clone(),
    };
    let derived = genform_app::run::derive(&request)?;
    let written = write_model(&derived.scene, &a.out)?;
    eprintln!("{} → {}", derived.summary, shown(&written));
    Ok(())
}

fn serve(a: ServeArgs) -> Result<()> {
    if let Some(host) = &a.host {
        eprintln!(
            "warning: listening on {host}: anyone who can reach this address can read the examples and run \
             folders and start runs on this machine"
        );
    }
    let options =
        genform_studio::ServeOptions { file: a.file, port: a.port, host: a.host, out: a.out, examples: a.examples };
    genform_studio::serve(options, |url| {
        use std::io::Write as _;
        println!("genform studio: {url}");
        let _ = std::io::stdout().flush();
    })
}

fn info(a: InfoArgs) -> Result<()> {
    print!("{}", formalism::info(&a.file)?);
    Ok(())
}

fn map(a: MapArgs) -> Result<()> {
    let bnf = formalism::compile_file(&a.grammar, genform_ge::compile)?;
    let mut options = if a.genr8 { genform_ge::MapOptions::genr8() } else { genform_ge::MapOptions::default() };
    if let Some(w) = a.max_wraps {
        options.max_wraps = w;
    }
    if a.layout == "per-choice" {
        options.layout = genform_ge::CodonLayout::PerChoice;
    }
    if let Some(d) = a.max_depth {
        match &mut options.genr8 {
            Some(g) => g.max_depth = Some(d),
            None => options.max_tree_depth = Some(d),
        }
    }
    let m = genform_ge::map(&bnf, &a.genome, &options)
        .map_err(|e| anyhow::anyhow!("cannot map with {}: {e}", a.grammar.display()))?;
    let mut out = String::new();
    if a.json {
        out = serde_json::to_string(&m)? + "\n";
    } else {
        for s in &m.steps {
            let step = describe_step(s);
            out += &format!("codon {:>3} = {:>4}  {:<18} {} of {} → {step}\n", s.pos, s.codon, s.nt, s.choice, s.n);
        }
        out += &match (&m.phenotype, &m.fail) {
            (Some(p), _) => format!("valid: {} codons read, {} wraps\n{p}\n", m.used_codons, m.wraps),
            (None, fail) => {
                let why = fail
                    .as_ref()
                    .and_then(|f| serde_json::to_value(f).ok())
                    .and_then(|v| v.as_str().map(String::from))
                    .unwrap_or_default();
                format!("invalid ({why}): {} codons read, {} wraps\n", m.used_codons, m.wraps)
            }
        };
    }
    print_all(&out)
}

/// Writes `text` to stdout; a closed pipe (`| head`) is not an error.
fn print_all(text: &str) -> Result<()> {
    use std::io::Write;
    match std::io::stdout().lock().write_all(text.as_bytes()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
    }
}

/// What a step decided, in words.
fn describe_step(s: &genform_ge::Step) -> String {
    use genform_ge::StepKind;
    match s.kind {
        StepKind::Expand => format!("production {}", s.choice),
        StepKind::Limited => format!("production {} (depth limit: terminal-only choices)", s.choice),
        StepKind::Repeat => (if s.choice + 2 > s.n { "repeat" } else { "stop" }).to_string(),
        StepKind::Option => (if s.choice == 1 { "include" } else { "leave out" }).to_string(),
        StepKind::Edge => format!("Edge{}", s.choice),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn written_files_are_shown_by_name_or_as_a_range() {
        let p = |s: &str| PathBuf::from(s);
        assert_eq!(shown(&[p("a.obj")]), "a.obj");
        assert_eq!(shown(&[p("a.obj"), p("a.mtl")]), "a.obj and a.mtl");
        assert_eq!(shown(&[p("s0.obj"), p("s1.obj"), p("s2.obj")]), "s0.obj … s2.obj (3 files)");
    }
}
