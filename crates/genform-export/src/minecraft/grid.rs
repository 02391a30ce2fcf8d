//! Block-grid helpers the writers share: [`check_grid`] refuses an
//! inconsistent grid, [`merge_grids`] joins several grids into one, and
//! [`dense_palette`] builds the palette the schematic formats write.

use super::error::MinecraftError;
use genform_core::blocks::{BlockGrid, BlockState};
use glam::IVec3;

/// Writers index cells by the grid's size: refuse a grid whose fields
/// disagree (they are public, so a caller can build one).
pub(super) fn check_grid(grid: &BlockGrid) -> Result<(), MinecraftError> {
    let s = grid.size;
    if grid.cells.len() as u64 != u64::from(s.x) * u64::from(s.y) * u64::from(s.z) {
        return Err(MinecraftError::InconsistentGrid { cells: grid.cells.len(), size: s });
    }
    Ok(())
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
pub(super) fn dense_palette(grid: &BlockGrid, air_first: bool) -> (Vec<BlockState>, Vec<u32>) {
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
mod tests {
    use super::*;
    use glam::UVec3;

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
