//! `genform`: the command-line front end. Parses arguments, loads grammars,
//! runs generators and writes files; the libraries do no process I/O.

mod args;
mod commands;
mod evolve;
mod sweep;

use std::process::ExitCode;

fn main() -> ExitCode {
    use std::io::IsTerminal as _;
    genform_app::set_sink(Box::new(|text| eprintln!("{text}")), std::io::stderr().is_terminal());
    let cli = args::parse();
    match commands::run(cli) {
        // Interrupted: the results were saved, and the process ends as
        // interrupted so that shell loops and scripts stop too.
        Ok(()) if evolve::interrupted() => evolve::end_as_interrupted(),
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // Diagnostics print with their own `Error:` headers; only the summary gets `error:`.
            eprint!("{}", genform_app::report(&e));
            ExitCode::FAILURE
        }
    }
}
