//! Per-instance set-up shared by the fast voxelizer and the oracle: the
//! unit-frame map, the lattice bounding box and whether the exact
//! `outside` count is affordable. Both voxelizers take every decision from
//! here, so they agree on which instances count and on which voxels.

use super::shape::{Shape, slope_of_top};
use crate::grid::Lattice;
use genform_core::scene::{Instance, Mesh, Primitive, Scene};
use glam::{DMat3, DVec3, Vec3, Vec3A};

/// Instances spanning more lattice rows than this get an estimated
/// `outside` count (see [`Prepared::capped`]).
pub(crate) const MAX_EXACT_ROWS: u128 = 1 << 20;

/// The lattice → unit-frame map of a solid instance, in `f32` for the
/// predicate and `f64` for the interval guesses.
#[derive(Clone, Debug)]
pub(crate) struct Solid {
    pub shape: Shape,
    /// Columns: how each lattice coordinate moves the unit point.
    pub m: [Vec3A; 3],
    pub t: Vec3A,
    pub m64: [DVec3; 3],
    pub t64: DVec3,
    /// How far outside the exact shape rounding can put a unit point.
    pub delta: f64,
    /// `1 / (m64[0] · voxel size along rows)`: reciprocal slopes of a row
    /// line in the unit frame (infinite where it does not move).
    pub inv_step: DVec3,
    /// For boxes whose map is a scaled permutation: the unit axis each
    /// lattice axis drives alone.
    pub separable: Option<[usize; 3]>,
    /// For other boxes: a cross-row lattice axis `l` (1 or 2) that alone
    /// drives one unit axis `c`, which no other lattice axis moves, as
    /// `(l, c)` (a box rotated about that axis). The predicate is then
    /// `P(index along l) ∧ Q(other two indices)`, so rows along `l` share
    /// their spans.
    pub split: Option<(usize, usize)>,
}

impl Solid {
    /// The part of the unit point that is constant along row `(py, pz)`.
    #[inline]
    pub fn row_base(&self, py: f32, pz: f32) -> Vec3A {
        self.m[1] * py + self.m[2] * pz + self.t
    }

    /// The unit point of lattice point `(px, ·, ·)` of a row with `base`.
    #[inline]
    pub fn unit(&self, px: f32, base: Vec3A) -> Vec3A {
        self.m[0] * px + base
    }

    /// The unit point of a lattice point (same arithmetic as `unit` on
    /// `row_base`, so both voxelizers see the same bits).
    #[inline]
    pub fn unit_point(&self, p: Vec3) -> Vec3A {
        self.unit(p.x, self.row_base(p.y, p.z))
    }

    #[cfg(any(test, feature = "test-support"))]
    #[inline]
    pub fn contains(&self, p: Vec3) -> bool {
        self.shape.contains(self.unit_point(p))
    }
}

/// What an instance is, ready to voxelize.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub(crate) enum Body<'a> {
    Solid(Solid),
    /// A mesh asset; its lattice-frame vertices are in the caller's buffer.
    Mesh(&'a Mesh),
}

/// An instance ready to voxelize.
#[derive(Clone, Debug)]
pub(crate) struct Prepared<'a> {
    pub body: Body<'a>,
    /// Inclusive lattice index ranges per lattice axis that hold every voxel
    /// of the instance.
    pub bbox: [(i64, i64); 3],
    /// More than [`MAX_EXACT_ROWS`] rows: only rows inside the grid are
    /// voxelized, and `outside` is estimated as
    /// `max(0, round(volume / voxel volume) − voxels inside the grid)`.
    pub capped: bool,
    /// The instance's volume in voxels (for the capped estimate; 0 unless
    /// capped).
    pub volume_voxels: f64,
}

impl Prepared<'_> {
    /// The row ranges to visit: the bounding box's, cut to the grid when capped.
    pub fn row_ranges(&self, lat: &Lattice) -> Option<[(i64, i64); 2]> {
        let [_, mut j, mut k] = self.bbox;
        if self.capped {
            j = (j.0.max(0), j.1.min(lat.dims[1] - 1));
            k = (k.0.max(0), k.1.min(lat.dims[2] - 1));
        }
        (j.0 <= j.1 && k.0 <= k.1).then_some([j, k])
    }

    /// The index range to visit along rows.
    pub fn x_range(&self, lat: &Lattice) -> Option<(i64, i64)> {
        let mut i = self.bbox[0];
        if self.capped {
            i = (i.0.max(0), i.1.min(lat.dims[0] - 1));
        }
        (i.0 <= i.1).then_some(i)
    }

    /// Folds an instance's exact counts into its `outside` contribution.
    pub fn outside(&self, in_grid: u64, outside_exact: u64) -> u64 {
        if self.capped {
            let est = self.volume_voxels.round();
            if est.is_finite() && est > in_grid as f64 { (est - in_grid as f64).min(u64::MAX as f64) as u64 } else { 0 }
        } else {
            outside_exact
        }
    }
}

/// Prepares `inst` of `scene`, writing a mesh's lattice-frame vertices to
/// `verts`. `None` for instances that cannot hold a voxel: a singular or
/// non-finite transform, a missing or empty mesh asset, non-finite vertices.
pub(crate) fn prepare<'a>(
    lat: &Lattice,
    scene: &'a Scene,
    inst: &Instance,
    verts: &mut Vec<Vec3>,
) -> Option<Prepared<'a>> {
    let shape = match inst.primitive {
        Primitive::Box => Shape::Box,
        Primitive::Sphere => Shape::Sphere,
        Primitive::Frustum { top } => Shape::Frustum { k: slope_of_top(top) },
        Primitive::TaperedBox { top } => Shape::Tapered { k: slope_of_top(top) },
        Primitive::Mesh(id) => return prepare_mesh(lat, scene.meshes.get(id as usize)?, inst, verts),
    };
    // Lattice-frame transform: rows of the world matrix renamed.
    let cols = [inst.transform.matrix3.x_axis, inst.transform.matrix3.y_axis, inst.transform.matrix3.z_axis]
        .map(|c| lat.to_lattice(c.into()).as_dvec3());
    let a = DMat3::from_cols(cols[0], cols[1], cols[2]);
    let b = lat.to_lattice(inst.transform.translation.into()).as_dvec3();
    let det = a.determinant();
    if !det.is_finite() || det == 0.0 || !b.is_finite() {
        return None;
    }
    let inv = a.inverse();
    let t64 = -(inv * b);
    let m64 = [inv.x_axis, inv.y_axis, inv.z_axis];
    if !m64.iter().all(|c| c.is_finite()) || !t64.is_finite() {
        return None;
    }
    let m = m64.map(|c| Vec3A::from(c.as_vec3()));
    let t = Vec3A::from(t64.as_vec3());
    if !m.iter().all(|c| c.is_finite()) || !t.is_finite() {
        return None;
    }
    // Lattice bounding box of the unit bounding box's corners.
    // The unit box's image is a parallelepiped around `b`: its half extent
    // along each axis is the sum of the absolute column contributions.
    let hw = shape.half_width();
    let half = a.x_axis.abs() * hw + a.y_axis.abs() * 0.5 + a.z_axis.abs() * hw;
    let (lo, hi) = (b - half, b + half);
    if !lo.is_finite() || !hi.is_finite() {
        return None;
    }
    let bbox = [0, 1, 2].map(|l| lat.index_range(l, lo[l], hi[l]));
    // Rounding bound for the f32 unit point over the box (see module doc of
    // `voxelize`): a generous multiple of 2⁻²⁴ times the largest term.
    let pmax = lo.abs().max(hi.abs());
    let s = m64[0].abs() * pmax.x + m64[1].abs() * pmax.y + m64[2].abs() * pmax.z + t64.abs();
    let delta = (s.max_element() + 1.0) * (1.0 + f64::from(shape.slope()).abs()) * 2f64.powi(-16);
    let separable = if shape == Shape::Box { permutation_of(&m) } else { None };
    let split = if shape == Shape::Box && separable.is_none() { split_axis(&m) } else { None };
    let volume_voxels = |_: ()| det.abs() * shape.volume() / lat.grid.voxel_volume();
    let inv_step = DVec3::ONE / (m64[0] * lat.size(0));
    let solid = Solid { shape, m, t, m64, t64, delta, inv_step, separable, split };
    Some(finish(Body::Solid(solid), bbox, volume_voxels))
}

/// The prepared instance; `volume_voxels` is computed only when the
/// estimate needs it (a mesh's is a sum over its triangles).
fn finish(body: Body<'_>, bbox: [(i64, i64); 3], volume_voxels: impl FnOnce(()) -> f64) -> Prepared<'_> {
    let len = |(a, b): (i64, i64)| (b - a + 1).max(0) as u128;
    let capped = len(bbox[1]) * len(bbox[2]) > MAX_EXACT_ROWS;
    let volume_voxels = if capped { volume_voxels(()) } else { 0.0 };
    Prepared { body, bbox, capped, volume_voxels }
}

/// For a map whose f32 matrix has exactly one non-zero per row and column:
/// the unit axis driven by each lattice axis.
fn permutation_of(m: &[Vec3A; 3]) -> Option<[usize; 3]> {
    let mut perm = [0; 3];
    let mut used = [false; 3];
    for (l, col) in m.iter().enumerate() {
        let mut nz = (0..3).filter(|&c| col[c] != 0.0);
        let (Some(c), None) = (nz.next(), nz.next()) else { return None };
        if used[c] {
            return None;
        }
        used[c] = true;
        perm[l] = c;
    }
    Some(perm)
}

/// The first cross-row lattice axis `l` whose column of `m` has exactly
/// one non-zero entry `c`, with `m[l'][c] == 0` for the other lattice
/// axes: `(l, c)`. Exact zeros make the other unit coordinates independent
/// of the index along `l` bit for bit (adding a zero product changes no
/// sum), and `c` independent of the other two indices.
fn split_axis(m: &[Vec3A; 3]) -> Option<(usize, usize)> {
    (1..3).find_map(|l| {
        let mut nz = (0..3).filter(|&c| m[l][c] != 0.0);
        let (Some(c), None) = (nz.next(), nz.next()) else { return None };
        (0..3).all(|o| o == l || m[o][c] == 0.0).then_some((l, c))
    })
}

fn prepare_mesh<'a>(lat: &Lattice, mesh: &'a Mesh, inst: &Instance, verts: &mut Vec<Vec3>) -> Option<Prepared<'a>> {
    let det = inst.transform.matrix3.determinant();
    if mesh.positions.is_empty() || mesh.triangles.is_empty() || !det.is_finite() || det == 0.0 {
        return None;
    }
    verts.clear();
    verts.extend(mesh.positions.iter().map(|&p| lat.to_lattice(inst.transform.transform_point3(p))));
    let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for v in verts.iter() {
        lo = lo.min(*v);
        hi = hi.max(*v);
    }
    if !lo.is_finite() || !hi.is_finite() {
        return None;
    }
    let bbox = [0, 1, 2].map(|l| lat.index_range(l, f64::from(lo[l]), f64::from(hi[l])));
    let volume_voxels = |_: ()| {
        let n = verts.len();
        let mut vol = 0.0;
        for t in &mesh.triangles {
            if t.iter().all(|&i| (i as usize) < n) {
                let [a, b, c] = t.map(|i| verts[i as usize].as_dvec3());
                vol += a.dot(b.cross(c)) / 6.0;
            }
        }
        vol.abs() / lat.grid.voxel_volume()
    };
    Some(finish(Body::Mesh(mesh), bbox, volume_voxels))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::Grid;
    use glam::Affine3A;

    fn lat() -> Lattice {
        Lattice::new(&Grid::new(Vec3::ZERO, Vec3::splat(4.0), [4; 3]).unwrap())
    }

    fn inst(transform: Affine3A, primitive: Primitive) -> Instance {
        Instance { transform, primitive, tag: 0 }
    }

    #[test]
    fn singular_and_non_finite_instances_are_skipped() {
        let s = Scene::new();
        let mut v = Vec::new();
        let flat = Affine3A::from_scale(Vec3::new(1.0, 0.0, 1.0));
        assert!(prepare(&lat(), &s, &inst(flat, Primitive::Box), &mut v).is_none());
        let nan = Affine3A::from_translation(Vec3::new(f32::NAN, 0.0, 0.0));
        assert!(prepare(&lat(), &s, &inst(nan, Primitive::Sphere), &mut v).is_none());
        assert!(prepare(&lat(), &s, &inst(Affine3A::IDENTITY, Primitive::Mesh(0)), &mut v).is_none());
    }

    #[test]
    fn boxes_and_bounds() {
        let s = Scene::new();
        let mut v = Vec::new();
        let t = Affine3A::from_scale_rotation_translation(Vec3::new(2.0, -1.0, 1.0), Default::default(), Vec3::ONE);
        let p = prepare(&lat(), &s, &inst(t, Primitive::Box), &mut v).unwrap();
        // x ∈ [0, 2]: centres 0.5, 1.5 (plus one voxel of margin each way).
        assert_eq!(p.bbox[0], (-1, 2));
        assert!(!p.capped);
        // The volume is only computed where the capped estimate needs it.
        assert_eq!(p.volume_voxels, 0.0);
        let Body::Solid(solid) = &p.body else { panic!() };
        assert_eq!(solid.separable, Some([0, 1, 2]));
        let r = Affine3A::from_rotation_z(0.3);
        let p = prepare(&lat(), &s, &inst(r, Primitive::Box), &mut v).unwrap();
        let Body::Solid(solid) = &p.body else { panic!() };
        assert_eq!(solid.separable, None);
        // Rotation about world z = lattice axis 2 here (rows along x).
        assert_eq!(solid.split, Some((2, 2)));
        let huge = Affine3A::from_scale(Vec3::splat(1e4));
        assert!(prepare(&lat(), &s, &inst(huge, Primitive::Box), &mut v).unwrap().capped);
    }
}
