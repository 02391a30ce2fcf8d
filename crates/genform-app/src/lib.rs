//! genform's application layer: everything a front door (the `genform`
//! command line, the studio, the Python package) does that is not about
//! its own medium — the formalism table and what each formalism does for
//! the verbs, loading grammars and scenes, the objectives that tie a
//! generator to scorers, run folders, reports, pictures, sweep and compare.
//! It has no argument parser, web server or terminal dependency and does no
//! printing: doors turn its values into output.

pub mod archive;
pub mod codon_objective;
pub mod codon_report;
pub mod codon_scene;
pub mod comparison;
pub mod footprints;
pub mod formalism;
pub mod grammar;
pub mod memory;
pub mod notes;
pub mod objective;
pub mod output;
pub mod pictures;
pub mod report;
pub mod run;
pub mod scene_config;
pub mod scene_file;
pub mod source_text;
pub mod sweep;
pub mod targets;
