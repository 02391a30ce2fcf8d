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
//!
//! [`BlockGrid`]: genform_core::blocks::BlockGrid

mod chunk;
mod colors;
mod constants;
mod error;
mod grid;
mod litematic;
mod mesh;
mod nbt;
mod nbt_file;
mod packing;
mod region;
mod schem;
mod tiles;
mod vox;

pub use colors::{block_color, known_block_color};
pub use constants::{DATA_VERSION_1_21_1, LITEMATIC_V7_DATA_VERSION, MAX_TERRAIN_CELLS, MIN_CHUNK_DATA_VERSION};
pub use error::MinecraftError;
pub use grid::merge_grids;
pub use litematic::{read_litematic, write_litematic};
pub use mesh::{BlockMesh, mesh_blocks};
pub(crate) use mesh::{block_meshes, for_each_block_triangle, has_drawn_blocks, shaped_block_meshes};
pub use region::{RegionFile, read_terrain, region_coords, region_file_name, regions_for_box, write_region};
pub use schem::{SchemVersion, read_schem, write_schem};
pub(crate) use tiles::{flat_grid, render_tiles};
pub use vox::{MAX_VOX_COLORS, write_vox};

#[cfg(test)]
pub(crate) mod test_grids {
    use genform_core::blocks::{BlockGrid, BlockState};
    use glam::{IVec3, UVec3};

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
