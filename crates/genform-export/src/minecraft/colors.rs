//! Display colours of blocks: a small table of common blocks and families
//! (roughly their texture's average), else the crate's hashed tag colour.

use crate::palette::tag_color;
use genform_core::blocks::BlockState;

/// Common blocks by id (without namespace), 8-bit sRGB.
const TABLE: &[(&str, [u8; 3])] = &[
    ("stone", [125, 125, 125]),
    ("quartz_block", [235, 229, 222]),
    ("lapis_block", [31, 67, 140]),
    ("smooth_quartz", [236, 230, 223]),
    ("chiseled_quartz_block", [231, 226, 218]),
    ("quartz_pillar", [235, 230, 224]),
    ("quartz_bricks", [234, 229, 221]),
    ("polished_andesite", [132, 134, 133]),
    ("polished_diorite", [192, 193, 194]),
    ("polished_granite", [154, 106, 89]),
    ("smooth_sandstone", [223, 214, 170]),
    ("white_terracotta", [209, 178, 161]),
    ("cobblestone", [122, 121, 122]),
    ("mossy_cobblestone", [110, 118, 95]),
    ("stone_bricks", [122, 121, 122]),
    ("mossy_stone_bricks", [115, 121, 105]),
    ("cracked_stone_bricks", [118, 117, 118]),
    ("smooth_stone", [159, 159, 159]),
    ("andesite", [136, 136, 137]),
    ("diorite", [189, 188, 189]),
    ("granite", [149, 103, 86]),
    ("deepslate", [80, 80, 82]),
    ("tuff", [108, 109, 103]),
    ("bedrock", [85, 85, 85]),
    ("dirt", [134, 96, 67]),
    ("coarse_dirt", [119, 86, 59]),
    ("rooted_dirt", [144, 104, 77]),
    ("grass_block", [95, 159, 53]),
    ("podzol", [92, 63, 24]),
    ("mycelium", [111, 99, 105]),
    ("dirt_path", [148, 122, 65]),
    ("farmland", [81, 44, 15]),
    ("mud", [60, 57, 61]),
    ("clay", [160, 166, 179]),
    ("gravel", [131, 127, 126]),
    ("sand", [219, 207, 163]),
    ("red_sand", [190, 102, 33]),
    ("sandstone", [216, 203, 155]),
    ("red_sandstone", [181, 97, 31]),
    ("snow", [249, 254, 254]),
    ("snow_block", [249, 254, 254]),
    ("powder_snow", [248, 253, 253]),
    ("ice", [145, 183, 253]),
    ("packed_ice", [141, 180, 250]),
    ("blue_ice", [116, 167, 253]),
    ("water", [63, 118, 228]),
    ("bubble_column", [63, 118, 228]),
    ("lava", [207, 92, 20]),
    ("obsidian", [15, 10, 24]),
    ("glass", [200, 220, 225]),
    ("glass_pane", [200, 220, 225]),
    ("bricks", [150, 97, 83]),
    ("terracotta", [152, 94, 67]),
    ("bookshelf", [117, 94, 59]),
    ("glowstone", [171, 131, 84]),
    ("torch", [255, 200, 80]),
    ("wall_torch", [255, 200, 80]),
    ("lantern", [106, 91, 83]),
    ("iron_block", [220, 220, 220]),
    ("gold_block", [246, 208, 61]),
    ("diamond_block", [98, 237, 228]),
    ("emerald_block", [42, 203, 87]),
    ("coal_ore", [105, 105, 105]),
    ("iron_ore", [136, 129, 122]),
    ("copper_ore", [124, 125, 120]),
    ("cactus", [85, 127, 43]),
    ("pumpkin", [198, 118, 24]),
    ("hay_block", [166, 139, 12]),
    ("short_grass", [91, 140, 60]),
    ("grass", [91, 140, 60]),
    ("tall_grass", [91, 140, 60]),
    ("fern", [80, 128, 55]),
    ("seagrass", [40, 110, 40]),
    ("tall_seagrass", [40, 110, 40]),
    ("kelp", [87, 130, 42]),
    ("kelp_plant", [87, 130, 42]),
    ("vine", [60, 100, 30]),
    ("lily_pad", [32, 128, 48]),
    ("sugar_cane", [148, 192, 101]),
    ("dandelion", [240, 220, 40]),
    ("poppy", [200, 30, 30]),
    ("structure_void", [255, 255, 255]),
];

/// Dye colours, for `<dye>_wool`, `_concrete`, `_terracotta`, ….
const DYES: &[(&str, [u8; 3])] = &[
    ("white", [234, 236, 237]),
    ("orange", [241, 118, 20]),
    ("magenta", [190, 69, 180]),
    ("light_blue", [58, 175, 217]),
    ("yellow", [249, 199, 36]),
    ("lime", [112, 185, 26]),
    ("pink", [238, 141, 172]),
    ("gray", [63, 68, 72]),
    ("light_gray", [142, 142, 135]),
    ("cyan", [21, 138, 145]),
    ("purple", [122, 42, 173]),
    ("blue", [53, 57, 157]),
    ("brown", [114, 72, 41]),
    ("green", [85, 110, 28]),
    ("red", [161, 39, 35]),
    ("black", [21, 21, 26]),
];

/// Wood types: (planks colour, log bark colour).
const WOODS: &[(&str, [u8; 3], [u8; 3])] = &[
    ("oak", [162, 131, 79], [109, 85, 51]),
    ("spruce", [115, 85, 49], [59, 38, 17]),
    ("birch", [192, 175, 121], [216, 215, 210]),
    ("jungle", [160, 115, 81], [85, 68, 25]),
    ("acacia", [168, 90, 50], [103, 97, 87]),
    ("dark_oak", [67, 43, 20], [60, 47, 26]),
    ("mangrove", [117, 54, 48], [84, 67, 41]),
    ("cherry", [226, 178, 172], [55, 33, 44]),
    ("bamboo", [194, 173, 80], [140, 160, 60]),
    ("crimson", [101, 48, 70], [92, 25, 29]),
    ("warped", [43, 105, 99], [58, 58, 77]),
];

/// The display colour of a block state (8-bit sRGB), from its id:
/// common blocks and families (dyed blocks, wood, leaves, stone variants)
/// have fixed colours; anything else gets [`crate::tag_color`] of its id.
pub fn block_color(state: &BlockState) -> [u8; 3] {
    let id = state.id();
    if let Some((_, c)) = TABLE.iter().find(|(n, _)| *n == id) {
        return *c;
    }
    // Dyed blocks: longest dye prefix first (light_blue before blue).
    if let Some((_, c)) = DYES
        .iter()
        .filter(|(d, _)| id.strip_prefix(d).is_some_and(|rest| rest.starts_with('_')))
        .max_by_key(|(d, _)| d.len())
    {
        return *c;
    }
    if id.ends_with("_leaves") {
        return if id.starts_with("cherry") { [229, 172, 194] } else { [58, 110, 36] };
    }
    if let Some((_, planks, bark)) = WOODS
        .iter()
        .filter(|(w, _, _)| id.strip_prefix(w).is_some_and(|rest| rest.starts_with('_')))
        .max_by_key(|(w, _, _)| w.len())
    {
        let barky =
            ["_log", "_wood", "_stem", "_hyphae"].iter().any(|s| id.ends_with(s)) && !id.starts_with("stripped");
        return if barky { *bark } else { *planks };
    }
    // Stairs, slabs and walls of a listed material take its colour.
    for suffix in ["_stairs", "_slab", "_wall"] {
        if let Some(base) = id.strip_suffix(suffix) {
            for cand in [base.to_string(), format!("{base}s")] {
                if let Some((_, c)) = TABLE.iter().find(|(n, _)| *n == cand) {
                    return *c;
                }
            }
        }
    }
    tag_color(id)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn families_and_fallback() {
        let c = |s: &str| block_color(&BlockState::parse(s).unwrap());
        assert_eq!(c("stone"), [125, 125, 125]);
        assert_eq!(c("minecraft:water[level=0]"), c("water"));
        assert_eq!(c("light_blue_wool"), [58, 175, 217]);
        assert_eq!(c("blue_concrete"), [53, 57, 157]);
        assert_eq!(c("oak_planks"), [162, 131, 79]);
        assert_eq!(c("oak_stairs[facing=east]"), [162, 131, 79]);
        assert_eq!(c("dark_oak_log[axis=y]"), [60, 47, 26]);
        assert_eq!(c("birch_leaves"), [58, 110, 36]);
        assert_eq!(c("stone_brick_stairs"), c("stone_bricks"));
        assert_eq!(c("mod:strange_block"), tag_color("strange_block"));
    }
}
