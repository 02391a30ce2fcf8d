//! Region files (`r.X.Z.mca`): 32×32 chunks in 4 KiB sectors. Reading
//! terrain into a [`BlockGrid`] and writing a grid back into a copy.
//!
//! The container is parsed here rather than by fastanvil's `Region`, which
//! trusts its header (a zero length entry underflows, a garbled offset can
//! index past its sector table); chunk payloads are decompressed with
//! flate2, or fastanvil's LZ4 reader for LZ4 chunks.

use super::chunk::{Chunk, SECTION_CELLS, SectionIndices};
use super::constants::MAX_TERRAIN_CELLS;
use super::error::MinecraftError;
use flate2::Compression;
use flate2::read::{GzDecoder, ZlibDecoder, ZlibEncoder};
use genform_core::blocks::{BlockGrid, BlockState};
use glam::IVec3;
use std::collections::{HashMap, HashSet};
use std::io::{Read, Write};

const SECTOR: usize = 4096;
const HEADER: usize = 2 * SECTOR;
/// A decompressed chunk larger than this is refused (a real one is well
/// under a few MiB; this stops a tiny garbled entry inflating to GiBs).
const MAX_CHUNK_NBT: u64 = 64 << 20;
/// Sectors one region entry can span.
const MAX_SECTORS: usize = 255;

/// The bytes of one region file and which region it is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RegionFile {
    /// Region x: chunks `32·x .. 32·x + 32`, blocks `512·x .. 512·x + 512`.
    pub x: i32,
    /// Region z.
    pub z: i32,
    /// The whole `.mca` file.
    pub bytes: Vec<u8>,
}

/// The region coordinates a file name says (`r.-1.2.mca` → (−1, 2)); any
/// leading directories are ignored. `None` for other names.
pub fn region_coords(file_name: &str) -> Option<(i32, i32)> {
    let name = file_name.rsplit(['/', '\\']).next()?;
    let mut parts = name.strip_prefix("r.")?.strip_suffix(".mca")?.split('.');
    let x = parts.next()?.parse().ok()?;
    let z = parts.next()?.parse().ok()?;
    parts.next().is_none().then_some((x, z))
}

/// The file name of region (`x`, `z`): `r.x.z.mca`.
pub fn region_file_name(x: i32, z: i32) -> String {
    format!("r.{x}.{z}.mca")
}

/// The regions a block box `[min, max_exclusive)` overlaps (x then z
/// ascending); empty when the box is.
pub fn regions_for_box(min: IVec3, max_exclusive: IVec3) -> Vec<(i32, i32)> {
    if min.x >= max_exclusive.x || min.z >= max_exclusive.z || min.y >= max_exclusive.y {
        return Vec::new();
    }
    let (x0, x1) = (min.x.div_euclid(512), (max_exclusive.x - 1).div_euclid(512));
    let (z0, z1) = (min.z.div_euclid(512), (max_exclusive.z - 1).div_euclid(512));
    (x0..=x1).flat_map(|x| (z0..=z1).map(move |z| (x, z))).collect()
}

/// A validated view of a region file's entries.
struct Container<'a> {
    rx: i32,
    rz: i32,
    bytes: &'a [u8],
}

/// Where one chunk's stored bytes are.
#[derive(Clone, Copy)]
struct Entry {
    /// Byte offset of the 4-byte length.
    start: usize,
    /// Length field + 4: the bytes to copy to keep the chunk as stored.
    stored: usize,
    /// Compression scheme byte.
    scheme: u8,
}

impl<'a> Container<'a> {
    fn new(region: &'a RegionFile) -> Result<Container<'a>, MinecraftError> {
        let n = region.bytes.len();
        // An empty file is a region with no chunks (Minecraft creates them).
        if n != 0 && n < HEADER {
            return Err(MinecraftError::CorruptRegion {
                x: region.x,
                z: region.z,
                reason: format!("{n} bytes, shorter than the 8192-byte header"),
            });
        }
        Ok(Container { rx: region.x, rz: region.z, bytes: &region.bytes })
    }

    /// World chunk coordinates of local chunk `i` (x + 32 z).
    fn chunk_xz(&self, i: usize) -> (i32, i32) {
        (self.rx * 32 + (i % 32) as i32, self.rz * 32 + (i / 32) as i32)
    }

    fn unreadable(&self, i: usize, reason: impl Into<String>) -> MinecraftError {
        let (x, z) = self.chunk_xz(i);
        MinecraftError::ChunkUnreadable { x, z, reason: reason.into() }
    }

    /// The entry of local chunk `i`, `None` when the chunk is absent.
    fn entry(&self, i: usize) -> Result<Option<Entry>, MinecraftError> {
        if self.bytes.is_empty() {
            return Ok(None);
        }
        let h = &self.bytes[4 * i..4 * i + 4];
        let offset = (usize::from(h[0]) << 16) | (usize::from(h[1]) << 8) | usize::from(h[2]);
        let sectors = usize::from(h[3]);
        if offset == 0 && sectors == 0 {
            return Ok(None);
        }
        let start = offset * SECTOR;
        if offset < 2 || start + 5 > self.bytes.len() {
            return Err(self.unreadable(i, format!("its entry points at sector {offset}, outside the file")));
        }
        let len = u32::from_be_bytes(self.bytes[start..start + 4].try_into().expect("4 bytes")) as usize;
        let scheme = self.bytes[start + 4];
        if len == 0 || start + 4 + len > self.bytes.len() {
            return Err(self.unreadable(i, format!("its length {len} runs past the end of the file")));
        }
        Ok(Some(Entry { start, stored: 4 + len, scheme }))
    }

    /// The chunk's NBT, decompressed; `None` when absent.
    fn nbt(&self, i: usize) -> Result<Option<Vec<u8>>, MinecraftError> {
        let Some(e) = self.entry(i)? else { return Ok(None) };
        let data = &self.bytes[e.start + 5..e.start + e.stored];
        let mut out = Vec::new();
        let limited = |r: &mut dyn Read, out: &mut Vec<u8>| r.take(MAX_CHUNK_NBT + 1).read_to_end(out).map(|_| ());
        let res = match e.scheme {
            1 => limited(&mut GzDecoder::new(data), &mut out),
            2 => limited(&mut ZlibDecoder::new(data), &mut out),
            3 => {
                out.extend_from_slice(data);
                Ok(())
            }
            4 => {
                let mut dec = fastanvil::Lz4DecoderWrapper::new(Vec::new());
                dec.write_all(data)
                    .map_err(|e| e.to_string())
                    .and_then(|_| dec.finish().map_err(|e| e.to_string()))
                    .map(|v| out = v)
                    .map_err(std::io::Error::other)
            }
            s if s & 0x80 != 0 => {
                return Err(self.unreadable(i, "it is stored in a separate c.X.Z.mcc file, which is not supported"));
            }
            s => return Err(self.unreadable(i, format!("unknown compression scheme {s}"))),
        };
        res.map_err(|err| self.unreadable(i, format!("cannot decompress it: {err}")))?;
        if out.len() as u64 > MAX_CHUNK_NBT {
            return Err(self.unreadable(i, format!("it decompresses to more than {MAX_CHUNK_NBT} bytes")));
        }
        Ok(Some(out))
    }

    /// The decoded chunk, `None` when absent.
    fn chunk(&self, i: usize) -> Result<Option<Chunk>, MinecraftError> {
        let Some(bytes) = self.nbt(i)? else { return Ok(None) };
        let (x, z) = self.chunk_xz(i);
        Chunk::decode(&bytes, x, z).map(Some)
    }
}

/// Reads the blocks of the box `[min, max_exclusive)` from region files.
///
/// Only fully generated chunks (status `full`) count: cells of missing or
/// unfinished chunks, of regions not given, and above or below the stored
/// sections stay [`BlockGrid::UNSET`]. A region given twice is read once
/// (the first). Errors name the chunk that cannot be read (bad data,
/// pre-1.18 DataVersion, wrong coordinates); chunks outside the box are
/// not looked at.
pub fn read_terrain(regions: &[RegionFile], min: IVec3, max_exclusive: IVec3) -> Result<BlockGrid, MinecraftError> {
    let side = |a: i32, b: i32| (i64::from(b) - i64::from(a)).max(0) as u64;
    let sides = [side(min.x, max_exclusive.x), side(min.y, max_exclusive.y), side(min.z, max_exclusive.z)];
    let cells = sides.iter().try_fold(1u64, |acc, &s| acc.checked_mul(s)).unwrap_or(u64::MAX);
    if cells > MAX_TERRAIN_CELLS {
        return Err(MinecraftError::BoxTooLarge { cells });
    }
    // Each side is below 2³⁰ here, so it fits the grid's u32 sizes.
    let size = glam::UVec3::new(sides[0] as u32, sides[1] as u32, sides[2] as u32);
    let mut grid = BlockGrid::new(min, size);
    if cells == 0 {
        return Ok(grid);
    }
    let mut index_of: HashMap<BlockState, u32> = HashMap::new();
    let mut seen = HashSet::new();
    for region in regions {
        if !seen.insert((region.x, region.z)) {
            continue;
        }
        let container = Container::new(region)?;
        let (cx0, cz0) = (region.x * 32, region.z * 32);
        for lz in 0..32 {
            for lx in 0..32 {
                let (cx, cz) = (cx0 + lx, cz0 + lz);
                let lo = IVec3::new(cx * 16, i32::MIN, cz * 16).max(min);
                let hi = IVec3::new(cx * 16 + 16, i32::MAX, cz * 16 + 16).min(max_exclusive);
                if lo.x >= hi.x || lo.z >= hi.z {
                    continue;
                }
                let Some(chunk) = container.chunk((lx + 32 * lz) as usize)? else { continue };
                if !chunk.is_full() {
                    continue;
                }
                for (sy, blocks) in chunk.section_blocks(|sy| sy * 16 < hi.y && sy * 16 + 16 > lo.y)? {
                    let lo = IVec3::new(lo.x, lo.y.max(sy * 16), lo.z);
                    let hi = IVec3::new(hi.x, hi.y.min(sy * 16 + 16), hi.z);
                    if lo.y >= hi.y {
                        continue;
                    }
                    let map: Vec<u32> = blocks
                        .palette
                        .iter()
                        .map(|s| {
                            *index_of.entry(s.clone()).or_insert_with(|| {
                                grid.palette.push(s.clone());
                                (grid.palette.len() - 1) as u32
                            })
                        })
                        .collect();
                    fill_section(&mut grid, IVec3::new(cx * 16, sy * 16, cz * 16), lo, hi, &map, &blocks.indices);
                }
            }
        }
    }
    Ok(grid)
}

/// Copies the part `[lo, hi)` of the section whose first block is `base`
/// into `grid`.
fn fill_section(grid: &mut BlockGrid, base: IVec3, lo: IVec3, hi: IVec3, map: &[u32], indices: &SectionIndices) {
    let (sx, sz) = (grid.size.x as usize, grid.size.z as usize);
    for y in lo.y..hi.y {
        for z in lo.z..hi.z {
            let g = grid.origin;
            let row = ((y - g.y) as usize * sz + (z - g.z) as usize) * sx;
            let (a, b) = (row + (lo.x - g.x) as usize, row + (hi.x - g.x) as usize);
            match indices {
                SectionIndices::Uniform => grid.cells[a..b].fill(map[0]),
                SectionIndices::PerBlock(idx) => {
                    let s = ((y - base.y) * 256 + (z - base.z) * 16) as usize;
                    let src = &idx[s + (lo.x - base.x) as usize..s + (hi.x - base.x) as usize];
                    for (d, &i) in grid.cells[a..b].iter_mut().zip(src) {
                        *d = map[i as usize];
                    }
                }
            }
        }
    }
}

/// Writes the set cells of `blocks` that fall inside `original`'s region
/// into a copy of it and returns the new file's bytes.
///
/// Unset cells and cells of other regions are left alone (call this once
/// per region file [`regions_for_box`] names). Each touched chunk is
/// decoded, its sections' `block_states` rewritten (palette entries added,
/// unused ones dropped, indices repacked; a missing section inside the
/// chunk's height range is created with biomes copied from its nearest
/// section), block entities at changed blocks removed, and `isLightOn`
/// cleared so Minecraft relights the chunk. Every other tag is kept as
/// read. Heightmaps are not recomputed: they may be stale until the game
/// updates them. Untouched chunks are copied as stored, compressed bytes
/// and timestamp included. The file is laid out anew: chunks in header
/// order, without gaps.
///
/// Errors: a corrupt header or touched chunk, a touched chunk that is
/// missing, unfinished or older than 1.18, a block above or below the
/// chunk's sections, a chunk that no longer fits a region entry.
pub fn write_region(original: &RegionFile, blocks: &BlockGrid) -> Result<Vec<u8>, MinecraftError> {
    super::grid::check_grid(blocks)?;
    let container = Container::new(original)?;
    let mut rewritten: HashMap<usize, Vec<u8>> = HashMap::new();
    for (i, cells) in touched_chunks(original, blocks) {
        let (cx, cz) = container.chunk_xz(i);
        let chunk = container.chunk(i)?;
        let mut chunk =
            chunk.ok_or_else(|| MinecraftError::ChunkNotGenerated { x: cx, z: cz, reason: "it is missing".into() })?;
        if !chunk.is_full() {
            let reason = format!("its generation stopped at status `{}`", chunk.status());
            return Err(MinecraftError::ChunkNotGenerated { x: cx, z: cz, reason });
        }
        let (smin, smax) = chunk.section_range().ok_or_else(|| MinecraftError::ChunkNotGenerated {
            x: cx,
            z: cz,
            reason: "it has no block sections".into(),
        })?;
        let mut by_section: HashMap<i32, Vec<(usize, u32)>> = HashMap::new();
        for (p, c) in cells {
            let sy = p.y.div_euclid(16);
            if sy < smin || sy > smax {
                return Err(MinecraftError::OutsideWorldHeight {
                    x: cx,
                    z: cz,
                    y: p.y,
                    min: smin * 16,
                    max: smax * 16 + 15,
                });
            }
            let local = (p - IVec3::new(cx * 16, sy * 16, cz * 16)).as_uvec3();
            by_section.entry(sy).or_default().push(((local.y * 256 + local.z * 16 + local.x) as usize, c));
        }
        let mut gone = HashSet::new();
        let mut ys: Vec<i32> = by_section.keys().copied().collect();
        ys.sort_unstable();
        for sy in ys {
            let mut want = vec![None; SECTION_CELLS];
            for &(k, c) in &by_section[&sy] {
                want[k] = Some(c);
            }
            for k in chunk.edit_section(sy, &blocks.palette, |k| want[k])? {
                let (x, y, z) = ((k % 16) as i32, (k / 256) as i32, ((k / 16) % 16) as i32);
                gone.insert([cx * 16 + x, sy * 16 + y, cz * 16 + z]);
            }
        }
        if gone.is_empty() {
            continue;
        }
        chunk.remove_block_entities(&gone);
        chunk.invalidate_light();
        let mut compressed = Vec::new();
        let nbt = chunk.encode();
        ZlibEncoder::new(&nbt[..], Compression::new(4))
            .read_to_end(&mut compressed)
            .map_err(|e| MinecraftError::ChunkUnreadable { x: cx, z: cz, reason: e.to_string() })?;
        if 5 + compressed.len() > MAX_SECTORS * SECTOR {
            return Err(MinecraftError::ChunkTooLarge { x: cx, z: cz, bytes: compressed.len() });
        }
        let mut stored = Vec::with_capacity(5 + compressed.len());
        stored.extend_from_slice(&(compressed.len() as u32 + 1).to_be_bytes());
        stored.push(2);
        stored.extend_from_slice(&compressed);
        rewritten.insert(i, stored);
    }
    layout(&container, &rewritten)
}

/// The set cells of `grid` inside region `r`, grouped by local chunk
/// index: (world position, grid palette index). Cells whose palette index
/// is out of range are skipped.
fn touched_chunks(r: &RegionFile, grid: &BlockGrid) -> Vec<(usize, Vec<(IVec3, u32)>)> {
    let lo = IVec3::new(r.x * 512, i32::MIN, r.z * 512).max(grid.origin);
    let hi = IVec3::new(r.x * 512 + 512, i32::MAX, r.z * 512 + 512).min(grid.origin + grid.size.as_ivec3());
    let mut out: HashMap<usize, Vec<(IVec3, u32)>> = HashMap::new();
    if lo.cmpge(hi).any() {
        return Vec::new();
    }
    let n = grid.palette.len() as u32;
    let (sx, sz) = (grid.size.x as usize, grid.size.z as usize);
    for y in lo.y..hi.y {
        for z in lo.z..hi.z {
            let row = ((y - grid.origin.y) as usize * sz + (z - grid.origin.z) as usize) * sx;
            for x in lo.x..hi.x {
                let c = grid.cells[row + (x - grid.origin.x) as usize];
                if c < n {
                    let i = (x.div_euclid(16) - r.x * 32) as usize + 32 * (z.div_euclid(16) - r.z * 32) as usize;
                    out.entry(i).or_default().push((IVec3::new(x, y, z), c));
                }
            }
        }
    }
    let mut v: Vec<_> = out.into_iter().collect();
    v.sort_unstable_by_key(|(i, _)| *i);
    v
}

/// A new region file: the header, then every chunk in index order, each
/// starting on a sector and zero padded; `rewritten` chunks replace their
/// stored bytes, the rest are copied with their timestamps.
fn layout(c: &Container, rewritten: &HashMap<usize, Vec<u8>>) -> Result<Vec<u8>, MinecraftError> {
    let mut out = vec![0u8; HEADER];
    if c.bytes.len() >= HEADER {
        out[SECTOR..HEADER].copy_from_slice(&c.bytes[SECTOR..HEADER]);
    }
    for i in 0..1024 {
        let stored: &[u8] = match rewritten.get(&i) {
            Some(s) => s,
            None => match c.entry(i) {
                Ok(Some(e)) => &c.bytes[e.start..e.start + e.stored],
                Ok(None) => continue,
                Err(e) => {
                    return Err(MinecraftError::CorruptRegion {
                        x: c.rx,
                        z: c.rz,
                        reason: format!("{e}; it cannot be copied"),
                    });
                }
            },
        };
        let sector = out.len() / SECTOR;
        let sectors = stored.len().div_ceil(SECTOR);
        if sector > 0xFF_FFFF || sectors > MAX_SECTORS {
            return Err(MinecraftError::CorruptRegion {
                x: c.rx,
                z: c.rz,
                reason: "the chunks do not fit the region file's addressing".into(),
            });
        }
        out[4 * i..4 * i + 4].copy_from_slice(&[
            (sector >> 16) as u8,
            (sector >> 8) as u8,
            sector as u8,
            sectors as u8,
        ]);
        out.extend_from_slice(stored);
        out.resize(out.len().next_multiple_of(SECTOR), 0);
    }
    Ok(out)
}

/// Every chunk's stored bytes by local index (tests compare them).
#[cfg(test)]
pub(crate) fn stored_chunks(region: &RegionFile) -> Vec<(usize, Vec<u8>)> {
    let c = Container::new(region).unwrap();
    (0..1024).filter_map(|i| c.entry(i).unwrap().map(|e| (i, c.bytes[e.start..e.start + e.stored].to_vec()))).collect()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::super::nbt;
    use super::*;
    use genform_core::blocks::BlockKind;
    use std::io::Cursor;

    /// A region of the real terrain fixtures (`examples/terrain/<dir>`).
    pub(crate) fn fixture(dir: &str) -> RegionFile {
        let path = format!("{}/../../examples/terrain/{dir}/r.0.0.mca", env!("CARGO_MANIFEST_DIR"));
        RegionFile { x: 0, z: 0, bytes: std::fs::read(path).unwrap() }
    }

    fn id_at(g: &BlockGrid, x: i32, y: i32, z: i32) -> Option<&str> {
        g.get(IVec3::new(x, y, z)).map(|s| s.id())
    }

    /// The decoded NBT of local chunk `i`, through fastnbt.
    fn fastnbt_chunk(bytes: &[u8], i: usize) -> Option<fastnbt::Value> {
        let mut r = fastanvil::Region::from_stream(Cursor::new(bytes)).unwrap();
        r.read_chunk(i % 32, i / 32).unwrap().map(|b| fastnbt::from_bytes(&b).unwrap())
    }

    #[test]
    fn region_names_and_boxes() {
        assert_eq!(region_coords("r.0.0.mca"), Some((0, 0)));
        assert_eq!(region_coords("world/region/r.-3.12.mca"), Some((-3, 12)));
        assert_eq!(region_coords("C:\\w\\r.1.-1.mca"), Some((1, -1)));
        for bad in ["r.0.mca", "r.0.0.0.mca", "r.a.0.mca", "c.0.0.mcc", "r.0.0.mcr", "r.0.0.mca.bak"] {
            assert_eq!(region_coords(bad), None, "{bad}");
        }
        assert_eq!(region_file_name(-1, 2), "r.-1.2.mca");
        assert_eq!(regions_for_box(IVec3::new(0, 0, 0), IVec3::new(512, 1, 512)), vec![(0, 0)]);
        assert_eq!(
            regions_for_box(IVec3::new(-1, 0, 500), IVec3::new(1, 1, 513)),
            vec![(-1, 0), (-1, 1), (0, 0), (0, 1)]
        );
        assert!(regions_for_box(IVec3::ZERO, IVec3::new(5, 0, 5)).is_empty());
    }

    #[test]
    fn reads_known_columns_of_the_fastanvil_fixture() {
        let r = fixture("fastanvil-1.19.4");
        // x from −16 (no such region given) to 256 (chunk 15: unfinished).
        let g = read_terrain(&[r], IVec3::new(-16, 40, 0), IVec3::new(256, 100, 64)).unwrap();
        assert_eq!(g.size, glam::UVec3::new(272, 60, 64));
        // Island column (20, 20): grass at 62 over dirt and stone, air above.
        assert_eq!(id_at(&g, 20, 62, 20), Some("grass_block"));
        assert_eq!(id_at(&g, 20, 63, 20), Some("air"));
        assert!((59..62).all(|y| id_at(&g, 20, y, 20) == Some("dirt")));
        assert_eq!(id_at(&g, 20, 58, 20), Some("stone"));
        // Under an oak at (0, 0): grass at 61, leaves 69..=72.
        assert_eq!(id_at(&g, 0, 61, 0), Some("grass_block"));
        assert!((69..=72).all(|y| id_at(&g, 0, y, 0) == Some("oak_leaves")));
        // Shallow sea at (50, 50): water at 62 over dirt.
        assert_eq!(id_at(&g, 50, 62, 50), Some("water"));
        assert_eq!(g.get(IVec3::new(50, 62, 50)).unwrap().kind(), BlockKind::Liquid);
        assert_eq!(id_at(&g, 50, 61, 50), Some("dirt"));
        // Missing region and unfinished chunk: unset.
        assert_eq!(g.get(IVec3::new(-1, 60, 5)), None);
        assert_eq!(g.get(IVec3::new(240, 60, 5)), None);
        assert_eq!(id_at(&g, 239, 62, 5), Some("water"));
        let unset = g.cells.iter().filter(|&&c| c == BlockGrid::UNSET).count();
        assert_eq!(unset, 2 * 16 * 60 * 64);
    }

    #[test]
    fn agrees_with_fastanvil_on_every_block() {
        use fastanvil::Chunk as _;
        let r = fixture("fastanvil-1.19.4");
        let mut fa = fastanvil::Region::from_stream(Cursor::new(&r.bytes)).unwrap();
        for (cx, cz) in [(0, 0), (3, 7), (14, 14)] {
            let min = IVec3::new(cx * 16, 30, cz * 16);
            let g = read_terrain(std::slice::from_ref(&r), min, min + IVec3::new(16, 70, 16)).unwrap();
            let raw = fa.read_chunk(cx as usize, cz as usize).unwrap().unwrap();
            let chunk: fastanvil::CurrentJavaChunk = fastnbt::from_bytes(&raw).unwrap();
            for (p, c) in g.iter_set() {
                let theirs = chunk.block((p.x - min.x) as usize, p.y as isize, (p.z - min.z) as usize).unwrap();
                let s = &g.palette[c as usize];
                // fastanvil's description leaves out `waterlogged` and `powered`.
                let props: Vec<String> = s
                    .properties
                    .iter()
                    .filter(|(k, _)| k != "waterlogged" && k != "powered")
                    .map(|(k, v)| format!("{k}={v}"))
                    .collect();
                assert_eq!(format!("{}|{}", s.name, props.join(",")), theirs.encoded_description(), "at {p}");
            }
            assert_eq!(g.set_count(), g.volume());
        }
    }

    #[test]
    fn reads_the_prismarine_1_21_fixture() {
        let g = read_terrain(&[fixture("prismarine-1.21.1")], IVec3::new(0, 50, 0), IVec3::new(80, 90, 64)).unwrap();
        // Status `minecraft:full` is recognised: 4×4 full chunks.
        let set_columns = (0..80).filter(|&x| g.get(IVec3::new(x, 60, 0)).is_some()).count();
        assert_eq!(set_columns, 64);
        // Land in the east, water in the west.
        assert_eq!(id_at(&g, 40, 64, 40), Some("grass_block"));
        assert_eq!(id_at(&g, 63, 67, 63), Some("grass_block"));
        assert!((59..=62).all(|y| id_at(&g, 20, y, 20) == Some("water")));
        assert_eq!(id_at(&g, 20, 58, 20), Some("sand"));
        assert_eq!(id_at(&g, 50, 68, 50), Some("short_grass"));
    }

    /// A test structure: a hollow 20×10×20 box with stairs, glass and unset
    /// cells, spanning four chunks.
    fn structure(origin: IVec3) -> BlockGrid {
        let mut g = BlockGrid::new(origin, glam::UVec3::new(20, 10, 20));
        let wall = BlockState::new("stone_bricks");
        let stairs =
            BlockState::parse("oak_stairs[facing=north,half=bottom,shape=straight,waterlogged=false]").unwrap();
        let glass = BlockState::new("glass");
        let air = BlockState::air();
        for p in (0..4000).map(|i| IVec3::new(i % 20, i / 400, (i / 20) % 20)) {
            let edge = p.x == 0 || p.x == 19 || p.z == 0 || p.z == 19;
            let state = match (edge, p.y) {
                (_, 9) => Some(&stairs),
                (true, 4) => Some(&glass),
                (true, _) => Some(&wall),
                (false, 0) => Some(&wall),
                (false, _) if p.x == 10 => None,
                _ => Some(&air).filter(|_| (p.x + p.z) % 3 != 0),
            };
            if let Some(s) = state {
                g.set(origin + p, s);
            }
        }
        g
    }

    #[test]
    fn write_then_read_back() {
        let r = fixture("fastanvil-1.19.4");
        let before = read_terrain(std::slice::from_ref(&r), IVec3::new(0, 60, 0), IVec3::new(48, 80, 48)).unwrap();
        let s = structure(IVec3::new(6, 62, 9));
        let bytes = write_region(&r, &s).unwrap();
        assert_eq!(bytes.len() % SECTOR, 0);
        let new = RegionFile { bytes, ..r.clone() };
        let after =
            read_terrain(std::slice::from_ref(&new), before.origin, before.origin + before.size.as_ivec3()).unwrap();
        for (p, _) in before.iter_set() {
            let want = s.get(p).or(before.get(p));
            assert_eq!(after.get(p), want, "at {p}");
        }
        // Four chunks were touched; every other chunk is stored byte for
        // byte as before, and decodes to the same NBT.
        let (old, new_chunks) = (stored_chunks(&r), stored_chunks(&new));
        assert_eq!(old.len(), new_chunks.len());
        let touched = [0, 1, 32, 33];
        for ((i, a), (j, b)) in old.iter().zip(&new_chunks) {
            assert_eq!(i, j);
            assert_eq!(a == b, !touched.contains(i), "chunk {i}");
        }
        for i in [2, 34, 100, 224] {
            assert_eq!(fastnbt_chunk(&r.bytes, i), fastnbt_chunk(&new.bytes, i));
        }
        // fastanvil reads the new file and its touched chunks, which keep
        // their other tags (heightmaps, structures, …) and are to be relit.
        for i in touched {
            let fastnbt::Value::Compound(a) = fastnbt_chunk(&r.bytes, i).unwrap() else { panic!() };
            let fastnbt::Value::Compound(b) = fastnbt_chunk(&new.bytes, i).unwrap() else { panic!() };
            let mut keys_a: Vec<_> = a.keys().filter(|k| *k != "isLightOn").collect();
            let mut keys_b: Vec<_> = b.keys().filter(|k| *k != "isLightOn").collect();
            keys_a.sort();
            keys_b.sort();
            assert_eq!(keys_a, keys_b);
            assert_eq!(a["Heightmaps"], b["Heightmaps"]);
            assert_eq!(b["isLightOn"], fastnbt::Value::Byte(0));
            let _: fastanvil::CurrentJavaChunk = fastnbt::from_bytes(&fastnbt::to_bytes(&b).unwrap()).unwrap();
        }
        // Writing the same blocks again changes nothing more.
        assert_eq!(write_region(&new, &s).unwrap(), new.bytes);
    }

    #[test]
    fn a_filled_section_collapses_to_one_palette_entry() {
        let r = fixture("prismarine-1.21.1");
        // Section y = 6 of chunk (2, 1) is all air; fill it with stone.
        let mut g = BlockGrid::new(IVec3::new(32, 96, 16), glam::UVec3::splat(16));
        let stone = g.intern(&BlockState::new("stone"));
        g.cells.fill(stone);
        let bytes = write_region(&r, &g).unwrap();
        let c =
            Container::new(&RegionFile { bytes: bytes.clone(), ..r.clone() }).unwrap().chunk(2 + 32).unwrap().unwrap();
        let sections = c.root.get("sections").and_then(nbt::Tag::as_list).unwrap();
        let s6 = sections.iter().find(|s| s.get("Y").and_then(nbt::Tag::as_i64) == Some(6)).unwrap();
        let states = s6.get("block_states").unwrap();
        assert_eq!(states.get("palette").and_then(nbt::Tag::as_list).unwrap().len(), 1);
        assert!(states.get("data").is_none());
        // Now one block of dirt in it: two entries at 4 bits, 256 longs.
        let mut one = BlockGrid::new(IVec3::new(40, 100, 20), glam::UVec3::ONE);
        one.set(IVec3::new(40, 100, 20), &BlockState::new("dirt"));
        let again = write_region(&RegionFile { bytes, ..r.clone() }, &one).unwrap();
        let c = Container::new(&RegionFile { bytes: again, ..r }).unwrap().chunk(2 + 32).unwrap().unwrap();
        let sections = c.root.get("sections").and_then(nbt::Tag::as_list).unwrap();
        let s6 = sections.iter().find(|s| s.get("Y").and_then(nbt::Tag::as_i64) == Some(6)).unwrap();
        let Some(nbt::Tag::LongArray(data)) = s6.get("block_states").and_then(|b| b.get("data")) else { panic!() };
        assert_eq!(data.len(), 256);
        // Block (8, 4, 4) of the section: index 4·256 + 4·16 + 8 = 1096 →
        // long 68, nibble 8 (dirt was added second: entry 1).
        assert_eq!((data[68] as u64 >> 32) & 0xF, 1);
        assert_eq!(data.iter().map(|l| l.count_ones()).sum::<u32>(), 1);
    }

    #[test]
    fn block_entities_at_changed_blocks_are_removed() {
        let r = fixture("fastanvil-1.19.4");
        let c = Container::new(&r).unwrap();
        // The first full chunk with a block entity.
        let (i, pos) = (0..1024)
            .find_map(|i| {
                let ch = c.chunk(i).ok()??;
                let e = ch.is_full().then(|| ch.root.get("block_entities")?.as_list()?.first().cloned())??;
                let k = |n| e.get(n).and_then(nbt::Tag::as_i64).unwrap() as i32;
                Some((i, IVec3::new(k("x"), k("y"), k("z"))))
            })
            .unwrap();
        let count = |bytes: &[u8]| {
            let region = RegionFile { bytes: bytes.to_vec(), ..r.clone() };
            let ch = Container::new(&region).unwrap().chunk(i).unwrap().unwrap();
            ch.root.get("block_entities").and_then(nbt::Tag::as_list).map_or(0, <[nbt::Tag]>::len)
        };
        let mut g = BlockGrid::new(pos, glam::UVec3::ONE);
        g.set(pos, &BlockState::new("stone"));
        let bytes = write_region(&r, &g).unwrap();
        assert_eq!(count(&bytes), count(&r.bytes) - 1);
    }

    #[test]
    fn refuses_what_it_cannot_write() {
        let r = fixture("fastanvil-1.19.4");
        let one = |p: IVec3| {
            let mut g = BlockGrid::new(p, glam::UVec3::ONE);
            g.set(p, &BlockState::new("stone"));
            g
        };
        // Chunk (20, 20) stopped at `structure_starts`; (31, 31) is absent.
        let e = write_region(&r, &one(IVec3::new(20 * 16, 70, 20 * 16))).unwrap_err();
        assert!(matches!(e, MinecraftError::ChunkNotGenerated { x: 20, z: 20, .. }), "{e}");
        assert!(e.to_string().contains("structure_starts"), "{e}");
        let e = write_region(&r, &one(IVec3::new(511, 70, 511))).unwrap_err();
        assert!(e.to_string().contains("chunk (31, 31)") && e.to_string().contains("missing"), "{e}");
        let e = write_region(&r, &one(IVec3::new(5, 320, 5))).unwrap_err();
        assert_eq!(e, MinecraftError::OutsideWorldHeight { x: 0, z: 0, y: 320, min: -64, max: 319 });
        // Cells outside the region and unset cells are not written at all.
        assert_eq!(write_region(&r, &one(IVec3::new(600, 70, 5))).unwrap(), layout_of(&r));
        assert_eq!(write_region(&r, &BlockGrid::new(IVec3::ZERO, glam::UVec3::splat(40))).unwrap(), layout_of(&r));
        // A wrongly named region file is caught by the chunks' own positions.
        let moved = RegionFile { x: 1, ..r.clone() };
        let e = read_terrain(&[moved], IVec3::new(512, 60, 0), IVec3::new(520, 61, 8)).unwrap_err();
        assert!(e.to_string().contains("says it is chunk (0, 0)"), "{e}");
        let e = read_terrain(std::slice::from_ref(&r), IVec3::new(0, 0, 0), IVec3::new(100_000, 384, 100_000));
        assert!(matches!(e, Err(MinecraftError::BoxTooLarge { .. })));
        let e = read_terrain(std::slice::from_ref(&r), IVec3::MIN, IVec3::MAX).unwrap_err();
        assert_eq!(e, MinecraftError::BoxTooLarge { cells: u64::MAX });
        let mut bad = one(IVec3::new(5, 70, 5));
        bad.cells.push(0);
        let e = write_region(&r, &bad).unwrap_err();
        assert!(e.to_string().contains("has 2 cells"), "{e}");
        assert!(matches!(crate::minecraft::write_vox(&bad), Err(MinecraftError::InconsistentGrid { .. })));
    }

    /// `r` laid out anew with nothing changed.
    fn layout_of(r: &RegionFile) -> Vec<u8> {
        layout(&Container::new(r).unwrap(), &HashMap::new()).unwrap()
    }

    /// A one-chunk region holding `nbt` (zlib) at local chunk 0.
    fn region_with(nbt_bytes: &[u8]) -> RegionFile {
        let mut z = Vec::new();
        ZlibEncoder::new(nbt_bytes, Compression::fast()).read_to_end(&mut z).unwrap();
        let mut stored = (z.len() as u32 + 1).to_be_bytes().to_vec();
        stored.push(2);
        stored.extend_from_slice(&z);
        let empty = RegionFile { x: 0, z: 0, bytes: Vec::new() };
        let c = Container::new(&empty).unwrap();
        RegionFile { x: 0, z: 0, bytes: layout(&c, &HashMap::from([(0, stored)])).unwrap() }
    }

    #[test]
    fn old_chunks_are_refused_by_version() {
        let old = nbt::Tag::Compound(vec![
            (b"DataVersion".to_vec(), nbt::Tag::Int(2586)),
            (b"Level".to_vec(), nbt::Tag::Compound(vec![(b"xPos".to_vec(), nbt::Tag::Int(0))])),
        ]);
        let r = region_with(&nbt::encode(b"", &old));
        let e = read_terrain(&[r], IVec3::ZERO, IVec3::ONE).unwrap_err();
        assert_eq!(e, MinecraftError::UnsupportedDataVersion { x: 0, z: 0, version: 2586 });
        assert!(e.to_string().contains("older than Minecraft 1.18"));
        // An empty file is an empty region; a short one is corrupt.
        let empty = RegionFile { x: 0, z: 0, bytes: Vec::new() };
        assert_eq!(read_terrain(&[empty], IVec3::ZERO, IVec3::ONE).unwrap().set_count(), 0);
        let short = RegionFile { x: 2, z: 3, bytes: vec![0; 100] };
        let e = read_terrain(&[short], IVec3::ZERO, IVec3::ONE).unwrap_err();
        assert!(e.to_string().starts_with("region file r.2.3.mca is corrupt"), "{e}");
    }

    #[test]
    fn garbled_regions_are_errors_not_panics() {
        let r = fixture("prismarine-1.21.1");
        // Only the first chunk's sectors, header included, to keep it fast.
        let first = Container::new(&r).unwrap().entry(0).unwrap().unwrap();
        let mut base = r.bytes[..first.start + first.stored].to_vec();
        base.resize(base.len().next_multiple_of(SECTOR), 0);
        let g = structure(IVec3::new(2, 62, 2));
        let (lo, hi) = (IVec3::new(0, 40, 0), IVec3::new(16, 80, 16));
        let mut rng = 99u64;
        let mut next = || {
            rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (rng >> 33) as usize
        };
        // Every compression scheme byte, on zlib data: errors, no panics.
        for scheme in [0, 1, 3, 4, 5, 0x82] {
            let mut b = base.clone();
            b[first.start + 4] = scheme;
            let region = RegionFile { x: 0, z: 0, bytes: b };
            let res = read_terrain(std::slice::from_ref(&region), lo, hi);
            assert!(res.is_err(), "scheme {scheme}");
            if scheme == 0x82 {
                assert!(res.unwrap_err().to_string().contains(".mcc"));
            }
        }
        for round in 0..300 {
            let mut b = base.clone();
            match round % 3 {
                0 => b.truncate(next() % b.len()),
                1 => {
                    // The header entry or chunk header of chunk 0.
                    let i = [0, 1, 2, 3, first.start, first.start + 3, first.start + 4][next() % 7];
                    b[i] = next() as u8;
                }
                _ => {
                    for _ in 0..4 {
                        let i = first.start + 5 + next() % (first.stored - 5);
                        b[i] = next() as u8;
                    }
                }
            }
            let region = RegionFile { x: 0, z: 0, bytes: b };
            let _ = read_terrain(std::slice::from_ref(&region), lo, hi);
            let _ = write_region(&region, &g);
        }
    }
}
