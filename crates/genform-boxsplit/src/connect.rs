//! Connection states, as Minecraft computes them when a player places a
//! block: after a derivation (and its `support` declarations), every placed
//! fence, glass pane, iron bars and wall gets its `north`/`east`/`south`/
//! `west` (and a wall its `up`) from its neighbours, and every placed stairs
//! its `shape` from the stairs beside it, so that a region, schematic or
//! Litematica file shows what the game would show. A grammar writes
//! `oak_fence` and gets `oak_fence[east=true,north=false,…]`.
//!
//! The neighbours are read in the world as it will be (the derived blocks
//! over the terrain; cells outside both read as air). Placed blocks change,
//! and the world's own connecting blocks inside the box on the sides that
//! face a placed block (a fence of the world joins a new wall); those
//! outside the box keep their states, as blocks outside the box must. Nothing is random; a stairs' shape depends
//! only on its neighbours' facing and half, a wall's sides on the wall
//! above it (done top down), so the result does not depend on any order
//! beyond that.
//!
//! The shapes are approximated where Minecraft asks for exact collision
//! boxes: a neighbour "has a full face" when it is solid and not one of the
//! partial blocks of [`partial`] (slabs other than double ones, stairs
//! except on their back, fences, walls, doors, lanterns, …); leaves,
//! pumpkins, melons, barriers and shulker boxes never take connections, as
//! in the game.

use genform_core::{BlockGrid, BlockKind, BlockState};
use glam::IVec3;

/// The six face neighbours.
const SIX: [IVec3; 6] = [IVec3::X, IVec3::NEG_X, IVec3::Y, IVec3::NEG_Y, IVec3::Z, IVec3::NEG_Z];

/// The four horizontal directions, in Minecraft's property names.
const SIDES: [(&str, IVec3); 4] =
    [("north", IVec3::NEG_Z), ("east", IVec3::X), ("south", IVec3::Z), ("west", IVec3::NEG_X)];

/// What kind of connecting block an id is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Connects {
    /// A wooden fence (`*_fence` except nether bricks).
    WoodFence,
    /// `nether_brick_fence`: connects to itself, not to wooden fences.
    NetherFence,
    /// Glass panes and iron bars.
    Pane,
    /// `*_wall` (not wall torches, signs, banners, heads, fans).
    Wall,
    /// `*_stairs`.
    Stairs,
}

fn connects(b: &BlockState) -> Option<Connects> {
    let id = b.id();
    if id == "nether_brick_fence" {
        Some(Connects::NetherFence)
    } else if id.ends_with("_fence") {
        Some(Connects::WoodFence)
    } else if id.ends_with("glass_pane") || id == "iron_bars" {
        Some(Connects::Pane)
    } else if id.ends_with("_wall")
        && ![
            "_wall_torch",
            "_wall_sign",
            "_wall_hanging_sign",
            "_wall_banner",
            "_wall_head",
            "_wall_skull",
            "_wall_fan",
        ]
        .iter()
        .any(|s| id.ends_with(s))
        && id != "wall_torch"
    {
        Some(Connects::Wall)
    } else if id.ends_with("_stairs") {
        Some(Connects::Stairs)
    } else {
        None
    }
}

fn prop<'a>(b: &'a BlockState, key: &str) -> Option<&'a str> {
    b.properties.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
}

/// `b` with `key=value` (properties stay sorted).
fn with(b: &mut BlockState, key: &str, value: &str) {
    match b.properties.binary_search_by(|(k, _)| k.as_str().cmp(key)) {
        Ok(i) => b.properties[i].1 = value.to_string(),
        Err(i) => b.properties.insert(i, (key.to_string(), value.to_string())),
    }
}

/// Blocks that never take a connection (Minecraft's exceptions).
fn exception(id: &str) -> bool {
    id.ends_with("_leaves")
        || id.ends_with("shulker_box")
        || matches!(id, "barrier" | "carved_pumpkin" | "jack_o_lantern" | "melon" | "pumpkin")
}

/// Solid blocks whose sides are not full faces (approximately: Minecraft
/// asks the collision box).
fn partial(id: &str) -> bool {
    const SUFFIXES: &[&str] = &[
        "_slab",
        "_stairs",
        "_fence",
        "_fence_gate",
        "_wall",
        "_pane",
        "_door",
        "_trapdoor",
        "_bed",
        "_head",
        "_skull",
        "_candle",
        "candle",
        "_chain",
        "lantern",
        "_rod",
        "_pot",
        "anvil",
        "chest",
        "_bars",
        "_carpet",
        "_button",
        "_plate",
        "_sign",
        "_banner",
        "_coral",
        "_coral_fan",
    ];
    const IDS: &[&str] = &[
        "chain",
        "ladder",
        "lectern",
        "enchanting_table",
        "cake",
        "campfire",
        "soul_campfire",
        "bell",
        "brewing_stand",
        "cauldron",
        "water_cauldron",
        "lava_cauldron",
        "powder_snow_cauldron",
        "hopper",
        "daylight_detector",
        "scaffolding",
        "grindstone",
        "stonecutter",
        "dirt_path",
        "farmland",
        "bamboo",
        "cactus",
        "sea_pickle",
        "turtle_egg",
        "flower_pot",
        "conduit",
        "lever",
        "repeater",
        "comparator",
        "end_portal_frame",
        "honey_block",
        "cobweb",
        "composter",
        "dragon_egg",
        "sniffer_egg",
        "decorated_pot",
        "pointed_dripstone",
        "amethyst_cluster",
        "big_dripleaf",
        "azalea",
        "flowering_azalea",
        "snow",
    ];
    SUFFIXES.iter().any(|s| id.ends_with(s)) || IDS.contains(&id) || id.starts_with("potted_")
}

/// Whether `n`, the neighbour on side `d` of a connecting block, shows a
/// full face towards it.
fn full_face(n: &BlockState, d: IVec3) -> bool {
    let id = n.id();
    if n.kind() != BlockKind::Solid || exception(id) {
        return false;
    }
    if id.ends_with("_slab") {
        return prop(n, "type") == Some("double");
    }
    if id.ends_with("_stairs") {
        // Only a stairs' back (the side it faces) is a full face.
        return prop(n, "facing").and_then(direction) == Some(-d);
    }
    !partial(id)
}

fn direction(name: &str) -> Option<IVec3> {
    SIDES.iter().find(|(n, _)| *n == name).map(|&(_, d)| d)
}

/// Minecraft's counter-clockwise turn, seen from above.
fn counter_clockwise(d: IVec3) -> IVec3 {
    IVec3::new(d.z, 0, -d.x)
}

/// Whether a fence gate `n` on side `d` lies in the line of the fence: its
/// facing is across `d`.
fn gate_in_line(n: &BlockState, d: IVec3) -> bool {
    n.id().ends_with("_fence_gate") && prop(n, "facing").and_then(direction).is_some_and(|f| f.x * d.x + f.z * d.z == 0)
}

/// Sets the connection states of every placed connecting block in `out`
/// over `world`; returns how many blocks changed.
pub(crate) fn connect(world: Option<&BlockGrid>, out: &mut BlockGrid) -> u64 {
    let air = BlockState::air();
    let (o, n) = (out.origin, out.size.as_ivec3());
    // Top down, so that a wall sees the final sides of the wall above it;
    // the palettes are classified once, not every cell.
    let wanted: Vec<bool> = out.palette.iter().map(|b| connects(b).is_some()).collect();
    let world_wanted: Vec<bool> =
        world.map_or(Vec::new(), |w| w.palette.iter().map(|b| connects(b).is_some()).collect());
    if !wanted.contains(&true) && !world_wanted.contains(&true) {
        return 0;
    }
    // The world's own connecting blocks inside the box that touch a placed
    // block: a fence of the world joins a new wall, as in the game.
    let touched_world = |p: IVec3| {
        let Some(w) = world else { return false };
        let of_world = w.index(p).is_some_and(|i| world_wanted.get(w.cells[i] as usize).copied().unwrap_or(false));
        of_world && SIX.iter().any(|&d| out.get(p + d).is_some())
    };
    let mut cells = Vec::new();
    let layer = (n.x * n.z) as usize;
    for y in (0..n.y).rev() {
        let start = y as usize * layer;
        for (i, &c) in out.cells[start..start + layer].iter().enumerate() {
            let i = i as i32;
            let p = o + IVec3::new(i % n.x, y, i / n.x);
            if wanted.get(c as usize).copied().unwrap_or(false) || c == BlockGrid::UNSET && touched_world(p) {
                cells.push(p);
            }
        }
    }
    // Stairs read their neighbours' facing and half only, never shapes;
    // walls read the final wall above: compute everything, then write.
    let mut changes: Vec<(IVec3, BlockState)> = Vec::new();
    // Where each changed cell's new state is in `changes` (looked up only).
    let mut done: std::collections::HashMap<IVec3, usize> = std::collections::HashMap::new();
    let mut changed = 0;
    for p in cells {
        let at = |q: IVec3| -> BlockState {
            if let Some(&i) = done.get(&q) {
                return changes[i].1.clone();
            }
            out.get(q).or_else(|| world.and_then(|w| w.get(q))).unwrap_or(&air).clone()
        };
        let old = at(p);
        let Some(kind) = connects(&old) else { continue };
        let mut b = old.clone();
        match kind {
            Connects::Stairs => stairs(&mut b, &at, p),
            _ => {
                let mut sides = [false; 4];
                for (i, &(_, d)) in SIDES.iter().enumerate() {
                    let nb = at(p + d);
                    let other = connects(&nb);
                    sides[i] = full_face(&nb, d)
                        || gate_in_line(&nb, d) && kind != Connects::Pane
                        || match kind {
                            Connects::WoodFence | Connects::NetherFence => other == Some(kind),
                            Connects::Pane => matches!(other, Some(Connects::Pane | Connects::Wall)),
                            Connects::Wall => matches!(other, Some(Connects::Pane | Connects::Wall)),
                            Connects::Stairs => false,
                        };
                }
                if kind == Connects::Wall {
                    wall(&mut b, &at(p + IVec3::Y), sides);
                } else {
                    for (i, &(s, _)) in SIDES.iter().enumerate() {
                        with(&mut b, s, if sides[i] { "true" } else { "false" });
                    }
                }
            }
        }
        if out.get(p).is_none() {
            // A block of the world: only the sides facing a placed block
            // change (the others stay as the game left them).
            for &(side, d) in &SIDES {
                if out.get(p + d).is_none()
                    && let Some(v) = prop(&old, side)
                {
                    with(&mut b, side, v);
                }
            }
        }
        if b != old {
            changed += 1;
            done.insert(p, changes.len());
            changes.push((p, b));
        }
    }
    for (p, b) in &changes {
        out.set(*p, b);
    }
    changed
}

/// A wall's sides: `tall` where the block above covers that side (a full
/// block, or a wall connected that way), `low` otherwise; `up` (the post)
/// by Minecraft's rule: at ends, corners, crossings and under a wall with
/// a post; not in a tall straight run; in a low straight run only under a
/// full block or a torch, lantern, sign or banner.
fn wall(b: &mut BlockState, above: &BlockState, sides: [bool; 4]) {
    let above_full = full_face(above, IVec3::NEG_Y) && !above.id().ends_with("_stairs");
    let above_wall = connects(above) == Some(Connects::Wall);
    let mut height = ["none"; 4];
    for (i, &(s, _)) in SIDES.iter().enumerate() {
        if sides[i] {
            let covered = above_full || above_wall && prop(above, s).is_some_and(|v| v != "none");
            height[i] = if covered { "tall" } else { "low" };
        }
        with(b, s, height[i]);
    }
    let [north, east, south, west] = height;
    let post_above = above_wall && prop(above, "up") == Some("true");
    let end_or_corner =
        (north == "none") != (south == "none") || (east == "none") != (west == "none") || height == ["none"; 4];
    let up = if post_above || end_or_corner {
        true
    } else if north == "tall" && south == "tall" || east == "tall" && west == "tall" {
        false
    } else {
        let id = above.id();
        above_full
            || above_wall
            || id.ends_with("torch")
            || id.ends_with("lantern")
            || id.ends_with("_sign")
            || id.ends_with("_banner")
    };
    with(b, "up", if up { "true" } else { "false" });
}

/// A stairs' `shape` from the stairs behind it (outer corners) and in
/// front of it (inner corners), as Minecraft's `getStairsShape`.
fn stairs(b: &mut BlockState, at: &dyn Fn(IVec3) -> BlockState, p: IVec3) {
    let Some(facing) = prop(b, "facing").and_then(direction) else { return };
    let half = prop(b, "half").unwrap_or("bottom").to_string();
    let stairs_of = |q: IVec3| {
        let n = at(q);
        (connects(&n) == Some(Connects::Stairs) && prop(&n, "half").unwrap_or("bottom") == half)
            .then(|| prop(&n, "facing").and_then(direction))
            .flatten()
    };
    // Whether the block on side `d` is not a stairs of the same facing and half.
    let takes = |d: IVec3| stairs_of(p + d) != Some(facing);
    let left = counter_clockwise(facing);
    let mut shape = "straight";
    if let Some(behind) = stairs_of(p + facing)
        && behind.x * facing.x + behind.z * facing.z == 0
        && takes(-behind)
    {
        shape = if behind == left { "outer_left" } else { "outer_right" };
    } else if let Some(front) = stairs_of(p - facing)
        && front.x * facing.x + front.z * facing.z == 0
        && takes(front)
    {
        shape = if front == left { "inner_left" } else { "inner_right" };
    }
    with(b, "shape", shape);
}

#[cfg(test)]
mod tests {
    use super::connect;
    use genform_core::{BlockGrid, BlockState};
    use glam::{IVec3, UVec3};

    /// Places `blocks` (position, state) in a 5×3×5 box at the origin over
    /// `world` and connects them.
    fn run(world: &[(IVec3, &str)], blocks: &[(IVec3, &str)]) -> BlockGrid {
        let mut w = BlockGrid::new(IVec3::splat(-1), UVec3::splat(7));
        for &(p, b) in world {
            w.set(p, &BlockState::parse(b).unwrap());
        }
        let mut out = BlockGrid::new(IVec3::ZERO, UVec3::new(5, 3, 5));
        for &(p, b) in blocks {
            out.set(p, &BlockState::parse(b).unwrap());
        }
        connect(Some(&w), &mut out);
        out
    }

    fn state(g: &BlockGrid, p: IVec3) -> String {
        let b = g.get(p).unwrap();
        let props: Vec<String> = b.properties.iter().map(|(k, v)| format!("{k}={v}")).collect();
        format!("{}[{}]", b.id(), props.join(","))
    }

    #[test]
    fn fences_join_fences_gates_and_full_faces() {
        let p = IVec3::new(2, 0, 2);
        let out = run(
            &[(p + IVec3::NEG_X, "stone"), (p + IVec3::Z, "oak_leaves")],
            &[(p, "oak_fence"), (p + IVec3::X, "spruce_fence"), (p + IVec3::NEG_Z, "oak_fence_gate[facing=east]")],
        );
        // West: stone; east: another wooden fence; north: a gate across the
        // line; south: leaves, which never connect.
        assert_eq!(state(&out, p), "oak_fence[east=true,north=true,south=false,west=true]");
        assert_eq!(state(&out, p + IVec3::X), "spruce_fence[east=false,north=false,south=false,west=true]");
        let out = run(&[], &[(p, "nether_brick_fence"), (p + IVec3::X, "oak_fence")]);
        assert_eq!(state(&out, p), "nether_brick_fence[east=false,north=false,south=false,west=false]");
    }

    #[test]
    fn panes_and_bars_join_each_other_and_walls() {
        let p = IVec3::new(2, 0, 2);
        let out = run(
            &[(p + IVec3::Z, "oak_slab[type=bottom]")],
            &[(p, "glass_pane"), (p + IVec3::X, "iron_bars"), (p + IVec3::NEG_X, "cobblestone_wall")],
        );
        assert_eq!(state(&out, p), "glass_pane[east=true,north=false,south=false,west=true]");
        // The wall: one side to the pane, low, so it is an end with a post.
        assert_eq!(state(&out, p + IVec3::NEG_X), "cobblestone_wall[east=low,north=none,south=none,up=true,west=none]");
    }

    #[test]
    fn walls_are_tall_under_blocks_and_lose_the_post_in_a_straight_run() {
        let out = run(
            &[(IVec3::new(2, 1, 2), "stone")],
            &[
                (IVec3::new(1, 0, 2), "stone_brick_wall"),
                (IVec3::new(2, 0, 2), "stone_brick_wall"),
                (IVec3::new(3, 0, 2), "stone_brick_wall"),
            ],
        );
        // Under stone: tall both ways, a tall straight run has no post.
        assert_eq!(
            state(&out, IVec3::new(2, 0, 2)),
            "stone_brick_wall[east=tall,north=none,south=none,up=false,west=tall]"
        );
        // The ends: low towards the middle, with a post.
        assert_eq!(
            state(&out, IVec3::new(1, 0, 2)),
            "stone_brick_wall[east=low,north=none,south=none,up=true,west=none]"
        );
    }

    #[test]
    fn stairs_turn_corners() {
        // The south-east corner of a hip roof: a row of north-facing stairs
        // along x meets a row of west-facing ones along z.
        let out = run(
            &[],
            &[
                (IVec3::new(1, 0, 2), "oak_stairs[facing=north,half=bottom]"),
                (IVec3::new(2, 0, 2), "oak_stairs[facing=north,half=bottom]"),
                (IVec3::new(2, 0, 1), "oak_stairs[facing=west,half=bottom]"),
            ],
        );
        // (2,0,2) has behind it (north) a stairs facing west, the
        // counter-clockwise turn of north, and nothing east: outer_left.
        assert!(state(&out, IVec3::new(2, 0, 2)).contains("shape=outer_left"), "{}", state(&out, IVec3::new(2, 0, 2)));
        assert!(state(&out, IVec3::new(1, 0, 2)).contains("shape=straight"));
        // (2,0,1) facing west: nothing behind (1,0,1) or in front (3,0,1).
        assert!(state(&out, IVec3::new(2, 0, 1)).contains("shape=straight"));
        // An inner corner: a west-facing stairs in front of a north-facing one.
        let out = run(
            &[],
            &[
                (IVec3::new(2, 0, 2), "oak_stairs[facing=north,half=top]"),
                (IVec3::new(2, 0, 3), "oak_stairs[facing=west,half=top]"),
            ],
        );
        assert!(state(&out, IVec3::new(2, 0, 2)).contains("shape=inner_left"), "{}", state(&out, IVec3::new(2, 0, 2)));
        // Halves differ: no corner.
        let out = run(
            &[],
            &[
                (IVec3::new(2, 0, 2), "oak_stairs[facing=north,half=bottom]"),
                (IVec3::new(2, 0, 3), "oak_stairs[facing=west,half=top]"),
            ],
        );
        assert!(state(&out, IVec3::new(2, 0, 2)).contains("shape=straight"));
    }

    #[test]
    fn a_fence_of_the_world_joins_a_placed_wall_on_that_side_only() {
        let p = IVec3::new(2, 0, 2);
        // A world fence in the box, stated as the game left it (joined west
        // to something the approximation would not join); a stone placed east.
        let mut w = BlockGrid::new(IVec3::splat(-1), UVec3::splat(7));
        w.set(p, &BlockState::parse("oak_fence[east=false,north=false,south=false,west=true]").unwrap());
        let mut out = BlockGrid::new(IVec3::ZERO, UVec3::new(5, 3, 5));
        out.set(p + IVec3::X, &BlockState::new("stone"));
        connect(Some(&w), &mut out);
        assert_eq!(state(&out, p), "oak_fence[east=true,north=false,south=false,west=true]");
        // Nothing placed beside it: it stays unset (the world's block).
        let mut out = BlockGrid::new(IVec3::ZERO, UVec3::new(5, 3, 5));
        out.set(p + IVec3::new(2, 0, 2), &BlockState::new("stone"));
        connect(Some(&w), &mut out);
        assert_eq!(out.get(p), None);
    }
}
