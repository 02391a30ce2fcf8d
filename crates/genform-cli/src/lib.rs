//! The library behind the `genform` binary: everything the command line
//! does that is worth testing or benchmarking without spawning a process
//! (loading grammars and scene configs, the objective that ties a
//! generator to scorers, run reports). The binary itself only parses
//! arguments and prints.

pub mod comparison;
pub mod grammar;
pub mod objective;
pub mod output;
pub mod report;
pub mod scene_config;
pub mod targets;
