//! Property tests: random small grammars on random boxes and worlds never
//! panic, and whatever they derive, splits partition the box (no cell is
//! painted twice; without `skip` every cell is painted).

use genform_boxsplit::{DeriveLimits, DeriveOptions, FailureKind, compile};
use genform_core::{BlockGrid, BlockState, Rng, SourceFile};
use glam::IVec3;
use proptest::prelude::*;

const RULES: [&str; 4] = ["A", "B", "C", "D"];
const BLOCKS: [&str; 5] = ["stone", "dirt", "m", "oak_stairs[facing=east]", "minecraft:glass"];

fn pick<'a>(r: &mut Rng, xs: &[&'a str]) -> &'a str {
    xs[r.index(xs.len())]
}

fn condition(r: &mut Rng, depth: u32) -> String {
    let atoms = [
        "X > 2",
        "Y <= 3",
        "Z == 1",
        "FULL(SOLID)",
        "NONEMPTY(LIQUID)",
        "EMPTY(AIR)",
        "COUNT(SOLID) >= 3",
        "X // 2 % 2 == 0",
        "FULL(G)",
        "SMALLEST > 1",
        "OFFSET_Y < 2",
    ];
    match (depth, r.index(4)) {
        (0, _) | (_, 0) => pick(r, &atoms).to_string(),
        (_, 1) => format!("not ({})", condition(r, depth - 1)),
        (_, 2) => format!("{} and {}", condition(r, depth - 1), condition(r, depth - 1)),
        _ => format!("({} or {})", condition(r, depth - 1), condition(r, depth - 1)),
    }
}

fn op(r: &mut Rng, depth: u32, rules: usize, skip: bool) -> String {
    let k = r.index(if depth == 0 { 4 } else { 7 });
    match k {
        0 => format!("fill {}", pick(r, &BLOCKS)),
        1 => "void".to_string(),
        2 if skip => "skip".to_string(),
        2 | 3 => RULES[r.index(rules)].to_string(),
        4 => {
            let perm = pick(r, &["x, y, z", "z, y, x", "y, x, z", "x, z, y", "y, z, x", "z, x, y"]);
            format!("reorient({perm}) {}", op(r, depth - 1, rules, skip))
        }
        _ => {
            let n = 1 + r.index(3);
            let sizes: Vec<&str> =
                (0..n).map(|_| pick(r, &["1", "2", "3", "-1", "-2", "-0.5", "X // 2", "-(Y % 3 + 1)"])).collect();
            let children: Vec<String> = (0..n).map(|_| op(r, depth - 1, rules, skip)).collect();
            let repeat = if r.bernoulli(0.4) { " repeat" } else { "" };
            let round = pick(r, &["", " round start", " round end", " round middle", " round truncate"]);
            format!(
                "split {} [{}]{repeat}{round} {{ {} }}",
                pick(r, &["x", "y", "z"]),
                sizes.join(", "),
                children.join(", ")
            )
        }
    }
}

fn grammar_text(seed: u64, skip: bool) -> String {
    let mut r = Rng::from_seed(seed);
    let rules = 1 + r.index(4);
    let mut out = String::from("group G = stone, water;\nmaterial m = 2 stone, 1 dirt;\n");
    for name in &RULES[..rules] {
        out.push_str(&format!("{name} {{\n"));
        let alts = 1 + r.index(3);
        for i in 0..alts {
            let guard = match r.index(3) {
                0 => String::new(),
                1 => format!("when {} ", condition(&mut r, 2)),
                _ if i == alts - 1 && i > 0 => "else ".to_string(),
                _ => format!("when {} ", condition(&mut r, 1)),
            };
            let weight = if guard.starts_with("else") {
                ""
            } else {
                pick(&mut r, &["", "weight 0 ", "weight 2 ", "weight 0.5 "])
            };
            out.push_str(&format!("    {guard}{weight}{{ {} }}\n", op(&mut r, 3, rules, skip)));
        }
        out.push_str("}\n");
    }
    out
}

fn random_world(seed: u64, size: IVec3) -> BlockGrid {
    let mut r = Rng::from_seed(seed ^ 0x5eed);
    let mut w = BlockGrid::new(IVec3::new(-1, 0, -1), (size + 1).as_uvec3());
    let kinds = ["stone", "water", "air", "short_grass"];
    for c in &mut w.cells {
        if !r.bernoulli(0.1) {
            *c = r.index(kinds.len()) as u32;
        }
    }
    w.palette = kinds.iter().map(|k| BlockState::new(k)).collect();
    w
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn random_grammars_never_panic_and_splits_partition_the_box(
        seed in any::<u64>(),
        sx in 1i32..9, sy in 1i32..9, sz in 1i32..9,
        skip in any::<bool>(),
        with_world in any::<bool>(),
    ) {
        let text = grammar_text(seed, skip);
        let file = SourceFile::new("random.bsg", text.clone());
        let (g, _) = match compile(&file) {
            Ok(ok) => ok,
            Err(e) => return Err(TestCaseError::fail(format!("generated grammar does not compile:\n{text}\n{}", e.short()))),
        };
        let size = IVec3::new(sx, sy, sz);
        let world = random_world(seed, size);
        let options = DeriveOptions { limits: Some(DeriveLimits { applications: 3000, backtracks: 300, depth: 64 }), trace: seed % 4 == 0 };
        let min = IVec3::new(0, 0, 0);
        match g.derive(with_world.then_some(&world), min, size, &mut Rng::from_seed(seed), &options) {
            Ok(d) => {
                prop_assert_eq!(d.blocks.size, size.as_uvec3());
                let set = d.blocks.set_count() as u64;
                prop_assert_eq!(d.stats.filled, set, "a cell was painted twice:\n{}", text);
                if !skip {
                    prop_assert_eq!(set, (sx * sy * sz) as u64, "a cell belongs to no child:\n{}", text);
                }
                prop_assert!(d.blocks.cells.iter().all(|&c| c == BlockGrid::UNSET || (c as usize) < d.blocks.palette.len()));
            }
            Err(e) => {
                prop_assert!(e.kind != FailureKind::InvalidBox);
                prop_assert!(!e.message.is_empty());
            }
        }
    }

    /// Token soup never panics the compiler.
    #[test]
    fn garbage_never_panics_the_compiler(parts in prop::collection::vec(prop::sample::select(vec![
        "A", "{", "}", "[", "]", "(", ")", ",", ";", "when", "else", "weight", "split", "x", "repeat", "round", "middle",
        "fill", "stone", "void", "skip", "reorient", "FULL", "SOLID", "X", "//", "%", ">", "==", "-", "1", "2.5", "and",
        "not", "let", "group", "material", "axiom", "limits", "=", "\"s\"", "grammar", "#c\n", "oak[", "]", "minecraft:x",
    ]), 0..60)) {
        let text = parts.join(" ");
        let _ = compile(&SourceFile::new("soup.bsg", text));
    }
}

#[test]
fn the_random_grammar_generator_makes_varied_grammars() {
    // Guard the property test's reach: over a few seeds the generator
    // produces derivations that succeed, fail and backtrack.
    let (mut ok, mut failed, mut backtracked) = (0, 0, 0);
    for seed in 0..200u64 {
        let (g, _) = compile(&SourceFile::new("r.bsg", grammar_text(seed, seed % 2 == 0))).unwrap();
        let world = random_world(seed, IVec3::splat(6));
        let o = DeriveOptions {
            limits: Some(DeriveLimits { applications: 3000, backtracks: 300, depth: 64 }),
            trace: false,
        };
        match g.derive(Some(&world), IVec3::ZERO, IVec3::splat(6), &mut Rng::from_seed(seed), &o) {
            Ok(d) => {
                ok += 1;
                backtracked += usize::from(d.stats.backtracks > 0);
            }
            Err(_) => failed += 1,
        }
    }
    assert!(ok > 20 && failed > 20 && backtracked > 5, "ok {ok} failed {failed} backtracked {backtracked}");
}

/// A building with a site, on random terrain: columns of ground (dirt)
/// at random heights or none, water over some, a cave under some, a trunk
/// on some.
const SITED: &str = "site foundation = cobblestone, yard = 1;\n\
    A { when Y >= 2 { split y [1, -1] { fill stone_bricks, B } } else { fill stone_bricks } }\n\
    B { split x [1, -1, 1] { fill oak_planks, skip, fill oak_planks } }\n";

/// The world over the box and one cell around it.
fn sited_world(seed: u64, min: IVec3, size: IVec3) -> BlockGrid {
    let mut r = Rng::from_seed(seed);
    let (lo, hi) = (min - IVec3::ONE, min + size + IVec3::ONE);
    let mut g = BlockGrid::new(lo, (hi - lo).as_uvec3());
    let [dirt, water, log, air] = ["dirt", "water", "oak_log", "air"].map(|b| BlockState::parse(b).unwrap());
    for z in lo.z..hi.z {
        for x in lo.x..hi.x {
            // Ground from below the box up to a random height in it (or none).
            let top = (r.index(5) > 0).then(|| lo.y + r.index((size.y + 1) as usize) as i32);
            if let Some(top) = top {
                for y in lo.y..=top {
                    g.set(IVec3::new(x, y, z), &dirt);
                }
                if top > lo.y + 2 && r.index(4) == 0 {
                    g.set(IVec3::new(x, top - 2, z), &air);
                }
            }
            let surface = top.unwrap_or(lo.y - 1);
            match r.index(6) {
                0 => {
                    for y in surface + 1..(surface + 3).min(hi.y) {
                        g.set(IVec3::new(x, y, z), &water);
                    }
                }
                // Trunks stand inside the box, two columns from the ring
                // around it and under its top, so none reaches out of it
                // (those are left standing).
                1 if x > min.x && z > min.z && x < min.x + size.x - 2 && z < min.z + size.z - 2 => {
                    for y in (surface + 1).max(min.y)..(surface + 4).min(min.y + size.y) {
                        g.set(IVec3::new(x, y, z), &log);
                    }
                }
                _ => {}
            }
        }
    }
    g
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// Whatever the terrain, a site's building stands: every footprint
    /// column is solid from under the floor down to its ground, the yard
    /// is open above the floor (but for trees reaching out of the box),
    /// nothing under a column's ground changes (caves stay), and a column
    /// with no ground under the box is counted.
    #[test]
    fn a_site_stands_on_its_ground(seed in any::<u64>(), sx in 5i32..12, sy in 4i32..14, sz in 5i32..12) {
        let (g, _) = compile(&SourceFile::new("sited.bsg", SITED)).unwrap();
        let (min, size) = (IVec3::new(3, 60, -4), IVec3::new(sx, sy, sz));
        let world = sited_world(seed, min, size);
        let result = g.derive(Some(&world), min, min + size, &mut Rng::from_seed(seed), &DeriveOptions::default());
        let d = match result {
            Ok(d) => d,
            Err(e) => {
                // Only a box that is ground up to its top has no floor.
                prop_assert_eq!(e.kind, FailureKind::InvalidBox, "{}", e.message);
                prop_assert!(e.message.contains("no floor") || e.message.contains("no room"), "{}", e.message);
                return Ok(());
            }
        };
        let site = d.site.clone().expect("a world was given");
        let at = |p: IVec3| d.blocks.get(p).cloned().unwrap_or_else(|| world.get(p).cloned().unwrap_or_else(BlockState::air));
        let ground = |b: &BlockState| b.kind() == genform_core::BlockKind::Solid && b.id() != "oak_log";
        let mut hanging = 0;
        for z in min.z..min.z + size.z {
            for x in min.x..min.x + size.x {
                let yard = x == min.x || z == min.z || x == min.x + size.x - 1 || z == min.z + size.z - 1;
                // Solid from the floor (the yard) or just under it down to the ground.
                let from = if yard { site.floor } else { site.floor - 1 };
                let mut y = from;
                while y >= min.y && !ground(&world.get(IVec3::new(x, y, z)).cloned().unwrap_or_else(BlockState::air)) {
                    prop_assert_eq!(at(IVec3::new(x, y, z)).kind(), genform_core::BlockKind::Solid, "({}, {}, {})", x, y, z);
                    y -= 1;
                }
                if y < min.y && !world.get(IVec3::new(x, min.y - 1, z)).is_some_and(&ground) && from >= min.y {
                    hanging += 1;
                }
                // Under the ground nothing changes.
                for y in min.y..=y.min(min.y + size.y - 1) {
                    let p = IVec3::new(x, y, z);
                    if y < site.floor {
                        prop_assert!(d.blocks.get(p).is_none(), "({}, {}, {}) changed under the ground", x, y, z);
                    }
                }
                // The yard is open above the floor, but for trees that reach
                // out of the box, left standing.
                if yard {
                    for y in site.floor + 1..min.y + size.y {
                        let p = IVec3::new(x, y, z);
                        let spared = d.blocks.get(p).is_none() && world.get(p).is_some_and(|b| b.id() == "oak_log");
                        prop_assert!(at(p).id() == "air" || spared, "({}, {}, {}): {}", x, y, z, at(p));
                    }
                }
            }
        }
        prop_assert_eq!(site.foundation_hanging, hanging);
    }
}
