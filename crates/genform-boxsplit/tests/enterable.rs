//! The buildings of `examples/boxsplit/` can be entered: derived in memory
//! (no terrain), every room is reachable on foot from the ground outside
//! through doors, ladders and stairs, and the parts that promise a shape
//! have it (doors in two halves, ladders against walls, stairs facing up
//! the roof, no doubled corner columns, a centred house door).
//!
//! `GENFORM_BSG_DIR` may point at another folder of examples (to measure an
//! older version); the numbers are printed with `--nocapture`.

use genform_boxsplit::{BoxGrammar, DeriveOptions, compile};
use genform_core::{BlockGrid, BlockKind, BlockState, Rng, SourceFile};
use glam::IVec3;
use walls::{Cell, Walls};

mod walls;

fn source(name: &str) -> String {
    let dir = std::env::var("GENFORM_BSG_DIR")
        .unwrap_or_else(|_| format!("{}/../../examples/boxsplit", env!("CARGO_MANIFEST_DIR")));
    std::fs::read_to_string(format!("{dir}/{name}.bsg")).expect("example exists")
}

fn load(name: &str) -> BoxGrammar {
    match compile(&SourceFile::new(format!("{name}.bsg"), source(name))) {
        Ok((g, warnings)) => {
            assert!(warnings.items.is_empty(), "{name}: {}", warnings.short());
            g
        }
        Err(e) => panic!("{name}:\n{}", e.short()),
    }
}

/// Derives `name` in a box of `size` (the grammar's own box for `None`).
fn derive(name: &str, size: Option<IVec3>, seed: u64) -> BlockGrid {
    let g = load(name);
    let size = size.unwrap_or_else(|| {
        let (lo, hi) = g.default_box().expect("examples declare a box");
        hi - lo
    });
    let t = std::time::Instant::now();
    let d = g.derive(None, IVec3::ZERO, size, &mut Rng::from_seed(seed), &DeriveOptions::default());
    let d = d.unwrap_or_else(|e| panic!("{name}: {e}"));
    let took = t.elapsed();
    assert!(took.as_millis() < 500, "{name} {size}: derived in {took:?}");
    d.blocks
}

fn prop<'a>(b: &'a BlockState, key: &str) -> Option<&'a str> {
    b.properties.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
}

fn is_door(b: &BlockState) -> bool {
    b.id().ends_with("_door")
}

/// The unit vector of a `facing` value.
fn dir(facing: &str) -> IVec3 {
    match facing {
        "north" => IVec3::NEG_Z,
        "south" => IVec3::Z,
        "west" => IVec3::NEG_X,
        "east" => IVec3::X,
        f => panic!("facing {f}"),
    }
}

/// The derived blocks in a window one column wider than the box on every
/// side: open air around the box, solid ground below it.
fn walls(g: &BlockGrid) -> Walls {
    Walls::new(g.origin + IVec3::new(-1, 0, -1), g.size.as_ivec3() + IVec3::new(2, 0, 2), |p| Cell::of(g.get(p)))
}

/// Sealed air (pockets, cells) and unreachable indoor cells of a derivation;
/// printed for the record.
fn measure(name: &str, g: &BlockGrid) -> (usize, usize, Vec<IVec3>) {
    let w = walls(g);
    let pockets = w.sealed_pockets(|_| true);
    let rooms = w.unreachable_rooms(|_| true);
    let cells: usize = pockets.iter().sum();
    eprintln!(
        "{name} {}: {} sealed pockets, {cells} cells (largest {:?}); {} indoor standing cells unreachable on foot",
        g.size,
        pockets.len(),
        pockets.first(),
        rooms.len()
    );
    (pockets.len(), cells, rooms)
}

fn assert_enterable(name: &str, g: &BlockGrid) {
    let (_, _, rooms) = measure(name, g);
    let pockets = walls(g).sealed_pockets(|_| true);
    assert!(pockets.iter().all(|&n| n <= 4), "{name} {}: sealed air pockets of {pockets:?} cells", g.size);
    assert!(
        rooms.is_empty(),
        "{name} {}: {} indoor cells unreachable, e.g. {:?}",
        g.size,
        rooms.len(),
        &rooms[..rooms.len().min(5)]
    );
}

/// Every door is two halves of one door (lower under upper, same facing and
/// hinge); returns the lower halves.
fn doors(name: &str, g: &BlockGrid) -> Vec<(IVec3, BlockState)> {
    let mut lower = Vec::new();
    for (p, c) in g.iter_set() {
        let b = &g.palette[c as usize];
        if !is_door(b) {
            continue;
        }
        let (other, want) = match prop(b, "half") {
            Some("lower") => (p + IVec3::Y, "upper"),
            Some("upper") => (p - IVec3::Y, "lower"),
            h => panic!("{name}: door at {p} has half {h:?}: {b}"),
        };
        let o = g.get(other).unwrap_or_else(|| panic!("{name}: door half at {p} has no other half"));
        assert!(is_door(o) && prop(o, "half") == Some(want), "{name}: door at {p}: {b} over/under {o}");
        for key in ["facing", "hinge"] {
            assert!(
                prop(b, key).is_some() && prop(b, key) == prop(o, key),
                "{name}: door halves at {p} differ in {key}"
            );
        }
        if want == "upper" {
            lower.push((p, b.clone()));
        }
    }
    // Each door leads from a floor to a floor (a step of a block at most).
    let w = walls(g);
    for (p, b) in &lower {
        let f = dir(prop(b, "facing").unwrap());
        for q in [*p + f, *p - f] {
            let floor = w.stands(q) && (w.supported(q) || w.supported(q - IVec3::Y));
            assert!(floor, "{name}: the door at {p} ({b}) opens onto no floor at {q}");
        }
    }
    lower
}

/// Every ladder hangs on a full block behind it (not glass, not air).
fn assert_ladders_on_walls(name: &str, g: &BlockGrid) -> usize {
    let mut n = 0;
    for (p, c) in g.iter_set() {
        let b = &g.palette[c as usize];
        if b.id() != "ladder" {
            continue;
        }
        n += 1;
        let facing = prop(b, "facing").unwrap_or_else(|| panic!("{name}: ladder at {p} without facing"));
        let behind = g.get(p - dir(facing));
        assert!(
            behind.is_some_and(|w| w.kind() == BlockKind::Solid
                && !w.id().ends_with("_pane")
                && !w.id().contains("glass")
                && !is_door(w)
                && w.id() != "ladder"),
            "{name}: ladder at {p} facing {facing} hangs on {behind:?}"
        );
    }
    n
}

fn castle_side(size: IVec3) -> i32 {
    (size.x.min(size.z) / 9).clamp(5, 15)
}

#[test]
fn castle_keep_and_towers_can_be_entered_and_climbed() {
    let cases = [
        (None, 0),
        (None, 1),
        (None, 2),
        (None, 3),
        (Some(IVec3::new(30, 16, 30)), 2),
        (Some(IVec3::new(24, 12, 24)), 3),
        (Some(IVec3::new(56, 24, 60)), 4),
        (Some(IVec3::new(128, 48, 100)), 5),
        (Some(IVec3::new(256, 64, 256)), 9),
    ];
    for (size, seed) in cases {
        let g = derive("castle", size, seed);
        let s = g.size.as_ivec3();
        assert_enterable("castle", &g);
        let doors = doors("castle", &g);
        assert!(assert_ladders_on_walls("castle", &g) > 0);
        // A door into each corner tower and into the keep in the middle.
        let t = castle_side(s);
        let count = |x0: i32, x1: i32, z0: i32, z1: i32| {
            doors.iter().filter(|(p, _)| (x0..x1).contains(&p.x) && (z0..z1).contains(&p.z)).count()
        };
        for (x0, z0) in [(0, 0), (s.x - t, 0), (0, s.z - t), (s.x - t, s.z - t)] {
            assert!(count(x0, x0 + t, z0, z0 + t) >= 1, "castle {s} seed {seed}: no door in the tower at {x0}, {z0}");
        }
        // A hollow keep (air in the middle, where an empty courtyard is unset).
        let keep = g.get(IVec3::new(s.x / 2, 3, s.z / 2)).is_some_and(|b| b.id() == "air");
        assert_eq!(keep, s.x - 2 * t >= 15 && s.z - 2 * t >= 15, "castle {s}: keep");
        assert!(!keep || count(t, s.x - t, t, s.z - t) >= 1, "castle {s} seed {seed}: no door into the keep");
    }
    // Smaller boxes get a keep alone, with its door and ladder.
    for (size, seed) in [(IVec3::new(20, 14, 18), 1), (IVec3::new(9, 8, 9), 2)] {
        let g = derive("castle", Some(size), seed);
        assert_enterable("castle", &g);
        assert!(!doors("castle", &g).is_empty() && assert_ladders_on_walls("castle", &g) > 0, "keep {size}");
    }
}

#[test]
fn castle_gate_is_where_the_comment_says() {
    let text = source("castle");
    let head: Vec<&str> =
        text.lines().take_while(|l| l.starts_with('#')).map(|l| l.trim_start_matches('#').trim()).collect();
    let head = head.join(" ");
    let said = ["north", "south"].into_iter().find(|side| head.contains(&format!("in the {side} wall")));
    let said = said.expect("the header comment names the gate's side");
    let g = derive("castle", None, 0);
    let s = g.size.as_ivec3();
    let t = castle_side(s);
    // The passage runs through the middle of the wall strip, from the ground.
    let open =
        |z: i32| (z - t / 2..=z + t / 2).all(|z| g.get(IVec3::new(s.x / 2, 2, z)).is_none_or(|b| b.id() == "air"));
    let north = open(t / 2);
    let south = open(s.z - 1 - t / 2);
    assert!(north != south, "gate north {north}, south {south}");
    assert_eq!(said, if north { "north" } else { "south" }, "the gate is on the other side (north is -z)");
}

#[test]
fn temple_can_be_entered_and_has_no_doubled_columns() {
    for (size, seed) in [
        (None, 0),
        (Some(IVec3::new(31, 16, 19)), 1),
        (Some(IVec3::new(19, 16, 31)), 1),
        (Some(IVec3::new(12, 10, 9)), 2),
    ] {
        let g = derive("temple", size, seed);
        assert_enterable("temple", &g);
        let columns: Vec<IVec3> =
            g.iter_set().filter(|&(_, c)| g.palette[c as usize].id() == "quartz_pillar").map(|(p, _)| p).collect();
        assert!(columns.len() >= 8, "temple {}: {} column blocks", g.size, columns.len());
        for &p in &columns {
            for d in [IVec3::X, IVec3::Z] {
                let q = g.get(p + d).map(BlockState::id);
                assert_ne!(q, Some("quartz_pillar"), "temple {}: columns side by side at {p} and {}", g.size, p + d);
            }
        }
    }
}

#[test]
fn house_has_a_centred_door_a_stairs_roof_and_windows() {
    for (size, seed) in [
        (None, 0),
        (Some(IVec3::new(9, 10, 7)), 1),
        (Some(IVec3::new(12, 11, 9)), 2),
        (Some(IVec3::new(7, 9, 13)), 3),
        (Some(IVec3::new(10, 9, 14)), 4),
        (Some(IVec3::new(5, 6, 5)), 5),
    ] {
        let g = derive("house", size, seed);
        let s = g.size.as_ivec3();
        assert_enterable("house", &g);
        // One door, centred on its wall: the wall runs across the facing.
        let doors = doors("house", &g);
        assert!(!doors.is_empty() && doors.len() <= 2, "house {s}: {} doors", doors.len());
        let facing = dir(prop(&doors[0].1, "facing").unwrap());
        assert!(doors.iter().all(|(_, b)| dir(prop(b, "facing").unwrap()) == facing));
        let along = if facing.x == 0 { IVec3::X } else { IVec3::Z };
        let lo = doors.iter().map(|(p, _)| p.dot(along)).min().unwrap();
        let hi = doors.iter().map(|(p, _)| p.dot(along)).max().unwrap();
        let wall = s.dot(along);
        assert_eq!(lo, wall - 1 - hi, "house {s}: door at {lo}..={hi} of a wall 0..{wall}");
        assert_eq!(hi - lo + 1, doors.len() as i32, "house {s}: the doors are side by side");
        // A roof of stairs, bottom half, rising inwards: open air downhill,
        // a block uphill.
        let mut stairs = 0;
        for (p, c) in g.iter_set() {
            let b = &g.palette[c as usize];
            if !b.id().ends_with("_stairs") {
                continue;
            }
            stairs += 1;
            assert_eq!(prop(b, "half"), Some("bottom"), "house {s}: {b} at {p}");
            let up = dir(prop(b, "facing").unwrap());
            assert!(
                g.get(p + up).is_some_and(|b| b.kind() == BlockKind::Solid),
                "house {s}: nothing uphill of {b} at {p}"
            );
            let down = p - up;
            let free = g.index(down).is_none() || g.get(down).is_none_or(|b| b.kind() == BlockKind::Air);
            assert!(free, "house {s}: {b} at {p} faces into the roof");
        }
        assert!(stairs >= 2 * (s.x.max(s.z) - 2), "house {s}: {stairs} stairs");
        // Glass panes in every wall that is long enough.
        for (axis, at) in [(2, 0), (2, s.z - 1), (0, 0), (0, s.x - 1)] {
            let wall_len = if axis == 2 { s.x } else { s.z };
            let panes =
                g.iter_set().filter(|&(p, c)| p[axis] == at && g.palette[c as usize].id() == "glass_pane").count();
            assert!(wall_len < 7 || panes > 0, "house {s}: no window in the wall at {}={at}", ["x", "y", "z"][axis]);
        }
    }
}

#[test]
fn derivations_are_deterministic() {
    for name in ["castle", "temple", "house"] {
        let a = derive(name, None, 7);
        let b = derive(name, None, 7);
        assert_eq!(a, b, "{name}");
    }
}
