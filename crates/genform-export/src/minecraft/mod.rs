//! Minecraft Java Edition data: block grids to and from region files,
//! schematics (Sponge `.schem` v2/v3, Litematica `.litematic`), MagicaVoxel
//! `.vox`, and greedy meshes of block grids for the 3D formats.
//!
//! Everything here works on bytes the caller read or will write; nothing
//! touches files. Grids are [`BlockGrid`]s: cell (x, y, z) is the block at
//! world position origin + (x, y, z), or unset.
//!
//! - [`read_terrain`] / [`write_region`]: 1.18+ region files (`r.X.Z.mca`);
//!   [`region_coords`], [`region_file_name`] and [`regions_for_box`] tell
//!   which files a box needs.
//! - [`write_schem`] / [`read_schem`], [`write_litematic`] /
//!   [`read_litematic`], [`write_vox`].
//! - [`mesh_blocks`]: one mesh per block state, coplanar faces merged.

mod chunk;
mod colors;
mod litematic;
mod mesh;
mod nbt;
mod nbt_file;
mod packing;
mod region;
mod schem;
mod tiles;
mod vox;

use genform_core::blocks::{BlockGrid, BlockState};
use glam::{IVec3, UVec3};

pub use colors::block_color;
pub use litematic::{read_litematic, write_litematic};
pub use mesh::{BlockMesh, mesh_blocks};
pub(crate) use mesh::{block_meshes, for_each_block_triangle, has_drawn_blocks};
pub use region::{RegionFile, read_terrain, region_coords, region_file_name, regions_for_box, write_region};
pub use schem::{SchemVersion, read_schem, write_schem};
pub(crate) use tiles::{flat_grid, render_tiles};
pub use vox::{MAX_VOX_COLORS, write_vox};

/// The first DataVersion with the 1.18 chunk layout (`sections` at the
/// root, paletted `block_states`): Minecraft 1.18.
pub const MIN_CHUNK_DATA_VERSION: i32 = 2860;

/// DataVersion of Minecraft 1.21.1, the default for written schematics.
pub const DATA_VERSION_1_21_1: i32 = 3955;

/// The first DataVersion (1.20.5) whose Litematica files are format 7.
pub const LITEMATIC_V7_DATA_VERSION: i32 = 3837;

/// The largest box [`read_terrain`] fills, in cells (2²⁷: 512 MiB of `u32`
/// cells).
pub const MAX_TERRAIN_CELLS: u64 = 1 << 27;

/// What went wrong reading or writing Minecraft data.
#[derive(thiserror::Error, Debug, Clone, PartialEq, Eq)]
pub enum MinecraftError {
    /// The region file as a whole cannot be used.
    #[error("region file r.{x}.{z}.mca is corrupt: {reason}")]
    CorruptRegion {
        /// Region x.
        x: i32,
        /// Region z.
        z: i32,
        /// What is wrong.
        reason: String,
    },
    /// One chunk's entry or data cannot be read.
    #[error("chunk ({x}, {z}) cannot be read: {reason}")]
    ChunkUnreadable {
        /// Chunk x (world chunk coordinates, blocks / 16).
        x: i32,
        /// Chunk z.
        z: i32,
        /// What is wrong.
        reason: String,
    },
    /// The chunk predates the 1.18 format.
    #[error(
        "chunk ({x}, {z}) has DataVersion {version}, older than Minecraft 1.18 ({min}); \
         only 1.18+ chunks can be read or written (open and save the world in 1.18 or later first)",
        min = MIN_CHUNK_DATA_VERSION
    )]
    UnsupportedDataVersion {
        /// Chunk x.
        x: i32,
        /// Chunk z.
        z: i32,
        /// Its DataVersion.
        version: i32,
    },
    /// Blocks were to be written into a chunk the region does not hold, or
    /// one whose generation is not finished.
    #[error(
        "cannot write into chunk ({x}, {z}): {reason}; load that area in Minecraft once so the chunk is fully generated"
    )]
    ChunkNotGenerated {
        /// Chunk x.
        x: i32,
        /// Chunk z.
        z: i32,
        /// Missing, or its status.
        reason: String,
    },
    /// Blocks were to be written above or below the chunk's sections.
    #[error("cannot write block y = {y} into chunk ({x}, {z}): its sections hold y {min}..={max}")]
    OutsideWorldHeight {
        /// Chunk x.
        x: i32,
        /// Chunk z.
        z: i32,
        /// The block's y.
        y: i32,
        /// Lowest block y the chunk holds.
        min: i32,
        /// Highest block y the chunk holds.
        max: i32,
    },
    /// A rewritten chunk no longer fits a region entry (255 sectors, 1 MiB).
    #[error("chunk ({x}, {z}) compresses to {bytes} bytes, more than a region entry holds (1044475)")]
    ChunkTooLarge {
        /// Chunk x.
        x: i32,
        /// Chunk z.
        z: i32,
        /// Its compressed size.
        bytes: usize,
    },
    /// The box to read is larger than [`MAX_TERRAIN_CELLS`].
    #[error("a box of {cells} cells is too large to read (at most {max})", max = MAX_TERRAIN_CELLS)]
    BoxTooLarge {
        /// Cells asked for.
        cells: u64,
    },
    /// A file is not the format it should be, or is damaged.
    #[error("the {format} file is malformed: {reason}")]
    Malformed {
        /// `schem`, `litematic`, ….
        format: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// A schematic's version is not one this reader knows.
    #[error("unsupported {format} version {version} (supported: {supported})")]
    UnsupportedVersion {
        /// `schem` or `litematic`.
        format: &'static str,
        /// The version found.
        version: i32,
        /// The versions that are read.
        supported: &'static str,
    },
    /// The grid is too large for the format.
    #[error("a {}×{}×{} grid is too large for {format}: {limit}", size.x, size.y, size.z)]
    TooLarge {
        /// `schem`, `litematic`, `vox`.
        format: &'static str,
        /// The grid size.
        size: UVec3,
        /// The format's limit, in words.
        limit: &'static str,
    },
    /// There are no blocks to write.
    #[error("there are no blocks to write")]
    Empty,
    /// A grid's cell count does not match its size.
    #[error("the grid has {cells} cells, but its size {}×{}×{} needs {}", size.x, size.y, size.z, u64::from(size.x) * u64::from(size.y) * u64::from(size.z))]
    InconsistentGrid {
        /// `cells.len()`.
        cells: usize,
        /// The grid's size.
        size: UVec3,
    },
}

/// Writers index cells by the grid's size: refuse a grid whose fields
/// disagree (they are public, so a caller can build one).
fn check_grid(grid: &BlockGrid) -> Result<(), MinecraftError> {
    let s = grid.size;
    if grid.cells.len() as u64 != u64::from(s.x) * u64::from(s.y) * u64::from(s.z) {
        return Err(MinecraftError::InconsistentGrid { cells: grid.cells.len(), size: s });
    }
    Ok(())
}

/// A `format` error with `reason`.
fn malformed(format: &'static str, reason: impl Into<String>) -> MinecraftError {
    MinecraftError::Malformed { format, reason: reason.into() }
}

/// One grid covering every grid of `grids` (their bounding box); where grids
/// overlap, a later grid's set cells win. `None` when `grids` is empty.
pub fn merge_grids(grids: &[BlockGrid]) -> Option<BlockGrid> {
    let first = grids.first()?;
    if grids.len() == 1 {
        return Some(first.clone());
    }
    let lo = grids.iter().map(|g| g.origin).reduce(IVec3::min)?;
    let hi = grids.iter().map(|g| g.origin + g.size.as_ivec3()).reduce(IVec3::max)?;
    let mut out = BlockGrid::new(lo, (hi - lo).max(IVec3::ZERO).as_uvec3());
    for g in grids {
        let map: Vec<u32> = g.palette.iter().map(|s| out.intern(s)).collect();
        let (sx, sz) = (g.size.x as usize, g.size.z as usize);
        let d = (g.origin - lo).as_uvec3();
        for y in 0..g.size.y as usize {
            for z in 0..sz {
                let src = (y * sz + z) * sx;
                let dst =
                    ((y + d.y as usize) * out.size.z as usize + z + d.z as usize) * out.size.x as usize + d.x as usize;
                for x in 0..sx {
                    let c = g.cells[src + x];
                    if let Some(&m) = map.get(c as usize) {
                        out.cells[dst + x] = m;
                    }
                }
            }
        }
    }
    Some(out)
}

/// The grid's palette with [`BlockGrid::UNSET`] and out-of-range cells
/// mapped to air: the dense palette the schematic formats need (air first
/// when `air_first`), and the cell → palette map. Unused palette entries
/// are dropped, so every entry written is used.
fn dense_palette(grid: &BlockGrid, air_first: bool) -> (Vec<BlockState>, Vec<u32>) {
    let mut used = vec![false; grid.palette.len()];
    let mut any_air = false;
    for &c in &grid.cells {
        match used.get_mut(c as usize) {
            Some(u) => *u = true,
            None => any_air = true,
        }
    }
    let air = BlockState::air();
    let mut palette = Vec::new();
    if air_first {
        palette.push(air.clone());
    }
    let mut map = vec![u32::MAX; grid.palette.len()];
    for (i, s) in grid.palette.iter().enumerate() {
        if used[i] {
            map[i] = match palette.iter().position(|p| p == s) {
                Some(k) => k as u32,
                None => {
                    palette.push(s.clone());
                    (palette.len() - 1) as u32
                }
            };
        }
    }
    let air_index = match palette.iter().position(|p| *p == air) {
        Some(k) => k as u32,
        None if any_air => {
            palette.push(air);
            (palette.len() - 1) as u32
        }
        None => 0,
    };
    let cells = grid.cells.iter().map(|&c| map.get(c as usize).copied().unwrap_or(air_index)).collect();
    (palette, cells)
}

#[cfg(test)]
pub(crate) mod test_grids {
    use super::*;

    /// A random grid of `size` with a few states (some with properties)
    /// and about a fifth of the cells unset.
    pub fn random(size: UVec3, seed: u64, states: usize) -> BlockGrid {
        let names = [
            "stone",
            "oak_stairs[facing=east,half=bottom]",
            "oak_stairs[facing=west,half=top,waterlogged=true]",
            "glass",
            "water[level=0]",
            "air",
            "red_wool",
            "oak_log[axis=y]",
            "torch",
            "redstone_wire[east=side,north=none,power=3,south=up,west=none]",
        ];
        let mut g = BlockGrid::new(IVec3::new(-3, 60, 17), size);
        let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        let all: Vec<BlockState> = (0..states)
            .map(|i| match names.get(i) {
                Some(n) => BlockState::parse(n).expect("valid test block"),
                None => BlockState::parse(&format!("test:block_{i}[n={i}]")).expect("valid test block"),
            })
            .collect();
        for i in 0..g.cells.len() {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let r = (s >> 11) as usize;
            g.cells[i] = if r.is_multiple_of(5) { BlockGrid::UNSET } else { g.intern(&all[r % states]) };
        }
        g
    }

    /// `g` with unset cells as air, palette order and unused entries
    /// ignored: a comparable list of strings per cell.
    pub fn as_strings(g: &BlockGrid) -> Vec<String> {
        g.cells.iter().map(|&c| g.palette.get(c as usize).map_or("minecraft:air".into(), |s| s.to_string())).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merging_grids_covers_both_and_later_wins() {
        let mut a = BlockGrid::new(IVec3::new(0, 0, 0), UVec3::new(2, 1, 1));
        a.set(IVec3::new(0, 0, 0), &BlockState::new("stone"));
        a.set(IVec3::new(1, 0, 0), &BlockState::new("dirt"));
        let mut b = BlockGrid::new(IVec3::new(1, -1, 2), UVec3::new(1, 2, 1));
        b.set(IVec3::new(1, 0, 2), &BlockState::new("glass"));
        let mut c = BlockGrid::new(IVec3::new(1, 0, 0), UVec3::new(1, 1, 1));
        c.set(IVec3::new(1, 0, 0), &BlockState::new("gold_block"));
        let m = merge_grids(&[a, b, c]).unwrap();
        assert_eq!((m.origin, m.size), (IVec3::new(0, -1, 0), UVec3::new(2, 2, 3)));
        assert_eq!(m.get(IVec3::new(0, 0, 0)).unwrap().id(), "stone");
        assert_eq!(m.get(IVec3::new(1, 0, 0)).unwrap().id(), "gold_block");
        assert_eq!(m.get(IVec3::new(1, 0, 2)).unwrap().id(), "glass");
        assert_eq!(m.get(IVec3::new(1, -1, 2)), None);
        assert_eq!(m.set_count(), 3);
        assert!(merge_grids(&[]).is_none());
    }

    #[test]
    fn dense_palettes_put_air_first_and_drop_unused() {
        let mut g = BlockGrid::new(IVec3::ZERO, UVec3::new(3, 1, 1));
        g.intern(&BlockState::new("unused"));
        g.set(IVec3::new(1, 0, 0), &BlockState::new("stone"));
        let (p, cells) = dense_palette(&g, true);
        assert_eq!(p.iter().map(|s| s.id()).collect::<Vec<_>>(), ["air", "stone"]);
        assert_eq!(cells, [0, 1, 0]);
        let (p, cells) = dense_palette(&g, false);
        assert_eq!(p.iter().map(|s| s.id()).collect::<Vec<_>>(), ["stone", "air"]);
        assert_eq!(cells, [1, 0, 1]);
    }
}
