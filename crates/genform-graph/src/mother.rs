//! The mother pattern of a production, as compiled: the vertices and
//! edges it matches, what each loads into the environment, and the named
//! vectors and spatial orders between its vertices. Both the production
//! and its search plans are built over it.

use crate::graph::Value;

/// What a mother element's env slot is loaded from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Load {
    X,
    Y,
    Attr(u32),
    Degree,
    Generation,
}

/// A vertex of the mother pattern.
#[derive(Clone, Debug)]
pub(crate) struct MVertex {
    pub(crate) name: String,
    pub(crate) label: Option<u32>,
    pub(crate) attrs: Vec<(u32, Value)>,
    pub(crate) wildcard: bool,
    pub(crate) at: Option<[f64; 2]>,
    pub(crate) loads: Vec<(u32, Load)>,
}

/// An edge of the mother pattern, between mother vertices `from` and `to`.
#[derive(Clone, Debug)]
pub(crate) struct MEdge {
    pub(crate) name: String,
    pub(crate) from: usize,
    pub(crate) to: usize,
    pub(crate) directed: bool,
    pub(crate) label: Option<u32>,
    pub(crate) attrs: Vec<(u32, Value)>,
    pub(crate) loads: Vec<(u32, Load)>,
}

/// A named vector from one mother vertex to another, kept in two env slots.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PairVector {
    pub(crate) from: usize,
    pub(crate) to: usize,
    /// Slot of the x component; y is the next one.
    pub(crate) slot: u32,
}

/// Required order of two mother vertices along x and y (spatial matching).
#[derive(Clone, Copy, Debug)]
pub(crate) struct SpatialPair {
    pub(crate) a: usize,
    pub(crate) b: usize,
    /// Per axis: the sign of b − a in the mother's layout (−1, 0, 1).
    pub(crate) order: [i8; 2],
}
