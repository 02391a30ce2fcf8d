//! Block structures ([`Scene::blocks`]) as solids.
//!
//! A block cell `(x, y, z)` is the unit box `[x, x+1) × [y, y+1) × [z, z+1)`
//! (half-open like the primitives' predicates, so neighbouring cells never
//! both hold a voxel centre on their shared face). Every set cell whose
//! block is not air (liquids and passable blocks included) is solid;
//! unset cells and air are empty.
//!
//! Cell boxes are axis-aligned on the integer grid, so the voxels a box
//! holds are decided exactly, axis by axis, by comparing lattice centres
//! with the integer bounds ([`Lattice::first_at_or_after`]); no unit-frame
//! map and no rounding are involved. The fast path covers the solid cells
//! of a grid with few disjoint boxes (greedily: a run along x, grown along
//! z, then along y) and holds each box's index range with the separable
//! box writer. The oracle tests every cell against every nearby centre.
//!
//! Each [`BlockGrid`] counts as one instance: its cells never overlap one
//! another, but voxels it shares with instances or other grids are overlap
//! voxels, and its held voxels outside the grid add to `outside`.

use super::out::{Out, Tally};
use super::scratch::VolumeScratch;
use super::spans::lattice_box;
use crate::grid::Lattice;
use genform_core::blocks::{BlockGrid, BlockKind};
use genform_core::scene::Scene;

/// Marks in `open` which cells of `g` are solid (non-air blocks); false
/// when the grid's cell count does not match its size (nothing is solid).
fn solid_cells(g: &BlockGrid, open: &mut Vec<bool>) -> bool {
    open.clear();
    let n = g.size.x as u128 * g.size.y as u128 * g.size.z as u128;
    if n != g.cells.len() as u128 {
        return false;
    }
    let solid: Vec<bool> = g.palette.iter().map(|b| b.kind() != BlockKind::Air).collect();
    open.extend(g.cells.iter().map(|&c| solid.get(c as usize).copied().unwrap_or(false)));
    true
}

/// Calls `f(min, max)` (world cell coordinates, `max` exclusive) for
/// disjoint boxes covering exactly the solid cells of `g`. `open` is
/// working memory.
pub(super) fn for_each_box(g: &BlockGrid, open: &mut Vec<bool>, mut f: impl FnMut([i64; 3], [i64; 3])) {
    if !solid_cells(g, open) {
        return;
    }
    let [sx, sy, sz] = [g.size.x, g.size.y, g.size.z].map(|s| s as usize);
    let at = |x: usize, y: usize, z: usize| (y * sz + z) * sx + x;
    let o = [g.origin.x, g.origin.y, g.origin.z].map(i64::from);
    for y in 0..sy {
        for z in 0..sz {
            let mut x = 0;
            while x < sx {
                if !open[at(x, y, z)] {
                    x += 1;
                    continue;
                }
                let row = at(0, y, z);
                let x1 = x + open[row + x..row + sx].iter().take_while(|&&c| c).count();
                let full = |open: &[bool], y: usize, z: usize| open[at(x, y, z)..at(x1, y, z)].iter().all(|&c| c);
                let mut z1 = z + 1;
                while z1 < sz && full(open, y, z1) {
                    z1 += 1;
                }
                let mut y1 = y + 1;
                while y1 < sy && (z..z1).all(|zz| full(open, y1, zz)) {
                    y1 += 1;
                }
                for yy in y..y1 {
                    for zz in z..z1 {
                        open[at(x, yy, zz)..at(x1, yy, zz)].fill(false);
                    }
                }
                let (min, max) = ([x, y, z], [x1, y1, z1]);
                f(std::array::from_fn(|a| o[a] + min[a] as i64), std::array::from_fn(|a| o[a] + max[a] as i64));
                x = x1;
            }
        }
    }
}

/// The lattice index range along lattice axis `l` whose centres lie in
/// `[a, b)` (possibly empty: `lo > hi`).
fn held_range(lat: &Lattice, l: usize, a: i64, b: i64) -> (i64, i64) {
    (lat.first_at_or_after(l, a as f64), lat.first_at_or_after(l, b as f64) - 1)
}

/// Holds the solid cells of every block grid of `scene` in `s`, one
/// instance per grid, counting those set in `target` as
/// [`super::rasterize`] does.
pub(super) fn rasterize_blocks(lat: &Lattice, scene: &Scene, s: &mut VolumeScratch, target: &[u64]) {
    let mut open = s.take_cells();
    for g in &scene.blocks {
        let mut tally = Tally::default();
        let mut out = Out { s, tally: &mut tally, target, record: None };
        for_each_box(g, &mut open, |min, max| {
            let r = [0, 1, 2].map(|l| held_range(lat, l, min[lat.axes[l]], max[lat.axes[l]]));
            lattice_box(lat, r[0], r[1], r[2], &mut out);
        });
        s.outside = s.outside.saturating_add(tally.outside);
    }
    s.put_cells(open);
}

/// The oracle's version: every solid cell against every lattice centre
/// near it, with `hold(i, j, k)` called for each held lattice voxel
/// (lattice order).
#[cfg(any(test, feature = "test-support"))]
pub(super) fn oracle_cells(lat: &Lattice, g: &BlockGrid, mut hold: impl FnMut(i64, i64, i64)) {
    let mut open = Vec::new();
    if !solid_cells(g, &mut open) {
        return;
    }
    for (p, _) in g.iter_set() {
        let Some(i) = g.index(p) else { continue };
        if !open[i] {
            continue;
        }
        let min = [p.x, p.y, p.z].map(i64::from);
        // Lattice order: bounds along each lattice axis.
        let lo = [0, 1, 2].map(|l| min[lat.axes[l]]);
        let r = [0, 1, 2].map(|l| lat.index_range(l, lo[l] as f64, (lo[l] + 1) as f64));
        let inside = |l: usize, i: i64| {
            let c = f64::from(lat.centre(l, i));
            c >= lo[l] as f64 && c < (lo[l] + 1) as f64
        };
        for k in (r[2].0..=r[2].1).filter(|&k| inside(2, k)) {
            for j in (r[1].0..=r[1].1).filter(|&j| inside(1, j)) {
                for i in (r[0].0..=r[0].1).filter(|&i| inside(0, i)) {
                    hold(i, j, k);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_core::blocks::BlockState;
    use glam::{IVec3, UVec3};

    fn grid(origin: IVec3, size: UVec3, f: impl Fn(i32, i32, i32) -> Option<&'static str>) -> BlockGrid {
        let mut g = BlockGrid::new(origin, size);
        for x in 0..size.x as i32 {
            for y in 0..size.y as i32 {
                for z in 0..size.z as i32 {
                    if let Some(id) = f(x, y, z) {
                        g.set(origin + IVec3::new(x, y, z), &BlockState::new(id));
                    }
                }
            }
        }
        g
    }

    /// The boxes cover every solid cell once and nothing else.
    fn check_cover(g: &BlockGrid) -> usize {
        let mut count = vec![0u8; g.volume()];
        let mut boxes = 0;
        for_each_box(g, &mut Vec::new(), |min, max| {
            boxes += 1;
            for x in min[0]..max[0] {
                for y in min[1]..max[1] {
                    for z in min[2]..max[2] {
                        let i = g.index(IVec3::new(x as i32, y as i32, z as i32)).unwrap();
                        count[i] += 1;
                    }
                }
            }
        });
        for (i, &c) in g.cells.iter().enumerate() {
            let solid = g.palette.get(c as usize).is_some_and(|b| b.kind() != BlockKind::Air);
            assert_eq!(count[i], u8::from(solid), "cell {i}");
        }
        boxes
    }

    #[test]
    fn boxes_cover_the_solid_cells_exactly() {
        let full = grid(IVec3::new(-3, 2, 5), UVec3::new(4, 3, 5), |_, _, _| Some("stone"));
        assert_eq!(check_cover(&full), 1, "a full grid is one box");
        // A hollow shell with air inside, unset cells and a water column.
        let shell = grid(IVec3::ZERO, UVec3::new(6, 5, 4), |x, y, z| {
            let edge = x == 0 || x == 5 || y == 0 || y == 4 || z == 0 || z == 3;
            match (edge, x, z) {
                (true, _, _) => Some("stone_bricks"),
                (false, 2, 1) => Some("water"),
                (false, 3, _) => None,
                _ => Some("air"),
            }
        });
        let n = check_cover(&shell);
        assert!(n < 20, "{n} boxes");
        // A checkerboard: one box per cell.
        let checker = grid(IVec3::ZERO, UVec3::new(5, 4, 3), |x, y, z| ((x + y + z) % 2 == 0).then_some("glass"));
        assert_eq!(check_cover(&checker), 30);
    }

    #[test]
    fn malformed_grids_hold_nothing() {
        let mut g = grid(IVec3::ZERO, UVec3::new(2, 2, 2), |_, _, _| Some("stone"));
        g.cells.pop();
        let mut n = 0;
        for_each_box(&g, &mut Vec::new(), |_, _| n += 1);
        assert_eq!(n, 0);
        // A palette index past the palette is no block.
        let mut g = grid(IVec3::ZERO, UVec3::new(2, 1, 1), |_, _, _| Some("stone"));
        g.cells[1] = 7;
        let mut boxes = Vec::new();
        for_each_box(&g, &mut Vec::new(), |min, max| boxes.push((min, max)));
        assert_eq!(boxes, vec![([0, 0, 0], [1, 1, 1])]);
    }
}
