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
//! - every footpath post reaches ground (neither air nor water) below it,
//!   and where the path crosses water at least one post goes down to the
//!   bed.
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

struct Case {
    grammar: &'static str,
    region: &'static str,
    /// Inclusive corners; `None`: the box the grammar declares.
    corners: Option<[i32; 6]>,
}

const PRISMARINE: &str = "prismarine-1.21.1";
const FASTANVIL: &str = "fastanvil-1.19.4";

/// Each example on its own region, and on the other one where it has a
/// place to go.
const CASES: &[Case] = &[
    Case { grammar: "tunnel", region: PRISMARINE, corners: None },
    Case { grammar: "tunnel", region: PRISMARINE, corners: Some([30, 63, 20, 60, 66, 24]) },
    Case { grammar: "tunnel", region: FASTANVIL, corners: Some([2, 61, 30, 40, 64, 34]) },
    Case { grammar: "footpath", region: FASTANVIL, corners: None },
    Case { grammar: "footpath", region: PRISMARINE, corners: Some([10, 54, 30, 50, 63, 31]) },
    Case { grammar: "bridge", region: PRISMARINE, corners: None },
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
    posts_through_water: usize,
    water_columns: usize,
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
    // Posts: placed logs, column by column, down to the ground.
    for z in min.z..max.z {
        for x in min.x..max.x {
            let logs: Vec<i32> = (min.y..max.y)
                .filter(|&y| {
                    let p = IVec3::new(x, y, z);
                    let a = at(after, p);
                    a.id() == "oak_log" && a != at(before, p)
                })
                .collect();
            let water = (min.y..max.y).any(|y| at(before, IVec3::new(x, y, z)).kind() == BlockKind::Liquid);
            c.water_columns += usize::from(water);
            let Some(&bottom) = logs.first() else { continue };
            c.posts += 1;
            let ground = at(after, IVec3::new(x, bottom - 1, z));
            if matches!(ground.kind(), BlockKind::Air | BlockKind::Liquid) {
                c.posts_without_ground += 1;
            } else if water {
                c.posts_through_water += 1;
            }
        }
    }
    c
}

#[test]
fn shipped_structures_hang_stand_and_lean_on_something() {
    let examples =
        std::env::var("GENFORM_STRUCTURES_EXAMPLES").map(PathBuf::from).unwrap_or(root().join("examples/boxsplit"));
    let measuring = std::env::var_os("GENFORM_STRUCTURES_EXAMPLES").is_some();
    let tmp = tempfile::tempdir().unwrap();
    let mut problems = Vec::new();
    for case in CASES {
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
        let run = genform(tmp.path(), &args).ok();
        let elapsed = started.elapsed();
        let a = IVec3::new(corners[0], corners[1], corners[2]);
        let b = IVec3::new(corners[3], corners[4], corners[5]);
        let (min, max) = (a.min(b), a.max(b) + IVec3::ONE);
        let original = RegionFile { x: 0, z: 0, bytes: std::fs::read(&world).unwrap() };
        let copy = RegionFile { x: 0, z: 0, bytes: std::fs::read(tmp.path().join("r.0.0.mca")).unwrap() };
        let (rmin, rmax) = (min - IVec3::ONE, max + IVec3::ONE);
        let before = read_terrain(std::slice::from_ref(&original), rmin, rmax).unwrap();
        let after = read_terrain(std::slice::from_ref(&copy), rmin, rmax).unwrap();
        let c = measure(case.grammar, &before, &after, min, max);
        let label = format!("{} on {} box {:?}", case.grammar, case.region, corners);
        eprintln!(
            "{label}: {c:?} ({:.0} ms, {} {})",
            elapsed.as_secs_f64() * 1000.0,
            run.stdout().trim(),
            run.stderr().trim()
        );
        let mut bad = |cond: bool, what: &str| {
            if cond {
                problems.push(format!("{label}: {what} ({c:?})"));
            }
        };
        bad(c.unattached_hanging > 0, "hanging blocks with nothing above");
        bad(c.unsupported_standing > 0, "standing blocks with nothing below");
        bad(c.floating_loose > 0, "snow or plants floating over a dug cell");
        bad(c.lining_free > 0, "free-standing lining");
        bad(c.posts_without_ground > 0, "posts that do not reach the ground");
        if case.grammar == "footpath" && c.water_columns > 0 {
            bad(c.posts_through_water == 0, "no post goes down through the water");
        }
        if case.grammar == "tunnel" && case.corners.is_none() {
            bad(c.hanging == 0, "the tunnel has no lanterns at all");
        }
    }
    if !measuring {
        assert!(problems.is_empty(), "{}", problems.join("\n"));
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
