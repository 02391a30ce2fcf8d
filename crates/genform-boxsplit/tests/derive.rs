//! Derivation semantics through the public API: splits, rounding, repeat,
//! reorientation, constraints, observers, backtracking, failures, limits,
//! traces and determinism.

use genform_boxsplit::{
    BoxGrammar, Derivation, DeriveFailure, DeriveLimits, DeriveOptions, FailureKind, TraceEvent, compile,
};
use genform_core::rng::Draws;
use genform_core::{BlockGrid, BlockState, Rng, SourceFile};
use glam::{IVec3, UVec3};

fn grammar(src: &str) -> BoxGrammar {
    match compile(&SourceFile::new("test.bsg", src)) {
        Ok((g, _)) => g,
        Err(e) => panic!("{}", e.short()),
    }
}

fn derive_in(src: &str, world: Option<&BlockGrid>, size: IVec3, trace: bool) -> Result<Derivation, DeriveFailure> {
    let options = DeriveOptions { limits: None, trace };
    grammar(src).derive(world, IVec3::ZERO, size, &mut Rng::from_seed(11), &options)
}

fn derive(src: &str, size: IVec3) -> Derivation {
    derive_in(src, None, size, false).unwrap_or_else(|e| panic!("{e}"))
}

/// Block id at `p` (`-` unset).
fn at(d: &Derivation, x: i32, y: i32, z: i32) -> String {
    d.blocks.get(IVec3::new(x, y, z)).map_or("-".to_string(), |b| b.id().to_string())
}

/// The ids along x at (y, z), one letter each (first letter of the id).
fn row_x(d: &Derivation, y: i32, z: i32) -> String {
    (0..d.blocks.size.x as i32).map(|x| at(d, x, y, z).chars().next().unwrap_or('?')).collect()
}

#[test]
fn splits_cover_every_cell_once_in_every_rounding_mode() {
    let blocks = "{ fill andesite, fill basalt, fill calcite, fill diorite, fill end_stone }";
    // Three weights share 4 (6 cells) or 5 (7 cells) after the two absolute pieces.
    for (mode, six, seven) in [
        ("truncate", "abcdde", "abcddde"),
        ("start", "abbcde", "abbccde"),
        ("end", "abcdde", "abccdde"),
        ("middle", "abccde", "abbccde"),
    ] {
        let src = format!("A {{ split x [1, -1, -1, -1, 1] round {mode} {blocks} }}");
        for (len, want) in [(6, six), (7, seven)] {
            let d = derive(&src, IVec3::new(len, 2, 1));
            assert_eq!(row_x(&d, 0, 0), want, "{mode} {len}");
            assert_eq!(row_x(&d, 1, 0), want, "{mode} {len}");
            assert_eq!(d.blocks.set_count(), 2 * len as usize, "{mode}: every cell painted");
            assert_eq!(d.stats.filled, 2 * len as u64, "{mode}: no cell painted twice");
        }
    }
}

#[test]
fn repeat_tiles_and_clips_the_last_copy() {
    let d = derive("A { split x [2, 1] repeat { fill stone, fill dirt } }", IVec3::new(8, 1, 1));
    assert_eq!(row_x(&d, 0, 0), "ssdssdss");
    let d = derive("A { split x [2, 1] repeat round start { fill stone, fill dirt } }", IVec3::new(8, 1, 1));
    assert_eq!(row_x(&d, 0, 0), "sdssdssd");
    let d = derive("A { split x [2, 1] repeat round middle { fill stone, fill dirt } }", IVec3::new(8, 1, 1));
    assert_eq!(row_x(&d, 0, 0), "dssdssds");
    // Relative sizes stretch the copies instead.
    let d = derive("A { split x [1, -2] repeat { fill andesite, fill dirt } }", IVec3::new(10, 1, 1));
    assert_eq!(row_x(&d, 0, 0), "addaddaddd");
    assert_eq!(d.blocks.set_count(), 10);
}

#[test]
fn reorient_permutes_the_local_axes() {
    let src = "A { B reorient(z, y, x) }\nB { when X == 5 and Z == 3 { split x [1, -1] { fill stone, fill dirt } } }";
    let d = derive(src, IVec3::new(3, 2, 5));
    // Local x is world z: the stone slab is the z = 0 row.
    for x in 0..3 {
        for y in 0..2 {
            assert_eq!(at(&d, x, y, 0), "stone");
            assert_eq!(at(&d, x, y, 4), "dirt");
        }
    }
    // A child carries its own orientation; the parent's stays.
    let src = "A { split y [1, 1] { B reorient(z, y, x), B } }\nB { split x [1, -1] { fill stone, fill dirt } }";
    let d = derive(src, IVec3::new(3, 2, 3));
    assert_eq!(row_x(&d, 0, 0), "sss");
    assert_eq!(row_x(&d, 1, 1), "sdd");
}

#[test]
fn constraints_with_and_or_not_and_else() {
    let src = "
        A {
            when X >= 4 and not (Z > 2) { fill stone }
            when X < 4 or Y // 2 == 3 { fill dirt }
            else { fill glass }
        }";
    let id = |size: IVec3| at(&derive(src, size), 0, 0, 0);
    assert_eq!(id(IVec3::new(5, 1, 2)), "stone");
    assert_eq!(id(IVec3::new(3, 1, 9)), "dirt");
    assert_eq!(id(IVec3::new(5, 7, 9)), "dirt");
    assert_eq!(id(IVec3::new(5, 1, 3)), "glass");
    // SMALLEST, LARGEST, world sizes, positions and offsets.
    let src = "
        A { split x [2, -1] { B, B } }
        B {
            when SMALLEST == 1 and LARGEST == 6 and WORLD_X == 7 and MIN_X == 12 and OFFSET_X == 2 { fill stone }
            else { fill dirt }
        }";
    let d = grammar(src)
        .derive(None, IVec3::new(10, 0, 0), IVec3::new(17, 6, 1), &mut Rng::from_seed(1), &DeriveOptions::default())
        .unwrap();
    assert_eq!(d.blocks.get(IVec3::new(10, 0, 0)).unwrap().id(), "dirt");
    assert_eq!(d.blocks.get(IVec3::new(12, 0, 0)).unwrap().id(), "stone");
    // `let` formulas are evaluated in the scope where they are used.
    let src = "let HALF = X // 2;\nA { split x [HALF, -1] { fill stone, fill dirt } }";
    assert_eq!(row_x(&derive(src, IVec3::new(7, 1, 1)), 0, 0), "sssdddd");
}

/// A 4×4×4 world: stone below y = 1, water at y = 1, air above, one unset
/// cell, a dandelion; and a box sticking out of it.
fn pond() -> BlockGrid {
    let mut w = BlockGrid::new(IVec3::ZERO, UVec3::new(4, 4, 4));
    for x in 0..4 {
        for z in 0..4 {
            w.set(IVec3::new(x, 0, z), &BlockState::new("stone"));
            w.set(IVec3::new(x, 1, z), &BlockState::new("water"));
            w.set(IVec3::new(x, 2, z), &BlockState::new("air"));
            w.set(IVec3::new(x, 3, z), &BlockState::new("air"));
        }
    }
    w.set(IVec3::new(1, 0, 1), &BlockState::new("grass_block"));
    w.set(IVec3::new(2, 2, 2), &BlockState::new("dandelion"));
    let unset = w.index(IVec3::new(3, 3, 3)).unwrap();
    w.cells[unset] = BlockGrid::UNSET;
    w
}

/// Evaluates `cond` on the box `min..max` of `world`: "1" or "0".
fn holds(world: Option<&BlockGrid>, cond: &str, min: IVec3, max: IVec3) -> bool {
    let src = format!("group GROUND = grass_block, dirt;\nA {{ when {cond} {{ fill stone }} else {{ fill dirt }} }}");
    let d = grammar(&src).derive(world, min, max, &mut Rng::from_seed(1), &DeriveOptions::default()).unwrap();
    d.blocks.get(min).unwrap().id() == "stone"
}

#[test]
fn observers_see_the_world_in_the_scope_box() {
    let w = pond();
    let w = Some(&w);
    let (lo, hi) = (IVec3::new(0, 0, 0), IVec3::new(4, 1, 4));
    assert!(holds(w, "FULL(SOLID)", lo, hi));
    assert!(!holds(w, "FULL(stone)", lo, hi), "the grass block is not stone");
    assert!(holds(w, "COUNT(stone) == 15 and COUNT(GROUND) == 1", lo, hi));
    assert!(holds(w, "NONEMPTY(GROUND) and EMPTY(LIQUID)", lo, hi));
    let water = (IVec3::new(0, 1, 0), IVec3::new(4, 2, 4));
    assert!(holds(w, "FULL(LIQUID) and FULL(water) and EMPTY(SOLID)", water.0, water.1));
    assert!(holds(w, "NONEMPTY(PASSABLE) and not FULL(AIR)", IVec3::new(0, 2, 0), IVec3::new(4, 3, 4)));
    // The unset cell and everything outside the world count as air.
    assert!(holds(w, "FULL(AIR)", IVec3::new(3, 3, 3), IVec3::new(6, 5, 6)));
    assert!(holds(w, "COUNT(AIR) == 8 and EMPTY(SOLID)", IVec3::new(-1, 3, -1), IVec3::new(1, 5, 1)));
    // No world at all: all air.
    assert!(holds(None, "FULL(AIR) and EMPTY(SOLID) and COUNT(AIR) == 8", lo, IVec3::new(2, 2, 2)));
    // Observers look at each scope's own box.
    let src = "A { split y [1, 1, -1] { B, B, B } }\nB { when FULL(SOLID) { fill stone } when FULL(LIQUID) { fill glass } else { skip } }";
    let d = grammar(src).derive(w, IVec3::ZERO, IVec3::new(4, 4, 4), &mut Rng::from_seed(1), &DeriveOptions::default());
    let d = d.unwrap();
    assert_eq!((at(&d, 2, 0, 2), at(&d, 2, 1, 2), at(&d, 2, 2, 2)), ("stone".into(), "glass".into(), "-".into()));
}

#[test]
fn skip_leaves_cells_unset_and_void_writes_air() {
    let d = derive("A { split x [1, 1, 1] { skip, void, fill stone } }", IVec3::new(3, 1, 1));
    assert_eq!((at(&d, 0, 0, 0), at(&d, 1, 0, 0), at(&d, 2, 0, 0)), ("-".into(), "air".into(), "stone".into()));
    assert_eq!(d.stats.filled, 2);
}

#[test]
fn materials_mix_blocks_by_weight_per_cell() {
    let src = "material wall = 3 stone_bricks, 1 cracked_stone_bricks;\nA { fill wall }";
    let d = derive(src, IVec3::new(40, 10, 10));
    let cracked =
        d.blocks.cells.iter().filter(|&&c| d.blocks.palette[c as usize].id() == "cracked_stone_bricks").count();
    let p = cracked as f64 / 4000.0;
    assert!((p - 0.25).abs() < 0.03, "share of cracked bricks {p}");
}

#[test]
fn backtracking_finds_the_only_derivation_and_the_trace_shows_it() {
    // The first choice (the only one with weight) fails three levels down;
    // the fills it made before failing must not survive.
    let src = "
        A {
            weight 1 { split x [1, -1] { fill stone, B } }
            weight 0 { split x [-1, 1] { fill dirt, C } }
        }
        B { split x [1, -1] { fill stone, D } }
        C { fill glass }
        D { when X > 100 { fill stone } }";
    let d = derive_in(src, None, IVec3::new(4, 1, 1), true).unwrap();
    assert_eq!(row_x(&d, 0, 0), "dddg");
    assert_eq!(d.stats.backtracks, 1);
    let trace = d.trace.unwrap();
    let fail = trace.events.iter().position(|e| matches!(e, TraceEvent::Fail { rule, .. } if rule == "D"));
    let back = trace.events.iter().position(
        |e| matches!(e, TraceEvent::Backtrack { rule, discarded_fills, .. } if rule == "A" && *discarded_fills == 2),
    );
    assert!(fail.is_some() && back.is_some() && fail < back, "{}", trace.to_json());
    assert!(matches!(trace.events.last(), Some(TraceEvent::Done { backtracks: 1, .. })));
}

#[test]
fn a_revisited_scope_reuses_its_remaining_alternatives() {
    // After B fails, A goes on with the alternatives it has left (without
    // the one it tried), and only the weight-0 one succeeds.
    let src = "
        A {
            when COUNT(AIR) > 0 weight 2 { B }
            when COUNT(AIR) > 0 weight 1 { B }
            when COUNT(AIR) > 0 weight 0 { fill stone }
        }
        B { when X > 9 { skip } }";
    let d = derive_in(src, None, IVec3::new(2, 1, 1), true).unwrap();
    assert_eq!(d.stats.backtracks, 2);
    assert_eq!(d.stats.applications, 5, "A, B, A again, B, A a third time");
    assert_eq!(at(&d, 0, 0, 0), "stone");
}

#[test]
fn a_failure_goes_back_to_its_own_ancestors_not_to_finished_siblings() {
    // S finished with an alternative left; F fails. S's choice cannot
    // matter to F (observers read only the pre-existing world), so the
    // derivation goes back to A directly instead of retrying S.
    let src = "
        A { weight 1 { split x [1, 1] { S, F } } weight 0 { fill glass } }
        S { weight 1 { fill stone } weight 1 { fill dirt } }
        F { when X > 5 { skip } }";
    let d = derive_in(src, None, IVec3::new(2, 1, 1), true).unwrap();
    assert_eq!(row_x(&d, 0, 0), "gg");
    assert_eq!((d.stats.backtracks, d.stats.applications), (1, 4), "A, S, F, then A again");
    let back: Vec<_> = d
        .trace
        .unwrap()
        .events
        .into_iter()
        .filter_map(
            |e| if let TraceEvent::Backtrack { rule, discarded, .. } = e { Some((rule, discarded)) } else { None },
        )
        .collect();
    assert_eq!(back, vec![("A".to_string(), 1)], "S's record is discarded with A's subtree");
}

#[test]
fn an_impossible_grammar_fails_with_a_trace_naming_the_rule() {
    let src = "
        axiom Row;
        Row { split x [1] repeat { Cell } }
        Cell {
            weight 2 { split y [1, -1] { fill stone, Cell } }
            weight 1 { split y [-1, 2] { Cell, fill dirt } }
        }";
    let e = derive_in(src, None, IVec3::new(2, 3, 1), false).unwrap_err();
    assert_eq!(e.kind, FailureKind::Exhausted);
    let f = e.failed.as_ref().unwrap();
    assert_eq!(f.rule, "Cell");
    assert!(e.message.contains("rule `Cell` at box at (0, "), "{}", e.message);
    assert!(e.message.contains("axiom `Row`"), "{}", e.message);
    assert!(matches!(e.trace.events.first(), Some(TraceEvent::Fail { rule, .. }) if rule == "Cell"));
    assert!(matches!(e.trace.events.last(), Some(TraceEvent::Exhausted { rule }) if rule == "Row"));
    // With tracing on, the trace holds every application and backtrack.
    let e = derive_in(src, None, IVec3::new(2, 3, 1), true).unwrap_err();
    assert!(e.trace.backtracks() > 0);
    assert!(e.trace.to_json().contains("\"event\": \"exhausted\""));
}

#[test]
fn failures_never_write_outside_the_parent() {
    // An absolute split larger than the box is a rule failure: the other
    // alternative is taken.
    let src = "A { weight 1 { split x [6, -1] { fill stone, fill dirt } } weight 0 { fill glass } }";
    let d = derive(src, IVec3::new(5, 1, 1));
    assert_eq!(row_x(&d, 0, 0), "ggggg");
    assert_eq!(d.blocks.size, UVec3::new(5, 1, 1));
    let e = derive_in("A { split x [6, -1] { fill stone, fill dirt } }", None, IVec3::new(5, 1, 1), false).unwrap_err();
    assert!(e.message.contains("need 6 blocks but the box is only 5 long"), "{}", e.message);
}

#[test]
fn limits_end_the_derivation_with_a_message() {
    let g = grammar("A { A }");
    let run = |limits: DeriveLimits| {
        let o = DeriveOptions { limits: Some(limits), trace: false };
        g.derive(None, IVec3::ZERO, IVec3::ONE, &mut Rng::from_seed(1), &o).unwrap_err()
    };
    let e = run(DeriveLimits { applications: 100, backtracks: 10, depth: 1000 });
    assert_eq!(e.kind, FailureKind::Applications);
    assert!(e.message.contains("100 rule applications"), "{}", e.message);
    let e = run(DeriveLimits { applications: 1000, backtracks: 10, depth: 50 });
    assert_eq!(e.kind, FailureKind::Depth);
    assert!(e.message.contains("50 nested"), "{}", e.message);
    // Each level has two ways on, the bottom never works: 2^30 backtracks
    // without a limit.
    let src = "
        limits backtracks = 500;
        R {
            when X > 1 { split x [1, -1] { fill stone, R } }
            when X > 1 { split x [1, -1] { fill dirt, R } }
        }";
    let e = derive_in(src, None, IVec3::new(30, 1, 1), false).unwrap_err();
    assert_eq!(e.kind, FailureKind::Backtracks);
    assert!(e.message.contains("500 backtracks"), "{}", e.message);
    // The grammar's own limits apply unless the options override them.
    assert_eq!(grammar(src).limits().backtracks, 500);
    // A deep but finite recursion is no problem for the explicit stack.
    let d = derive("C { when Y > 1 { split y [1, -1] { fill stone, C } } else { fill dirt } }", IVec3::new(1, 5000, 1));
    assert_eq!(d.stats.max_depth, 5000);
}

#[test]
fn same_seed_same_blocks() {
    let text = std::fs::read_to_string(format!("{}/../../examples/boxsplit/castle.bsg", env!("CARGO_MANIFEST_DIR")));
    let g = grammar(&text.unwrap());
    let run = |seed| {
        g.derive(None, IVec3::ZERO, IVec3::new(40, 20, 40), &mut Rng::from_seed(seed), &DeriveOptions::default())
            .unwrap()
            .blocks
    };
    let a = run(5);
    assert_eq!(a, run(5));
    assert_ne!(a, run(6));
}

/// Always takes the last candidate.
struct Last;
impl Draws for Last {
    fn next_f64(&mut self) -> f64 {
        unreachable!("box-split draws by weight")
    }
    fn choose(&mut self, weights: &[f64]) -> usize {
        weights.len() - 1
    }
}

#[test]
fn every_choice_goes_through_the_draws_trait() {
    let src = "material m = stone, dirt;\nA { weight 5 { fill glass } weight 1 { fill m } }";
    let d = grammar(src).derive(None, IVec3::ZERO, IVec3::new(3, 1, 1), &mut Last, &DeriveOptions::default()).unwrap();
    assert_eq!(row_x(&d, 0, 0), "ddd");
}

#[test]
fn an_empty_or_huge_box_is_an_error() {
    let g = grammar("A { skip }");
    let o = DeriveOptions::default();
    let e = g.derive(None, IVec3::ZERO, IVec3::new(0, 3, 3), &mut Rng::from_seed(1), &o).unwrap_err();
    assert_eq!(e.kind, FailureKind::InvalidBox);
    let e = g.derive(None, IVec3::ZERO, IVec3::new(1 << 12, 1 << 12, 1 << 12), &mut Rng::from_seed(1), &o).unwrap_err();
    assert_eq!(e.kind, FailureKind::InvalidBox);
    // Corners far apart: no overflow.
    let e = g.derive(None, IVec3::splat(i32::MIN), IVec3::splat(i32::MAX), &mut Rng::from_seed(1), &o).unwrap_err();
    assert_eq!(e.kind, FailureKind::InvalidBox);
    // Far from the origin, and far from the world, is fine.
    let far = IVec3::new(i32::MAX - 2, -64, i32::MIN);
    let g = grammar("A { when FULL(AIR) { fill stone } }");
    let world = BlockGrid::new(IVec3::new(i32::MIN, 0, i32::MAX - 5), UVec3::ONE);
    assert!(g.derive(Some(&world), far, far + 2, &mut Rng::from_seed(1), &o).is_ok());
}

#[test]
fn the_trace_round_trips_through_json() {
    let d = derive_in("A { split x [1, -1] { fill stone, B } }\nB { void }", None, IVec3::new(3, 1, 1), true).unwrap();
    let t = d.trace.unwrap();
    let json = t.to_json();
    let back: genform_boxsplit::Trace = serde_json::from_str(&json).unwrap();
    assert_eq!(back, t);
    assert!(json.contains("\"rule\": \"B\""), "{json}");
    assert!(json.contains("\"min\""), "{json}");
}

#[test]
fn a_division_by_zero_in_a_constraint_stops_the_derivation_naming_rule_and_formula() {
    let src = "axiom A;\nA {\n  when X // (X - 4) > 1 { fill stone }\n  else { void }\n}\n";
    // X = 5: the divisor is 1, the derivation runs.
    assert!(derive_in(src, None, IVec3::new(5, 1, 1), false).is_ok());
    let e = derive_in(src, None, IVec3::new(4, 1, 1), false).unwrap_err();
    assert_eq!(e.kind, FailureKind::DivisionByZero);
    assert!(e.message.contains("rule `A`"), "{}", e.message);
    assert!(e.message.contains("test.bsg:3:8") && e.message.contains("`X // (X - 4)`"), "{}", e.message);
}

#[test]
fn a_zero_divisor_in_a_split_size_or_a_remainder_is_an_error_too() {
    let src = "axiom A;\nA { split x [Y % (Z - 1), -1] { fill stone, void } }\n";
    let e = derive_in(src, None, IVec3::new(4, 2, 1), false).unwrap_err();
    assert_eq!(e.kind, FailureKind::DivisionByZero);
    assert!(e.message.contains("test.bsg:2:14") && e.message.contains("`Y % (Z - 1)`"), "{}", e.message);
    // `mod(a, b)` is `a % b` written as a call: checked the same way.
    let src = "axiom A;\nA { split x [mod(Y, Z - 1), -1] { fill stone, void } }\n";
    let e = derive_in(src, None, IVec3::new(4, 2, 1), false).unwrap_err();
    assert_eq!(e.kind, FailureKind::DivisionByZero);
    assert!(e.message.contains("test.bsg:2:14") && e.message.contains("`mod(Y, Z - 1)`"), "{}", e.message);
}

#[test]
fn a_division_guarded_by_and_or_if_is_not_evaluated_when_the_guard_fails() {
    let src = "axiom A;\nA {\n  when X != 4 && 8 / (X - 4) > 1 { fill stone }\n  when if(X == 4, 1, 1 / (X - 4)) > 0 { void }\n}\n";
    let d = derive_in(src, None, IVec3::new(4, 1, 1), false).unwrap();
    assert_eq!(at(&d, 0, 0, 0), "air");
}

#[test]
fn a_constant_division_by_zero_is_a_compile_error() {
    let e = compile(&SourceFile::new("t.bsg", "let k = 3 // 0;\naxiom A;\nA { fill stone }\n")).unwrap_err();
    assert!(e.to_string().contains("division by zero"), "{e}");
}
