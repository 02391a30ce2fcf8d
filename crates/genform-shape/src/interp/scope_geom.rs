//! The handle of a scope's polygon or mass in the run's geometry arena.
//! The interpreter's stacks hold these and the geometry operations make
//! them, so the handle stands below both.

/// What a scope's geometry is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum GeomKind {
    Polygon,
    Mass,
}

/// A polygon or mass: `len` points from `start` in
/// [`Stacks::pts`](super::Stacks::pts). An empty one (fewer than 3 points)
/// is what cutting can leave: it emits nothing.
#[derive(Clone, Copy, Debug)]
pub(super) struct Geom {
    pub(super) kind: GeomKind,
    pub(super) start: u32,
    pub(super) len: u32,
}
