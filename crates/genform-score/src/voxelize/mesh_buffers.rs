//! The buffers the mesh rasterizer ([`super::mesh_rows`]) fills per
//! instance, apart from it because the scratch owns them between
//! evaluations.

/// Working memory of [`mesh_rows`](super::mesh_rows::mesh_rows), kept in the scratch.
#[derive(Clone, Debug, Default)]
pub(crate) struct MeshBuffers {
    /// `(row, x)` per crossing, in triangle order.
    pub(super) crossings: Vec<(u32, f64)>,
    /// Per row of the bounding box: its last crossing ([`NONE`]: none).
    pub(super) head: Vec<u32>,
    /// Per crossing: the one before it in its row ([`NONE`]: none).
    pub(super) next: Vec<u32>,
    /// One row's crossing coordinates.
    pub(super) xs: Vec<f64>,
    /// Voxel centres along the rows and along lattice axes 1 and 2 over
    /// the instance's bounding box (`f32` centres, widened).
    pub(super) centres: [Vec<f64>; 3],
    /// Per vertex: its projection `(y, z)` and row coordinate `x` widened to
    /// `f64`, and its lattice coordinates along axes 1 and 2 (bounds only).
    pub(super) points: Vec<Point>,
}

/// A vertex converted once per instance rather than once per triangle.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Point {
    pub(super) p: P2,
    pub(super) x: f64,
    pub(super) u: f64,
    pub(super) v: f64,
    /// The rows its slack box reaches: the least `j` and `k` at or above
    /// `u − slack`, `v − slack` and the greatest at or below `u + slack`,
    /// `v + slack`, clamped to one past the instance's rows (see
    /// [`row_bounds`](super::mesh_rows)).
    pub(super) rows: [i64; 4],
}

/// No crossing (end of a row's list).
pub(super) const NONE: u32 = u32::MAX;

pub(super) type P2 = (f64, f64);
