//! Where the built-in variables live in every rule's env. Both the
//! compiled programs and the fast evaluator read this layout, so it stands
//! apart from either.

/// Env indices of the built-in variables (the same in every rule).
pub(crate) const ENV_SX: usize = 0;
pub(crate) const ENV_DEPTH: usize = 3;
pub(crate) const ENV_INDEX: usize = 4;
pub(crate) const ENV_COUNT: usize = 5;
/// The first of the `lot.*` values ([`crate::LotProps`], in its order).
pub(crate) const ENV_LOT: usize = 6;
/// Names of the built-in variables, in env order.
pub(crate) const BUILTINS: [&str; ENV_LOT + crate::lot_props::LotProps::COUNT] = [
    "sx",
    "sy",
    "sz",
    "depth",
    "index",
    "count",
    "lot.height",
    "lot.min_height",
    "lot.levels",
    "lot.use",
    "lot.index",
    "lot.street",
    "lot.street_edge",
];
