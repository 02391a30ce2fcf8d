//! The fast voxelizer's per-thread working memory.

use super::mesh_buffers::MeshBuffers;
use crate::bits::{BitRows, bit_range};
use crate::grid::Lattice;
use crate::span_cache::{CachePool, CacheSlot, MeshKeys, Span, SpanCache};
use glam::Vec3;

/// One of the scratch's two bit planes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Plane {
    /// Voxels held by at least one instance.
    Occupied,
    /// Voxels held by at least two instances.
    Overlap,
}

/// What [`VolumeScratch::finish`] counted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct PlaneCounts {
    pub held: u64,
    pub overlap: u64,
    /// Held voxels also set in the plane passed in.
    pub held_and: u64,
}

/// Rows of more words than this track which words they touched.
const RANGED_WORDS: usize = 8;

/// Set bits of a word. (Without a `popcnt` target feature `count_ones` is a
/// dozen instructions: callers avoid it where they know the answer.)
#[inline]
fn ones(w: u64) -> u64 {
    u64::from(w.count_ones())
}

/// Zeroes the rows `touched` of `data` (rows of `N` words from `off`).
/// With `N` a constant each row is a few vector stores, not a call to memset.
fn zero_rows<const N: usize>(data: &mut [u64], off: usize, touched: &[u32]) {
    for &r in touched {
        let row = off + r as usize * N;
        if let Ok(a) = <&mut [u64; N]>::try_from(&mut data[row..row + N]) {
            *a = [0; N];
        }
    }
}

/// Marks the bits `m` (`len` of them) of one word held once more:
/// `overlap |= occupied & m; occupied |= m`, counting what is new. Spans
/// rarely overlap and are often wholly in or out of the target, so most
/// calls need no bit counting.
#[inline]
fn mark(occ: &mut u64, ovl: &mut u64, m: u64, len: u64, target: Option<u64>, c: &mut PlaneCounts) {
    let o = *occ;
    let again = m & o;
    if again != 0 {
        let new = again & !*ovl;
        if new != 0 {
            *ovl |= new;
            c.overlap += ones(new);
        }
    }
    let fresh = m & !o;
    if fresh != 0 {
        *occ = o | fresh;
        let n = if fresh == m { len } else { ones(fresh) };
        c.held += n;
        if let Some(t) = target {
            let hit = fresh & t;
            if hit != 0 {
                c.held_and += if hit == fresh { n } else { ones(hit) };
            }
        }
    }
}

/// Per-thread working memory of the fast voxelizer: the occupied and overlap
/// bit planes of the grid, the rows touched so far, and buffers for meshes.
/// Get one from [`crate::VolumeScorer::scratch`]; after the first few
/// scenes it no longer allocates.
///
/// Each row keeps its occupied words and then its overlap words side by
/// side (row 0 on a 64-byte boundary), so that marking a span touches as
/// few cache lines as possible.
#[derive(Clone, Debug)]
pub struct VolumeScratch {
    words: usize,
    stride: usize,
    /// Index of row 0 in `data` (chosen for 64-byte alignment).
    off: usize,
    data: Vec<u64>,
    /// One bit per row: touched since the last clear.
    seen: Vec<u64>,
    /// For rows longer than [`RANGED_WORDS`]: the touched word range per
    /// row, `lo | hi << 32`. Shorter rows are counted whole (they fill one
    /// or two cache lines anyway).
    meta: Vec<u64>,
    touched: Vec<u32>,
    /// Held lattice voxels outside the grid so far.
    pub(crate) outside: u64,
    /// Counted as spans are marked.
    counts: PlaneCounts,
    verts: Vec<Vec3>,
    mesh: MeshBuffers,
    /// Block cells not yet covered by a box (block structures).
    cells: Vec<bool>,
    /// Mesh instances' spans kept across evaluations (scorers' scratches
    /// only), and the spans of the instance being recorded.
    cache: CacheSlot<Lattice>,
    spans: Vec<Span>,
    /// Per mesh of the Scene being voxelized: its cache key, once looked up.
    mesh_keys: MeshKeys,
}

impl VolumeScratch {
    pub(crate) fn new(lat: &Lattice) -> VolumeScratch {
        let stride = 2 * lat.words;
        let data = vec![0u64; stride * lat.rows + 8];
        let off = (64 - data.as_ptr() as usize % 64) % 64 / 8;
        VolumeScratch {
            words: lat.words,
            stride,
            off,
            data,
            seen: vec![0; lat.rows.div_ceil(64)],
            meta: if lat.words > RANGED_WORDS { vec![0; lat.rows] } else { Vec::new() },
            touched: Vec::new(),
            outside: 0,
            counts: PlaneCounts::default(),
            verts: Vec::new(),
            mesh: MeshBuffers::default(),
            cells: Vec::new(),
            cache: CacheSlot::default(),
            spans: Vec::new(),
            mesh_keys: Vec::new(),
        }
    }

    /// A scratch whose mesh instances are cached in a cache of `pool`.
    pub(crate) fn with_cache(lat: &Lattice, pool: &CachePool<Lattice>) -> VolumeScratch {
        VolumeScratch { cache: pool.take(), ..VolumeScratch::new(lat) }
    }

    /// Whether this scratch has the shape `lat` needs.
    pub(crate) fn fits(&self, lat: &Lattice) -> bool {
        self.words == lat.words && self.seen.len() == lat.rows.div_ceil(64) && self.rows() == lat.rows
    }

    fn rows(&self) -> usize {
        (self.data.len() - 8) / self.stride
    }

    /// Remembers row `r` as touched, covering words `wa..=wb`.
    #[inline]
    fn touch(&mut self, r: usize, wa: usize, wb: usize) {
        let (wa, wb) = (wa as u64, wb as u64);
        let (seen, bit) = (&mut self.seen[r / 64], 1u64 << (r % 64));
        if *seen & bit == 0 {
            *seen |= bit;
            self.touched.push(r as u32);
            if let Some(m) = self.meta.get_mut(r) {
                *m = wa | wb << 32;
            }
        } else if let Some(m) = self.meta.get_mut(r) {
            *m = (*m & 0xFFFF_FFFF).min(wa) | (*m >> 32).max(wb) << 32;
        }
    }

    /// Marks bits `a..=b` of row `r` held by one more instance, counting
    /// new held voxels, new overlap voxels and new held voxels set in
    /// `target` (a [`BitRows`] layout of the lattice, or empty).
    #[inline(always)]
    pub(crate) fn write(&mut self, r: usize, a: usize, b: usize, target: &[u64]) {
        let w = a / 64;
        if w != b / 64 {
            return self.write_words(r, a, b, target);
        }
        // One word (most spans of meshes): inlined, a few bounds checks.
        self.touch(r, w, w);
        let i = self.off + r * self.stride + w;
        let t = target.get(r * self.words + w).copied();
        let (data, counts) = (&mut self.data, &mut self.counts);
        let (lo, hi) = data.split_at_mut(i + self.words);
        let (la, lb) = ((a % 64) as u32, (b % 64) as u32);
        mark(&mut lo[i], &mut hi[0], bit_range(la, lb), u64::from(lb - la + 1), t, counts);
    }

    /// [`VolumeScratch::write`] of a span over two or more words (`a / 64 <
    /// b / 64`).
    #[inline(never)]
    fn write_words(&mut self, r: usize, a: usize, b: usize, target: &[u64]) {
        let (wa, wb) = (a / 64, b / 64);
        self.touch(r, wa, wb);
        let base = self.off + r * self.stride;
        let (occ, ovl) = self.data[base..base + self.stride].split_at_mut(self.words);
        let t = target.get(r * self.words..(r + 1) * self.words);
        // Counts in a local (registers); the first, middle and last word
        // masks written out rather than chosen per word.
        let mut c = self.counts;
        let (la, lb) = ((a % 64) as u32, (b % 64) as u32);
        mark(&mut occ[wa], &mut ovl[wa], u64::MAX << la, u64::from(64 - la), t.map(|t| t[wa]), &mut c);
        for w in wa + 1..wb {
            mark(&mut occ[w], &mut ovl[w], u64::MAX, 64, t.map(|t| t[w]), &mut c);
        }
        mark(&mut occ[wb], &mut ovl[wb], u64::MAX >> (63 - lb), u64::from(lb + 1), t.map(|t| t[wb]), &mut c);
        self.counts = c;
    }

    /// Remembers the `n` consecutive rows from `first` as touched, covering
    /// words `wa..=wb`: a word of `seen` at a time where ranges are not kept.
    #[inline]
    fn touch_rows(&mut self, first: usize, n: usize, wa: usize, wb: usize) {
        if !self.meta.is_empty() {
            for r in first..first + n {
                self.touch(r, wa, wb);
            }
            return;
        }
        let end = first + n;
        let mut r = first;
        while r < end {
            let (w, lo) = (r / 64, r % 64);
            let hi = (lo + (end - r)).min(64) - 1;
            let bits = bit_range(lo as u32, hi as u32);
            let seen = &mut self.seen[w];
            let mut new = bits & !*seen;
            *seen |= bits;
            while new != 0 {
                self.touched.push((w * 64) as u32 + new.trailing_zeros());
                new &= new - 1;
            }
            r = w * 64 + hi + 1;
        }
    }

    /// [`VolumeScratch::write`] of the same bits `a..=b` into the `n`
    /// consecutive rows from `first` (the rows of a separable box).
    #[inline]
    pub(crate) fn write_rows(&mut self, first: usize, n: usize, a: usize, b: usize, target: &[u64]) {
        let (wa, wb) = (a / 64, b / 64);
        // The word masks and their sizes are the same for every row.
        let mut masks = [(0u64, 0u64); 4];
        if wb - wa >= masks.len() {
            for r in first..first + n {
                self.write(r, a, b, target);
            }
            return;
        }
        for (w, m) in (wa..wb + 1).zip(&mut masks) {
            let lo = if w == wa { a % 64 } else { 0 };
            let hi = if w == wb { b % 64 } else { 63 };
            *m = (bit_range(lo as u32, hi as u32), (hi - lo + 1) as u64);
        }
        let masks = &masks[..wb - wa + 1];
        self.touch_rows(first, n, wa, wb);
        let (words, stride) = (self.words, self.stride);
        let start = self.off + first * stride;
        let block = &mut self.data[start..start + n * stride];
        // Counts in a local, so that they stay in registers across rows.
        let mut c = self.counts;
        if target.is_empty() {
            for row in block.chunks_exact_mut(stride) {
                let (occ, ovl) = row.split_at_mut(words);
                for ((o, v), &(m, len)) in occ[wa..=wb].iter_mut().zip(&mut ovl[wa..=wb]).zip(masks) {
                    mark(o, v, m, len, None, &mut c);
                }
            }
        } else {
            let rows =
                block.chunks_exact_mut(stride).zip(target[first * words..(first + n) * words].chunks_exact(words));
            for (row, t) in rows {
                let (occ, ovl) = row.split_at_mut(words);
                let words = occ[wa..=wb].iter_mut().zip(&mut ovl[wa..=wb]).zip(masks).zip(&t[wa..=wb]);
                for (((o, v), &(m, len)), &t) in words {
                    mark(o, v, m, len, Some(t), &mut c);
                }
            }
        }
        self.counts = c;
    }

    /// The touched word range of row `r`.
    #[inline]
    fn range(&self, r: usize) -> (usize, usize) {
        match self.meta.get(r) {
            Some(&m) => ((m & 0xFFFF_FFFF) as usize, (m >> 32) as usize),
            None => (0, self.words - 1),
        }
    }

    /// A copy of one plane as bit rows.
    pub(crate) fn plane(&self, which: Plane) -> BitRows {
        let mut b = BitRows::new(self.words, self.rows());
        let shift = if which == Plane::Occupied { 0 } else { self.words };
        for &r in &self.touched {
            let r = r as usize;
            let src = self.off + r * self.stride + shift;
            b.data_mut()[r * self.words..(r + 1) * self.words].copy_from_slice(&self.data[src..src + self.words]);
        }
        b
    }

    /// `(|occupied|, |occupied ∧ plane|)` over the touched rows, for a plane
    /// laid out as [`BitRows`] of this scratch's lattice.
    pub(crate) fn held_and(&self, plane: &[u64]) -> (u64, u64) {
        let (mut held, mut and) = (0, 0);
        for &r in &self.touched {
            let r = r as usize;
            let (lo, hi) = self.range(r);
            let row = self.off + r * self.stride;
            for w in lo..=hi {
                let o = self.data[row + w];
                if o != 0 {
                    held += ones(o);
                    and += ones(o & plane[r * self.words + w]);
                }
            }
        }
        (held, and)
    }

    /// The counts so far (held and overlap voxels, held voxels in the
    /// target given to the writes); then empties the planes (touched rows
    /// only), the counts and `outside`.
    pub(crate) fn finish(&mut self) -> PlaneCounts {
        let words = self.words;
        for &r in &self.touched {
            self.seen[r as usize / 64] = 0;
        }
        if self.meta.is_empty() {
            // Short rows are cleared whole, with fixed-size stores.
            let (data, off, touched) = (&mut self.data[..], self.off, &self.touched[..]);
            match self.stride {
                2 => zero_rows::<2>(data, off, touched),
                4 => zero_rows::<4>(data, off, touched),
                6 => zero_rows::<6>(data, off, touched),
                8 => zero_rows::<8>(data, off, touched),
                10 => zero_rows::<10>(data, off, touched),
                12 => zero_rows::<12>(data, off, touched),
                14 => zero_rows::<14>(data, off, touched),
                // Rows keep ranges beyond RANGED_WORDS words, so the stride is at most 16.
                _ => zero_rows::<16>(data, off, touched),
            }
        } else {
            for &r in &self.touched {
                let (r, (lo, hi)) = (r as usize, self.range(r as usize));
                let row = self.off + r * self.stride;
                self.data[row + lo..row + hi + 1].fill(0);
                self.data[row + words + lo..row + words + hi + 1].fill(0);
            }
        }
        self.touched.clear();
        self.outside = 0;
        std::mem::take(&mut self.counts)
    }

    /// Empties the planes (touched rows only) and `outside`.
    pub(crate) fn clear(&mut self) {
        self.finish();
    }

    pub(crate) fn take_verts(&mut self) -> Vec<Vec3> {
        std::mem::take(&mut self.verts)
    }

    pub(crate) fn put_verts(&mut self, v: Vec<Vec3>) {
        self.verts = v;
    }

    pub(crate) fn take_mesh_buffers(&mut self) -> MeshBuffers {
        std::mem::take(&mut self.mesh)
    }

    pub(crate) fn put_mesh_buffers(&mut self, m: MeshBuffers) {
        self.mesh = m;
    }

    /// Mesh instances replayed from this scratch's cache so far.
    #[cfg(test)]
    pub(crate) fn cache_hits(&self) -> u64 {
        self.cache.cache.as_ref().map_or(0, |c| c.hits)
    }

    /// The cache, the recording buffer and the mesh keys' buffer.
    pub(crate) fn take_cache(&mut self) -> (Option<SpanCache<Lattice>>, Vec<Span>, MeshKeys) {
        (self.cache.cache.take(), std::mem::take(&mut self.spans), std::mem::take(&mut self.mesh_keys))
    }

    pub(crate) fn put_cache(&mut self, cache: Option<SpanCache<Lattice>>, spans: Vec<Span>, keys: MeshKeys) {
        self.cache.cache = cache;
        self.spans = spans;
        self.mesh_keys = keys;
    }

    pub(crate) fn take_cells(&mut self) -> Vec<bool> {
        std::mem::take(&mut self.cells)
    }

    pub(crate) fn put_cells(&mut self, c: Vec<bool>) {
        self.cells = c;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::Grid;

    #[test]
    fn writes_count_and_clear() {
        for (width, ranged) in [(130, false), (700, true)] {
            writes_count_and_clear_on(width, ranged);
        }
    }

    /// Writing a block of rows equals writing its rows one by one, across
    /// words of the touched-row bits and over rows touched before.
    #[test]
    fn block_writes_equal_row_writes() {
        for width in [130, 700] {
            let lat = Lattice::new(
                &Grid::new(glam::Vec3::ZERO, glam::Vec3::new(width as f32, 100.0, 3.0), [width, 100, 3]).unwrap(),
            );
            let mut target = BitRows::new(lat.words, lat.rows);
            for r in (0..lat.rows).step_by(3) {
                target.set_range(r, 10, 100);
            }
            let (mut block, mut single) = (VolumeScratch::new(&lat), VolumeScratch::new(&lat));
            for s in [&mut block, &mut single] {
                s.write(70, 0, 20, target.data());
                s.write(250, 5, 6, target.data());
            }
            block.write_rows(60, 230, 15, 120, target.data());
            for r in 60..290 {
                single.write(r, 15, 120, target.data());
            }
            assert_eq!(block.touched.len(), 230);
            let (p, q) = (block.plane(Plane::Occupied), single.plane(Plane::Occupied));
            assert!(p.data() == q.data());
            assert!(block.plane(Plane::Overlap).data() == single.plane(Plane::Overlap).data());
            assert_eq!(block.finish(), single.finish());
            assert!(block.data.iter().all(|&w| w == 0) && block.seen.iter().all(|&m| m == 0));
        }
    }

    fn writes_count_and_clear_on(width: u32, ranged: bool) {
        let size = glam::Vec3::new(width as f32, 2.0, 1.0);
        let lat = Lattice::new(&Grid::new(glam::Vec3::ZERO, size, [width, 2, 1]).unwrap());
        let mut s = VolumeScratch::new(&lat);
        assert_eq!(s.meta.is_empty(), !ranged);
        assert_eq!((s.data.as_ptr() as usize + 8 * s.off) % 64, 0);
        let mut target = BitRows::new(lat.words, lat.rows);
        target.set_range(1, 0, 64);
        s.write(1, 60, 70, target.data());
        s.write_rows(1, 1, 65, 129, target.data());
        s.write(0, 3, 3, target.data());
        let occ = s.plane(Plane::Occupied);
        assert_eq!(occ.count(), 11 + 59 + 1);
        assert_eq!(s.plane(Plane::Overlap).count(), 6);
        assert_eq!(s.held_and(target.data()), (71, 5));
        let c = s.finish();
        assert_eq!(c, PlaneCounts { held: 71, overlap: 6, held_and: 5 });
        assert!(s.touched.is_empty() && s.data.iter().all(|&w| w == 0) && s.seen.iter().all(|&m| m == 0));
    }
}
