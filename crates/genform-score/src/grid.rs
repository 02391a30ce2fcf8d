//! The voxel grid and the lattice the voxelizers work on.
//!
//! A [`Grid`] is a box `[min, max]` cut into `dims` voxels per axis. Voxel
//! `i` along an axis has its centre at `min + (i + 0.5)·size` (the reference
//! convention, shapegenetics.md §1.5); a voxel belongs to a shape when its
//! centre does. The same formula extends to every integer `i`, giving an
//! infinite lattice of centres: voxels of a model that fall outside the grid
//! are counted on it.
//!
//! Internally voxels are stored in rows of bits along one *row axis*
//! (`Lattice`): the axis with the smallest voxel size, so that a shape
//! spans as few rows as possible (the spaceship grid, 100×200×100 over
//! 10×10×20 units, runs its rows along y). The other two axes follow
//! cyclically, so every computation in lattice coordinates is a world
//! computation with the components renamed, never re-associated.

use crate::error::ScoreError;
use glam::Vec3;

/// The most voxels a grid may have (2²⁸ ≈ 268 million, 32 MiB per bit
/// plane). Larger grids are refused with [`ScoreError::TooManyVoxels`].
pub const MAX_VOXELS: u64 = 1 << 28;

/// Lattice indices are clamped to `±LATTICE_LIMIT`: shapes reaching further
/// from the grid than 2³¹ voxels are cut there (only their `outside` count
/// can be affected).
pub(crate) const LATTICE_LIMIT: i64 = 1 << 31;

const AXES: [char; 3] = ['x', 'y', 'z'];

/// A box of `dims[0] × dims[1] × dims[2]` voxels over `[min, max]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    min: Vec3,
    max: Vec3,
    dims: [u32; 3],
}

impl Grid {
    /// A grid over `[min, max]` with `dims` voxels per axis. The bounds must
    /// be finite with `min < max` on every axis, every axis needs at least
    /// one voxel, and there may be at most [`MAX_VOXELS`] voxels in all.
    pub fn new(min: Vec3, max: Vec3, dims: [u32; 3]) -> Result<Grid, ScoreError> {
        if !min.is_finite() || !max.is_finite() {
            return Err(ScoreError::NonFiniteGrid { min: min.to_array(), max: max.to_array() });
        }
        for a in 0..3 {
            if min[a] >= max[a] {
                return Err(ScoreError::EmptyGridAxis { axis: AXES[a], min: min[a], max: max[a] });
            }
            if dims[a] == 0 {
                return Err(ScoreError::ZeroVoxels { axis: AXES[a] });
            }
        }
        let count = dims.iter().map(|&d| u128::from(d)).product::<u128>();
        if count > u128::from(MAX_VOXELS) {
            let count = u64::try_from(count).unwrap_or(u64::MAX);
            return Err(ScoreError::TooManyVoxels { count, max: MAX_VOXELS });
        }
        Ok(Grid { min, max, dims })
    }

    /// The lower corner.
    pub fn min(&self) -> Vec3 {
        self.min
    }

    /// The upper corner.
    pub fn max(&self) -> Vec3 {
        self.max
    }

    /// Voxels per axis.
    pub fn dims(&self) -> [u32; 3] {
        self.dims
    }

    /// The number of voxels.
    pub fn voxel_count(&self) -> u64 {
        self.dims.iter().map(|&d| u64::from(d)).product()
    }

    /// The voxel size per axis, `(max − min) / dims`.
    pub fn voxel_size(&self) -> Vec3 {
        Vec3::from_array(std::array::from_fn(|a| self.size64(a) as f32))
    }

    /// The volume of one voxel (computed in `f64`).
    pub fn voxel_volume(&self) -> f64 {
        (0..3).map(|a| self.size64(a)).product()
    }

    /// The centre of lattice voxel `idx` (any integers: indices outside
    /// `0..dims` name lattice voxels outside the grid). Computed in `f64` as
    /// `min + (i + 0.5)·size` and rounded once to `f32`, so centres are
    /// monotone in the index.
    pub fn center(&self, idx: [i64; 3]) -> Vec3 {
        Vec3::from_array(std::array::from_fn(|a| self.center_along(a, idx[a])))
    }

    /// The lattice voxel whose centre is nearest `p`:
    /// `round((p − min)/size − 0.5)` per axis, clamped to ±2³¹ (NaN gives 0).
    pub fn lattice_index(&self, p: Vec3) -> [i64; 3] {
        std::array::from_fn(|a| {
            let t = ((f64::from(p[a]) - f64::from(self.min[a])) / self.size64(a) - 0.5).round();
            (t as i64).clamp(-LATTICE_LIMIT, LATTICE_LIMIT)
        })
    }

    /// Whether lattice voxel `idx` lies in the grid.
    pub fn contains(&self, idx: [i64; 3]) -> bool {
        (0..3).all(|a| idx[a] >= 0 && idx[a] < i64::from(self.dims[a]))
    }

    fn size64(&self, a: usize) -> f64 {
        (f64::from(self.max[a]) - f64::from(self.min[a])) / f64::from(self.dims[a])
    }

    fn center_along(&self, a: usize, i: i64) -> f32 {
        (f64::from(self.min[a]) + (i as f64 + 0.5) * self.size64(a)) as f32
    }
}

/// `x.ceil()` up to the sign of a zero result, without the libm call that
/// `ceil` is on x86-64 without SSE4.1 (the voxelizers' per-row bounds).
#[inline]
pub(crate) fn ceil(x: f64) -> f64 {
    // Beyond 2⁵² every f64 is an integer; NaN fails the test and stays NaN.
    if x.abs() < 4_503_599_627_370_496.0 {
        let t = x as i64 as f64;
        if t < x { t + 1.0 } else { t }
    } else {
        x
    }
}

/// `x.floor()` up to the sign of a zero result (see [`ceil`]).
#[inline]
pub(crate) fn floor(x: f64) -> f64 {
    if x.abs() < 4_503_599_627_370_496.0 {
        let t = x as i64 as f64;
        if t > x { t - 1.0 } else { t }
    } else {
        x
    }
}

/// A grid seen in lattice order: lattice axis 0 is the row axis, world axis
/// `axes[0]`; lattice axes 1 and 2 follow cyclically. Bits of voxel
/// `(i, j, k)` (lattice order) live in row `k·dims[1] + j`, bit `i`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Lattice {
    pub grid: Grid,
    /// World axis of each lattice axis.
    pub axes: [usize; 3],
    /// Voxels per lattice axis.
    pub dims: [i64; 3],
    min: [f64; 3],
    size: [f64; 3],
    /// `u64` words per row.
    pub words: usize,
    /// Number of rows, `dims[1]·dims[2]`.
    pub rows: usize,
}

impl Lattice {
    /// The lattice of `grid`, rows along its finest axis (x on ties).
    pub fn new(grid: &Grid) -> Lattice {
        let s = [0, 1, 2].map(|a| grid.size64(a));
        let row = if s[1] < s[0] && s[1] <= s[2] {
            1
        } else if s[2] < s[0] && s[2] < s[1] {
            2
        } else {
            0
        };
        Lattice::with_row_axis(grid, row)
    }

    /// The lattice of `grid` with rows along world axis `row`.
    pub fn with_row_axis(grid: &Grid, row: usize) -> Lattice {
        let s = [0, 1, 2].map(|a| grid.size64(a));
        let axes = [row, (row + 1) % 3, (row + 2) % 3];
        let dims = axes.map(|a| i64::from(grid.dims[a]));
        Lattice {
            grid: *grid,
            axes,
            dims,
            min: axes.map(|a| f64::from(grid.min[a])),
            size: axes.map(|a| s[a]),
            words: (dims[0] as usize).div_ceil(64),
            rows: (dims[1] * dims[2]) as usize,
        }
    }

    /// World point → lattice order (an exact renaming of components).
    pub fn to_lattice(&self, p: Vec3) -> Vec3 {
        Vec3::new(p[self.axes[0]], p[self.axes[1]], p[self.axes[2]])
    }

    /// Lattice-order triple → world order.
    pub fn to_world<T: Copy>(&self, v: [T; 3]) -> [T; 3] {
        let mut w = v;
        for l in 0..3 {
            w[self.axes[l]] = v[l];
        }
        w
    }

    /// Centre coordinate of voxel `i` along lattice axis `l` (the same value
    /// [`Grid::center`] gives).
    #[inline]
    pub fn centre(&self, l: usize, i: i64) -> f32 {
        (self.min[l] + (i as f64 + 0.5) * self.size[l]) as f32
    }

    /// Voxel size along lattice axis `l`.
    pub fn size(&self, l: usize) -> f64 {
        self.size[l]
    }

    /// The continuous lattice coordinate of `x` along axis `l`: centres sit
    /// at integers.
    #[inline]
    pub fn coord(&self, l: usize, x: f64) -> f64 {
        (x - self.min[l]) / self.size[l] - 0.5
    }

    /// The lattice-index range `[lo, hi]` whose centres along axis `l` may lie
    /// in `[a, b]`, widened by one voxel each way against rounding and
    /// clamped to ±[`LATTICE_LIMIT`].
    pub fn index_range(&self, l: usize, a: f64, b: f64) -> (i64, i64) {
        let lo = (ceil(self.coord(l, a)) - 1.0).clamp(-(LATTICE_LIMIT as f64), LATTICE_LIMIT as f64);
        let hi = (floor(self.coord(l, b)) + 1.0).clamp(-(LATTICE_LIMIT as f64), LATTICE_LIMIT as f64);
        (lo as i64, hi as i64)
    }

    /// The smallest index whose centre along axis `l` is `>= x` (clamped to
    /// ±[`LATTICE_LIMIT`]). Exact: decided by comparing real centres.
    pub fn first_at_or_after(&self, l: usize, x: f64) -> i64 {
        if x.is_nan() {
            return LATTICE_LIMIT;
        }
        let lim = LATTICE_LIMIT as f64;
        let mut i = ceil(self.coord(l, x)).clamp(-lim, lim) as i64;
        while i > -LATTICE_LIMIT && f64::from(self.centre(l, i - 1)) >= x {
            i -= 1;
        }
        while i < LATTICE_LIMIT && f64::from(self.centre(l, i)) < x {
            i += 1;
        }
        i
    }

    /// Row index of lattice row `(j, k)`, `None` outside the grid.
    #[inline]
    pub fn row(&self, j: i64, k: i64) -> Option<usize> {
        if j >= 0 && j < self.dims[1] && k >= 0 && k < self.dims[2] {
            Some((k * self.dims[1] + j) as usize)
        } else {
            None
        }
    }

    /// Lattice `(j, k)` of row `r`.
    pub fn row_jk(&self, r: usize) -> (i64, i64) {
        let r = r as i64;
        (r % self.dims[1], r / self.dims[1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(min: [f32; 3], max: [f32; 3], dims: [u32; 3]) -> Result<Grid, ScoreError> {
        Grid::new(Vec3::from_array(min), Vec3::from_array(max), dims)
    }

    #[test]
    fn validation_names_the_problem() {
        assert!(matches!(grid([f32::NAN, 0., 0.], [1.; 3], [1; 3]), Err(ScoreError::NonFiniteGrid { .. })));
        assert_eq!(
            grid([0.; 3], [1., 0., 1.], [1; 3]),
            Err(ScoreError::EmptyGridAxis { axis: 'y', min: 0.0, max: 0.0 })
        );
        assert_eq!(grid([0.; 3], [1.; 3], [1, 1, 0]), Err(ScoreError::ZeroVoxels { axis: 'z' }));
        assert_eq!(
            grid([0.; 3], [1.; 3], [1 << 10, 1 << 10, 1 << 9]),
            Err(ScoreError::TooManyVoxels { count: 1 << 29, max: MAX_VOXELS })
        );
        assert!(grid([0.; 3], [1.; 3], [1 << 10, 1 << 10, 1 << 8]).is_ok());
        let e = grid([0.; 3], [1.; 3], [u32::MAX; 3]).unwrap_err();
        assert!(e.to_string().contains("use fewer voxels"), "{e}");
    }

    #[test]
    fn fast_ceil_and_floor_agree_with_libm() {
        let xs = [0.0, -0.0, 0.5, -0.5, 1.0, -1.0, 2.5, -2.5, 1e-300, -1e-300, 4.5e15, -4.5e15, 1e300, -1e300];
        for x in xs.into_iter().chain((0..2000).map(|i| (i as f64 - 1000.0) * 0.37)) {
            assert_eq!(ceil(x), x.ceil(), "{x}");
            assert_eq!(floor(x), x.floor(), "{x}");
        }
        for x in [f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!((ceil(x), floor(x)), (x, x));
        }
        assert!(ceil(f64::NAN).is_nan() && floor(f64::NAN).is_nan());
    }

    #[test]
    fn centres_and_indices_follow_the_reference_convention() {
        let g = grid([-5., -5., -2.], [5., 5., 18.], [100, 200, 100]).unwrap();
        assert_eq!(g.voxel_size(), Vec3::new(0.1, 0.05, 0.2));
        assert_eq!(g.voxel_count(), 2_000_000);
        assert!((g.voxel_volume() - 0.001).abs() < 1e-15);
        assert_eq!(g.center([0, 0, 0]), Vec3::new(-4.95, -4.975, -1.9));
        assert_eq!(g.center([-1, 200, 100]), Vec3::new(-5.05, 5.025, 18.1));
        assert_eq!(g.lattice_index(Vec3::new(-4.95, -4.975, -1.9)), [0, 0, 0]);
        assert_eq!(g.lattice_index(Vec3::new(0.0, 0.01, 17.99)), [50, 100, 99]);
        assert_eq!(g.lattice_index(Vec3::new(-100.0, 0.0, 0.0))[0], -951);
        assert_eq!(g.lattice_index(Vec3::splat(f32::INFINITY)), [LATTICE_LIMIT; 3]);
        assert!(g.contains([99, 199, 99]) && !g.contains([100, 0, 0]) && !g.contains([0, -1, 0]));
    }

    #[test]
    fn lattice_rows_run_along_the_finest_axis() {
        let g = grid([-5., -5., -2.], [5., 5., 18.], [100, 200, 100]).unwrap();
        let l = Lattice::new(&g);
        assert_eq!(l.axes, [1, 2, 0]);
        assert_eq!(l.dims, [200, 100, 100]);
        assert_eq!((l.words, l.rows), (4, 10_000));
        assert_eq!(l.to_lattice(Vec3::new(1., 2., 3.)), Vec3::new(2., 3., 1.));
        assert_eq!(l.to_world([2, 3, 1]), [1, 2, 3]);
        assert_eq!(l.centre(0, 3), g.center([0, 3, 0]).y);
        let cube = Lattice::new(&grid([0.; 3], [1.; 3], [4; 3]).unwrap());
        assert_eq!(cube.axes, [0, 1, 2]);
        assert_eq!(cube.row(3, 2), Some(11));
        assert_eq!(cube.row_jk(11), (3, 2));
        assert_eq!(cube.row(4, 0), None);
    }

    #[test]
    fn first_at_or_after_is_exact() {
        let g = grid([-5.; 3], [5.; 3], [100; 3]).unwrap();
        let l = Lattice::new(&g);
        for i in -120..120 {
            let c = f64::from(l.centre(0, i));
            assert_eq!(l.first_at_or_after(0, c), i);
            assert_eq!(l.first_at_or_after(0, c + 1e-9), i + 1);
            assert_eq!(l.first_at_or_after(0, c - 1e-9), i);
        }
        assert_eq!(l.first_at_or_after(0, f64::INFINITY), LATTICE_LIMIT);
        assert_eq!(l.first_at_or_after(0, f64::NEG_INFINITY), -LATTICE_LIMIT);
    }
}
