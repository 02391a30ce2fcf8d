//! The volume scorer: a Scene's voxels against weighted target volumes
//! (thesis §4.1, reference §1.5).
//!
//! For targets `V_i` with fill weight `w_i` and avoid weight `w̃_i`, and the
//! voxelized model `M`:
//!
//! - `good = Σ_i w_i · |V_i ∧ M|`
//! - `bad = Σ_i w̃_i · |M ∧ ¬V_i|`
//! - `overlap` = voxels held by two or more instances
//! - `outside` = held lattice voxels outside the grid (see [`crate::voxelize`])
//! - `target = Σ_i max(w_i, 0) · |V_i|`, the most `good` can reach.
//!
//! The model is every instance of the Scene and every non-air cell of its
//! block structures ([`Scene::blocks`], unit boxes on the integer grid), so
//! box-split buildings can be steered towards a voxel target; see
//! [`crate::voxelize`] for which voxels each holds.
//!
//! Weights are used as given, so a negative `w_i` turns a target into a
//! volume to stay out of, as in the thesis' `s_vol`; such targets add
//! nothing to `target`. The reference implementation's "avoid" scenes
//! instead keep unit weights here and put negative `g` and `b` into the
//! [`crate::Fitness`]; both work.

use crate::error::ScoreError;
use crate::fitness::Counts;
use crate::grid::{Grid, Lattice};
use crate::span_cache::CachePool;
use crate::voxel_set::VoxelSet;
use crate::voxelize::{Plane, VolumeScratch, Voxelized, rasterize};
use genform_core::scene::Scene;

/// One target volume and its weights.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeTarget {
    /// The target's voxels (see [`crate::target`]).
    pub voxels: VoxelSet,
    /// `w_i`: weight of each model voxel inside the target (counted in `good`).
    pub fill: f64,
    /// `w̃_i`: weight of each model voxel outside the target (counted in `bad`).
    pub avoid: f64,
}

impl VolumeTarget {
    /// A target with unit weights, the reference's single-target setting.
    pub fn new(voxels: VoxelSet) -> VolumeTarget {
        VolumeTarget { voxels, fill: 1.0, avoid: 1.0 }
    }
}

/// Scores Scenes against volume targets on one grid. Immutable and shared
/// between threads; each thread brings its own [`VolumeScratch`].
#[derive(Clone, Debug)]
pub struct VolumeScorer {
    lat: Lattice,
    targets: Vec<VolumeTarget>,
    target_total: f64,
    /// The scratches' caches of mesh instances (see `span_cache`); clones
    /// share it.
    caches: CachePool<Lattice>,
}

impl VolumeScorer {
    /// A scorer on `grid`. Every target must be voxelized on `grid` and
    /// have finite weights.
    pub fn new(grid: Grid, targets: Vec<VolumeTarget>) -> Result<VolumeScorer, ScoreError> {
        for (index, t) in targets.iter().enumerate() {
            if *t.voxels.grid() != grid {
                return Err(ScoreError::GridMismatch { index });
            }
            if !t.fill.is_finite() || !t.avoid.is_finite() {
                return Err(ScoreError::BadWeight { index, fill: t.fill, avoid: t.avoid });
            }
        }
        let target_total = targets.iter().map(|t| t.fill.max(0.0) * t.voxels.count() as f64).sum();
        Ok(VolumeScorer { lat: Lattice::new(&grid), targets, target_total, caches: CachePool::default() })
    }

    /// The grid.
    pub fn grid(&self) -> &Grid {
        &self.lat.grid
    }

    /// The targets.
    pub fn targets(&self) -> &[VolumeTarget] {
        &self.targets
    }

    /// Fresh working memory for one thread, with a cache of mesh
    /// instances' spans that outlives it (given back when it is dropped).
    pub fn scratch(&self) -> VolumeScratch {
        VolumeScratch::with_cache(&self.lat, &self.caches)
    }

    /// Empties the caches of mesh instances' spans (for measurements that
    /// must not profit from earlier evaluations; results never depend on
    /// them).
    pub fn clear_caches(&self) {
        self.caches.clear();
    }

    fn ready(&self, s: &mut VolumeScratch) {
        if !s.fits(&self.lat) {
            *s = self.scratch();
        }
    }

    /// Voxelizes `scene` and counts it against the targets. Visits only the
    /// rows the model touches and leaves `scratch` clear.
    pub fn counts(&self, scene: &Scene, scratch: &mut VolumeScratch) -> Counts {
        self.ready(scratch);
        rasterize(&self.lat, scene, scratch, self.first_plane());
        self.count_and_clear(scratch)
    }

    /// The voxelized model (for previews and tests).
    pub fn model_voxels(&self, scene: &Scene, scratch: &mut VolumeScratch) -> Voxelized {
        self.ready(scratch);
        rasterize(&self.lat, scene, scratch, &[]);
        let v = Voxelized {
            occupancy: VoxelSet::from_bits(self.lat.clone(), scratch.plane(Plane::Occupied)),
            overlap: VoxelSet::from_bits(self.lat.clone(), scratch.plane(Plane::Overlap)),
            outside: scratch.outside,
        };
        scratch.clear();
        v
    }

    /// The counts of an already voxelized model (from [`crate::voxelize::voxelize`]
    /// or the oracle), over all rows.
    pub fn counts_of(&self, v: &Voxelized) -> Counts {
        let all = 0..self.lat.rows;
        let occ = v.occupancy.bits();
        let mut c = Counts {
            overlap: v.overlap.count() as f64,
            outside: v.outside as f64,
            target: self.target_total,
            ..Counts::default()
        };
        for t in &self.targets {
            let tb = t.voxels.bits();
            c.good += t.fill * occ.count_and(tb, all.clone()) as f64;
            c.bad += t.avoid * occ.count_andnot(tb, all.clone()) as f64;
        }
        c
    }

    /// The first target's bits (counted while voxelizing), or nothing.
    fn first_plane(&self) -> &[u64] {
        self.targets.first().map_or(&[][..], |t| t.voxels.bits().data())
    }

    /// Counts the voxelized model in `s` against the targets and clears it.
    /// The first target was counted during voxelization; the others take a
    /// pass over the touched rows each.
    fn count_and_clear(&self, s: &mut VolumeScratch) -> Counts {
        let mut c = Counts { outside: s.outside as f64, target: self.target_total, ..Counts::default() };
        let mut add = |t: &VolumeTarget, held: u64, and: u64| {
            c.good += t.fill * and as f64;
            c.bad += t.avoid * (held - and) as f64;
        };
        for t in self.targets.iter().skip(1) {
            let (held, and) = s.held_and(t.voxels.bits().data());
            add(t, held, and);
        }
        let p = s.finish();
        if let Some(t) = self.targets.first() {
            add(t, p.held, p.held_and);
        }
        c.overlap = p.overlap as f64;
        c
    }

    /// The targets as a Scene of boxes (runs of voxels merged), for
    /// previews: tagged `target`, or `target0`, `target1`, … when there are
    /// several.
    pub fn target_scene(&self) -> Scene {
        let mut scene = Scene::new();
        for (i, t) in self.targets.iter().enumerate() {
            let tag = if self.targets.len() == 1 { "target".to_string() } else { format!("target{i}") };
            t.voxels.add_to_scene(&mut scene, &tag);
        }
        scene
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::voxelize::{oracle, voxelize};
    use genform_core::scene::{Instance, Primitive};
    use glam::{Affine3A, Quat, Vec3};

    fn boxes(items: &[(Vec3, Vec3)]) -> Scene {
        let mut s = Scene::new();
        for &(centre, size) in items {
            s.instances.push(Instance {
                transform: Affine3A::from_scale_rotation_translation(size, Quat::IDENTITY, centre),
                primitive: Primitive::Box,
                tag: 0,
            });
        }
        s
    }

    /// 4×4×4 unit voxels over [0, 4]³; target = the voxels with x < 2.
    fn setup(fill: f64, avoid: f64) -> VolumeScorer {
        let grid = Grid::new(Vec3::ZERO, Vec3::splat(4.0), [4; 3]).unwrap();
        let mut t = VoxelSet::new(&grid);
        for x in 0..2 {
            for y in 0..4 {
                for z in 0..4 {
                    t.insert([x, y, z]);
                }
            }
        }
        VolumeScorer::new(grid, vec![VolumeTarget { voxels: t, fill, avoid }]).unwrap()
    }

    #[test]
    fn two_overlapping_boxes_by_hand() {
        let scorer = setup(2.0, 3.0);
        // A = [0,2]³ (8 voxels), B = [1,3]³ (8 voxels, 1 shared with A),
        // C = [3,5]×[0,1]² (1 voxel in the grid, 1 outside).
        let scene = boxes(&[
            (Vec3::splat(1.0), Vec3::splat(2.0)),
            (Vec3::splat(2.0), Vec3::splat(2.0)),
            (Vec3::new(4.0, 0.5, 0.5), Vec3::new(2.0, 1.0, 1.0)),
        ]);
        let mut s = scorer.scratch();
        let c = scorer.counts(&scene, &mut s);
        // Model: 8 + 8 − 1 + 1 = 16 voxels. In the target (x ∈ {0, 1}): all 8 of
        // A and B's 4 at x = 1 less the shared one → 11. Outside the target: 5.
        assert_eq!(c, Counts { good: 2.0 * 11.0, bad: 3.0 * 5.0, overlap: 1.0, outside: 1.0, target: 2.0 * 32.0 });
        // Reusing the scratch gives the same counts; an empty scene nothing.
        assert_eq!(scorer.counts(&scene, &mut s), c);
        assert_eq!(scorer.counts(&Scene::new(), &mut s), Counts { target: 64.0, ..Counts::default() });
        // The oracle's voxels count the same.
        assert_eq!(scorer.counts_of(&oracle::voxelize(scorer.grid(), &scene)), c);
        let v = scorer.model_voxels(&scene, &mut s);
        assert_eq!((v.occupancy.count(), v.overlap.count(), v.outside), (16, 1, 1));
        assert_eq!(scorer.counts(&scene, &mut s), c);
    }

    #[test]
    fn several_targets_sum_with_their_weights() {
        let one = setup(1.0, 1.0);
        let grid = *one.grid();
        let mut avoid = VoxelSet::new(&grid);
        avoid.insert([1, 1, 1]);
        avoid.insert([3, 3, 3]);
        let targets = vec![one.targets()[0].clone(), VolumeTarget { voxels: avoid, fill: -5.0, avoid: 0.5 }];
        let scorer = VolumeScorer::new(grid, targets).unwrap();
        let scene = boxes(&[(Vec3::splat(1.0), Vec3::splat(2.0)), (Vec3::splat(2.0), Vec3::splat(2.0))]);
        let c = scorer.counts(&scene, &mut scorer.scratch());
        // 15 model voxels: 11 in the first target; (1,1,1) in the second.
        assert_eq!(c.good, 11.0 - 5.0);
        assert_eq!(c.bad, 4.0 + 0.5 * 14.0);
        assert_eq!(c.target, 32.0, "negative fill weights add nothing to T");
        assert_eq!(c.overlap, 1.0);
    }

    #[test]
    fn target_scene_voxelizes_back_to_the_target() {
        let grid = Grid::new(Vec3::new(-5.0, -5.0, -2.0), Vec3::new(5.0, 5.0, 18.0), [20, 40, 20]).unwrap();
        let mut scene = boxes(&[(Vec3::new(0.3, 0.2, 3.0), Vec3::new(3.0, 1.0, 6.0))]);
        scene.instances.push(Instance {
            transform: Affine3A::from_scale_rotation_translation(
                Vec3::splat(4.0),
                Quat::from_rotation_y(0.4),
                Vec3::Z * 8.0,
            ),
            primitive: Primitive::Sphere,
            tag: 0,
        });
        let target = voxelize(&grid, &scene).occupancy;
        let scorer = VolumeScorer::new(grid, vec![VolumeTarget::new(target.clone())]).unwrap();
        let preview = scorer.target_scene();
        assert!(preview.instances.len() < target.count() as usize / 2, "runs are merged");
        assert_eq!(voxelize(&grid, &preview).occupancy, target);
    }

    /// Random boxes and spheres (some rotated, overlapping, sticking out)
    /// scored against one or two random targets: the counts made while
    /// voxelizing equal those of the oracle's voxels.
    #[test]
    fn counts_equal_the_oracle_counts() {
        let grid = Grid::new(Vec3::new(-2.0, -1.0, -1.5), Vec3::new(2.0, 1.5, 1.5), [70, 9, 13]).unwrap();
        let mut scratch = None;
        for seed in 0..48 {
            let mut rng = genform_core::Rng::stream(seed, &[3]);
            let mut f = |lo: f64, hi: f64| rng.uniform(lo, hi) as f32;
            let targets: Vec<VolumeTarget> = (0..1 + seed % 2)
                .map(|i| {
                    let mut t = VoxelSet::new(&grid);
                    let density = f(0.0, 1.0);
                    for x in 0..70 {
                        for y in 0..9 {
                            for z in 0..13 {
                                if f(0.0, 1.0) < density {
                                    t.insert([x, y, z]);
                                }
                            }
                        }
                    }
                    VolumeTarget { voxels: t, fill: 1.5 - i as f64, avoid: 0.5 }
                })
                .collect();
            let scorer = VolumeScorer::new(grid, targets).unwrap();
            let s = scratch.get_or_insert_with(|| scorer.scratch());
            let mut scene = Scene::new();
            for _ in 0..1 + seed % 7 {
                let rot = if f(0.0, 1.0) < 0.5 { Quat::from_rotation_z(f(-1.0, 1.0)) } else { Quat::IDENTITY };
                let size = Vec3::new(f(-2.5, 2.5), f(0.2, 1.5), f(0.2, 1.5));
                let at = Vec3::new(f(-2.5, 2.5), f(-1.0, 1.5), f(-1.5, 1.5));
                scene.instances.push(Instance {
                    transform: Affine3A::from_scale_rotation_translation(size, rot, at),
                    primitive: if f(0.0, 1.0) < 0.7 { Primitive::Box } else { Primitive::Sphere },
                    tag: 0,
                });
            }
            let want = scorer.counts_of(&oracle::voxelize(&grid, &scene));
            assert_eq!(scorer.counts(&scene, s), want, "seed {seed}");
        }
    }

    /// A block structure of `size` cells at `origin`, stone where `f` says.
    fn blocks(origin: glam::IVec3, size: glam::UVec3, f: impl Fn(glam::IVec3) -> bool) -> Scene {
        let mut g = genform_core::BlockGrid::new(origin, size);
        for y in 0..size.y as i32 {
            for z in 0..size.z as i32 {
                for x in 0..size.x as i32 {
                    let p = glam::IVec3::new(x, y, z);
                    let id = if f(p) { "stone" } else { "air" };
                    g.set(origin + p, &genform_core::BlockState::new(id));
                }
            }
        }
        let mut s = Scene::new();
        s.blocks.push(g);
        s
    }

    /// Half-unit voxels over [0, 8]³; target = the box [2, 6] × [0, 4] × [1, 5]
    /// (8 × 8 × 8 voxels).
    fn block_target() -> VolumeScorer {
        let grid = Grid::new(Vec3::ZERO, Vec3::splat(8.0), [16; 3]).unwrap();
        let mut t = VoxelSet::new(&grid);
        for x in 4..12 {
            for y in 0..8 {
                for z in 2..10 {
                    t.insert([x, y, z]);
                }
            }
        }
        VolumeScorer::new(grid, vec![VolumeTarget::new(t)]).unwrap()
    }

    #[test]
    fn blocks_filling_the_target_score_the_maximum() {
        let scorer = block_target();
        let fitness = crate::Fitness::default();
        let mut s = scorer.scratch();
        let (origin, size) = (glam::IVec3::new(2, 0, 1), glam::UVec3::splat(4));
        let full = scorer.counts(&blocks(origin, size, |_| true), &mut s);
        assert_eq!(full, Counts { good: 512.0, target: 512.0, ..Counts::default() });
        assert_eq!(fitness.eval(&full, 0), fitness.good, "the most a model can score");
        // The lower half: half the target, nothing else — a lower score.
        let half = scorer.counts(&blocks(origin, size, |p| p.y < 2), &mut s);
        assert_eq!(half, Counts { good: 256.0, target: 512.0, ..Counts::default() });
        assert!(fitness.eval(&half, 0) < fitness.eval(&full, 0));
        // One cell further along x: a slab of the target missed, one outside it covered.
        let shifted = scorer.counts(&blocks(origin + glam::IVec3::X, size, |_| true), &mut s);
        assert_eq!((shifted.good, shifted.bad), (384.0, 128.0));
        assert!(fitness.eval(&shifted, 0) < fitness.eval(&full, 0));
        // The scratch is left clear: the full structure counts as before.
        assert_eq!(scorer.counts(&blocks(origin, size, |_| true), &mut s), full);
    }

    #[test]
    fn blocks_count_like_the_box_they_fill() {
        let scorer = block_target();
        let mut s = scorer.scratch();
        let (origin, size) = (glam::IVec3::new(5, -1, 3), glam::UVec3::new(4, 2, 8));
        let structure = blocks(origin, size, |_| true);
        let centre = origin.as_vec3() + size.as_vec3() * 0.5;
        let boxed = boxes(&[(centre, size.as_vec3())]);
        assert_eq!(scorer.model_voxels(&structure, &mut s), scorer.model_voxels(&boxed, &mut s));
        let c = scorer.counts(&structure, &mut s);
        assert_eq!(c, scorer.counts(&boxed, &mut s));
        assert_eq!(c, scorer.counts_of(&oracle::voxelize(scorer.grid(), &structure)));
        assert!(c.good > 0.0 && c.bad > 0.0 && c.outside > 0.0, "{c:?}");
        // Blocks and an instance over the same place overlap.
        let mut both = structure.clone();
        both.instances.extend(boxed.instances);
        let c2 = scorer.counts(&both, &mut s);
        assert_eq!((c2.good, c2.bad, c2.overlap), (c.good, c.bad, c.good + c.bad));
    }

    #[test]
    fn scorers_check_their_targets() {
        let grid = Grid::new(Vec3::ZERO, Vec3::ONE, [2; 3]).unwrap();
        let other = Grid::new(Vec3::ZERO, Vec3::ONE, [3; 3]).unwrap();
        let t = |g: &Grid, fill| VolumeTarget { voxels: VoxelSet::new(g), fill, avoid: 1.0 };
        assert_eq!(
            VolumeScorer::new(grid, vec![t(&grid, 1.0), t(&other, 1.0)]).unwrap_err(),
            ScoreError::GridMismatch { index: 1 }
        );
        assert!(matches!(
            VolumeScorer::new(grid, vec![t(&grid, f64::NAN)]),
            Err(ScoreError::BadWeight { index: 0, .. })
        ));
        // A scratch made for another grid is replaced, not misused.
        let scorer = VolumeScorer::new(grid, vec![t(&grid, 1.0)]).unwrap();
        let mut s = VolumeScorer::new(other, vec![]).unwrap().scratch();
        let c = scorer.counts(&boxes(&[(Vec3::splat(0.5), Vec3::ONE)]), &mut s);
        assert_eq!(c.bad, 8.0);
    }
}
