//! Spans of mesh instances kept across evaluations, for the voxelizer and
//! the silhouette rasterizer.
//!
//! A mesh instance's spans depend only on where they are drawn (the
//! lattice, or the camera and image), the mesh and the instance's
//! transform, so an instance seen before can be marked again from its
//! recorded spans instead of being voxelized or rasterized. Evolution sees the
//! same instances again and again: in a GA run on `tree_avoid`, 95–97 % of
//! the mesh instances of the individuals evaluated after generation 5 had
//! the same mesh and the same transform bits as one evaluated before
//! (children share most of their derivation with their parents). The
//! replayed spans are the recorded ones, so results are the same bits with
//! or without the cache, at any thread count.
//!
//! Keys are the transform's bits and a hash of the mesh; every mesh behind
//! a hash is kept and compared in full before its hash is trusted, so a
//! hash collision can only cost speed. An instance's spans are recorded
//! the second time it is met (the first time only its key's fingerprint
//! is remembered), so models that never repeat — a batch of unrelated
//! random genomes — pay almost nothing for the cache. Two generations
//! bound the memory: new spans go into the young one; when it holds
//! [`YOUNG_SPANS`] spans the old one is dropped and the young one takes its
//! place (a hit in the old one moves the entry back to the young one).

use genform_core::scene::{Instance, Mesh, Scene};
use rustc_hash::{FxHashMap, FxHashSet, FxHasher};
use std::hash::{Hash, Hasher};
use std::sync::{Arc, Mutex};

/// Spans the young generation holds before it becomes the old one (12
/// bytes each).
const YOUNG_SPANS: usize = 1 << 19;

/// Fingerprints of instances met once kept before they are forgotten.
const SEEN_MAX: usize = 1 << 18;

/// Distinct meshes one cache keeps (scenes with meshes made anew for every
/// model do not fill it with ones never seen again).
const MAX_MESHES: usize = 64;

/// Meshes larger than this are drawn every time (hashing and comparing
/// them would cost a good part of drawing them).
const MAX_TRIANGLES: usize = 1 << 14;

/// `(row, first index, last index)` of a marked span (a lattice row, or a
/// pixel row).
pub(crate) type Span = (u32, u32, u32);

/// An instance: its mesh's hash and its transform's bits.
type Key = (u64, [u32; 12]);

/// Where an instance's spans lie in its generation's arena.
#[derive(Clone, Copy, Debug)]
struct Entry {
    start: usize,
    len: usize,
    /// The instance's contribution to `outside` (voxels).
    outside: u64,
    /// The spans' rows `first..=last` and index range `lo..=hi`.
    bounds: Bounds,
}

/// Per mesh id of a Scene: its cache key once looked up (`Some(None)`: not
/// cached).
pub(crate) type MeshKeys = Vec<Option<Option<u64>>>;

/// `[first row, last row, least index, greatest index]` of some spans.
pub(crate) type Bounds = [u32; 4];

/// The entries of one generation and their spans, back to back (one
/// allocation for all, reused when the generation is dropped).
#[derive(Clone, Debug, Default)]
struct Generation {
    entries: FxHashMap<Key, Entry>,
    spans: Vec<Span>,
}

impl Generation {
    fn clear(&mut self) {
        self.entries.clear();
        self.spans.clear();
    }

    fn spans(&self, e: &Entry) -> &[Span] {
        &self.spans[e.start..e.start + e.len]
    }
}

/// One thread's cache of mesh instances' spans drawn on an `O` (a lattice,
/// a camera frame).
#[derive(Clone, Debug)]
pub(crate) struct SpanCache<O> {
    /// Where the spans are drawn (a scratch may move to another scorer).
    owner: Option<O>,
    young: Generation,
    old: Generation,
    /// Fingerprints of the keys met once and not recorded.
    seen: FxHashSet<u64>,
    /// Every mesh met, by hash (`None`: another mesh had the same hash;
    /// never cached).
    meshes: FxHashMap<u64, Option<Mesh>>,
    /// An old entry's spans on their way to the young generation.
    moving: Vec<Span>,
    /// Instances replayed so far.
    pub(crate) hits: u64,
}

/// What to do with an instance.
pub(crate) enum Lookup<'a> {
    /// Replay these spans (within `bounds`) and add `outside`.
    Hit { spans: &'a [Span], outside: u64, bounds: Bounds },
    /// Draw it (voxelize or rasterize) and record its spans (met before).
    Record,
    /// Draw it (first met).
    Draw,
}

impl<O> Default for SpanCache<O> {
    fn default() -> SpanCache<O> {
        SpanCache {
            owner: None,
            young: Generation::default(),
            old: Generation::default(),
            seen: FxHashSet::default(),
            meshes: FxHashMap::default(),
            moving: Vec::new(),
            hits: 0,
        }
    }
}

impl<O> SpanCache<O> {
    /// Empties the cache, keeping its memory.
    fn reset(&mut self) {
        self.owner = None;
        self.young.clear();
        self.old.clear();
        self.seen.clear();
        self.meshes.clear();
        self.hits = 0;
    }
}

impl<O: PartialEq + Clone> SpanCache<O> {
    /// Empties the cache unless its spans are drawn on `owner`.
    pub(crate) fn drawn_on(&mut self, owner: &O) {
        if self.owner.as_ref() != Some(owner) {
            let hits = self.hits;
            self.reset();
            self.owner = Some(owner.clone());
            self.hits = hits;
        }
    }

    /// The hash of `mesh` if its instances may be cached: the mesh is known
    /// under it (remembered now if there is room).
    pub(crate) fn mesh_key(&mut self, mesh: &Mesh) -> Option<u64> {
        if mesh.triangles.len() > MAX_TRIANGLES {
            return None;
        }
        let mut h = FxHasher::default();
        for p in &mesh.positions {
            p.to_array().map(f32::to_bits).hash(&mut h);
        }
        mesh.triangles.hash(&mut h);
        let hash = h.finish();
        let room = self.meshes.len() < MAX_MESHES;
        match self.meshes.get_mut(&hash) {
            Some(Some(known)) if known == mesh => Some(hash),
            Some(slot) => {
                // Two meshes, one hash: neither is cached from now on.
                *slot = None;
                None
            }
            None if room => {
                self.meshes.insert(hash, Some(mesh.clone()));
                Some(hash)
            }
            None => None,
        }
    }

    /// The key of mesh `id` of `scene`, looked up once per Scene (`keys`:
    /// per mesh id, emptied for each Scene).
    pub(crate) fn scene_mesh_key(
        &mut self,
        scene: &Scene,
        id: u32,
        keys: &mut Vec<Option<Option<u64>>>,
    ) -> Option<u64> {
        let id = id as usize;
        if keys.len() <= id {
            keys.resize(scene.meshes.len().max(id + 1), None);
        }
        *keys[id].get_or_insert_with(|| scene.meshes.get(id).and_then(|m| self.mesh_key(m)))
    }

    /// What to do with `inst` (of the mesh with key `mesh`).
    pub(crate) fn lookup(&mut self, mesh: u64, inst: &Instance) -> Lookup<'_> {
        let key = key(mesh, inst);
        if !self.young.entries.contains_key(&key) {
            let Some(e) = self.old.entries.remove(&key) else {
                let mut h = FxHasher::default();
                key.hash(&mut h);
                if self.seen.len() >= SEEN_MAX {
                    self.seen.clear();
                }
                return if self.seen.insert(h.finish()) { Lookup::Draw } else { Lookup::Record };
            };
            // Back into the young generation (through a buffer: making room
            // may drop the old one).
            let mut moving = std::mem::take(&mut self.moving);
            moving.clear();
            moving.extend_from_slice(self.old.spans(&e));
            self.insert_entry(key, &moving, e.outside);
            self.moving = moving;
        }
        self.hits += 1;
        match self.young.entries.get(&key) {
            Some(e) => Lookup::Hit { spans: self.young.spans(e), outside: e.outside, bounds: e.bounds },
            None => Lookup::Draw,
        }
    }

    /// Records the spans of `inst` (of the mesh with key `mesh`).
    pub(crate) fn insert(&mut self, mesh: u64, inst: &Instance, spans: &[Span], outside: u64) {
        self.insert_entry(key(mesh, inst), spans, outside);
    }

    fn insert_entry(&mut self, key: Key, spans: &[Span], outside: u64) {
        if self.young.spans.len() + spans.len() > YOUNG_SPANS {
            // The old generation goes; its allocations serve the new young.
            std::mem::swap(&mut self.old, &mut self.young);
            self.young.clear();
        }
        let start = self.young.spans.len();
        self.young.spans.extend_from_slice(spans);
        let bounds = spans.iter().fold([u32::MAX, 0, u32::MAX, 0], |[r0, r1, x0, x1], &(r, a, b)| {
            [r0.min(r), r1.max(r), x0.min(a), x1.max(b)]
        });
        self.young.entries.insert(key, Entry { start, len: spans.len(), outside, bounds });
    }
}

fn key(mesh: u64, inst: &Instance) -> Key {
    (mesh, inst.transform.to_cols_array().map(f32::to_bits))
}

/// The caches of one scorer's scratches: a scratch takes one when it is
/// made and gives it back when it is dropped, so a cache outlives the
/// per-generation scratches of a run.
#[derive(Debug)]
pub(crate) struct CachePool<O>(Arc<Mutex<Vec<SpanCache<O>>>>);

impl<O> Default for CachePool<O> {
    fn default() -> CachePool<O> {
        CachePool(Arc::default())
    }
}

impl<O> Clone for CachePool<O> {
    fn clone(&self) -> CachePool<O> {
        CachePool(self.0.clone())
    }
}

impl<O> CachePool<O> {
    /// A cache for a new scratch (one given back, or an empty one).
    pub(crate) fn take(&self) -> CacheSlot<O> {
        let cache = self.0.lock().unwrap_or_else(|p| p.into_inner()).pop().unwrap_or_default();
        CacheSlot { cache: Some(cache), pool: Some(self.clone()) }
    }

    /// Empties every cache given back, keeping their memory (benchmarks
    /// measuring cold caches).
    pub(crate) fn clear(&self) {
        for c in self.0.lock().unwrap_or_else(|p| p.into_inner()).iter_mut() {
            c.reset();
        }
    }
}

/// A scratch's cache, given back to its pool on drop. A clone starts
/// without one (a cache is one thread's).
#[derive(Debug)]
pub(crate) struct CacheSlot<O> {
    pub cache: Option<SpanCache<O>>,
    pool: Option<CachePool<O>>,
}

impl<O> Default for CacheSlot<O> {
    fn default() -> CacheSlot<O> {
        CacheSlot { cache: None, pool: None }
    }
}

impl<O> Clone for CacheSlot<O> {
    fn clone(&self) -> CacheSlot<O> {
        CacheSlot::default()
    }
}

impl<O> Drop for CacheSlot<O> {
    fn drop(&mut self) {
        if let (Some(cache), Some(pool)) = (self.cache.take(), &self.pool) {
            pool.0.lock().unwrap_or_else(|p| p.into_inner()).push(cache);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{Grid, Lattice};
    use crate::voxel_set::VoxelSet;
    use crate::voxelize::VolumeScratch;
    use crate::voxelize::tests::{cube_mesh, tree_assets};
    use crate::{VolumeScorer, VolumeTarget};
    use genform_core::scene::{Primitive, Scene};
    use glam::{Affine3A, Quat, Vec3};
    use std::sync::Arc as StdArc;

    /// Trunks and leaves (and a box) placed by `seed`; `stretch` scales the
    /// trunk asset's own vertices (same mesh id, other content).
    fn forest(seed: u64, stretch: f32) -> Scene {
        let mut rng = genform_core::Rng::stream(seed, &[]);
        let [mut trunk, leaf] = tree_assets();
        trunk.positions.iter_mut().for_each(|p| p.y *= stretch);
        let mut scene = Scene::new();
        let ids = [scene.mesh(&StdArc::new(trunk)), scene.mesh(&StdArc::new(leaf))];
        for n in 0..16 {
            let mut u = || rng.next_f64() as f32;
            let size = Vec3::new(0.3 + u(), 0.5 + 2.0 * u(), 0.3 + u());
            let r = Quat::from_rotation_y(7.0 * u()) * Quat::from_rotation_z(1.5 * u());
            let at = Vec3::new(4.0 * u() - 2.0, 4.0 * u() - 2.0, 4.0 * u() - 2.0);
            let transform = Affine3A::from_scale_rotation_translation(size, r, at);
            let primitive = if n == 5 { Primitive::Box } else { Primitive::Mesh(ids[n % 2]) };
            scene.instances.push(Instance { transform, primitive, tag: 0 });
        }
        scene
    }

    /// A scorer on a 40³ grid whose target is the voxels with x < 20.
    fn scorer() -> VolumeScorer {
        scorer_at(-2.5)
    }

    /// The same on a grid whose corner is at `min` (5 units a side).
    fn scorer_at(min: f32) -> VolumeScorer {
        let grid = Grid::new(Vec3::splat(min), Vec3::splat(min + 5.0), [40; 3]).unwrap();
        let mut t = VoxelSet::new(&grid);
        for x in 0..20 {
            for y in 0..40 {
                for z in 0..40 {
                    t.insert([x, y, z]);
                }
            }
        }
        VolumeScorer::new(grid, vec![VolumeTarget { voxels: t, fill: 1.0, avoid: 1.0 }]).unwrap()
    }

    /// Scenes that share instances, and one whose trunk asset has other
    /// vertices under the same id, go through one cached scratch in turn:
    /// every count equals a cacheless scratch's, and instances were
    /// replayed.
    #[test]
    fn replayed_instances_count_like_voxelized_ones() {
        let scorer = scorer();
        let a = forest(1, 1.0);
        let mut b = forest(2, 1.0);
        // Half of `b` is `a`'s, in another order.
        b.instances.truncate(8);
        b.instances.extend(a.instances[..8].iter().rev().cloned());
        let stretched = forest(1, 1.5);
        let mut cached = scorer.scratch();
        for (n, scene) in [&a, &b, &a, &stretched, &a, &b, &stretched, &a].into_iter().enumerate() {
            let mut fresh = VolumeScratch::new(&Lattice::new(scorer.grid()));
            assert_eq!(scorer.counts(scene, &mut cached), scorer.counts(scene, &mut fresh), "scene {n}");
        }
        assert!(cached.cache_hits() >= 20, "{} instances replayed", cached.cache_hits());
    }

    /// A scorer's cache outlives its scratches (a run's generations each
    /// make new ones) until it is cleared.
    #[test]
    fn caches_outlive_scratches_until_cleared() {
        let scorer = scorer();
        let a = forest(3, 1.0);
        let want = {
            let mut s = scorer.scratch();
            // Recorded the second time each instance is met.
            scorer.counts(&a, &mut s);
            scorer.counts(&a, &mut s)
        };
        let mut s = scorer.scratch();
        assert_eq!(scorer.counts(&a, &mut s), want);
        assert_eq!(s.cache_hits(), 15, "every mesh instance replayed at once");
        drop(s);
        scorer.clear_caches();
        let mut s = scorer.scratch();
        assert_eq!(scorer.counts(&a, &mut s), want);
        assert_eq!(s.cache_hits(), 0);
        // A clone of a scratch starts without a cache.
        assert_eq!(s.clone().cache_hits(), 0);
    }

    /// A scratch handed from one scorer to another of the same size (so it
    /// is kept, not remade) forgets the first one's spans.
    #[test]
    fn a_scratch_moved_to_another_grid_forgets_its_spans() {
        let (a, b) = (scorer_at(-2.5), scorer_at(-2.0));
        let scene = forest(4, 1.0);
        let mut s = a.scratch();
        for _ in 0..3 {
            a.counts(&scene, &mut s);
        }
        let mut fresh = VolumeScratch::new(&Lattice::new(b.grid()));
        assert_eq!(b.counts(&scene, &mut s), b.counts(&scene, &mut fresh));
        assert_eq!(s.cache_hits(), 15, "only a's replays");
    }

    /// Meshes too large, or met after the cache knows enough of them, are
    /// not cached; a known mesh is recognised by its content.
    #[test]
    fn which_meshes_are_cached() {
        let mut c = SpanCache::<()>::default();
        let cube = cube_mesh();
        let k = c.mesh_key(&cube).unwrap();
        assert_eq!(c.mesh_key(&cube.clone()), Some(k));
        for n in 1..MAX_MESHES {
            let mut m = cube.clone();
            m.positions[0].x += n as f32;
            assert!(c.mesh_key(&m).is_some());
        }
        let mut late = cube.clone();
        late.positions[0].y += 0.5;
        assert_eq!(c.mesh_key(&late), None, "the cache knows {MAX_MESHES} meshes already");
        let huge =
            Mesh { positions: vec![Vec3::ZERO; 3], triangles: vec![[0, 1, 2]; MAX_TRIANGLES + 1], ..Mesh::default() };
        assert_eq!(SpanCache::<()>::default().mesh_key(&huge), None);
    }
}
