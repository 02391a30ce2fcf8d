//! The library behind the `genform` binary: everything the command line
//! does that is worth testing or benchmarking without spawning a process
//! (the formalism table and what each formalism does for the verbs,
//! loading grammars and scene configs, the objective that ties a
//! generator to scorers, run reports). The binary itself parses
//! arguments, dispatches verbs and prints.

pub mod archive;
pub mod codon_objective;
pub mod codon_report;
pub mod codon_scene;
pub mod comparison;
pub mod formalism;
pub mod grammar;
pub mod objective;
pub mod output;
pub mod pictures;
pub mod report;
pub mod scene_config;
pub mod source_text;
pub mod sweep;
pub mod targets;
