//! `site foundation = B, yard = N;`: a building written for an empty box,
//! set on real ground. The box reaches from below the ground to above it;
//! before the derivation the site finds the floor, and after it lays the
//! foundation and clears the plot, so that the building neither floats nor
//! sinks into a slope:
//!
//! - **floor**: one above the median of the columns' top ground (a solid
//!   block that is not a tree's, or water — a floor never goes under
//!   water), so about half the footprint was lower and half higher; caves
//!   under the ground do not count;
//! - **plot**: the box from the floor up, less a yard of `N` columns on
//!   every side; the axiom derives in it (its `OFFSET_*` and `WORLD_*`
//!   count from the plot, so a grammar written for an empty box reads the
//!   same numbers);
//! - **foundation**: under the floor, each column of the footprint is
//!   filled with the foundation block down to its ground (through air,
//!   water, plants, snow and trees; a cave under the ground stays), so
//!   every column stands on the ground; the yard is paved with it on the
//!   floor layer where it holds no ground;
//! - **clearing**: above the floor, the yard and the cells of the plot the
//!   grammar leaves as they are (`skip`) become air where the world held a
//!   block: terrain higher than the floor is cut back, so doors open onto
//!   the yard and no hill stands in a room.
//!
//! Without a world the site does nothing: the grammar derives in the whole
//! box as before, standing on the box's floor.

use crate::grammar::Site;
use genform_core::{BlockGrid, BlockKind, BlockState};
use glam::IVec3;

/// Where a building goes in its box, found from the world.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Plot {
    /// World y of the floor layer.
    pub floor: i32,
    /// The box the axiom derives in.
    pub min: IVec3,
    pub size: IVec3,
}

/// A tree's block: cut trees are not ground.
fn tree(b: &BlockState) -> bool {
    let id = b.id();
    ["_log", "_wood", "_leaves", "_mushroom_block"].iter().any(|s| id.ends_with(s))
        || matches!(id, "mushroom_stem" | "mangrove_roots" | "bee_nest")
}

/// Ground a building may stand on.
fn solid_ground(b: &BlockState) -> bool {
    b.kind() == BlockKind::Solid && !tree(b)
}

/// Ground for finding the floor: water counts, so no floor is laid under it.
fn floor_ground(b: &BlockState) -> bool {
    solid_ground(b) || b.kind() == BlockKind::Liquid
}

fn world_at(world: &BlockGrid, p: IVec3) -> BlockState {
    world.get(p).cloned().unwrap_or_else(BlockState::air)
}

/// The plot of a box `min .. min + size` on `world`, or an error saying why
/// there is none.
pub(crate) fn plot(site: &Site, world: &BlockGrid, min: IVec3, size: IVec3) -> Result<Plot, String> {
    // Each column's top ground (below the box where it holds none); a cave
    // under the ground does not lower it.
    let mut tops = Vec::with_capacity((size.x * size.z) as usize);
    for z in min.z..min.z + size.z {
        for x in min.x..min.x + size.x {
            let top = (min.y..min.y + size.y).rev().find(|&y| floor_ground(&world_at(world, IVec3::new(x, y, z))));
            tops.push(top.unwrap_or(min.y - 1));
        }
    }
    tops.sort_unstable();
    let floor = tops[tops.len() / 2] + 1;
    if floor >= min.y + size.y {
        return Err(format!(
            "the site's box (y {}..={}) is ground up to its top in most columns, so there is no floor; \
             give a box whose top is above the ground",
            min.y,
            min.y + size.y - 1
        ));
    }
    let floor = floor.max(min.y);
    let yard = IVec3::new(site.yard, 0, site.yard);
    let plot_min = IVec3::new(min.x, floor, min.z) + yard;
    let plot_size = IVec3::new(size.x, min.y + size.y - floor, size.z) - 2 * yard;
    if plot_size.cmplt(IVec3::ONE).any() {
        return Err(format!(
            "the site leaves no room for the building: floor at y {floor}, a yard of {} on every side of a {}×{} box",
            site.yard, size.x, size.z
        ));
    }
    Ok(Plot { floor, min: plot_min, size: plot_size })
}

/// What laying the foundation and clearing the plot did.
#[derive(Clone, Debug, Default)]
pub(crate) struct Laid {
    pub foundation: u64,
    pub cleared: u64,
    /// Foundation columns whose bottom cell has no ground under it (the box
    /// did not reach down to the ground there).
    pub hanging: u64,
    /// Wood of a tree the site cut that lies just outside the box, where
    /// the site may not change anything: it is left without its trunk.
    pub cut_wood: Vec<IVec3>,
}

/// A tree's trunk or branch (leaves decay by themselves in the game).
fn wood(b: &BlockState) -> bool {
    let id = b.id();
    id.ends_with("_log") || id.ends_with("_wood") || matches!(id, "mushroom_stem" | "mangrove_roots")
}

/// The wood in the box of trees that reach out of it (wood joined through
/// faces, edges or corners to wood in the ring of cells around the box):
/// the site cannot take such a tree away whole, so it leaves it standing
/// (no clearing, no paving), and only the building's own blocks cut it.
fn reaching_out(world: &BlockGrid, min: IVec3, size: IVec3) -> std::collections::HashSet<IVec3> {
    let max = min + size;
    let inside = |p: IVec3| p.cmpge(min).all() && p.cmplt(max).all();
    let near = |p: IVec3| p.cmpge(min - IVec3::ONE).all() && p.cmple(max).all();
    let mut seen = std::collections::HashSet::new();
    let mut stack = Vec::new();
    for y in min.y - 1..=max.y {
        for z in min.z - 1..=max.z {
            for x in min.x - 1..=max.x {
                let p = IVec3::new(x, y, z);
                if !inside(p) && wood(&world_at(world, p)) && seen.insert(p) {
                    stack.push(p);
                }
            }
        }
    }
    while let Some(p) = stack.pop() {
        for d in (0..27).map(|i| IVec3::new(i % 3 - 1, i / 9 - 1, (i / 3) % 3 - 1)) {
            let q = p + d;
            if near(q) && wood(&world_at(world, q)) && seen.insert(q) {
                stack.push(q);
            }
        }
    }
    seen.retain(|&p| inside(p));
    seen
}

/// The whole box `min .. min + size`: the plot's derived blocks `derived`,
/// the foundation under the floor, the paved yard and the cleared cells;
/// `draw` picks one of the foundation's blocks.
pub(crate) fn lay(
    plot: &Plot,
    world: &BlockGrid,
    min: IVec3,
    size: IVec3,
    derived: &BlockGrid,
    foundation: &mut dyn FnMut() -> BlockState,
) -> (BlockGrid, Laid) {
    // The plot's cells, their states taken into the palette in the order
    // they are met (as `BlockGrid::set` would, without its search per cell).
    let mut out = BlockGrid::new(min, size.as_uvec3());
    let mut remap = vec![BlockGrid::UNSET; derived.palette.len()];
    for (p, c) in derived.iter_set() {
        let slot = &mut remap[c as usize];
        if *slot == BlockGrid::UNSET {
            out.palette.push(derived.palette[c as usize].clone());
            *slot = (out.palette.len() - 1) as u32;
        }
        let i = out.index(p).expect("the plot lies in the box");
        out.cells[i] = *slot;
    }
    let mut laid = Laid::default();
    let air = BlockState::air();
    let in_plot = |p: IVec3| p.cmpge(plot.min).all() && p.cmplt(plot.min + plot.size).all();
    let spared = reaching_out(world, min, size);
    for z in min.z..min.z + size.z {
        for x in min.x..min.x + size.x {
            // The yard's floor cell is paved; under the floor each column is
            // filled down to its ground (through water, never into a cave
            // under the ground).
            let column = IVec3::new(x, plot.floor, z);
            let top = if in_plot(column) { plot.floor - 1 } else { plot.floor };
            for y in (min.y..=top).rev() {
                let p = IVec3::new(x, y, z);
                if solid_ground(&world_at(world, p)) || spared.contains(&p) {
                    break;
                }
                out.set(p, &foundation());
                laid.foundation += 1;
                if y == min.y && !solid_ground(&world_at(world, p - IVec3::Y)) {
                    laid.hanging += 1;
                }
            }
            for y in plot.floor + 1..min.y + size.y {
                let p = IVec3::new(x, y, z);
                if world_at(world, p).kind() != BlockKind::Air
                    && (!in_plot(p) || out.get(p).is_none())
                    && !spared.contains(&p)
                {
                    out.set(p, &air);
                    laid.cleared += 1;
                }
            }
        }
    }
    // Wood in the ring around the box joined to wood the site changed.
    let changed = |p: IVec3| out.get(p).is_some_and(|b| *b != world_at(world, p));
    let max = min + size;
    for y in min.y - 1..=max.y {
        for z in min.z - 1..=max.z {
            for x in min.x - 1..=max.x {
                let p = IVec3::new(x, y, z);
                let outside = p.cmplt(min).any() || p.cmpge(max).any();
                if outside && wood(&world_at(world, p)) {
                    let cut = (0..27).map(|i| IVec3::new(i % 3 - 1, i / 9 - 1, (i / 3) % 3 - 1)).any(|d| {
                        let q = p + d;
                        wood(&world_at(world, q)) && changed(q)
                    });
                    if cut {
                        laid.cut_wood.push(p);
                    }
                }
            }
        }
    }
    (out, laid)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grammar::Paint;

    /// A world grid over `min..min+size` with ground up to `top(x, z)`
    /// (inclusive) and air above.
    fn hill(min: IVec3, size: IVec3, top: impl Fn(i32, i32) -> i32) -> BlockGrid {
        let mut g = BlockGrid::new(min, size.as_uvec3());
        let dirt = BlockState::parse("dirt").unwrap();
        for z in min.z..min.z + size.z {
            for x in min.x..min.x + size.x {
                for y in min.y..=top(x, z) {
                    g.set(IVec3::new(x, y, z), &dirt);
                }
            }
        }
        g
    }

    #[test]
    fn the_floor_is_one_above_the_median_top_ground() {
        let site = Site { foundation: Paint::Block(1), yard: 1 };
        // A slope along x: ground top 60 + x / 2 over x 0..10.
        let world = hill(IVec3::new(-1, 50, -1), IVec3::new(12, 30, 12), |x, _| 60 + x.max(0) / 2);
        let p = plot(&site, &world, IVec3::new(0, 55, 0), IVec3::new(10, 20, 10)).unwrap();
        // Tops 60, 60, 61, 61, 62, 62, 63, 63, 64, 64 along x: the median is 62.
        assert_eq!(p.floor, 63);
        assert_eq!((p.min, p.size), (IVec3::new(1, 63, 1), IVec3::new(8, 12, 8)));
        let all_ground = plot(&site, &world, IVec3::new(0, 50, 0), IVec3::new(10, 5, 10));
        assert!(all_ground.unwrap_err().contains("up to its top"));
        let narrow = plot(&Site { yard: 5, ..site }, &world, IVec3::new(0, 55, 0), IVec3::new(10, 20, 10));
        assert!(narrow.unwrap_err().contains("no room"));
    }

    #[test]
    fn foundation_fills_under_the_floor_and_the_slope_above_it_is_cut() {
        let site = Site { foundation: Paint::Block(1), yard: 1 };
        let world = hill(IVec3::new(-1, 50, -1), IVec3::new(12, 30, 12), |x, _| 60 + x.max(0) / 2);
        let (min, size) = (IVec3::new(0, 55, 0), IVec3::new(10, 20, 10));
        let p = plot(&site, &world, min, size).unwrap();
        // The building: one floor layer over its plot.
        let mut derived = BlockGrid::new(p.min, p.size.as_uvec3());
        let stone = BlockState::parse("stone").unwrap();
        for z in p.min.z..p.min.z + p.size.z {
            for x in p.min.x..p.min.x + p.size.x {
                derived.set(IVec3::new(x, p.floor, z), &stone);
            }
        }
        let cobble = BlockState::parse("cobblestone").unwrap();
        let (out, laid) = lay(&p, &world, min, size, &derived, &mut || cobble.clone());
        assert_eq!(laid.hanging, 0);
        for z in 0..10 {
            for x in 0..10 {
                let top = 60 + x / 2;
                // Under the floor: ground or foundation, nothing open.
                for y in min.y..p.floor {
                    let b =
                        out.get(IVec3::new(x, y, z)).cloned().unwrap_or_else(|| world_at(&world, IVec3::new(x, y, z)));
                    assert_eq!(b.kind(), BlockKind::Solid, "({x}, {y}, {z})");
                }
                // Above it: the slope is cut back to air.
                for y in p.floor + 1..=top {
                    assert_eq!(out.get(IVec3::new(x, y, z)).map(BlockState::id), Some("air"), "({x}, {y}, {z})");
                }
            }
        }
        // Columns lower than the floor got foundation: x 0..6 have tops
        // 60..62, each filled up to 62.
        let expected: u64 = (0..6).map(|x| (62 - (60 + x / 2)) as u64 * 10).sum::<u64>()
            // the yard's floor cells with no ground (x 0..6 of the ring at y 63)
            + (0..6).map(|x| if x == 0 { 10 } else { 2 }).sum::<u64>();
        assert_eq!(laid.foundation, expected);
    }

    #[test]
    fn caves_under_the_ground_stay_and_trees_reaching_out_are_left_standing() {
        let site = Site { foundation: Paint::Block(1), yard: 1 };
        // Flat ground at 60 with a cave at 57 under x 4; a trunk at (1, 61..64, 5) whose
        // branch at (-1, 64, 5) lies outside the box (x from 0).
        let mut world = hill(IVec3::new(-1, 50, -1), IVec3::new(12, 30, 12), |_, _| 60);
        let air = BlockState::air();
        world.set(IVec3::new(4, 57, 4), &air);
        let log = BlockState::parse("oak_log").unwrap();
        for y in 61..=64 {
            world.set(IVec3::new(1, y, 5), &log);
        }
        world.set(IVec3::new(0, 64, 5), &log);
        world.set(IVec3::new(-1, 64, 5), &log);
        let (min, size) = (IVec3::new(0, 55, 0), IVec3::new(10, 20, 10));
        let p = plot(&site, &world, min, size).unwrap();
        assert_eq!(p.floor, 61);
        let derived = BlockGrid::new(p.min, p.size.as_uvec3());
        let cobble = BlockState::parse("cobblestone").unwrap();
        let (out, laid) = lay(&p, &world, min, size, &derived, &mut || cobble.clone());
        assert_eq!(out.get(IVec3::new(4, 57, 4)), None, "the cave is left alone");
        for y in 61..=64 {
            assert_eq!(out.get(IVec3::new(1, y, 5)), None, "the trunk reaching out stays at y {y}");
        }
        assert!(laid.cut_wood.is_empty());
        // The yard is paved on the floor layer where it is not the trunk.
        assert_eq!(out.get(IVec3::new(0, 61, 0)), Some(&cobble));
    }
}
