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
