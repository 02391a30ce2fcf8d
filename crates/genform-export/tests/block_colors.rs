//! Every block id of the Minecraft versions the exporter writes has a
//! preview colour of its own (not the hashed fallback), and previews of
//! wooden structures show wood, not magenta.
//!
//! The id lists are the box-split compiler's (`crates/genform-boxsplit/data`,
//! extracted from the npm package `minecraft-data` 3.119.0, MIT; see the
//! README there): 1.21.1 (DataVersion 3955, the default) and 1.19.4
//! (DataVersion 3337), which together hold every id of the versions between.

use genform_core::BlockState;
use genform_core::blocks::BlockGrid;
use genform_core::scene::Scene;
use genform_export::minecraft::{block_color, known_block_color};
use genform_export::{RenderOptions, render_rgb, tag_color};
use glam::{IVec3, UVec3};

const BLOCKS_1_21_1: &str = include_str!("../../genform-boxsplit/data/blocks-1.21.1.txt");
const BLOCKS_1_19_4: &str = include_str!("../../genform-boxsplit/data/blocks-1.19.4.txt");

fn ids(text: &str) -> Vec<&str> {
    text.lines().map(str::trim).filter(|l| !l.is_empty() && !l.starts_with('#')).collect()
}

fn color(id: &str) -> [u8; 3] {
    known_block_color(id).unwrap_or_else(|| panic!("{id}: no preview colour"))
}

/// Hue in degrees, saturation and value in [0, 1].
fn hsv([r, g, b]: [u8; 3]) -> (f32, f32, f32) {
    let [r, g, b] = [r, g, b].map(|c| f32::from(c) / 255.0);
    let (max, min) = (r.max(g).max(b), r.min(g).min(b));
    let d = max - min;
    let hue = if d == 0.0 {
        0.0
    } else if max == r {
        60.0 * ((g - b) / d).rem_euclid(6.0)
    } else if max == g {
        60.0 * ((b - r) / d + 2.0)
    } else {
        60.0 * ((r - g) / d + 4.0)
    };
    (hue, if max == 0.0 { 0.0 } else { d / max }, max)
}

fn distance(a: [u8; 3], b: [u8; 3]) -> i32 {
    a.iter().zip(b).map(|(&x, y)| (i32::from(x) - i32::from(y)).abs()).max().unwrap_or(0)
}

/// Magenta as the hashed fallback paints stripped wood (220, 127, 214):
/// red and blue both well above green.
fn magenta([r, g, b]: [u8; 3]) -> bool {
    let [r, g, b] = [r, g, b].map(i32::from);
    r > g + 40 && b > g + 40
}

#[test]
fn every_block_id_of_1_19_4_to_1_21_1_has_a_colour() {
    let new = ids(BLOCKS_1_21_1);
    let old = ids(BLOCKS_1_19_4);
    assert!(new.len() > 1000 && old.len() > 900, "lists read: {} and {}", new.len(), old.len());
    let missing: Vec<&str> = new.iter().chain(&old).copied().filter(|id| known_block_color(id).is_none()).collect();
    assert!(missing.is_empty(), "{} ids without a preview colour: {missing:?}", missing.len());
    for &id in new.iter().chain(&old) {
        let state = BlockState::new(id);
        assert_eq!(block_color(&state), color(id), "{id}");
        assert_eq!(known_block_color(&format!("minecraft:{id}")), Some(color(id)), "{id} with namespace");
    }
    // Unknown ids still get the hashed colour.
    assert_eq!(known_block_color("mod:strange_block"), None);
    assert_eq!(block_color(&BlockState::new("mod:strange_block")), tag_color("strange_block"));
}

#[test]
fn stripped_wood_is_wood_coloured() {
    for wood in ["oak", "spruce", "birch", "jungle", "acacia", "dark_oak", "mangrove"] {
        for kind in ["log", "wood"] {
            let id = format!("stripped_{wood}_{kind}");
            let c = color(&id);
            let (hue, sat, _) = hsv(c);
            assert!(!magenta(c), "{id}: {c:?}");
            assert!((0.0..=50.0).contains(&hue) && sat < 0.7, "{id}: {c:?} hue {hue} saturation {sat}");
            // Close to the planks (the same inner wood), not to the bark.
            assert!(distance(c, color(&format!("{wood}_planks"))) <= 40, "{id}: {c:?}");
        }
    }
    let [r, g, b] = color("stripped_spruce_wood");
    assert!(r > g && g > b, "stripped_spruce_wood brownish: {:?}", [r, g, b]);
    let (_, sat, _) = hsv([r, g, b]);
    assert!(sat < 0.6, "stripped_spruce_wood saturation {sat}");
    assert_ne!(color("stripped_spruce_wood"), color("spruce_wood"), "stripped is the inner colour, not bark");
    assert_eq!(color("stripped_spruce_wood"), color("stripped_spruce_log"));
    for (a, b) in [("stripped_crimson_stem", "crimson_planks"), ("stripped_warped_hyphae", "warped_planks")] {
        assert!(distance(color(a), color(b)) <= 50, "{a}: {:?} vs {b}: {:?}", color(a), color(b));
    }
}

#[test]
fn waxed_copper_is_copper_of_the_same_oxidation() {
    for stage in ["", "exposed_", "weathered_", "oxidized_"] {
        let plain = if stage.is_empty() { "copper_block".to_string() } else { format!("{stage}copper") };
        assert_eq!(color(&format!("waxed_{plain}")), color(&plain), "{plain}");
        for shape in ["cut_copper", "cut_copper_slab", "cut_copper_stairs", "chiseled_copper", "copper_grate"] {
            let id = format!("{stage}{shape}");
            assert_eq!(color(&format!("waxed_{id}")), color(&id), "{id}");
        }
        for shape in ["copper_door", "copper_trapdoor", "copper_bulb", "cut_copper"] {
            assert!(distance(color(&format!("{stage}{shape}")), color(&plain)) <= 25, "{stage}{shape}");
        }
    }
    // Oxidation turns copper from orange to green.
    let (fresh, oxidized) = (color("copper_block"), color("waxed_oxidized_copper"));
    assert!(fresh[0] > fresh[1] && fresh[1] > fresh[2], "{fresh:?}");
    assert!(oxidized[1] > oxidized[0] && oxidized[1] > oxidized[2], "{oxidized:?}");
}

#[test]
fn dyed_blocks_take_the_dye_colour() {
    let red_wool = color("red_wool");
    assert!(red_wool[0] > 2 * red_wool[1] && red_wool[0] > 2 * red_wool[2], "red_wool {red_wool:?}");
    let materials = [
        "wool",
        "carpet",
        "bed",
        "banner",
        "wall_banner",
        "candle",
        "concrete",
        "concrete_powder",
        "stained_glass",
        "stained_glass_pane",
        "shulker_box",
        "glazed_terracotta",
    ];
    // Strongly coloured dyes keep their hue on every material but
    // terracotta (which is muted); glazed terracotta is patterned, so
    // only roughly.
    for (dye, lo, hi) in [("red", 340.0, 20.0), ("lime", 70.0, 110.0), ("blue", 220.0, 250.0), ("yellow", 35.0, 65.0)] {
        for m in materials {
            let id = format!("{dye}_{m}");
            let (hue, sat, _) = hsv(color(&id));
            let in_range = if lo < hi { (lo..=hi).contains(&hue) } else { hue >= lo || hue <= hi };
            assert!(in_range && sat > 0.3, "{id}: {:?} hue {hue} saturation {sat}", color(&id));
        }
    }
    assert_eq!(color("red_carpet"), red_wool);
    assert_eq!(color("red_wall_banner"), color("red_banner"));
    assert_eq!(color("white_candle_cake"), color("cake"));
    // Terracotta is earthier than concrete of the same dye.
    for dye in ["red", "blue", "green", "magenta"] {
        let (_, t, _) = hsv(color(&format!("{dye}_terracotta")));
        let (_, c, _) = hsv(color(&format!("{dye}_concrete")));
        assert!(t < c, "{dye}: terracotta saturation {t} vs concrete {c}");
    }
    // Look-alikes outside the family keep their own colours.
    assert_ne!(color("red_nether_bricks"), red_wool);
    assert_ne!(color("red_sand"), red_wool);
    assert_ne!(color("blue_ice"), color("blue_wool"));
    assert_ne!(color("brown_mushroom_block"), color("brown_wool"));
}

#[test]
fn shapes_and_wall_variants_take_their_base() {
    let same = |a: &str, b: &str| assert_eq!(color(a), color(b), "{a} vs {b}");
    same("oak_stairs", "oak_planks");
    same("spruce_fence", "spruce_planks");
    same("spruce_fence_gate", "spruce_planks");
    same("birch_door", "birch_planks");
    same("acacia_trapdoor", "acacia_planks");
    same("dark_oak_button", "dark_oak_planks");
    same("cherry_pressure_plate", "cherry_planks");
    same("crimson_slab", "crimson_planks");
    same("stone_brick_wall", "stone_bricks");
    same("mossy_cobblestone_slab", "mossy_cobblestone");
    same("deepslate_tile_stairs", "deepslate_tiles");
    same("polished_blackstone_brick_wall", "polished_blackstone_bricks");
    same("end_stone_brick_slab", "end_stone_bricks");
    same("smooth_quartz_stairs", "smooth_quartz");
    same("cut_red_sandstone_slab", "cut_red_sandstone");
    same("stone_button", "stone");
    same("polished_blackstone_pressure_plate", "polished_blackstone");
    same("iron_door", "iron_block");
    same("glass_pane", "glass");
    same("wall_torch", "torch");
    same("soul_wall_torch", "soul_torch");
    same("redstone_wall_torch", "redstone_torch");
    same("zombie_wall_head", "zombie_head");
    same("wither_skeleton_wall_skull", "wither_skeleton_skull");
    same("jungle_wall_sign", "jungle_sign");
    same("fire_coral_wall_fan", "fire_coral_fan");
    same("infested_deepslate", "deepslate");
    same("potted_red_tulip", "red_tulip");
    same("potted_flowering_azalea_bush", "flowering_azalea");
    same("potted_warped_fungus", "warped_fungus");
}

/// A bridge as `examples/boxsplit/bridge.bsg` builds it — a deck of spruce
/// planks with stripped spruce wood in it, spruce fence railings, piers of
/// stone bricks, cracked stone bricks and andesite — over grass, stone and
/// water.
fn bridge() -> BlockGrid {
    let size = UVec3::new(24, 10, 5);
    let mut g = BlockGrid::new(IVec3::ZERO, size);
    let s = |id: &str| BlockState::new(id);
    for x in 0..24i32 {
        for z in 0..5 {
            let ground = ((x - 12).abs() / 3).clamp(1, 6);
            for y in 0..ground {
                g.set(IVec3::new(x, y, z), &s(if y + 1 == ground { "grass_block" } else { "stone" }));
            }
            if ground < 2 {
                g.set(IVec3::new(x, 1, z), &s("water"));
            }
            // Every third deck block is stripped wood, whole rows of it.
            let deck = if x % 3 == 1 || z == 2 { "stripped_spruce_wood" } else { "spruce_planks" };
            g.set(IVec3::new(x, 8, z), &s(deck));
            if z == 0 || z == 4 {
                g.set(IVec3::new(x, 9, z), &s("spruce_fence[east=true,west=true]"));
            }
            if x % 6 == 2 {
                let pier = ["stone_bricks", "cracked_stone_bricks", "andesite"][(x as usize + z as usize) % 3];
                for y in ground.max(2)..8 {
                    g.set(IVec3::new(x, y, z), &s(pier));
                }
            }
        }
    }
    g
}

#[test]
fn a_bridge_preview_has_no_magenta() {
    let mut scene = Scene::new();
    scene.blocks.push(bridge());
    let opts = RenderOptions { width: 400, height: 300, ..RenderOptions::default() };
    let (rgb, _, _) = render_rgb(&scene, &opts);
    let pixels: Vec<[u8; 3]> = rgb.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
    let purple = pixels.iter().filter(|&&p| magenta(p)).count();
    assert_eq!(purple, 0, "magenta pixels in the bridge preview");
    // The stripped deck is drawn: many brown pixels (red over green over
    // blue, not grey), far from the background.
    let brown = pixels
        .iter()
        .filter(|&&[r, g, b]| {
            let [r, g, b] = [r, g, b].map(i32::from);
            r > g + 10 && g > b + 10 && r < 220
        })
        .count();
    assert!(brown > 2000, "only {brown} brown pixels");
    // The old fallback colour of stripped spruce wood would have shown.
    assert!(magenta(tag_color("stripped_spruce_wood")));
}
