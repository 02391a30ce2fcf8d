//! Spans of mesh instances kept across evaluations.
//!
//! A mesh instance's spans depend only on the lattice, the mesh and the
//! instance's transform, so an instance seen before can be marked again
//! from its recorded spans instead of being voxelized. Evolution sees the
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
//! bound the memory:
//! new spans go into the young map; when it holds [`YOUNG_SPANS`] spans the
//! old map is dropped and the young one takes its place (a hit in the old
//! map moves the entry back to the young one).

use crate::grid::Lattice;
use genform_core::scene::{Instance, Mesh};
use std::collections::HashMap;
use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};
use std::sync::{Arc, Mutex};

/// Spans the young map holds before it becomes the old one (12 bytes each).
const YOUNG_SPANS: usize = 1 << 19;

/// Fingerprints of instances met once kept before they are forgotten.
const SEEN_MAX: usize = 1 << 18;

/// Distinct meshes one cache keeps (scenes with meshes made anew for every
/// model do not fill it with ones never seen again).
const MAX_MESHES: usize = 64;

/// Meshes larger than this are voxelized every time (hashing and comparing
/// them would cost a good part of voxelizing them).
const MAX_TRIANGLES: usize = 1 << 14;

/// `(lattice row, first index, last index)` of a marked span.
pub(crate) type Span = (u32, u32, u32);

/// An instance: its mesh's hash and its transform's bits.
type Key = (u64, [u32; 12]);

/// What replaying an instance takes.
#[derive(Clone, Debug)]
struct Entry {
    spans: Box<[Span]>,
    /// The instance's contribution to `outside`.
    outside: u64,
}

/// One thread's cache of mesh instances' spans.
#[derive(Clone, Debug, Default)]
pub struct SpanCache {
    /// The lattice the spans are on (a scratch may move to another scorer).
    lattice: Option<Lattice>,
    young: HashMap<Key, Entry>,
    old: HashMap<Key, Entry>,
    young_spans: usize,
    /// Fingerprints of the keys met once and not recorded.
    seen: std::collections::HashSet<u64>,
    /// Every mesh met, by hash (`None`: another mesh had the same hash;
    /// never cached).
    meshes: HashMap<u64, Option<Mesh>>,
    /// Instances replayed so far.
    pub(crate) hits: u64,
}

/// What to do with an instance.
pub(crate) enum Lookup<'a> {
    /// Replay these spans and add `outside`.
    Hit { spans: &'a [Span], outside: u64 },
    /// Voxelize it and record its spans (met before).
    Record,
    /// Voxelize it (first met).
    Voxelize,
}

impl SpanCache {
    /// Empties the cache unless its spans are on `lat`.
    pub(crate) fn on_lattice(&mut self, lat: &Lattice) {
        if self.lattice.as_ref() != Some(lat) {
            *self = SpanCache { lattice: Some(lat.clone()), hits: self.hits, ..SpanCache::default() };
        }
    }

    /// The hash of `mesh` if its instances may be cached: the mesh is known
    /// under it (remembered now if there is room).
    pub(crate) fn mesh_key(&mut self, mesh: &Mesh) -> Option<u64> {
        if mesh.triangles.len() > MAX_TRIANGLES {
            return None;
        }
        let mut h = DefaultHasher::new();
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

    /// What to do with `inst` (of the mesh with key `mesh`).
    pub(crate) fn lookup(&mut self, mesh: u64, inst: &Instance) -> Lookup<'_> {
        let key = key(mesh, inst);
        if !self.young.contains_key(&key) {
            let Some(entry) = self.old.remove(&key) else {
                let mut h = DefaultHasher::new();
                key.hash(&mut h);
                if self.seen.len() >= SEEN_MAX {
                    self.seen.clear();
                }
                return if self.seen.insert(h.finish()) { Lookup::Voxelize } else { Lookup::Record };
            };
            self.insert_entry(key, entry);
        }
        self.hits += 1;
        match self.young.get(&key) {
            Some(e) => Lookup::Hit { spans: &e.spans, outside: e.outside },
            None => Lookup::Voxelize,
        }
    }

    /// Records the spans of `inst` (of the mesh with key `mesh`).
    pub(crate) fn insert(&mut self, mesh: u64, inst: &Instance, spans: &[Span], outside: u64) {
        self.insert_entry(key(mesh, inst), Entry { spans: spans.into(), outside });
    }

    fn insert_entry(&mut self, key: Key, entry: Entry) {
        if self.young_spans + entry.spans.len() > YOUNG_SPANS {
            self.old = std::mem::take(&mut self.young);
            self.young_spans = 0;
        }
        self.young_spans += entry.spans.len();
        self.young.insert(key, entry);
    }
}

fn key(mesh: u64, inst: &Instance) -> Key {
    (mesh, inst.transform.to_cols_array().map(f32::to_bits))
}

/// The caches of one scorer's scratches: a scratch takes one when it is
/// made and gives it back when it is dropped, so a cache outlives the
/// per-generation scratches of a run.
#[derive(Clone, Debug, Default)]
pub struct CachePool(Arc<Mutex<Vec<SpanCache>>>);

impl CachePool {
    /// A cache for a new scratch (one given back, or an empty one).
    pub(crate) fn take(&self) -> CacheSlot {
        let cache = self.0.lock().unwrap_or_else(|p| p.into_inner()).pop().unwrap_or_default();
        CacheSlot { cache: Some(cache), pool: Some(self.clone()) }
    }

    /// Empties every cache given back (benchmarks measuring cold caches).
    pub fn clear(&self) {
        self.0.lock().unwrap_or_else(|p| p.into_inner()).clear();
    }
}

/// A scratch's cache, given back to its pool on drop. A clone starts
/// without one (a cache is one thread's).
#[derive(Debug, Default)]
pub(crate) struct CacheSlot {
    pub cache: Option<SpanCache>,
    pool: Option<CachePool>,
}

impl Clone for CacheSlot {
    fn clone(&self) -> CacheSlot {
        CacheSlot::default()
    }
}

impl Drop for CacheSlot {
    fn drop(&mut self) {
        if let (Some(cache), Some(pool)) = (self.cache.take(), &self.pool) {
            pool.0.lock().unwrap_or_else(|p| p.into_inner()).push(cache);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{cube_mesh, tree_assets};
    use super::*;
    use crate::grid::{Grid, Lattice};
    use crate::voxel_set::VoxelSet;
    use crate::voxelize::VolumeScratch;
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
        let mut c = SpanCache::default();
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
        assert_eq!(SpanCache::default().mesh_key(&huge), None);
    }
}
