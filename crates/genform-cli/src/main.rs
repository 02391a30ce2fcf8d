//! `genform`: the command-line front end. Parses arguments, loads grammars,
//! runs generators and writes files; the libraries do no process I/O.

mod args;
mod commands;
mod evolve;
mod serve;

use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = args::parse();
    match commands::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // Diagnostics print with their own `Error:` headers; only the summary gets `error:`.
            eprint!("{}", genform_cli::source_text::report(&e));
            ExitCode::FAILURE
        }
    }
}
