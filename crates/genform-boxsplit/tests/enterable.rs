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
use std::collections::VecDeque;

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

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Cell {
    /// Air, an unset cell, plants and the like.
    Open,
    /// Either half of a door, or a trapdoor.
    Door,
    Ladder,
    Stairs,
    /// Everything else, glass panes and slabs included.
    Solid,
}

/// The derived blocks as cells; outside the box is open air above a solid
/// ground (y < 0).
struct Walls {
    size: IVec3,
    cells: Vec<Cell>,
}

impl Walls {
    fn new(g: &BlockGrid) -> Walls {
        let kinds: Vec<Cell> = g
            .palette
            .iter()
            .map(|b| match b.id() {
                "ladder" => Cell::Ladder,
                id if id.ends_with("_door") || id.ends_with("_trapdoor") => Cell::Door,
                id if id.ends_with("_stairs") => Cell::Stairs,
                _ if matches!(b.kind(), BlockKind::Air | BlockKind::Passable) => Cell::Open,
                _ => Cell::Solid,
            })
            .collect();
        let cells =
            g.cells.iter().map(|&c| if c == BlockGrid::UNSET { Cell::Open } else { kinds[c as usize] }).collect();
        Walls { size: g.size.as_ivec3(), cells }
    }

    fn inside(&self, p: IVec3) -> bool {
        p.cmpge(IVec3::ZERO).all() && p.cmplt(self.size).all()
    }

    fn index(&self, p: IVec3) -> usize {
        ((p.y * self.size.z + p.z) * self.size.x + p.x) as usize
    }

    fn at(&self, p: IVec3) -> Cell {
        if p.y < 0 {
            Cell::Solid
        } else if self.inside(p) {
            self.cells[self.index(p)]
        } else {
            Cell::Open
        }
    }

    /// Air flood from the box's faces through air, doors, ladders and
    /// stairs: the sizes of the components it does not reach, largest first.
    fn sealed_pockets(&self) -> Vec<usize> {
        let s = self.size;
        let through = |c: Cell| c != Cell::Solid;
        let mut seen = vec![false; self.cells.len()];
        let mut queue = VecDeque::new();
        let mut flood = |start: IVec3, seen: &mut Vec<bool>| -> usize {
            let mut n = 0;
            seen[self.index(start)] = true;
            queue.push_back(start);
            while let Some(p) = queue.pop_front() {
                n += 1;
                for d in [IVec3::X, IVec3::NEG_X, IVec3::Y, IVec3::NEG_Y, IVec3::Z, IVec3::NEG_Z] {
                    let q = p + d;
                    if self.inside(q) && !seen[self.index(q)] && through(self.at(q)) {
                        seen[self.index(q)] = true;
                        queue.push_back(q);
                    }
                }
            }
            n
        };
        for y in 0..s.y {
            for z in 0..s.z {
                for x in 0..s.x {
                    let p = IVec3::new(x, y, z);
                    let face = x == 0 || y == 0 || z == 0 || x == s.x - 1 || y == s.y - 1 || z == s.z - 1;
                    if face && through(self.at(p)) && !seen[self.index(p)] {
                        flood(p, &mut seen);
                    }
                }
            }
        }
        let mut pockets = Vec::new();
        for i in 0..self.cells.len() {
            if !seen[i] && through(self.cells[i]) {
                let (sx, sz) = (s.x as usize, s.z as usize);
                let p = IVec3::new((i % sx) as i32, (i / (sx * sz)) as i32, ((i / sx) % sz) as i32);
                pockets.push(flood(p, &mut seen));
            }
        }
        pockets.sort_unstable_by(|a, b| b.cmp(a));
        pockets
    }

    /// A player (two cells high) can be here: feet and head in open cells.
    fn passable(&self, p: IVec3) -> bool {
        matches!(self.at(p), Cell::Open | Cell::Door | Cell::Ladder)
    }

    fn stands(&self, p: IVec3) -> bool {
        self.passable(p) && self.passable(p + IVec3::Y)
    }

    fn supported(&self, p: IVec3) -> bool {
        self.at(p) == Cell::Ladder || !self.passable(p - IVec3::Y)
    }

    fn fall(&self, mut p: IVec3) -> IVec3 {
        while !self.supported(p) {
            p -= IVec3::Y;
        }
        p
    }

    /// Where a player can walk from the ground around the box: walking,
    /// falling, stepping or jumping up one block (stairs, a floor's edge)
    /// with room overhead, climbing ladders. Indexed by feet position in a
    /// frame one cell wider than the box on every horizontal side.
    fn walk(&self) -> Vec<bool> {
        let s = self.size;
        let (fx, fy, fz) = (s.x + 2, s.y, s.z + 2);
        let key = |p: IVec3| (((p.y * fz) + p.z + 1) * fx + p.x + 1) as usize;
        let in_frame = |p: IVec3| p.x >= -1 && p.x <= s.x && p.z >= -1 && p.z <= s.z && p.y >= 0 && p.y < fy;
        let mut seen = vec![false; (fx * fy * fz) as usize];
        let mut queue = VecDeque::new();
        let visit = |p: IVec3, seen: &mut Vec<bool>, queue: &mut VecDeque<IVec3>| {
            if in_frame(p) && !seen[key(p)] {
                seen[key(p)] = true;
                queue.push_back(p);
            }
        };
        for x in -1..=s.x {
            for z in [-1, s.z] {
                visit(IVec3::new(x, 0, z), &mut seen, &mut queue);
            }
        }
        for z in -1..=s.z {
            for x in [-1, s.x] {
                visit(IVec3::new(x, 0, z), &mut seen, &mut queue);
            }
        }
        while let Some(p) = queue.pop_front() {
            for d in [IVec3::X, IVec3::NEG_X, IVec3::Z, IVec3::NEG_Z] {
                let q = p + d;
                if self.stands(q) {
                    visit(self.fall(q), &mut seen, &mut queue);
                } else if !self.passable(q) && self.stands(q + IVec3::Y) && self.passable(p + 2 * IVec3::Y) {
                    visit(q + IVec3::Y, &mut seen, &mut queue);
                }
            }
            if self.at(p) == Cell::Ladder && self.passable(p + 2 * IVec3::Y) {
                visit(p + IVec3::Y, &mut seen, &mut queue);
            }
            if self.passable(p - IVec3::Y) {
                visit(self.fall(p - IVec3::Y), &mut seen, &mut queue);
            }
        }
        let mut reach = vec![false; self.cells.len()];
        for y in 0..s.y {
            for z in 0..s.z {
                for x in 0..s.x {
                    let p = IVec3::new(x, y, z);
                    reach[self.index(p)] = seen[key(p)];
                }
            }
        }
        reach
    }

    /// Places to stand indoors (on a floor, two cells high, with something
    /// solid overhead) that nobody can walk to from the ground outside.
    fn unreachable_rooms(&self) -> Vec<IVec3> {
        let reach = self.walk();
        let mut out = Vec::new();
        let s = self.size;
        for z in 0..s.z {
            for x in 0..s.x {
                let mut roofed = false;
                for y in (0..s.y).rev() {
                    let p = IVec3::new(x, y, z);
                    if !self.passable(p) {
                        roofed = true;
                    } else if roofed
                        && self.stands(p)
                        && !self.passable(p - IVec3::Y)
                        && self.at(p) != Cell::Ladder
                        && !reach[self.index(p)]
                    {
                        out.push(p);
                    }
                }
            }
        }
        out
    }
}

/// Sealed air (pockets, cells) and unreachable indoor cells of a derivation;
/// printed for the record.
fn measure(name: &str, g: &BlockGrid) -> (usize, usize, Vec<IVec3>) {
    let w = Walls::new(g);
    let pockets = w.sealed_pockets();
    let rooms = w.unreachable_rooms();
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
    let w = Walls::new(g);
    let pockets = w.sealed_pockets();
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
    let w = Walls::new(g);
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
            let free = !Walls::new(&g).inside(down) || g.get(down).is_none_or(|b| b.kind() == BlockKind::Air);
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
