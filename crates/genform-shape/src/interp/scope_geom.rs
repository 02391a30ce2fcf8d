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
    /// A lot stored in the reverse of the order its corners were written
    /// in (to turn counter-clockwise): the written edge `j` is the stored
    /// edge `len − 2 − j` (mod `len`), so edge indices (`ridge = i`,
    /// `overhang = […]`, `setback(…, edges = […])`) follow the writing.
    pub(super) reversed: bool,
}

impl Geom {
    /// The stored edge of the written edge `j`.
    pub(super) fn stored_edge(&self, j: usize) -> usize {
        let m = self.len as usize;
        if self.reversed && m > 0 { (2 * m - 2 - j % m) % m } else { j }
    }
}
