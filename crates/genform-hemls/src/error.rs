//! Why growth stopped. Apart from the growth engine because its join
//! phase stops with the same error, and the engine calls the join phase.

use genform_core::Span;
use thiserror::Error;

/// Why growth stopped.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum GrowError {
    /// A rule cannot be applied as written.
    #[error("rule {} (for Edge{kind}): {message}", rule + 1)]
    Rule {
        /// Index of the rule in [`Hemls::rules`](crate::grammar::Hemls::rules).
        rule: usize,
        /// The rule's type (its predecessor's `N`).
        kind: u32,
        /// Where the rule stands in its file.
        span: Span,
        /// What is wrong, as a sentence.
        message: String,
    },
    /// The grammar or the settings cannot seed a surface.
    #[error("{message}")]
    Invalid {
        /// What is wrong, as a sentence.
        message: String,
    },
    /// A coordinate became infinite or NaN.
    #[error(
        "a vertex coordinate became infinite or NaN at step {step} (a charge exactly on a vertex, a huge \
         displacement, or a scale that overflows over many steps); move the charge, lower its constant, or grow \
         fewer steps"
    )]
    NonFinite {
        /// The step (1-based) it happened in.
        step: u32,
    },
    /// The surface would grow past an element limit.
    #[error(
        "growth stopped at step {step}: the surface would have more than {limit} {what}; raise max_{what} in the \
         [limits] table of the --env file, or grow fewer steps"
    )]
    Limit {
        /// `"vertices"`, `"edges"` or `"faces"`.
        what: &'static str,
        /// The limit that would be passed.
        limit: usize,
        /// The step (1-based) that would pass it.
        step: u32,
    },
}
