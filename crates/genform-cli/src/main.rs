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
        // Interrupted twice: the results were saved all the same, and the
        // exit status says the user asked to quit.
        Ok(()) if evolve::interrupted_twice() => ExitCode::from(130),
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // Diagnostics print with their own `Error:` headers; only the summary gets `error:`.
            eprint!("{}", genform_app::report(&e));
            ExitCode::FAILURE
        }
    }
}
