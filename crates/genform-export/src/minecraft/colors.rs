//! Display colours of blocks (roughly their texture's average, 8-bit sRGB)
//! for every block id of Minecraft Java Edition 1.19.4 to 1.21.1: a table
//! of single blocks, and rules for the families (dyed blocks by material,
//! woods, copper by oxidation, corals, and the shapes — stairs, slabs,
//! walls, fences, doors, … — of a base material). Ids none of them knows
//! (mods' blocks, newer versions) get the crate's hashed tag colour.

use crate::palette::tag_color;
use genform_core::blocks::BlockState;

/// Single blocks by id (without namespace).
const TABLE: &[(&str, [u8; 3])] = &[
    // Stone and its relatives.
    ("stone", [125, 125, 125]),
    ("smooth_stone", [159, 159, 159]),
    ("cobblestone", [122, 121, 122]),
    ("mossy_cobblestone", [110, 118, 95]),
    ("stone_bricks", [122, 121, 122]),
    ("mossy_stone_bricks", [115, 121, 105]),
    ("cracked_stone_bricks", [118, 117, 118]),
    ("chiseled_stone_bricks", [119, 118, 119]),
    ("andesite", [136, 136, 137]),
    ("polished_andesite", [132, 134, 133]),
    ("diorite", [189, 188, 189]),
    ("polished_diorite", [192, 193, 194]),
    ("granite", [149, 103, 86]),
    ("polished_granite", [154, 106, 89]),
    ("deepslate", [80, 80, 82]),
    ("cobbled_deepslate", [77, 77, 80]),
    ("polished_deepslate", [72, 72, 73]),
    ("chiseled_deepslate", [54, 54, 54]),
    ("deepslate_bricks", [70, 70, 71]),
    ("cracked_deepslate_bricks", [64, 64, 65]),
    ("deepslate_tiles", [54, 54, 55]),
    ("cracked_deepslate_tiles", [52, 52, 52]),
    ("reinforced_deepslate", [80, 83, 79]),
    ("tuff", [108, 109, 103]),
    ("polished_tuff", [97, 104, 99]),
    ("chiseled_tuff", [89, 93, 87]),
    ("tuff_bricks", [98, 101, 95]),
    ("chiseled_tuff_bricks", [98, 102, 95]),
    ("calcite", [223, 224, 220]),
    ("dripstone_block", [134, 107, 92]),
    ("pointed_dripstone", [129, 102, 89]),
    ("bedrock", [85, 85, 85]),
    ("obsidian", [15, 10, 24]),
    ("crying_obsidian", [33, 10, 60]),
    ("basalt", [80, 81, 86]),
    ("polished_basalt", [88, 88, 91]),
    ("smooth_basalt", [72, 72, 78]),
    ("blackstone", [42, 36, 41]),
    ("polished_blackstone", [53, 48, 56]),
    ("chiseled_polished_blackstone", [53, 48, 56]),
    ("polished_blackstone_bricks", [48, 42, 49]),
    ("cracked_polished_blackstone_bricks", [44, 37, 43]),
    ("gilded_blackstone", [56, 43, 38]),
    ("sandstone", [216, 203, 155]),
    ("smooth_sandstone", [223, 214, 170]),
    ("cut_sandstone", [217, 206, 159]),
    ("chiseled_sandstone", [216, 203, 155]),
    ("red_sandstone", [181, 97, 31]),
    ("smooth_red_sandstone", [181, 97, 31]),
    ("cut_red_sandstone", [189, 101, 31]),
    ("chiseled_red_sandstone", [183, 96, 27]),
    ("bricks", [150, 97, 83]),
    ("mud_bricks", [137, 103, 79]),
    ("packed_mud", [142, 106, 79]),
    ("prismarine", [99, 156, 151]),
    ("prismarine_bricks", [99, 171, 158]),
    ("dark_prismarine", [51, 91, 75]),
    ("quartz_block", [235, 229, 222]),
    ("smooth_quartz", [236, 230, 223]),
    ("chiseled_quartz_block", [231, 226, 218]),
    ("quartz_pillar", [235, 230, 224]),
    ("quartz_bricks", [234, 229, 221]),
    ("purpur_block", [169, 125, 169]),
    ("purpur_pillar", [171, 129, 171]),
    ("end_stone", [219, 222, 158]),
    ("end_stone_bricks", [218, 224, 162]),
    ("netherrack", [97, 38, 38]),
    ("nether_bricks", [44, 21, 26]),
    ("cracked_nether_bricks", [40, 20, 23]),
    ("chiseled_nether_bricks", [47, 23, 28]),
    ("red_nether_bricks", [69, 7, 9]),
    ("magma_block", [142, 63, 31]),
    ("soul_sand", [81, 62, 51]),
    ("soul_soil", [75, 57, 46]),
    ("amethyst_block", [133, 97, 191]),
    ("budding_amethyst", [132, 96, 186]),
    ("amethyst_cluster", [163, 126, 207]),
    ("large_amethyst_bud", [161, 126, 204]),
    ("medium_amethyst_bud", [158, 123, 202]),
    ("small_amethyst_bud", [155, 120, 200]),
    // Ores and mineral blocks.
    ("coal_ore", [105, 105, 105]),
    ("iron_ore", [136, 129, 122]),
    ("copper_ore", [124, 125, 120]),
    ("gold_ore", [145, 133, 106]),
    ("redstone_ore", [140, 110, 110]),
    ("emerald_ore", [117, 137, 124]),
    ("lapis_ore", [107, 118, 141]),
    ("diamond_ore", [121, 141, 140]),
    ("deepslate_coal_ore", [74, 74, 76]),
    ("deepslate_iron_ore", [106, 99, 94]),
    ("deepslate_copper_ore", [92, 93, 89]),
    ("deepslate_gold_ore", [115, 103, 78]),
    ("deepslate_redstone_ore", [104, 73, 74]),
    ("deepslate_emerald_ore", [78, 104, 87]),
    ("deepslate_lapis_ore", [79, 90, 115]),
    ("deepslate_diamond_ore", [83, 106, 106]),
    ("nether_gold_ore", [115, 54, 42]),
    ("nether_quartz_ore", [117, 65, 62]),
    ("ancient_debris", [96, 64, 56]),
    ("coal_block", [16, 15, 15]),
    ("iron_block", [220, 220, 220]),
    ("gold_block", [246, 208, 61]),
    ("diamond_block", [98, 237, 228]),
    ("emerald_block", [42, 203, 87]),
    ("lapis_block", [31, 67, 140]),
    ("redstone_block", [175, 24, 5]),
    ("netherite_block", [66, 61, 63]),
    ("raw_copper_block", [154, 105, 79]),
    ("raw_gold_block", [221, 169, 46]),
    ("raw_iron_block", [166, 135, 107]),
    // Ground.
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
    ("suspicious_gravel", [129, 125, 123]),
    ("sand", [219, 207, 163]),
    ("suspicious_sand", [217, 204, 159]),
    ("red_sand", [190, 102, 33]),
    ("terracotta", [152, 94, 67]),
    ("moss_block", [89, 109, 45]),
    ("crimson_nylium", [130, 31, 31]),
    ("warped_nylium", [43, 114, 101]),
    ("sculk", [12, 29, 36]),
    ("sculk_vein", [8, 48, 57]),
    ("sculk_catalyst", [30, 45, 45]),
    ("sculk_sensor", [7, 70, 84]),
    ("calibrated_sculk_sensor", [40, 70, 100]),
    ("sculk_shrieker", [198, 205, 169]),
    // Snow, ice, liquids.
    ("snow", [249, 254, 254]),
    ("snow_block", [249, 254, 254]),
    ("powder_snow", [248, 253, 253]),
    ("ice", [145, 183, 253]),
    ("frosted_ice", [140, 180, 250]),
    ("packed_ice", [141, 180, 250]),
    ("blue_ice", [116, 167, 253]),
    ("water", [63, 118, 228]),
    ("bubble_column", [63, 118, 228]),
    ("lava", [207, 92, 20]),
    // Plants.
    ("short_grass", [91, 140, 60]),
    ("grass", [91, 140, 60]),
    ("tall_grass", [91, 140, 60]),
    ("fern", [80, 128, 55]),
    ("large_fern", [80, 128, 55]),
    ("dead_bush", [107, 79, 40]),
    ("seagrass", [40, 110, 40]),
    ("tall_seagrass", [40, 110, 40]),
    ("kelp", [87, 130, 42]),
    ("kelp_plant", [87, 130, 42]),
    ("dried_kelp_block", [50, 58, 38]),
    ("sea_pickle", [90, 97, 39]),
    ("vine", [60, 100, 30]),
    ("glow_lichen", [112, 131, 121]),
    ("lily_pad", [32, 128, 48]),
    ("sugar_cane", [148, 192, 101]),
    ("cactus", [85, 127, 43]),
    ("bamboo", [93, 144, 19]),
    ("bamboo_sapling", [92, 89, 35]),
    ("moss_carpet", [89, 109, 45]),
    ("azalea", [101, 124, 47]),
    ("flowering_azalea", [112, 121, 64]),
    ("big_dripleaf", [112, 141, 46]),
    ("big_dripleaf_stem", [91, 115, 46]),
    ("small_dripleaf", [92, 120, 42]),
    ("hanging_roots", [161, 115, 91]),
    ("spore_blossom", [206, 96, 158]),
    ("cave_vines", [106, 110, 42]),
    ("cave_vines_plant", [88, 101, 38]),
    ("sweet_berry_bush", [70, 100, 40]),
    ("dandelion", [240, 220, 40]),
    ("poppy", [200, 30, 30]),
    ("blue_orchid", [47, 162, 168]),
    ("allium", [158, 137, 183]),
    ("azure_bluet", [169, 204, 127]),
    ("red_tulip", [180, 50, 35]),
    ("orange_tulip", [200, 110, 40]),
    ("white_tulip", [200, 210, 190]),
    ("pink_tulip", [220, 160, 190]),
    ("oxeye_daisy", [215, 220, 200]),
    ("cornflower", [70, 105, 220]),
    ("lily_of_the_valley", [225, 230, 220]),
    ("wither_rose", [40, 45, 25]),
    ("torchflower", [200, 130, 50]),
    ("torchflower_crop", [90, 120, 60]),
    ("pink_petals", [238, 160, 190]),
    ("sunflower", [245, 200, 40]),
    ("lilac", [180, 140, 180]),
    ("rose_bush", [160, 40, 40]),
    ("peony", [220, 170, 220]),
    ("pitcher_plant", [100, 130, 160]),
    ("pitcher_crop", [100, 130, 90]),
    ("wheat", [150, 145, 65]),
    ("carrots", [81, 124, 37]),
    ("potatoes", [84, 135, 47]),
    ("beetroots", [93, 91, 30]),
    ("melon", [111, 145, 30]),
    ("melon_stem", [92, 140, 40]),
    ("attached_melon_stem", [141, 120, 46]),
    ("pumpkin", [198, 118, 24]),
    ("pumpkin_stem", [92, 140, 40]),
    ("attached_pumpkin_stem", [141, 120, 46]),
    ("carved_pumpkin", [150, 84, 17]),
    ("jack_o_lantern", [214, 152, 52]),
    ("cocoa", [145, 86, 40]),
    ("chorus_plant", [93, 57, 93]),
    ("chorus_flower", [151, 120, 151]),
    ("brown_mushroom", [153, 116, 92]),
    ("red_mushroom", [217, 75, 68]),
    ("brown_mushroom_block", [149, 111, 81]),
    ("red_mushroom_block", [200, 46, 45]),
    ("mushroom_stem", [203, 196, 185]),
    ("crimson_fungus", [141, 44, 29]),
    ("warped_fungus", [74, 109, 88]),
    ("crimson_roots", [126, 8, 41]),
    ("warped_roots", [20, 138, 124]),
    ("nether_sprouts", [19, 151, 133]),
    ("nether_wart", [111, 18, 19]),
    ("nether_wart_block", [114, 2, 2]),
    ("warped_wart_block", [22, 119, 121]),
    ("shroomlight", [240, 146, 70]),
    ("weeping_vines", [105, 1, 0]),
    ("weeping_vines_plant", [132, 16, 12]),
    ("twisting_vines", [20, 143, 124]),
    ("twisting_vines_plant", [20, 135, 122]),
    ("mangrove_roots", [74, 59, 38]),
    ("muddy_mangrove_roots", [70, 59, 45]),
    ("hay_block", [166, 139, 12]),
    ("ochre_froglight", [241, 220, 150]),
    ("verdant_froglight", [210, 235, 200]),
    ("pearlescent_froglight", [240, 225, 230]),
    ("frogspawn", [70, 60, 60]),
    ("turtle_egg", [228, 226, 191]),
    ("sniffer_egg", [160, 80, 60]),
    ("dragon_egg", [12, 9, 15]),
    ("honey_block", [251, 185, 52]),
    ("honeycomb_block", [229, 148, 29]),
    ("bee_nest", [202, 160, 74]),
    ("beehive", [180, 146, 90]),
    ("slime_block", [111, 192, 91]),
    ("sponge", [195, 192, 74]),
    ("wet_sponge", [171, 181, 70]),
    ("cobweb", [228, 233, 234]),
    ("bone_block", [229, 225, 207]),
    // Leaves (the plains' foliage tint where the game tints them) and saplings.
    ("oak_leaves", [58, 110, 36]),
    ("spruce_leaves", [59, 90, 59]),
    ("birch_leaves", [87, 115, 55]),
    ("jungle_leaves", [58, 110, 36]),
    ("acacia_leaves", [58, 110, 36]),
    ("dark_oak_leaves", [58, 110, 36]),
    ("mangrove_leaves", [58, 110, 36]),
    ("cherry_leaves", [229, 172, 194]),
    ("azalea_leaves", [90, 115, 44]),
    ("flowering_azalea_leaves", [99, 112, 62]),
    ("pale_oak_leaves", [160, 166, 160]),
    ("oak_sapling", [77, 106, 40]),
    ("spruce_sapling", [44, 60, 36]),
    ("birch_sapling", [118, 150, 84]),
    ("jungle_sapling", [48, 81, 16]),
    ("acacia_sapling", [118, 117, 23]),
    ("dark_oak_sapling", [61, 90, 30]),
    ("cherry_sapling", [164, 117, 143]),
    ("pale_oak_sapling", [120, 125, 115]),
    ("mangrove_propagule", [96, 174, 83]),
    // Wood that is not a wood type's planks or log.
    ("bamboo_block", [127, 144, 58]),
    ("stripped_bamboo_block", [193, 173, 80]),
    ("bamboo_mosaic", [190, 170, 78]),
    ("petrified_oak_slab", [162, 131, 79]),
    ("bookshelf", [117, 94, 59]),
    ("chiseled_bookshelf", [110, 90, 60]),
    ("crafting_table", [120, 90, 55]),
    ("cartography_table", [103, 87, 67]),
    ("fletching_table", [197, 180, 133]),
    ("smithing_table", [57, 58, 70]),
    ("loom", [142, 119, 91]),
    ("barrel", [134, 100, 58]),
    ("composter", [117, 79, 40]),
    ("lectern", [173, 137, 83]),
    ("note_block", [88, 58, 40]),
    ("jukebox", [93, 64, 47]),
    ("chest", [155, 114, 42]),
    ("trapped_chest", [155, 114, 42]),
    ("ladder", [124, 96, 54]),
    ("scaffolding", [174, 134, 80]),
    ("campfire", [140, 100, 50]),
    ("soul_campfire", [60, 120, 130]),
    // Light sources.
    ("torch", [255, 200, 80]),
    ("soul_torch", [80, 180, 190]),
    ("redstone_torch", [200, 60, 30]),
    ("lantern", [106, 91, 83]),
    ("soul_lantern", [71, 99, 114]),
    ("glowstone", [171, 131, 84]),
    ("sea_lantern", [172, 199, 190]),
    ("redstone_lamp", [95, 54, 30]),
    ("end_rod", [205, 196, 185]),
    ("fire", [211, 140, 53]),
    ("soul_fire", [51, 192, 197]),
    ("candle", [233, 209, 163]),
    ("light", [250, 245, 200]),
    // Glass.
    ("glass", [200, 220, 225]),
    ("glass_pane", [200, 220, 225]),
    ("tinted_glass", [44, 38, 46]),
    // Metal, redstone, utility blocks.
    ("iron_bars", [136, 139, 135]),
    ("chain", [50, 56, 68]),
    ("anvil", [68, 68, 68]),
    ("chipped_anvil", [68, 68, 68]),
    ("damaged_anvil", [68, 68, 68]),
    ("heavy_weighted_pressure_plate", [220, 220, 220]),
    ("light_weighted_pressure_plate", [246, 208, 61]),
    ("bell", [253, 235, 110]),
    ("lightning_rod", [198, 109, 83]),
    ("heavy_core", [82, 86, 94]),
    ("cauldron", [74, 73, 74]),
    ("water_cauldron", [70, 90, 140]),
    ("lava_cauldron", [140, 80, 45]),
    ("powder_snow_cauldron", [160, 160, 165]),
    ("hopper", [67, 66, 67]),
    ("brewing_stand", [122, 100, 80]),
    ("flower_pot", [124, 68, 53]),
    ("decorated_pot", [150, 90, 70]),
    ("rail", [125, 111, 88]),
    ("powered_rail", [154, 110, 74]),
    ("detector_rail", [123, 104, 90]),
    ("activator_rail", [115, 87, 74]),
    ("redstone_wire", [150, 20, 10]),
    ("repeater", [160, 157, 156]),
    ("comparator", [166, 161, 160]),
    ("lever", [111, 93, 72]),
    ("tripwire", [200, 200, 200]),
    ("tripwire_hook", [140, 130, 110]),
    ("daylight_detector", [130, 116, 94]),
    ("target", [226, 170, 157]),
    ("tnt", [182, 88, 84]),
    ("observer", [98, 98, 98]),
    ("piston", [110, 104, 95]),
    ("sticky_piston", [110, 104, 95]),
    ("piston_head", [153, 127, 85]),
    ("moving_piston", [110, 104, 95]),
    ("dispenser", [110, 109, 110]),
    ("dropper", [110, 109, 110]),
    ("crafter", [112, 102, 97]),
    ("furnace", [110, 109, 109]),
    ("blast_furnace", [108, 108, 107]),
    ("smoker", [107, 97, 88]),
    ("stonecutter", [123, 118, 111]),
    ("grindstone", [142, 142, 142]),
    ("lodestone", [147, 149, 152]),
    ("respawn_anchor", [40, 20, 60]),
    ("enchanting_table", [70, 45, 60]),
    ("beacon", [117, 220, 215]),
    ("conduit", [159, 139, 113]),
    ("ender_chest", [40, 55, 55]),
    ("shulker_box", [139, 96, 139]),
    ("cake", [230, 210, 205]),
    ("candle_cake", [230, 210, 205]),
    ("spawner", [36, 46, 62]),
    ("trial_spawner", [60, 70, 80]),
    ("vault", [55, 65, 72]),
    ("end_portal", [20, 20, 30]),
    ("end_gateway", [20, 20, 30]),
    ("end_portal_frame", [90, 120, 100]),
    ("nether_portal", [89, 11, 192]),
    // Heads.
    ("skeleton_skull", [200, 200, 200]),
    ("wither_skeleton_skull", [40, 40, 40]),
    ("zombie_head", [70, 110, 50]),
    ("creeper_head", [80, 160, 70]),
    ("dragon_head", [30, 30, 30]),
    ("piglin_head", [230, 160, 150]),
    ("player_head", [70, 50, 35]),
    // Technical blocks.
    ("command_block", [181, 136, 108]),
    ("chain_command_block", [131, 161, 147]),
    ("repeating_command_block", [129, 111, 176]),
    ("structure_block", [88, 74, 90]),
    ("jigsaw", [80, 69, 81]),
    ("barrier", [230, 60, 60]),
    ("structure_void", [255, 255, 255]),
    ("air", [255, 255, 255]),
    ("cave_air", [255, 255, 255]),
    ("void_air", [255, 255, 255]),
    // Newer than 1.21.1 (not checked against a list): 1.21.4's pale garden
    // and resin.
    ("pale_moss_block", [107, 112, 104]),
    ("pale_moss_carpet", [107, 112, 104]),
    ("pale_hanging_moss", [107, 112, 104]),
    ("creaking_heart", [87, 81, 79]),
    ("open_eyeblossom", [220, 140, 60]),
    ("closed_eyeblossom", [110, 105, 110]),
    ("resin_block", [217, 99, 25]),
    ("resin_bricks", [206, 88, 24]),
    ("chiseled_resin_bricks", [200, 84, 24]),
    ("resin_clump", [217, 99, 25]),
];

/// The 16 dyes and their colour per material: wool (also carpets, beds,
/// banners and candles), concrete, concrete powder, terracotta, glazed
/// terracotta, stained glass (and panes), shulker boxes.
const DYES: &[(&str, [[u8; 3]; 7])] = &[
    (
        "white",
        [
            [234, 236, 237],
            [207, 213, 214],
            [226, 227, 228],
            [210, 178, 161],
            [188, 212, 203],
            [250, 250, 250],
            [215, 220, 221],
        ],
    ),
    (
        "orange",
        [[241, 118, 20], [224, 97, 1], [227, 132, 32], [162, 84, 38], [155, 147, 92], [216, 127, 51], [234, 106, 8]],
    ),
    (
        "magenta",
        [
            [190, 69, 180],
            [169, 48, 159],
            [193, 84, 185],
            [150, 88, 109],
            [208, 100, 192],
            [178, 76, 216],
            [173, 54, 163],
        ],
    ),
    (
        "light_blue",
        [
            [58, 175, 217],
            [36, 137, 199],
            [74, 181, 213],
            [113, 109, 138],
            [95, 165, 209],
            [102, 153, 216],
            [49, 163, 212],
        ],
    ),
    (
        "yellow",
        [
            [249, 198, 40],
            [241, 175, 21],
            [233, 199, 55],
            [186, 133, 35],
            [234, 192, 89],
            [229, 229, 51],
            [248, 188, 29],
        ],
    ),
    (
        "lime",
        [[112, 185, 26], [94, 169, 24], [125, 189, 42], [104, 118, 53], [163, 198, 55], [127, 204, 25], [99, 172, 23]],
    ),
    (
        "pink",
        [
            [238, 141, 172],
            [214, 101, 143],
            [229, 153, 181],
            [162, 78, 79],
            [235, 154, 181],
            [242, 127, 165],
            [230, 121, 157],
        ],
    ),
    ("gray", [[63, 68, 72], [55, 58, 62], [77, 81, 85], [58, 42, 36], [83, 90, 94], [76, 76, 76], [55, 58, 62]]),
    (
        "light_gray",
        [
            [142, 142, 135],
            [125, 125, 115],
            [155, 155, 148],
            [135, 107, 98],
            [144, 166, 168],
            [153, 153, 153],
            [124, 124, 115],
        ],
    ),
    (
        "cyan",
        [[21, 138, 145], [21, 119, 136], [37, 148, 157], [87, 91, 91], [52, 119, 125], [76, 127, 153], [20, 121, 135]],
    ),
    (
        "purple",
        [[122, 42, 173], [100, 32, 156], [132, 56, 178], [118, 70, 86], [110, 48, 152], [127, 63, 178], [103, 32, 156]],
    ),
    ("blue", [[53, 57, 157], [45, 47, 143], [70, 73, 167], [74, 60, 91], [47, 65, 139], [51, 76, 178], [43, 45, 140]]),
    ("brown", [[114, 72, 41], [96, 60, 32], [126, 85, 54], [77, 51, 36], [120, 106, 86], [102, 76, 51], [106, 66, 35]]),
    (
        "green",
        [[85, 110, 28], [73, 91, 36], [97, 119, 45], [76, 83, 42], [117, 142, 67], [102, 127, 51], [79, 100, 31]],
    ),
    ("red", [[161, 39, 35], [142, 33, 33], [168, 54, 51], [143, 61, 47], [181, 59, 53], [153, 51, 51], [140, 31, 30]]),
    ("black", [[21, 21, 26], [8, 10, 15], [25, 27, 32], [37, 23, 17], [68, 30, 32], [25, 25, 25], [25, 25, 29]]),
];

/// What follows `<dye>_` in a dyed block's id, and its column in [`DYES`].
const DYED: &[(&str, usize)] = &[
    ("wool", 0),
    ("carpet", 0),
    ("bed", 0),
    ("banner", 0),
    ("candle", 0),
    ("concrete", 1),
    ("concrete_powder", 2),
    ("terracotta", 3),
    ("glazed_terracotta", 4),
    ("stained_glass", 5),
    ("stained_glass_pane", 5),
    ("shulker_box", 6),
];

/// Wood types: (name, [planks, bark of logs and wood, stripped logs and
/// wood]). Crimson and warped have stems and hyphae instead.
const WOODS: &[(&str, [[u8; 3]; 3])] = &[
    ("oak", [[162, 131, 79], [109, 85, 51], [177, 144, 86]]),
    ("spruce", [[115, 85, 49], [59, 38, 17], [116, 90, 52]]),
    ("birch", [[192, 175, 121], [216, 215, 210], [196, 176, 118]]),
    ("jungle", [[160, 115, 81], [85, 68, 25], [171, 133, 85]]),
    ("acacia", [[168, 90, 50], [103, 97, 87], [175, 93, 60]]),
    ("dark_oak", [[67, 43, 20], [60, 47, 26], [97, 76, 49]]),
    ("mangrove", [[117, 54, 48], [84, 67, 41], [120, 54, 48]]),
    ("cherry", [[226, 178, 172], [55, 33, 44], [215, 145, 149]]),
    ("bamboo", [[194, 173, 80], [127, 144, 58], [193, 173, 80]]),
    ("crimson", [[101, 48, 70], [92, 25, 29], [137, 57, 90]]),
    ("warped", [[43, 105, 99], [58, 58, 77], [57, 150, 147]]),
    // 1.21.4
    ("pale_oak", [[227, 217, 216], [87, 81, 79], [246, 238, 237]]),
];

/// Copper by oxidation stage: (id prefix, colour).
const COPPER: &[(&str, [u8; 3])] = &[
    ("", [192, 107, 79]),
    ("exposed_", [161, 125, 103]),
    ("weathered_", [108, 153, 110]),
    ("oxidized_", [82, 162, 132]),
];

/// Corals: (name, living colour). Dead corals are all grey.
const CORALS: &[(&str, [u8; 3])] = &[
    ("tube", [49, 87, 207]),
    ("brain", [207, 91, 159]),
    ("bubble", [165, 26, 162]),
    ("fire", [164, 35, 47]),
    ("horn", [216, 200, 66]),
];

/// Colour of dead coral blocks, plants and fans.
const DEAD_CORAL: [u8; 3] = [130, 123, 119];

/// Shapes made of a base material, longest first where one ends another.
const SHAPES: &[&str] = &[
    "_pressure_plate",
    "_hanging_sign",
    "_fence_gate",
    "_trapdoor",
    "_stairs",
    "_button",
    "_fence",
    "_carpet",
    "_slab",
    "_wall",
    "_door",
    "_pane",
    "_sign",
];

/// The display colour of a block state (8-bit sRGB), from its id: the
/// [`known_block_color`] of the id, else [`crate::tag_color`] of the id.
pub fn block_color(state: &BlockState) -> [u8; 3] {
    let id = state.id();
    known_block_color(id).unwrap_or_else(|| tag_color(id))
}

/// The display colour of a block id (with or without namespace, without
/// properties), roughly its texture's average in 8-bit sRGB; `None` for an
/// id no table or rule knows — every block of Minecraft Java Edition 1.19.4
/// to 1.21.1 has one.
///
/// Families share rules: `<dye>_<material>` takes the dye's colour for
/// that material (wool, carpets, beds, banners and candles; concrete,
/// concrete powder, terracotta, glazed terracotta, stained glass, shulker
/// boxes); logs and wood take their wood type's bark, `stripped_` ones its
/// inner colour, everything else of a wood type its planks; copper blocks
/// their oxidation stage; `waxed_` and `infested_` blocks the block they
/// cover; `potted_` plants the plant; wall-mounted torches, signs, banners,
/// heads and coral fans the standing ones; stairs, slabs, walls, fences,
/// doors, trapdoors, buttons, pressure plates, panes and carpets their base
/// material (`stone_brick_stairs` → `stone_bricks`, `purpur_slab` →
/// `purpur_block`).
pub fn known_block_color(id: &str) -> Option<[u8; 3]> {
    resolve(id.split_once(':').map_or(id, |(_, id)| id))
}

fn resolve(id: &str) -> Option<[u8; 3]> {
    if let Some((_, c)) = TABLE.iter().find(|(n, _)| *n == id) {
        return Some(*c);
    }
    for prefix in ["waxed_", "infested_", "potted_"] {
        if let Some(rest) = id.strip_prefix(prefix) {
            // `potted_azalea_bush` holds an `azalea`.
            return resolve(rest).or_else(|| rest.strip_suffix("_bush").and_then(resolve));
        }
    }
    // Wall-mounted variants: `wall_torch`, `oak_wall_sign`, `red_wall_banner`,
    // `creeper_wall_head`, `tube_coral_wall_fan`.
    if let Some(rest) = id.strip_prefix("wall_") {
        return resolve(rest);
    }
    if id.contains("_wall_") {
        return resolve(&id.replacen("_wall_", "_", 1));
    }
    dyed(id).or_else(|| wood(id)).or_else(|| copper(id)).or_else(|| coral(id)).or_else(|| shape(id))
}

/// `<dye>_<material>`, longest dye first (`light_blue` before `blue`).
fn dyed(id: &str) -> Option<[u8; 3]> {
    let (_, colors, rest) = DYES
        .iter()
        .filter_map(|(d, c)| Some((d, c, id.strip_prefix(d)?.strip_prefix('_')?)))
        .max_by_key(|(d, _, _)| d.len())?;
    if rest == "candle_cake" {
        return resolve("cake");
    }
    DYED.iter().find(|(m, _)| *m == rest).map(|(_, i)| colors[*i])
}

/// Planks, logs, wood and everything made of a wood type's planks.
fn wood(id: &str) -> Option<[u8; 3]> {
    let (stripped, id) = id.strip_prefix("stripped_").map_or((false, id), |rest| (true, rest));
    let (_, [planks, bark, inner], rest) = WOODS
        .iter()
        .filter_map(|(w, c)| Some((w, c, id.strip_prefix(w)?.strip_prefix('_')?)))
        .max_by_key(|(w, _, _)| w.len())?;
    let log = matches!(rest, "log" | "wood" | "stem" | "hyphae");
    match (stripped, rest) {
        (true, _) if log => Some(*inner),
        (false, _) if log => Some(*bark),
        // Hanging signs are made of stripped logs.
        (false, "hanging_sign") => Some(*inner),
        (
            false,
            "planks" | "sign" | "door" | "trapdoor" | "fence" | "fence_gate" | "button" | "pressure_plate" | "slab"
            | "stairs",
        ) => Some(*planks),
        _ => None,
    }
}

/// Copper blocks by oxidation stage (`waxed_` already taken off).
fn copper(id: &str) -> Option<[u8; 3]> {
    let (stage, color) = COPPER.iter().rev().find(|(p, _)| id.starts_with(p))?;
    let rest = &id[stage.len()..];
    let shade = match rest {
        "copper" if !stage.is_empty() => 1.0,
        "copper_block" if stage.is_empty() => 1.0,
        "cut_copper" | "copper_door" | "copper_trapdoor" => 1.0,
        "chiseled_copper" => 0.95,
        "copper_bulb" => 0.9,
        // Half open.
        "copper_grate" => 0.85,
        _ => return None,
    };
    Some(color.map(|c| (f32::from(c) * shade).round() as u8))
}

/// Coral blocks, plants and fans, living or dead.
fn coral(id: &str) -> Option<[u8; 3]> {
    let (dead, id) = id.strip_prefix("dead_").map_or((false, id), |rest| (true, rest));
    let (name, rest) = id.split_once("_coral")?;
    let (_, c) = CORALS.iter().find(|(n, _)| *n == name)?;
    matches!(rest, "" | "_block" | "_fan").then_some(if dead { DEAD_CORAL } else { *c })
}

/// Stairs, slabs, walls, … take their base material's colour: the base
/// itself, or with `s` (`stone_brick` → `stone_bricks`), `_block`
/// (`purpur` → `purpur_block`) or `_planks` added.
fn shape(id: &str) -> Option<[u8; 3]> {
    let base = SHAPES.iter().find_map(|s| id.strip_suffix(s))?;
    [base.to_string(), format!("{base}s"), format!("{base}_block"), format!("{base}_planks")]
        .iter()
        .find_map(|b| resolve(b))
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
        assert_eq!(c("blue_concrete"), [45, 47, 143]);
        assert_eq!(c("oak_planks"), [162, 131, 79]);
        assert_eq!(c("oak_stairs[facing=east]"), [162, 131, 79]);
        assert_eq!(c("dark_oak_log[axis=y]"), [60, 47, 26]);
        assert_eq!(c("birch_leaves"), [87, 115, 55]);
        assert_eq!(c("stone_brick_stairs"), c("stone_bricks"));
        assert_eq!(c("mod:strange_block"), tag_color("strange_block"));
        assert_eq!(known_block_color("strange_block"), None);
    }

    #[test]
    fn rules_resolve_to_their_base() {
        let k = |s: &str| known_block_color(s).unwrap_or_else(|| panic!("{s} unknown"));
        assert_eq!(k("stripped_spruce_wood"), WOODS[1].1[2]);
        assert_eq!(k("stripped_spruce_log"), k("stripped_spruce_wood"));
        assert_eq!(k("spruce_hanging_sign"), k("stripped_spruce_log"));
        assert_eq!(k("oak_wall_hanging_sign"), k("oak_hanging_sign"));
        assert_eq!(k("waxed_weathered_cut_copper_stairs"), k("weathered_cut_copper"));
        assert_eq!(k("waxed_copper_block"), k("copper_block"));
        assert_eq!(k("potted_azalea_bush"), k("azalea"));
        assert_eq!(k("potted_oak_sapling"), k("oak_sapling"));
        assert_eq!(k("infested_mossy_stone_bricks"), k("mossy_stone_bricks"));
        assert_eq!(k("red_wall_banner"), k("red_wool"));
        assert_eq!(k("lime_candle_cake"), k("cake"));
        assert_eq!(k("light_blue_stained_glass_pane"), k("light_blue_stained_glass"));
        assert_eq!(k("dead_tube_coral_wall_fan"), DEAD_CORAL);
        assert_eq!(k("brain_coral_fan"), k("brain_coral_block"));
        assert_eq!(k("purpur_stairs"), k("purpur_block"));
        assert_eq!(k("quartz_slab"), k("quartz_block"));
        assert_eq!(k("nether_brick_fence"), k("nether_bricks"));
        assert_eq!(k("iron_trapdoor"), k("iron_block"));
        assert_eq!(k("moss_carpet"), k("moss_block"));
        assert_eq!(k("minecraft:wall_torch"), k("torch"));
        assert_eq!(k("bamboo_mosaic_stairs"), k("bamboo_mosaic"));
        // Families do not swallow look-alikes.
        assert_ne!(k("red_nether_bricks"), k("red_wool"));
        assert_ne!(k("blue_ice"), k("blue_wool"));
        assert_eq!(known_block_color("oak_nonsense"), None);
        assert_eq!(known_block_color("green_nonsense"), None);
        assert_eq!(known_block_color("copper"), None);
        assert_eq!(known_block_color("potted_nonsense"), None);
    }
}
