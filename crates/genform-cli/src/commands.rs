//! The verbs: validated settings in, files out, through the application
//! library's requests (`sample` and `info` reach every formalism through
//! its table).

use anyhow::Result;
use std::path::PathBuf;

use crate::args::{Cli, Command, DeriveArgs, InfoArgs, MapArgs, SampleArgs};
use genform_app::{output_format, write_model};

/// Runs one command.
pub fn run(cli: Cli) -> Result<()> {
    if let Some(bytes) = cli.max_memory {
        genform_app::set_budget(bytes);
    }
    // One command per process: everything it reads is its input.
    let _session = genform_app::session();
    match cli.command {
        Command::Sample(a) => sample(a),
        Command::Derive(a) => derive(a),
        Command::Info(a) => info(a),
        Command::Evolve(a) => crate::evolve::evolve(a),
        Command::Score(a) => crate::evolve::score(a),
        Command::Compare(a) => crate::evolve::compare(a),
        Command::Sweep(a) => crate::sweep::sweep(a),
        Command::Map(a) => map(a),
        #[cfg(feature = "studio")]
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
    let request = a.request()?;
    let formalism = genform_app::formalism_of(&a.file)?;
    formalism.check(&request)?;
    // Everything the grammar reads (its meshes, context, footprints) and
    // the files the flags name are inputs that no output may replace.
    let loaded = formalism.load(&a.file)?;
    request.admit_inputs()?;
    genform_app::refuse_outputs(&request.outputs())?;
    let sample = loaded.sample(&request)?;
    match &request.out {
        Some(out) => {
            let written = sample.write(out, &request.export())?;
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
    genform_app::admit_read(&a.file, "grammar or scene")?;
    genform_app::admit_read(&a.genome, "genome")?;
    genform_app::refuse_outputs(&[("--out", &a.out)])?;
    output_format(&a.out)?;
    let request = genform_app::DeriveRequest {
        file: a.file.clone(),
        genome: a.genome.clone(),
        limits: a.limits.overrides(),
        set: a.set.clone(),
    };
    let derived = genform_app::derive(&request)?;
    genform_app::refuse_outputs(&[("--out", &a.out)])?;
    let written = write_model(&derived.scene, &a.out)?;
    eprintln!("{} → {}", derived.summary, shown(&written));
    Ok(())
}

#[cfg(feature = "studio")]
fn serve(a: crate::args::ServeArgs) -> Result<()> {
    if let Some(host) = &a.host {
        eprintln!(
            "warning: listening on {host}: anyone who can reach this address can read the examples and run \
             folders and start runs on this machine"
        );
    }
    let options =
        genform_studio::ServeOptions { file: a.file, port: a.port, host: a.host, out: a.out, examples: a.examples };
    genform_studio::serve(options, |url, warnings| {
        use std::io::Write as _;
        for w in warnings {
            eprintln!("{w}");
        }
        println!("genform studio: {url}");
        let _ = std::io::stdout().flush();
    })
}

fn info(a: InfoArgs) -> Result<()> {
    print!("{}", genform_app::info(&a.file)?);
    Ok(())
}

fn map(a: MapArgs) -> Result<()> {
    print_all(&genform_app::map(&a.request())?)
}

/// Writes `text` to stdout; a closed pipe (`| head`) is not an error.
fn print_all(text: &str) -> Result<()> {
    use std::io::Write;
    match std::io::stdout().lock().write_all(text.as_bytes()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
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
