//! Where the built-in variables live in every rule's env. Both the
//! compiled programs and the fast evaluator read this layout, so it stands
//! apart from either.

/// Env indices of the built-in variables (the same in every rule).
pub(crate) const ENV_SX: usize = 0;
pub(crate) const ENV_DEPTH: usize = 3;
pub(crate) const ENV_INDEX: usize = 4;
pub(crate) const ENV_COUNT: usize = 5;
/// Names of the built-in variables, in env order.
pub(crate) const BUILTINS: [&str; 6] = ["sx", "sy", "sz", "depth", "index", "count"];
