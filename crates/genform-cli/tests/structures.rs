//! Structures a Minecraft builder would accept: the shipped box-split
//! examples are sampled by the real binary into a copy of each shipped
//! region, the region is read back, and the test checks block by block,
//! with its own reading of the blocks (kinds and ids, nothing of the
//! grammar crate), that
//!
//! - no hanging lantern or chain has air (nothing solid) above it, and no
//!   standing lantern or torch nothing below it;
//! - no snow layer or plant was left floating over a cell the structure
//!   dug out;
//! - no tunnel lining block stands where the terrain was not solid with
//!   nothing solid on either side across the tunnel;
//! - no tree is left floating: every connected body of wood (logs, stems)
//!   rests on ground, as before the structure, counted in a larger read of
//!   the region than the box;
//! - every fence is joined (`east=true`, …) to the fences beside it, as
//!   the game would show it;
//! - every footpath post and every bridge pier column reaches ground
//!   (neither air nor water) below it, and where a footpath crosses water
//!   at least one post goes down through it (its logs replaced water) to
//!   the bed.
//!
//! Besides the regions the examples were written for, the cases run on two
//! regions they were not (issue #43): a snowy 1.20.6 region (a bridge over
//! its valley, a tunnel through its low hill) and a 1.19.4 river region (a
//! tunnel into a cliff that overhangs the river, footpaths across a stream
//! and a deeper inlet); docs/box-split.md tabulates the counts.
//!
//! `block_states_survive_every_minecraft_format` writes stairs, slabs,
//! doors, ladders, trapdoors, lanterns, logs and fences to `.mca`,
//! `.schem` and `.litematic` and reads each back with a reader of its own
//! (fastnbt values, flate2, the bit packing decoded here).
//!
//! `GENFORM_STRUCTURES_EXAMPLES=DIR` measures the grammars of another
//! folder instead (for before/after numbers) and only prints.

mod common;

use common::{genform, root, s};
use genform_core::{BlockGrid, BlockKind, BlockState};
use genform_export::minecraft::{RegionFile, read_terrain};
use glam::IVec3;
use std::path::PathBuf;
use std::time::Instant;
use walls::{Cell, Walls};

#[path = "../../genform-boxsplit/tests/walls/mod.rs"]
mod walls;

struct Case {
    grammar: &'static str,
    region: &'static str,
    /// Inclusive corners; `None`: the box the grammar declares.
    corners: Option<[i32; 6]>,
}

const PRISMARINE: &str = "prismarine-1.21.1";
const FASTANVIL: &str = "fastanvil-1.19.4";
/// Regions no example was written for (see examples/terrain/README.md).
const SNOWY: &str = "prismarine-1.20.6";
const RIVER: &str = "prismarine-1.19.4";

/// Each example on its own region, and on the other one where it has a
/// place to go.
const CASES: &[Case] = &[
    Case { grammar: "tunnel", region: PRISMARINE, corners: None },
    // Through an oak at (39, 64..69, 21) whose crown reaches out of the box.
    Case { grammar: "tunnel", region: PRISMARINE, corners: Some([30, 63, 20, 60, 66, 24]) },
    Case { grammar: "tunnel", region: FASTANVIL, corners: Some([2, 61, 30, 40, 64, 34]) },
    Case { grammar: "footpath", region: FASTANVIL, corners: None },
    Case { grammar: "footpath", region: PRISMARINE, corners: Some([10, 54, 30, 50, 63, 31]) },
    Case { grammar: "bridge", region: PRISMARINE, corners: None },
    // Regions the examples were not written for (issue #43's acceptance).
    // A bridge over the snowy valley: banks at y 65-68, floor at 63.
    Case { grammar: "bridge", region: SNOWY, corners: Some([0, 62, 6, 28, 67, 8]) },
    // A tunnel through the low snowy hill (ground 68-69 over a floor at 64).
    Case { grammar: "tunnel", region: SNOWY, corners: Some([12, 64, 9, 39, 67, 13]) },
    // Tunnels under the river cliff whose edge overhangs the water (x 15,
    // z 67-74: grass at 71 over dirt at 69-70 over air at 63-68): one into
    // the cliff, its top layer in the overhang, one along the cliff's foot
    // under its overhanging edge.
    Case { grammar: "tunnel", region: RIVER, corners: Some([4, 65, 68, 17, 69, 72]) },
    Case { grammar: "tunnel", region: RIVER, corners: Some([11, 63, 50, 17, 67, 80]) },
    // Footpaths across the river: the shallow stream (bed 60-61) and the
    // deeper inlet (bed 57-61) between banks at 62-63.
    Case { grammar: "footpath", region: RIVER, corners: Some([65, 59, 6, 88, 63, 7]) },
    Case { grammar: "footpath", region: RIVER, corners: Some([30, 56, 2, 40, 63, 3]) },
    // Every terrain example on every shipped region: a bridge over the
    // 1.19.4 island's pond and over the river region's stream, a footpath
    // across the snowy hollow.
    Case { grammar: "bridge", region: FASTANVIL, corners: Some([26, 52, 41, 64, 66, 43]) },
    Case { grammar: "bridge", region: RIVER, corners: Some([64, 56, 5, 90, 66, 7]) },
    Case { grammar: "footpath", region: SNOWY, corners: Some([0, 62, 6, 28, 66, 7]) },
];

#[derive(Debug, Default)]
struct Counts {
    hanging: usize,
    unattached_hanging: usize,
    unsupported_standing: usize,
    floating_loose: usize,
    lining_free: usize,
    posts: usize,
    posts_without_ground: usize,
    /// Posts that replaced water on their way down and stand on the bed.
    posts_to_bed: usize,
    /// The most water blocks one post replaced.
    deepest_post_water: usize,
    water_columns: usize,
    /// Placed fences, and sides of them towards another fence that are not
    /// `true` (the game joins them).
    fences: usize,
    fence_sides_unjoined: usize,
    /// Wood blocks in bodies that rest on nothing, before and after.
    floating_trees_before: usize,
    floating_trees_after: usize,
}

fn at(g: &BlockGrid, p: IVec3) -> BlockState {
    g.get(p).cloned().unwrap_or_else(BlockState::air)
}

fn solid(b: &BlockState) -> bool {
    b.kind() == BlockKind::Solid
}

fn prop<'a>(b: &'a BlockState, key: &str) -> Option<&'a str> {
    b.properties.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
}

fn hangs(b: &BlockState) -> bool {
    matches!(b.id(), "lantern" | "soul_lantern") && prop(b, "hanging") == Some("true") || b.id() == "chain"
}

fn stands(b: &BlockState) -> bool {
    matches!(b.id(), "lantern" | "soul_lantern") && prop(b, "hanging") != Some("true") || b.id() == "torch"
}

fn tree(b: &BlockState) -> bool {
    let id = b.id();
    ["_log", "_wood", "_leaves", "_mushroom_block"].iter().any(|s| id.ends_with(s))
        || matches!(id, "mushroom_stem" | "mangrove_roots" | "cocoa" | "bee_nest")
}

/// A tree's wood: what holds a tree up (leaves resting on a slope do not).
fn wood(b: &BlockState) -> bool {
    let id = b.id();
    id.ends_with("_log") || id.ends_with("_wood") || matches!(id, "mushroom_stem" | "mangrove_roots")
}

/// Wood blocks in `g` (read over `min..max`) whose 26-connected body of
/// wood rests on nothing: no member stands on a solid block that is not a
/// tree block,
/// and none lies on the bottom layer or on a side or the top of the read
/// (a body there may stand outside it).
fn floating_trees(g: &BlockGrid, original: &BlockGrid, min: IVec3, max: IVec3) -> usize {
    let inside = |p: IVec3| p.cmpge(min).all() && p.cmplt(max).all();
    let mut seen = std::collections::HashSet::new();
    let mut floating = 0;
    for y in min.y..max.y {
        for z in min.z..max.z {
            for x in min.x..max.x {
                let start = IVec3::new(x, y, z);
                if !wood(&at(g, start)) || !seen.insert(start) {
                    continue;
                }
                let (mut body, mut stack, mut holds, mut grown) = (0, vec![start], false, false);
                while let Some(p) = stack.pop() {
                    body += 1;
                    grown |= at(g, p) == at(original, p);
                    let below = at(g, p - IVec3::Y);
                    let edge = p.y == min.y
                        || p.x == min.x
                        || p.z == min.z
                        || p.x == max.x - 1
                        || p.z == max.z - 1
                        || p.y == max.y - 1;
                    holds |= edge || solid(&below) && !tree(&below);
                    for d in (0..27).map(|i| IVec3::new(i % 3 - 1, i / 9 - 1, (i / 3) % 3 - 1)) {
                        let q = p + d;
                        if inside(q) && wood(&at(g, q)) && seen.insert(q) {
                            stack.push(q);
                        }
                    }
                }
                if !holds && grown {
                    floating += body;
                }
            }
        }
    }
    floating
}

/// The bridge's pier material (examples/boxsplit/bridge.bsg).
const PIER: &[&str] = &["stone_bricks", "cracked_stone_bricks", "andesite"];

const LINING: &[&str] = &["stone_bricks", "mossy_stone_bricks", "cracked_stone_bricks"];

fn measure(grammar: &str, before: &BlockGrid, after: &BlockGrid, min: IVec3, max: IVec3) -> Counts {
    let mut c = Counts::default();
    let size = max - min;
    // The tunnel runs along the box's longer horizontal side.
    let across = if size.z > size.x { IVec3::X } else { IVec3::Z };
    for y in min.y..max.y {
        for z in min.z..max.z {
            for x in min.x..max.x {
                let p = IVec3::new(x, y, z);
                let (b, a) = (at(before, p), at(after, p));
                let placed = a != b;
                let up = at(after, p + IVec3::Y);
                let down = at(after, p - IVec3::Y);
                if placed && hangs(&a) {
                    c.hanging += 1;
                    if !(solid(&up) || hangs(&up)) {
                        c.unattached_hanging += 1;
                    }
                }
                if placed && stands(&a) && !solid(&down) {
                    c.unsupported_standing += 1;
                }
                if placed && a.id().ends_with("_fence") {
                    c.fences += 1;
                    for (side, d) in
                        [("north", IVec3::NEG_Z), ("east", IVec3::X), ("south", IVec3::Z), ("west", IVec3::NEG_X)]
                    {
                        if at(after, p + d).id().ends_with("_fence") && prop(&a, side) != Some("true") {
                            c.fence_sides_unjoined += 1;
                        }
                    }
                }
                if grammar == "tunnel" && placed && LINING.contains(&a.id()) && !solid(&b) {
                    let free = !solid(&at(after, p + across)) && !solid(&at(after, p - across));
                    c.lining_free += usize::from(free);
                }
            }
        }
    }
    // Snow layers and plants over a cell the structure emptied, up to the
    // layer above the box.
    for y in min.y + 1..=max.y {
        for z in min.z..max.z {
            for x in min.x..max.x {
                let p = IVec3::new(x, y, z);
                let a = at(after, p);
                let (below_before, below_after) = (at(before, p - IVec3::Y), at(after, p - IVec3::Y));
                if a.kind() == BlockKind::Passable && solid(&below_before) && !solid(&below_after) {
                    c.floating_loose += 1;
                }
            }
        }
    }
    // Posts: a footpath's placed logs, a bridge's placed pier blocks,
    // column by column, down to the ground; a post goes to the bed where
    // its blocks replaced water.
    let post = |id: &str| match grammar {
        "footpath" => id == "oak_log",
        "bridge" => PIER.contains(&id),
        _ => false,
    };
    for z in min.z..max.z {
        for x in min.x..max.x {
            let logs: Vec<i32> = (min.y..max.y)
                .filter(|&y| {
                    let p = IVec3::new(x, y, z);
                    let a = at(after, p);
                    post(a.id()) && a != at(before, p)
                })
                .collect();
            let water = (min.y..max.y).any(|y| at(before, IVec3::new(x, y, z)).kind() == BlockKind::Liquid);
            c.water_columns += usize::from(water);
            let Some(&bottom) = logs.first() else { continue };
            c.posts += 1;
            let ground = at(after, IVec3::new(x, bottom - 1, z));
            let wet = logs.iter().filter(|&&y| at(before, IVec3::new(x, y, z)).kind() == BlockKind::Liquid).count();
            let through = wet > 0;
            c.deepest_post_water = c.deepest_post_water.max(wet);
            if matches!(ground.kind(), BlockKind::Air | BlockKind::Liquid) {
                c.posts_without_ground += 1;
            } else if through {
                c.posts_to_bed += 1;
            }
        }
    }
    c
}

/// The grammars to sample, and whether the test only measures (another
/// folder's, from `GENFORM_STRUCTURES_EXAMPLES`: it prints, never fails).
fn examples() -> (PathBuf, bool) {
    match std::env::var("GENFORM_STRUCTURES_EXAMPLES") {
        Ok(dir) => (PathBuf::from(dir), true),
        Err(_) => (root().join("examples/boxsplit"), false),
    }
}

/// What no structure may do, terrain or building: each fault it shows.
fn faults(c: &Counts) -> Vec<&'static str> {
    [
        (c.unattached_hanging > 0, "hanging blocks with nothing above"),
        (c.unsupported_standing > 0, "standing blocks with nothing below"),
        (c.floating_loose > 0, "snow or plants floating over a dug cell"),
        (c.lining_free > 0, "free-standing lining"),
        (c.floating_trees_after > c.floating_trees_before, "trees left floating"),
        (c.fence_sides_unjoined > 0, "fences not joined to the fences beside them"),
        (c.posts_without_ground > 0, "posts that do not reach the ground"),
    ]
    .into_iter()
    .filter_map(|(bad, what)| bad.then_some(what))
    .collect()
}

#[test]
fn shipped_structures_hang_stand_and_lean_on_something() {
    let (examples, measuring) = examples();
    let tmp = tempfile::tempdir().unwrap();
    let mut problems = Vec::new();
    for case in CASES {
        let placed = place(case, &examples, tmp.path(), IVec3::ONE);
        let (before, after, min, max, corners) =
            (&placed.before, &placed.after, placed.min, placed.max, placed.corners);
        let mut c = measure(case.grammar, before, after, min, max);
        (c.floating_trees_before, c.floating_trees_after) = placed.floating_trees();
        let label = format!("{} on {} box {:?}", case.grammar, case.region, corners);
        eprintln!("{label}: {c:?} ({})", placed.run);
        let mut bad = |cond: bool, what: &str| {
            if cond {
                problems.push(format!("{label}: {what} ({c:?})"));
            }
        };
        for what in faults(&c) {
            bad(true, what);
        }
        if case.grammar == "footpath" && c.water_columns > 0 {
            bad(c.posts_to_bed == 0, "no post goes down through the water to the bed");
        }
        // On the regions found for issue #43 the counts must not pass by
        // being empty: the tunnels hang lanterns, the footpaths cross the
        // river (the snowy region has no water).
        let found = [SNOWY, RIVER].contains(&case.region);
        if case.grammar == "footpath" && case.region == RIVER {
            bad(c.water_columns == 0, "the footpath crosses no water");
        }
        if case.grammar == "tunnel" && (case.corners.is_none() || found) {
            bad(c.hanging == 0, "the tunnel has no lanterns at all");
        }
    }
    if !measuring {
        assert!(problems.is_empty(), "{}", problems.join("\n"));
    }
}

/// The buildings, written for an empty box, set into every shipped region
/// on uneven ground: boxes from below the ground to above it.
const BUILDINGS: &[Case] = &[
    Case { grammar: "house", region: PRISMARINE, corners: Some([44, 60, 30, 59, 90, 41]) },
    Case { grammar: "house", region: FASTANVIL, corners: Some([20, 55, 20, 35, 90, 31]) },
    Case { grammar: "house", region: SNOWY, corners: Some([14, 60, 8, 29, 90, 19]) },
    Case { grammar: "house", region: RIVER, corners: Some([60, 55, 60, 75, 95, 71]) },
    Case { grammar: "house", region: RIVER, corners: Some([100, 55, 150, 115, 95, 161]) },
    Case { grammar: "temple", region: PRISMARINE, corners: Some([22, 50, 10, 62, 95, 40]) },
    Case { grammar: "temple", region: FASTANVIL, corners: Some([10, 48, 10, 50, 95, 40]) },
    Case { grammar: "temple", region: SNOWY, corners: Some([12, 58, 10, 52, 95, 40]) },
    Case { grammar: "temple", region: RIVER, corners: Some([60, 48, 60, 100, 95, 90]) },
    Case { grammar: "castle", region: PRISMARINE, corners: Some([28, 58, 28, 63, 90, 63]) },
    Case { grammar: "castle", region: FASTANVIL, corners: Some([0, 40, 20, 39, 85, 59]) },
    Case { grammar: "castle", region: SNOWY, corners: Some([16, 58, 16, 51, 90, 51]) },
    Case { grammar: "castle", region: RIVER, corners: Some([90, 55, 60, 150, 90, 120]) },
    Case { grammar: "mosaic", region: PRISMARINE, corners: Some([32, 50, 0, 63, 90, 31]) },
    Case { grammar: "mosaic", region: FASTANVIL, corners: Some([0, 30, 0, 47, 90, 47]) },
    Case { grammar: "mosaic", region: SNOWY, corners: Some([0, 58, 16, 47, 90, 63]) },
    Case { grammar: "mosaic", region: RIVER, corners: Some([60, 55, 100, 107, 95, 147]) },
];

/// The top solid block that is not a tree's in each column of the box
/// (`None`: no ground in the column's read).
fn ground_heights(g: &BlockGrid, min: IVec3, max: IVec3) -> Vec<i32> {
    let mut out = Vec::new();
    for z in min.z..max.z {
        for x in min.x..max.x {
            let top = (g.origin.y..max.y).rev().find(|&y| {
                let b = at(g, IVec3::new(x, y, z));
                solid(&b) && !tree(&b)
            });
            out.extend(top);
        }
    }
    out.sort_unstable();
    out
}

/// What a building on terrain got wrong.
#[derive(Debug, Default)]
struct Standing {
    /// Placed solid blocks joined (through faces, over placed solid blocks)
    /// to no ground: solid blocks the structure left as they were.
    floating: usize,
    /// Columns whose lowest placed solid block has air, water or a plant
    /// below it.
    hollow_under: usize,
    /// Sealed air the building made or bounds, in cells, and indoor places
    /// to stand nobody reaches on foot from the ground around.
    sealed_cells: usize,
    unreachable: usize,
}

/// `floor`: the floor the site reported; rooms and pockets below it (caves
/// under the foundation) are the ground's, not the building's.
fn standing(before: &BlockGrid, after: &BlockGrid, min: IVec3, max: IVec3, floor: i32) -> Standing {
    let mut st = Standing::default();
    let changed = |p: IVec3| at(before, p) != at(after, p);
    let in_box = |p: IVec3| p.cmpge(min).all() && p.cmplt(max).all();
    let placed_solid = |p: IVec3| in_box(p) && changed(p) && solid(&at(after, p));
    let ground = |p: IVec3| !changed(p) && solid(&at(after, p)) && !tree(&at(after, p));
    let faces = [IVec3::X, IVec3::NEG_X, IVec3::Y, IVec3::NEG_Y, IVec3::Z, IVec3::NEG_Z];
    let cells: Vec<IVec3> = (min.y..max.y)
        .flat_map(|y| (min.z..max.z).flat_map(move |z| (min.x..max.x).map(move |x| IVec3::new(x, y, z))))
        .collect();
    let mut joined = std::collections::HashSet::new();
    let mut stack: Vec<IVec3> =
        cells.iter().copied().filter(|&p| placed_solid(p) && faces.iter().any(|&d| ground(p + d))).collect();
    joined.extend(stack.iter().copied());
    while let Some(p) = stack.pop() {
        for d in faces {
            if placed_solid(p + d) && joined.insert(p + d) {
                stack.push(p + d);
            }
        }
    }
    st.floating = cells.iter().filter(|&&p| placed_solid(p) && !joined.contains(&p)).count();
    for z in min.z..max.z {
        for x in min.x..max.x {
            if let Some(y) = (min.y..max.y).find(|&y| placed_solid(IVec3::new(x, y, z))) {
                let below = at(after, IVec3::new(x, y - 1, z));
                st.hollow_under += usize::from(!solid(&below));
            }
        }
    }
    let window = (before.origin, before.size.as_ivec3());
    let walls = Walls::new(window.0, window.1, |p| Cell::of(Some(&at(after, p))));
    let near_placed =
        |p: IVec3| in_box(p) && p.y >= floor && (changed(p) || faces.iter().any(|&d| placed_solid(p + d)));
    st.sealed_cells = walls.sealed_pockets(near_placed).iter().sum();
    st.unreachable = walls.unreachable_rooms(placed_solid).iter().filter(|p| p.y > floor).count();
    st
}

#[test]
fn buildings_stand_on_the_ground_and_can_be_entered() {
    let (examples, measuring) = examples();
    let tmp = tempfile::tempdir().unwrap();
    let mut problems = Vec::new();
    for case in BUILDINGS {
        // The ground around the box decides where one can walk in from.
        let placed = place(case, &examples, tmp.path(), IVec3::new(3, 1, 3));
        let (before, after, min, max) = (&placed.before, &placed.after, placed.min, placed.max);
        let heights = ground_heights(before, min, max);
        let mut c = measure(case.grammar, before, after, min, max);
        (c.floating_trees_before, c.floating_trees_after) = placed.floating_trees();
        let floor = placed.run.split("floor at y ").nth(1).and_then(|r| r.split(',').next()?.parse().ok());
        let st = standing(before, after, min, max, floor.unwrap_or(min.y));
        let label = format!("{} on {} box {:?}", case.grammar, case.region, placed.corners);
        eprintln!(
            "{label}: ground {}..{} (median {}); {st:?}; {c:?} ({})",
            heights.first().unwrap_or(&0),
            heights.last().unwrap_or(&0),
            heights.get(heights.len() / 2).unwrap_or(&0),
            placed.run
        );
        let mut bad = |cond: bool, what: &str| {
            if cond {
                problems.push(format!("{label}: {what} ({st:?}; {c:?})"));
            }
        };
        bad(st.floating > 0, "blocks joined to no ground");
        bad(st.hollow_under > 0, "columns with nothing under their lowest block");
        bad(st.sealed_cells > 0, "sealed rooms");
        bad(st.unreachable > 0, "rooms nobody walks into");
        for what in faults(&c) {
            bad(true, what);
        }
    }
    if !measuring {
        assert!(problems.is_empty(), "{}", problems.join("\n"));
    }
}

/// A grammar sampled by the real binary into a copy of its case's region,
/// read back around the box.
struct Placed {
    /// The region as it was and as written, read over the box and `margin`
    /// more cells on every side.
    before: BlockGrid,
    after: BlockGrid,
    /// The box, `max` exclusive, and as the case gives it (inclusive).
    min: IVec3,
    max: IVec3,
    corners: [i32; 6],
    original: RegionFile,
    copy: RegionFile,
    /// What the run printed, and how long it took.
    run: String,
}

fn place(case: &Case, examples: &std::path::Path, dir: &std::path::Path, margin: IVec3) -> Placed {
    let world = root().join("examples/terrain").join(case.region).join("r.0.0.mca");
    let grammar = examples.join(format!("{}.bsg", case.grammar));
    let mut args = vec!["sample".to_string(), s(&grammar).to_string(), "--world".into(), s(&world).to_string()];
    let corners = case.corners.unwrap_or_else(|| declared_box(&grammar));
    if case.corners.is_some() {
        args.extend(["--box".into(), corners.map(|v| v.to_string()).join(",")]);
    }
    args.extend(["--out".into(), "r.0.0.mca".into()]);
    let started = Instant::now();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let run = genform(dir, &args).ok();
    let elapsed = started.elapsed();
    let run = format!("{:.0} ms, {} {}", elapsed.as_secs_f64() * 1000.0, run.stdout().trim(), run.stderr().trim());
    let a = IVec3::new(corners[0], corners[1], corners[2]);
    let b = IVec3::new(corners[3], corners[4], corners[5]);
    let (min, max) = (a.min(b), a.max(b) + IVec3::ONE);
    let original = RegionFile { x: 0, z: 0, bytes: std::fs::read(&world).unwrap() };
    let copy = RegionFile { x: 0, z: 0, bytes: std::fs::read(dir.join("r.0.0.mca")).unwrap() };
    let (rmin, rmax) = (min - margin, max + margin);
    let before = read_terrain(std::slice::from_ref(&original), rmin, rmax).unwrap();
    let after = read_terrain(std::slice::from_ref(&copy), rmin, rmax).unwrap();
    Placed { before, after, min, max, corners, original, copy, run }
}

impl Placed {
    /// Floating tree blocks before and after, read well beyond the box
    /// (trees reach out of it).
    fn floating_trees(&self) -> (usize, usize) {
        let (tmin, tmax) = (self.min - IVec3::new(8, 8, 8), self.max + IVec3::new(8, 16, 8));
        let wide_before = read_terrain(std::slice::from_ref(&self.original), tmin, tmax).unwrap();
        let wide_after = read_terrain(std::slice::from_ref(&self.copy), tmin, tmax).unwrap();
        (floating_trees(&wide_before, &wide_before, tmin, tmax), floating_trees(&wide_after, &wide_before, tmin, tmax))
    }
}

/// The corners of `box …;` in a grammar file.
fn declared_box(grammar: &std::path::Path) -> [i32; 6] {
    let text = std::fs::read_to_string(grammar).unwrap();
    let line = text.lines().find(|l| l.starts_with("box ")).expect("the grammar declares a box");
    let inner = line.trim_start_matches("box ").split(';').next().unwrap();
    let v: Vec<i32> = inner.split(',').map(|t| t.trim().parse().unwrap()).collect();
    [v[0], v[1], v[2], v[3], v[4], v[5]]
}

/// Columns of the block-state grammar, west to east: (bottom, top) as the
/// grammar writes them.
const STATE_COLUMNS: &[(&str, &str)] = &[
    (
        "oak_stairs[facing=east,half=bottom,shape=straight,waterlogged=false]",
        "oak_stairs[facing=west,half=top,shape=straight,waterlogged=false]",
    ),
    ("stone_slab[type=bottom,waterlogged=false]", "stone_slab[type=top,waterlogged=false]"),
    (
        "oak_door[facing=south,half=lower,hinge=left,open=false,powered=false]",
        "oak_door[facing=south,half=upper,hinge=left,open=false,powered=false]",
    ),
    ("ladder[facing=north,waterlogged=false]", "ladder[facing=north,waterlogged=false]"),
    (
        "oak_trapdoor[facing=east,half=top,open=true,powered=false,waterlogged=false]",
        "spruce_trapdoor[facing=west,half=bottom,open=false,powered=false,waterlogged=false]",
    ),
    ("lantern[hanging=false,waterlogged=false]", "soul_lantern[hanging=true,waterlogged=false]"),
    ("oak_log[axis=x]", "birch_log[axis=z]"),
    ("oak_fence", "oak_fence"),
    ("oak_fence", "oak_fence"),
];

/// What each column holds once written: the fences with the connections
/// the game would give them (west onto the log or the other fence).
fn expected_state(column: usize, top: bool) -> String {
    let (bottom, upper) = STATE_COLUMNS[column];
    let written = if top { upper } else { bottom };
    match column {
        7 => "oak_fence[east=true,north=false,south=false,west=true]".into(),
        8 => "oak_fence[east=false,north=false,south=false,west=true]".into(),
        _ => written.to_string(),
    }
}

/// `name[k=v,…]` from an NBT palette entry (`Name`, `Properties`), the
/// properties sorted.
fn entry_state(entry: &fastnbt::Value) -> String {
    use fastnbt::Value;
    let Value::Compound(m) = entry else { panic!("palette entry is not a compound") };
    let Some(Value::String(name)) = m.get("Name") else { panic!("palette entry without Name") };
    let mut props: Vec<String> = match m.get("Properties") {
        Some(Value::Compound(p)) => p
            .iter()
            .map(|(k, v)| match v {
                Value::String(v) => format!("{k}={v}"),
                other => panic!("property {k} is {other:?}"),
            })
            .collect(),
        _ => Vec::new(),
    };
    props.sort();
    let id = name.strip_prefix("minecraft:").unwrap_or(name);
    if props.is_empty() { id.to_string() } else { format!("{id}[{}]", props.join(",")) }
}

/// A `[k=v,…]` state string without its namespace, properties sorted.
fn plain(state: &str) -> String {
    let state = state.strip_prefix("minecraft:").unwrap_or(state);
    match state.split_once('[') {
        Some((id, rest)) => {
            let mut props: Vec<&str> = rest.trim_end_matches(']').split(',').collect();
            props.sort();
            format!("{id}[{}]", props.join(","))
        }
        None => state.to_string(),
    }
}

fn compound<'a>(v: &'a fastnbt::Value, key: &str) -> &'a std::collections::HashMap<String, fastnbt::Value> {
    match v {
        fastnbt::Value::Compound(m) => match m.get(key) {
            Some(fastnbt::Value::Compound(c)) => c,
            other => panic!("{key} is {other:?}"),
        },
        _ => panic!("not a compound"),
    }
}

fn gunzip(bytes: &[u8]) -> fastnbt::Value {
    use std::io::Read;
    let mut raw = Vec::new();
    flate2::read::GzDecoder::new(bytes).read_to_end(&mut raw).unwrap();
    fastnbt::from_bytes(&raw).unwrap()
}

/// Sponge schematic: palette name → index, varint data, x fastest, then z, then y.
fn read_schem_states(bytes: &[u8]) -> (IVec3, std::collections::HashMap<IVec3, String>) {
    use fastnbt::Value;
    let root = gunzip(bytes);
    let Value::Compound(top) = &root else { panic!() };
    // v2 at the root; v3 under `Schematic`.
    let m = match top.get("Schematic") {
        Some(Value::Compound(m)) => m,
        _ => top,
    };
    let num = |k: &str| match m.get(k) {
        Some(Value::Short(v)) => *v as u16 as i32,
        other => panic!("{k} is {other:?}"),
    };
    let (w, l) = (num("Width"), num("Length"));
    let Some(Value::IntArray(off)) = m.get("Offset") else { panic!("no Offset") };
    let origin = IVec3::new(off[0], off[1], off[2]);
    let (palette, data) = match (m.get("Palette"), m.get("BlockData")) {
        (Some(Value::Compound(p)), Some(Value::ByteArray(d))) => (p, d),
        _ => panic!("no Palette/BlockData"),
    };
    let mut names = std::collections::HashMap::new();
    for (k, v) in palette {
        let Value::Int(i) = v else { panic!() };
        names.insert(*i as u32, plain(k));
    }
    let (mut cells, mut i, mut value, mut shift) = (std::collections::HashMap::new(), 0i32, 0u32, 0);
    for &b in data.iter() {
        let b = b as u8;
        value |= u32::from(b & 0x7f) << shift;
        shift += 7;
        if b & 0x80 == 0 {
            let p = IVec3::new(i % w, i / (w * l), (i / w) % l);
            cells.insert(origin + p, names[&value].clone());
            (i, value, shift) = (i + 1, 0, 0);
        }
    }
    (origin, cells)
}

/// Litematica: each region's palette and its tightly packed indices
/// (entries may span two longs), x fastest, then z, then y.
fn read_litematic_states(bytes: &[u8]) -> std::collections::HashMap<IVec3, String> {
    use fastnbt::Value;
    let root = gunzip(bytes);
    let regions = compound(&root, "Regions");
    let mut cells = std::collections::HashMap::new();
    for region in regions.values() {
        let Value::Compound(r) = region else { panic!() };
        let xyz = |k: &str| {
            let Some(Value::Compound(c)) = r.get(k) else { panic!("{k}") };
            let g = |a: &str| match c.get(a) {
                Some(Value::Int(v)) => *v,
                other => panic!("{a} is {other:?}"),
            };
            IVec3::new(g("x"), g("y"), g("z"))
        };
        let (pos, size) = (xyz("Position"), xyz("Size"));
        let Some(Value::List(palette)) = r.get("BlockStatePalette") else { panic!("palette") };
        let Some(Value::LongArray(longs)) = r.get("BlockStates") else { panic!("BlockStates") };
        let bits = (usize::BITS - (palette.len() - 1).leading_zeros()).max(2) as usize;
        let n = size.abs();
        for i in 0..(n.x * n.y * n.z) as usize {
            let start = i * bits;
            let (word, off) = (start / 64, start % 64);
            let mut v = (longs[word] as u64) >> off;
            if off + bits > 64 {
                v |= (longs[word + 1] as u64) << (64 - off);
            }
            let v = (v & ((1u64 << bits) - 1)) as usize;
            let i = i as i32;
            let p = IVec3::new(i % n.x, i / (n.x * n.z), (i / n.x) % n.z);
            cells.insert(pos + p, entry_state(&palette[v]));
        }
    }
    cells
}

/// A region file's blocks in `min..max`: the chunk table, zlib chunks,
/// sections with their palettes and aligned packing (4 bits at least).
fn read_region_states(bytes: &[u8], min: IVec3, max: IVec3) -> std::collections::HashMap<IVec3, String> {
    use fastnbt::Value;
    use std::io::Read;
    let mut cells = std::collections::HashMap::new();
    for cz in min.z.div_euclid(16)..=(max.z - 1).div_euclid(16) {
        for cx in min.x.div_euclid(16)..=(max.x - 1).div_euclid(16) {
            let slot = 4 * ((cx & 31) + (cz & 31) * 32) as usize;
            let sector = u32::from_be_bytes([0, bytes[slot], bytes[slot + 1], bytes[slot + 2]]) as usize;
            let at = sector * 4096;
            let len = u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
            assert_eq!(bytes[at + 4], 2, "zlib chunk");
            let mut raw = Vec::new();
            flate2::read::ZlibDecoder::new(&bytes[at + 5..at + 4 + len]).read_to_end(&mut raw).unwrap();
            let chunk: Value = fastnbt::from_bytes(&raw).unwrap();
            let Value::Compound(c) = &chunk else { panic!() };
            let Some(Value::List(sections)) = c.get("sections") else { panic!("sections") };
            for section in sections {
                let Value::Compound(s) = section else { panic!() };
                let sy = match s.get("Y") {
                    Some(Value::Byte(y)) => i32::from(*y),
                    other => panic!("Y is {other:?}"),
                };
                if sy * 16 + 15 < min.y || sy * 16 >= max.y {
                    continue;
                }
                let states = compound(section, "block_states");
                let Some(Value::List(palette)) = states.get("palette") else { panic!("palette") };
                let bits = (usize::BITS - (palette.len().max(2) - 1).leading_zeros()).max(4) as usize;
                for i in 0..4096usize {
                    let v = match states.get("data") {
                        Some(Value::LongArray(d)) => {
                            let per = 64 / bits;
                            ((d[i / per] as u64 >> ((i % per) * bits)) & ((1u64 << bits) - 1)) as usize
                        }
                        _ => 0,
                    };
                    let i = i as i32;
                    let p = IVec3::new(cx * 16 + i % 16, sy * 16 + i / 256, cz * 16 + (i / 16) % 16);
                    if p.cmpge(min).all() && p.cmplt(max).all() {
                        cells.insert(p, entry_state(&palette[v]));
                    }
                }
            }
        }
    }
    cells
}

#[test]
fn block_states_survive_every_minecraft_format() {
    let tmp = tempfile::tempdir().unwrap();
    let n = STATE_COLUMNS.len();
    let columns: Vec<String> =
        STATE_COLUMNS.iter().map(|(b, t)| format!("split y [1, 1] {{ fill {b}, fill {t} }}")).collect();
    let grammar = format!(
        "box 2, 100, 3, {}, 101, 3;\nA {{ split x [{}] {{ {} }} }}\n",
        2 + n - 1,
        vec!["1"; n].join(", "),
        columns.join(", ")
    );
    std::fs::write(tmp.path().join("states.bsg"), grammar).unwrap();
    let world = root().join("examples/terrain").join(PRISMARINE).join("r.0.0.mca");
    let (min, max) = (IVec3::new(2, 100, 3), IVec3::new(2 + n as i32, 102, 4));
    let mut read: Vec<(&str, std::collections::HashMap<IVec3, String>)> = Vec::new();
    for out in ["r.0.0.mca", "states.schem", "states.litematic"] {
        common::ok(tmp.path(), &["sample", "states.bsg", "--world", s(&world), "--out", out]);
        let bytes = std::fs::read(tmp.path().join(out)).unwrap();
        let cells = if out.ends_with(".mca") {
            read_region_states(&bytes, min, max)
        } else if out.ends_with(".schem") {
            read_schem_states(&bytes).1
        } else {
            // Litematica keeps no world position: its cells are relative to the box.
            read_litematic_states(&bytes).into_iter().map(|(p, b)| (p + min, b)).collect()
        };
        read.push((out, cells));
    }
    for (out, cells) in &read {
        for (x, column) in (0..n).zip(min.x..) {
            for (top, y) in [(false, min.y), (true, min.y + 1)] {
                let p = IVec3::new(column, y, min.z);
                assert_eq!(cells.get(&p).map(String::as_str), Some(expected_state(x, top).as_str()), "{out} at {p}");
            }
        }
    }
}
