//! The example grammars in `examples/boxsplit/`: they compile without
//! warnings and derive on hand-made worlds with the properties they promise.

use genform_boxsplit::{BoxGrammar, Derivation, DeriveOptions, compile};
use genform_core::{BlockGrid, BlockKind, BlockState, Rng, SourceFile};
use glam::IVec3;

fn load(name: &str) -> BoxGrammar {
    let path = format!("{}/../../examples/boxsplit/{name}.bsg", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("example exists");
    match compile(&SourceFile::new(format!("{name}.bsg"), text)) {
        Ok((g, warnings)) => {
            assert!(warnings.items.is_empty(), "{name}: {}", warnings.short());
            g
        }
        Err(e) => panic!("{name}:\n{}", e.short()),
    }
}

fn derive(name: &str, world: Option<&BlockGrid>, size: IVec3, seed: u64) -> Derivation {
    let g = load(name);
    let d = g.derive(world, IVec3::ZERO, size, &mut Rng::from_seed(seed), &DeriveOptions::default());
    d.unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// A world of `size` with the block `f(x, y, z)` in every cell (`""`: air).
fn world(size: IVec3, f: impl Fn(i32, i32, i32) -> &'static str) -> BlockGrid {
    let mut g = BlockGrid::new(IVec3::ZERO, size.as_uvec3());
    for x in 0..size.x {
        for y in 0..size.y {
            for z in 0..size.z {
                let id = f(x, y, z);
                g.set(IVec3::new(x, y, z), &BlockState::new(if id.is_empty() { "air" } else { id }));
            }
        }
    }
    g
}

fn solid(w: &BlockGrid, p: IVec3) -> bool {
    w.get(p).is_some_and(|b| b.kind() == BlockKind::Solid)
}

fn placed(d: &Derivation, p: IVec3) -> Option<&str> {
    d.blocks.get(p).map(|b| b.id())
}

/// No block (air included) is placed where the world has a solid block.
fn assert_no_solid_replaced(name: &str, w: &BlockGrid, d: &Derivation) {
    for (p, _) in d.blocks.iter_set() {
        assert!(!solid(w, p), "{name}: a block was placed over terrain at {p}");
    }
}

/// For every column (x, z) holding `ids`, they form one contiguous run from
/// `top` down whose lowest block stands directly on a solid world block.
/// Returns the columns that have one.
fn assert_columns_stand_on_ground(
    name: &str,
    w: &BlockGrid,
    d: &Derivation,
    ids: &[&str],
    top: i32,
) -> Vec<(i32, i32)> {
    let size = d.blocks.size.as_ivec3();
    let mut columns = Vec::new();
    for x in 0..size.x {
        for z in 0..size.z {
            let ys: Vec<i32> =
                (0..size.y).filter(|&y| placed(d, IVec3::new(x, y, z)).is_some_and(|id| ids.contains(&id))).collect();
            let Some(&low) = ys.first() else { continue };
            assert_eq!(ys, (low..=top).collect::<Vec<_>>(), "{name}: column ({x}, {z}) is not one run up to {top}");
            assert!(solid(w, IVec3::new(x, low - 1, z)), "{name}: column ({x}, {z}) ends at y {low} above no ground");
            columns.push((x, z));
        }
    }
    columns
}

#[test]
fn bridge_supports_reach_the_ground_without_cutting_terrain() {
    // A valley with a river at the bottom, across x; a ledge of rock juts
    // out under the pier at x = 26, with air below it.
    let size = IVec3::new(40, 14, 5);
    let valley = world(size, |x, y, _| {
        let ground = ((x - 20).abs() / 2 + 1).min(13);
        if x == 26 && y == 7 {
            "stone"
        } else if y < ground {
            if y + 1 == ground { "grass_block" } else { "stone" }
        } else if y < 4 {
            "water"
        } else {
            ""
        }
    });
    let d = derive("bridge", Some(&valley), size, 1);
    assert_no_solid_replaced("bridge", &valley, &d);
    let piers = ["stone_bricks", "cracked_stone_bricks", "andesite"];
    let columns = assert_columns_stand_on_ground("bridge", &valley, &d, &piers, 11);
    // Piers every sixth block, each the full width, except at the ledge.
    let xs: Vec<i32> = columns.iter().filter(|c| c.1 == 0).map(|c| c.0).collect();
    assert_eq!(xs, vec![2, 8, 14, 20, 32, 38]);
    assert!(columns.iter().all(|c| xs.contains(&c.0)));
    assert_eq!(columns.len(), 6 * 5);
    // The river pier stands in the water on the river bed.
    assert_eq!(valley.get(IVec3::new(20, 1, 2)).unwrap().id(), "water");
    assert!(piers.contains(&placed(&d, IVec3::new(20, 1, 2)).unwrap()));
    // The column at the ledge was tried and given up by backtracking.
    assert!(d.stats.backtracks >= 5, "{:?}", d.stats);
    // A deck with railings along the top, all the way across.
    for x in 0..40 {
        assert!(matches!(placed(&d, IVec3::new(x, 12, 2)), Some("spruce_planks" | "stripped_spruce_wood")));
        assert_eq!(placed(&d, IVec3::new(x, 13, 0)), Some("spruce_fence"));
        assert_eq!(placed(&d, IVec3::new(x, 13, 2)), Some("air"));
    }
}

#[test]
fn bridge_over_a_ravine_without_ground_gets_no_piers() {
    // Both banks rise into the deck; in between a chasm without a bottom.
    let size = IVec3::new(30, 10, 3);
    let ravine = world(size, |x, y, _| if !(4..=25).contains(&x) && y < 9 { "stone" } else { "" });
    let d = derive("bridge", Some(&ravine), size, 2);
    assert_no_solid_replaced("bridge", &ravine, &d);
    let piers = ["stone_bricks", "cracked_stone_bricks", "andesite"];
    assert!(assert_columns_stand_on_ground("bridge", &ravine, &d, &piers, 7).is_empty());
    // The deck stops at the banks, which rise into its lower layer.
    assert_eq!(placed(&d, IVec3::new(2, 8, 1)), None);
    assert!(placed(&d, IVec3::new(15, 8, 1)).is_some());
}

#[test]
fn footpath_posts_go_down_to_the_ground_through_water() {
    // A pond (water below y = 3) with an islet at x 8..12, a sunken bar at
    // x 16..23 that stays under water, and banks as high as the box.
    let size = IVec3::new(30, 6, 3);
    let pond = world(size, |x, y, _| {
        let ground = match x {
            8..12 => 4,
            16..23 => 2,
            0..3 | 27.. => 6,
            _ => 1,
        };
        if y < ground {
            "dirt"
        } else if y < 3 {
            "water"
        } else {
            ""
        }
    });
    let d = derive("footpath", Some(&pond), size, 3);
    assert_no_solid_replaced("footpath", &pond, &d);
    let posts = assert_columns_stand_on_ground("footpath", &pond, &d, &["oak_log"], 4);
    // Posts stand every fourth block at both edges: on the islet, and down
    // through the water to the pond floor and the sunken bar.
    let every: Vec<(i32, i32)> = [5, 9, 13, 17, 21, 25].iter().flat_map(|&x| [(x, 0), (x, 2)]).collect();
    assert_eq!(posts, every);
    for (x, z) in posts {
        let ground = (0..6).take_while(|&y| solid(&pond, IVec3::new(x, y, z))).count() as i32;
        assert_eq!(placed(&d, IVec3::new(x, ground, z)), Some("oak_log"), "post at x {x} reaches the ground");
    }
    // The walk runs from bank to bank; the banks themselves stay.
    for x in 0..30 {
        let on_bank = !(3..27).contains(&x);
        assert_eq!(placed(&d, IVec3::new(x, 5, 1)).is_none(), on_bank, "walk at x {x}");
    }
}

#[test]
fn tunnel_lines_only_the_strips_inside_the_hill() {
    // A hill across the middle of the box; its flanks are lower near the
    // ends, so some strips hold rock and some do not.
    let size = IVec3::new(30, 6, 7);
    let hill = world(size, |x, y, z| if y < 14 - ((x - 15).abs() + (z - 3).abs() / 2) { "stone" } else { "" });
    let d = derive("tunnel", Some(&hill), size, 4);
    let strip_has_rock = |x: i32, ys: std::ops::Range<i32>, zs: std::ops::Range<i32>| {
        ys.clone().any(|y| zs.clone().any(|z| solid(&hill, IVec3::new(x, y, z))))
    };
    for x in 0..30 {
        // Walls: the strips at z = 0 and z = 6, lined block by block where
        // the hill is, never above it.
        for z in [0, 6] {
            for y in 0..6 {
                let p = IVec3::new(x, y, z);
                assert_eq!(placed(&d, p).is_some(), solid(&hill, p), "wall at {p}");
            }
        }
        // Roof: the top layer between the walls, wherever the top of the
        // passage (or the roof layer) holds rock, and the top dug under it.
        let roofed = placed(&d, IVec3::new(x, 5, 3)).is_some();
        assert_eq!(roofed, strip_has_rock(x, 4..6, 1..6), "roof strip at x {x}");
        assert_eq!(placed(&d, IVec3::new(x, 4, 2)) == Some("air"), roofed, "top of the passage at x {x}");
        // Below it the passage is dug out only where it runs through rock.
        let dug = placed(&d, IVec3::new(x, 1, 3)) == Some("air");
        assert_eq!(dug, strip_has_rock(x, 0..4, 1..6), "passage at x {x}");
    }
    // Lanterns hang under the roof.
    let mut lanterns = 0;
    for (p, c) in d.blocks.iter_set() {
        if d.blocks.palette[c as usize].id() == "lantern" {
            lanterns += 1;
            assert!(placed(&d, p + IVec3::Y).is_some_and(|b| b != "air"), "lantern at {p} hangs from nothing");
        }
    }
    assert!(lanterns > 0);
}

#[test]
fn castle_scales_to_a_large_box() {
    let size = IVec3::new(256, 64, 256);
    let d = derive("castle", None, size, 9);
    let b = &d.blocks;
    let ids: Vec<&str> = b.palette.iter().map(|s| s.id()).collect();
    for want in ["stone_bricks", "glass_pane", "spruce_planks", "gravel", "air"] {
        assert!(ids.contains(&want), "no {want} in {ids:?}");
    }
    // Corner towers (15 wide) stand on the ground layer in all four corners.
    for (x, z) in [(0, 0), (255, 0), (0, 255), (255, 255)] {
        assert!(matches!(
            placed(&d, IVec3::new(x, 10, z)),
            Some("stone_bricks" | "cracked_stone_bricks" | "mossy_stone_bricks")
        ));
    }
    // The gate passage in the middle of the north wall is open.
    assert_eq!(placed(&d, IVec3::new(128, 2, 7)), Some("air"));
    // The keep in the middle has floors and a ring of merlons.
    assert!(placed(&d, IVec3::new(128, 63, 128)).is_some());
    assert!(d.stats.filled > 800_000, "{:?}", d.stats);
    assert_eq!(d.stats.backtracks, 0);
}

#[test]
fn buildings_fill_their_boxes_sensibly() {
    let d = derive("house", None, IVec3::new(9, 10, 7), 1);
    assert_eq!(placed(&d, IVec3::new(4, 0, 3)), Some("cobblestone"));
    assert_eq!(placed(&d, IVec3::new(4, 1, 6)), Some("oak_door"), "door");
    assert_eq!(placed(&d, IVec3::new(0, 3, 0)), Some("oak_log"));
    assert!(d.blocks.palette.iter().any(|b| b.id() == "glass_pane"));
    // Stepped roof: the ridge is one block wide along x.
    assert!(placed(&d, IVec3::new(4, 9, 3)).is_some());
    assert!(placed(&d, IVec3::new(4, 9, 2)).is_none());
    let d = derive("temple", None, IVec3::new(31, 16, 19), 1);
    assert_eq!(placed(&d, IVec3::new(1, 3, 1)), Some("quartz_pillar"), "corner column");
    assert_eq!(placed(&d, IVec3::new(29, 3, 17)), Some("quartz_pillar"), "corner column");
    assert_eq!(placed(&d, IVec3::new(0, 0, 0)).map(|s| s == "stone_bricks" || s == "polished_andesite"), Some(true));
    // Both long boxes and turned ones work.
    let d = derive("temple", None, IVec3::new(19, 16, 31), 1);
    assert_eq!(placed(&d, IVec3::new(1, 3, 1)), Some("quartz_pillar"));
}
