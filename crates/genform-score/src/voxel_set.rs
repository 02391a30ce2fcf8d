//! A set of voxels of one grid: targets and voxelized models.

use crate::bits::BitRows;
use crate::grid::{Grid, Lattice};
use genform_core::scene::{Instance, Primitive, Scene};
use glam::{Affine3A, Vec3};

/// A set of voxels of a [`Grid`], one bit per voxel. Indices are in world
/// axis order `[x, y, z]`.
#[derive(Clone, Debug, PartialEq)]
pub struct VoxelSet {
    lat: Lattice,
    bits: BitRows,
}

impl VoxelSet {
    /// The empty set on `grid`.
    pub fn new(grid: &Grid) -> VoxelSet {
        let lat = Lattice::new(grid);
        let bits = BitRows::new(lat.words, lat.rows);
        VoxelSet { lat, bits }
    }

    pub(crate) fn from_bits(lat: Lattice, bits: BitRows) -> VoxelSet {
        debug_assert_eq!(bits.data().len(), lat.words * lat.rows);
        VoxelSet { lat, bits }
    }

    pub(crate) fn bits(&self) -> &BitRows {
        &self.bits
    }

    #[cfg(test)]
    pub(crate) fn lattice(&self) -> &Lattice {
        &self.lat
    }

    /// The grid the voxels belong to.
    pub fn grid(&self) -> &Grid {
        &self.lat.grid
    }

    /// The number of voxels in the set.
    pub fn count(&self) -> u64 {
        self.bits.count()
    }

    /// Whether voxel `idx` is in the set (`false` outside the grid).
    pub fn contains(&self, idx: [u32; 3]) -> bool {
        let [i, j, k] = [0, 1, 2].map(|l| i64::from(idx[self.lat.axes[l]]));
        match self.lat.row(j, k) {
            Some(r) if i < self.lat.dims[0] => self.bits.get(r, i as usize),
            _ => false,
        }
    }

    /// Adds voxel `idx`; returns `false` (and adds nothing) when it lies
    /// outside the grid.
    pub fn insert(&mut self, idx: [u32; 3]) -> bool {
        let [i, j, k] = [0, 1, 2].map(|l| i64::from(idx[self.lat.axes[l]]));
        match self.lat.row(j, k) {
            Some(r) if i < self.lat.dims[0] => {
                self.bits.set_range(r, i as usize, i as usize);
                true
            }
            _ => false,
        }
    }

    /// Calls `f` with every voxel of the set, in storage order.
    pub fn for_each(&self, mut f: impl FnMut([u32; 3])) {
        self.bits.for_each_run(|r, a, b| {
            let (j, k) = self.lat.row_jk(r);
            for i in a..=b {
                f(self.lat.to_world([i as u32, j as u32, k as u32]));
            }
        });
    }

    /// The set as a Scene of boxes tagged `tag`, for previews: runs of
    /// voxels along the grid's row axis become one box each.
    pub fn to_scene(&self, tag: &str) -> Scene {
        let mut scene = Scene::new();
        self.add_to_scene(&mut scene, tag);
        scene
    }

    /// Adds the boxes of [`VoxelSet::to_scene`] to `scene`.
    pub fn add_to_scene(&self, scene: &mut Scene, tag: &str) {
        let tag = scene.tag(tag);
        let g = &self.lat.grid;
        let size = g.voxel_size();
        self.bits.for_each_run(|r, a, b| {
            let (j, k) = self.lat.row_jk(r);
            let lo = g.center(self.lat.to_world([a as i64, j, k]));
            let hi = g.center(self.lat.to_world([b as i64, j, k]));
            let mut scale = size;
            scale[self.lat.axes[0]] = (b - a + 1) as f32 * size[self.lat.axes[0]];
            scene.instances.push(Instance {
                transform: Affine3A::from_scale_rotation_translation(scale, glam::Quat::IDENTITY, (lo + hi) * 0.5),
                primitive: Primitive::Box,
                tag,
            });
        });
    }
}

/// The voxel a world point falls in, if inside the grid (for tests and
/// tools; the voxelizers decide by voxel centres, not by this).
pub fn voxel_of(grid: &Grid, p: Vec3) -> Option<[u32; 3]> {
    let idx = grid.lattice_index(p);
    grid.contains(idx).then(|| idx.map(|i| i as u32))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn insert_contains_and_scene_of_runs() {
        let g = Grid::new(Vec3::ZERO, Vec3::new(4.0, 2.0, 2.0), [4, 4, 2]).unwrap();
        let mut s = VoxelSet::new(&g);
        // y is the finest axis: rows run along y.
        assert_eq!(s.lattice().axes, [1, 2, 0]);
        for y in 0..3 {
            assert!(s.insert([1, y, 1]));
        }
        assert!(s.insert([3, 0, 0]));
        assert!(!s.insert([4, 0, 0]));
        assert_eq!(s.count(), 4);
        assert!(s.contains([1, 2, 1]) && !s.contains([1, 3, 1]) && !s.contains([9, 9, 9]));
        let mut all = Vec::new();
        s.for_each(|v| all.push(v));
        all.sort();
        assert_eq!(all, vec![[1, 0, 1], [1, 1, 1], [1, 2, 1], [3, 0, 0]]);
        let scene = s.to_scene("target");
        assert_eq!(scene.instances.len(), 2);
        assert_eq!(scene.tags, vec!["target".to_string()]);
        let b = scene.bounds(Default::default()).unwrap();
        assert_eq!(b, (Vec3::new(1.0, 0.0, 0.0), Vec3::new(4.0, 1.5, 2.0)));
        assert_eq!(voxel_of(&g, Vec3::new(1.2, 0.7, 1.9)), Some([1, 1, 1]));
        assert_eq!(voxel_of(&g, Vec3::new(-0.2, 0.7, 1.9)), None);
    }
}
