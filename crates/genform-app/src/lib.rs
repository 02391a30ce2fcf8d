//! genform's application layer: everything a front door (the `genform`
//! command line, the studio, the Python package) does that is not about
//! its own medium — the formalism table, scenes, the scorer registry, the
//! optimizer table, the run loop, run folders, reports, pictures, sweep,
//! compare, breeding — behind requests, responses and handles. It has no
//! argument parser, web server or terminal dependency and does no
//! printing: doors turn its values into output.
//!
//! Its modules are private; this page is its whole surface. Within the
//! crate, files import one another without a circle, lower layers first:
//! foundations (`text`, `files`, `notes`, `memory`, `units`, `toml_doc`,
//! `footprints`), the formalism table, the scorer registry and the
//! optimizer table, scenes, objectives, reports, runs (see ARCHITECTURE.md).

mod caps;
mod files;
mod footprints;
mod formalism;
mod gate;
mod grammar;
mod memory;
mod notes;
mod objective;
mod optimizers;
mod report;
mod run;
mod scene;
mod scoring;
mod text;
mod toml_doc;
mod units;

pub use files::{output_format, unknown_format, write_atomic, write_model};
pub use formalism::{
    COMMON_SAMPLE_OPTIONS, FormalismRef, Genomes, LimitOverrides, Loaded, LoadedGrammar, ModelSettings, SAMPLE_OPTIONS,
    Sample, SampleOption, SampleRequest, SceneLimits, ValueKind, ends_with_any, express, formalism_of, formalisms,
    genome_summary, grammar_files_help, info, sample_option,
};
pub use gate::{Refused, Session, SessionGuard, admit_read, confine, create_dir, refuse_outputs, session};
pub use grammar::GrammarHandle;
pub use memory::{Budget, MemoryUse, OverBudget, Reservation, budget, in_use, parse_size, reserve, set_budget, usage};
pub use notes::set_sink;
pub use objective::{EvalScratch, OpenScene, TreeObjective};
pub use optimizers::OptimizerSettings;
pub use optimizers::{OPTIMIZERS, OptimizerRow, Searches, algorithm_names, check_name as check_algorithm};
pub use run::breed::{AskTellOptimizer, AskTellRequest, BreedRequest, BreedSession, ModelJob, ask_tell};
pub use run::compare::{CompareOutcome, CompareRequest};
pub use run::control::{
    CHECKPOINT_EVERY, Control, EvolveRequest, RunOutcome, ScoreRequest, Start, Tick, Watch, stop_reason_name,
};
pub use run::derive::{DeriveRequest, Derived, derive};
pub use run::map::{MapRequest, map};
pub use run::steering::{SteerEntry, SteerSet, Steerable, read_log as read_steering_log};
pub use run::sweep::{RunDone, SweepRequest, SweepResult, run as sweep, write as write_sweep};
pub use run::{Admitted, admit, compare, evolve, score, settings_patch};
pub use scene::patch::{parse_patch, parse_set, patch_from_json};
pub use scene::{RunConfig, Scene, SceneSummary};
pub use scoring::{FitnessConfig, Scoring};
pub use text::{SourceErrors, report};
pub use units::parse_duration;
