//! Growth acceptance tests: the numbers of genr8.md §9 for the four
//! predefined grammars, the disc invariant after every step, growth without
//! rewriting, stochastic / context / timed rules, limits and errors, and a
//! property test over random small grammars.

use genform_core::{Draws, Rng, TagId};
use genform_hemls::grammar::{self, Age, AxiomSide, Branch, EdgeSym, Hemls, Item, Predecessor, Rule, Successor, Turn};
use genform_hemls::settings; // `testkit` names `crate::grammar` and `crate::settings`
use genform_hemls::{Environment, GrowError, Growth, GrowthLimits, Map, Settings, grow, grow_with};
use glam::DVec3;
use proptest::prelude::*;
use std::collections::HashMap;

#[path = "../src/testkit.rs"]
mod testkit;
use testkit::*;

/// Grows with every step validated (links, disc, V − E + F = 1).
fn grow_checked(h: &Hemls, s: &Settings) -> Result<Growth, GrowError> {
    let mut errors = Vec::new();
    let g = grow_with(h, s, &Environment::default(), &mut Rng::from_seed(7), &mut |k, m: &Map| {
        if let Err(e) = m.validate() {
            errors.push(format!("step {k}: {e}"));
        }
        assert_eq!(m.euler_characteristic(), 1, "step {k}");
    });
    assert!(errors.is_empty(), "{errors:?}");
    g
}

fn bbox(m: &Map) -> (DVec3, DVec3) {
    m.positions().iter().fold((DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)), |(lo, hi), p| (lo.min(*p), hi.max(*p)))
}

/// Area and perimeter of the outer boundary (flat, in the xy plane).
fn boundary_area_perimeter(m: &Map) -> (f64, f64) {
    let b = m.boundary();
    let p = m.positions();
    let (mut area, mut per) = (0.0, 0.0);
    for i in 0..b.len() {
        let (u, v) = (p[b[i] as usize], p[b[(i + 1) % b.len()] as usize]);
        area += u.x * v.y - v.x * u.y;
        per += (v - u).length();
    }
    (area.abs() / 2.0, per)
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * b.abs().max(1.0)
}

/// Whether two segments cross anywhere but at a shared endpoint (xy plane).
fn segments_cross(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> bool {
    let orient = |p: DVec3, q: DVec3, r: DVec3| (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x);
    let scale = (b - a).length() * (d - c).length();
    let eps = 1e-9 * scale;
    let (o1, o2, o3, o4) = (orient(a, b, c), orient(a, b, d), orient(c, d, a), orient(c, d, b));
    if o1.abs() <= eps && o2.abs() <= eps {
        // Collinear: overlap of more than a point?
        let dir = (b - a).normalize();
        let (t0, t1) = ((c - a).dot(dir), (d - a).dot(dir));
        let (lo, hi) = (t0.min(t1), t0.max(t1));
        return lo.max(0.0) < hi.min((b - a).length()) - 1e-9;
    }
    (o1 > eps && o2 < -eps || o1 < -eps && o2 > eps) && (o3 > eps && o4 < -eps || o3 < -eps && o4 > eps)
}

/// Number of crossing edge pairs of a flat map (grid-accelerated).
fn crossings(m: &Map) -> usize {
    let p = m.positions();
    let (lo, hi) = bbox(m);
    let n = m.edge_count();
    let cells = ((n as f64).sqrt().ceil() as usize).max(1);
    let size = ((hi - lo).max_element() / cells as f64).max(1e-12);
    let cell = |v: f64, o: f64| (((v - o) / size) as usize).min(cells - 1);
    let mut grid: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    for e in 0..n {
        let (a, b) = m.edge_ends(e);
        let (pa, pb) = (p[a as usize], p[b as usize]);
        for i in cell(pa.x.min(pb.x), lo.x)..=cell(pa.x.max(pb.x), lo.x) {
            for j in cell(pa.y.min(pb.y), lo.y)..=cell(pa.y.max(pb.y), lo.y) {
                grid.entry((i, j)).or_default().push(e);
            }
        }
    }
    let mut found = std::collections::HashSet::new();
    for list in grid.values() {
        for (x, &e) in list.iter().enumerate() {
            for &f in &list[x + 1..] {
                let (a, b) = m.edge_ends(e);
                let (c, d) = m.edge_ends(f);
                if segments_cross(p[a as usize], p[b as usize], p[c as usize], p[d as usize]) {
                    found.insert((e.min(f), e.max(f)));
                }
            }
        }
    }
    found.len()
}

/// The types of a face's sides.
fn face_side_kinds(m: &Map, f: usize, kinds: &HashMap<(u32, u32), u32>) -> Vec<u32> {
    let l = m.face_loop(f);
    (0..l.len())
        .map(|i| {
            let (a, b) = (l[i], l[(i + 1) % l.len()]);
            kinds[&(a.min(b), a.max(b))]
        })
        .collect()
}

fn edge_kind_map(m: &Map) -> HashMap<(u32, u32), u32> {
    (0..m.edge_count())
        .map(|e| {
            let (a, b) = m.edge_ends(e);
            ((a.min(b), a.max(b)), m.edge_kinds()[e])
        })
        .collect()
}

#[test]
fn koch_snowflake_counts_area_perimeter_and_box() {
    let areas = [0.4330127, 0.5773503, 0.6415003, 0.6700114, 0.6826830];
    for n in 0..=4u32 {
        let g = grow_checked(&koch(), &settings(n, 1.0)).unwrap();
        let m = &g.map;
        let e = 3 * 4usize.pow(n);
        assert_eq!((m.vertex_count(), m.edge_count(), m.face_count()), (e, e, 1), "n = {n}");
        let (area, per) = boundary_area_perimeter(m);
        assert!(close(area, areas[n as usize], 1e-6), "n = {n}: area {area}");
        assert!(close(per, 3.0 * (4.0f64 / 3.0).powi(n as i32), 1e-9), "n = {n}: perimeter {per}");
        let (lo, hi) = bbox(m);
        let want_y = if n == 0 { 3f64.sqrt() / 2.0 } else { 2.0 / 3f64.sqrt() };
        assert!(close(hi.x - lo.x, 1.0, 1e-9) && close(hi.y - lo.y, want_y, 1e-9), "n = {n}: {lo} {hi}");
        assert!(hi.z.abs() < 1e-12 && lo.z.abs() < 1e-12);
        assert_eq!(crossings(m), 0, "n = {n}");
    }
    // Growth is a similarity: with s = 1.5 the area scales by s^(2n).
    let g = grow_checked(&koch(), &settings(3, 1.5)).unwrap();
    let (area, _) = boundary_area_perimeter(&g.map);
    assert!(close(area, 0.6700114 * 1.5f64.powi(6), 1e-6), "area {area}");
}

#[test]
fn quadratic_koch_island_keeps_area_one() {
    let sides = [1.0, 1.5, 1.625, 1.65625];
    for n in 0..=3u32 {
        let g = grow_checked(&quadratic_koch(), &settings(n, 1.0)).unwrap();
        let m = &g.map;
        let e = 4 * 8usize.pow(n);
        assert_eq!((m.vertex_count(), m.edge_count(), m.face_count()), (e, e, 1), "n = {n}");
        let (area, per) = boundary_area_perimeter(m);
        assert!(close(area, 1.0, 1e-9), "n = {n}: area {area}");
        assert!(close(per, 4.0 * 2f64.powi(n as i32), 1e-9));
        let (lo, hi) = bbox(m);
        assert!(close(hi.x - lo.x, sides[n as usize], 1e-9) && close(hi.y - lo.y, sides[n as usize], 1e-9));
        assert_eq!(crossings(m), 0, "n = {n}");
    }
}

#[test]
fn four_sided_tiles_make_a_grid_of_squares() {
    let s = 1.5f64;
    for n in 0..=5u32 {
        let g = grow_checked(&four_sided_tiles(), &settings(n, s)).unwrap();
        let m = &g.map;
        let k = 2usize.pow(n);
        assert_eq!(m.face_count(), k * k, "n = {n}");
        assert_eq!(m.vertex_count(), (k + 1) * (k + 1), "n = {n}");
        assert_eq!(m.edge_count(), 2 * k * (k + 1), "n = {n}");
        let kinds = m.edge_kinds();
        assert_eq!(kinds.iter().filter(|&&t| t == 0).count(), k * (k + 1));
        assert_eq!(kinds.iter().filter(|&&t| t == 1).count(), k * (k + 1));
        let p = m.positions();
        let side = s.powi(n as i32) / k as f64;
        for (e, &kind) in kinds.iter().enumerate() {
            let (a, b) = m.edge_ends(e);
            let d = p[b as usize] - p[a as usize];
            assert!(close(d.length(), side, 1e-9), "edge {e} length {}", d.length());
            // Type 0 runs parallel to the first side (x), type 1 along y.
            let along = if kind == 0 { d.x } else { d.y };
            assert!(close(along.abs(), side, 1e-9), "edge {e} of type {kind} is {d}");
        }
        for f in 0..m.face_count() {
            let l = m.face_loop(f);
            assert_eq!(l.len(), 4, "face {f}");
            let q: Vec<DVec3> = l.iter().map(|&v| p[v as usize]).collect();
            assert!(close((q[2] - q[0]).length(), side * 2f64.sqrt(), 1e-9), "face {f} is not a square");
            // Counter-clockwise seen from +z.
            let z = (q[1] - q[0]).cross(q[2] - q[1]).z;
            assert!(z > 0.0, "face {f} is clockwise");
            assert!((m.face_normal(f).unwrap() - DVec3::Z).length() < 1e-9);
        }
        assert_eq!(crossings(m), 0, "n = {n}");
    }
}

#[test]
fn paper_square_grammar_without_tilde_gives_the_same_grid() {
    // The paper's Table 2: no `~`, BranchAngle 90 (the help file's version
    // has `~` and no BranchAngle).
    let mut h = hemls(
        "Edge0 + Edge1 + Edge0 + Edge1",
        &["Edge0 -> Edge0 [ [ + Edge1 ] - Edge1 ] Edge0", "Edge1 -> Edge1 [ [ + Edge0 ] - Edge0 ] Edge1"],
        90.0,
        false,
    );
    h.branch_angle = Some(90.0);
    let g = grow_checked(&h, &settings(3, 1.5)).unwrap();
    let m = &g.map;
    assert_eq!((m.vertex_count(), m.edge_count(), m.face_count()), (81, 144, 64));
    assert!((0..m.face_count()).all(|f| m.face_loop(f).len() == 4));
    assert_eq!(crossings(m), 0);
}

#[test]
fn three_sided_tiles_make_equilateral_triangles_with_one_edge_of_each_type() {
    let s = 1.5f64;
    for n in 0..=4u32 {
        let g = grow_checked(&three_sided_tiles(), &settings(n, s)).unwrap();
        let m = &g.map;
        let k = 2usize.pow(n);
        assert_eq!(m.face_count(), k * k, "n = {n}");
        assert_eq!(m.vertex_count(), (k + 1) * (k + 2) / 2, "n = {n}");
        assert_eq!(m.edge_count(), 3 * k * (k + 1) / 2, "n = {n}");
        for t in 0..3 {
            assert_eq!(m.edge_kinds().iter().filter(|&&x| x == t).count(), k * (k + 1) / 2, "n = {n}, type {t}");
        }
        let side = s.powi(n as i32) / k as f64;
        let p = m.positions();
        let kinds = edge_kind_map(m);
        for f in 0..m.face_count() {
            let l = m.face_loop(f);
            assert_eq!(l.len(), 3, "face {f}");
            for i in 0..3 {
                let d = p[l[(i + 1) % 3] as usize] - p[l[i] as usize];
                assert!(close(d.length(), side, 1e-9), "face {f} side {}", d.length());
            }
            let mut t = face_side_kinds(m, f, &kinds);
            t.sort_unstable();
            assert_eq!(t, vec![0, 1, 2], "face {f}");
        }
        assert_eq!(crossings(m), 0, "n = {n}");
    }
}

#[test]
fn every_join_reading_grows_the_predefined_grammars_alike() {
    // The default join test was chosen on random EA grammars; the
    // hand-written ones must not notice which reading is in force.
    for (name, h) in [
        ("koch", koch()),
        ("quadratic_koch", quadratic_koch()),
        ("tiles4", four_sided_tiles()),
        ("tiles3", three_sided_tiles()),
    ] {
        let base = grow_checked(&h, &settings(4, 1.5)).unwrap();
        for join in genform_hemls::JoinTest::ALL {
            let s = Settings { join, ..settings(4, 1.5) };
            let g = grow_checked(&h, &s).unwrap();
            assert_eq!(g.steps, base.steps, "{name} with {join:?}");
            assert_eq!(g.map.positions(), base.map.positions(), "{name} with {join:?}");
            assert_eq!(g.map.edge_kinds(), base.map.edge_kinds(), "{name} with {join:?}");
        }
    }
}

#[test]
fn deterministic_grammars_draw_nothing_and_repeat_exactly() {
    struct Counting(u64);
    impl Draws for Counting {
        fn next_f64(&mut self) -> f64 {
            self.0 += 1;
            0.5
        }
    }
    let mut d = Counting(0);
    let g = grow(&four_sided_tiles(), &settings(4, 1.5), &Environment::default(), &mut d).unwrap();
    assert_eq!(d.0, 0);
    let again = grow(&four_sided_tiles(), &settings(4, 1.5), &Environment::default(), &mut Rng::from_seed(99)).unwrap();
    assert_eq!(g.map.positions(), again.map.positions());
    assert_eq!(g.map.to_surface(TagId::default()), again.map.to_surface(TagId::default()));
}

fn square_of(kind: u32) -> String {
    format!("Edge{kind} + Edge{kind} + Edge{kind} + Edge{kind}")
}

#[test]
fn growth_only_scales_about_the_centre() {
    let h = hemls(&square_of(0), &[], 90.0, false);
    let g = grow_checked(&h, &settings(4, 1.5)).unwrap();
    for p in g.map.positions() {
        assert!(close(p.x.abs(), 2.53125, 1e-12) && close(p.y.abs(), 2.53125, 1e-12) && p.z == 0.0, "{p}");
    }
    let c = DVec3::new(1.0, -2.0, 3.0);
    let s = Settings { fixed_center: true, start_position: c, ..settings(4, 1.5) };
    let g = grow_checked(&h, &s).unwrap();
    for p in g.map.positions() {
        let d = *p - c;
        assert!(close(d.x.abs(), 2.53125, 1e-12) && close(d.y.abs(), 2.53125, 1e-12) && d.z.abs() < 1e-12);
    }
    let s = Settings { fixed_perimeter: true, ..settings(4, 1.5) };
    let seed = grow_checked(&h, &settings(0, 1.5)).unwrap();
    let g = grow_checked(&h, &s).unwrap();
    assert_eq!(g.map.positions(), seed.map.positions());
    // Per-axis scale.
    let s = Settings { scale: DVec3::new(2.0, 1.0, 1.0), ..settings(2, 1.0) };
    let g = grow_checked(&h, &s).unwrap();
    let (lo, hi) = bbox(&g.map);
    assert!(close(hi.x - lo.x, 4.0, 1e-12) && close(hi.y - lo.y, 1.0, 1e-12));
}

#[test]
fn fixed_perimeter_moves_only_interior_vertices() {
    let s = Settings { fixed_perimeter: true, ..settings(2, 1.5) };
    let g = grow_checked(&four_sided_tiles(), &s).unwrap();
    let m = &g.map;
    // The boundary vertices stay on the seed square's sides.
    for &v in &m.boundary() {
        let p = m.positions()[v as usize];
        assert!(close(p.x.abs().max(p.y.abs()), 0.5, 1e-12), "{p}");
    }
}

#[test]
fn stochastic_rules_follow_their_weights_and_the_draws() {
    // With weight 3: E0 → E0 E0; with weight 1: E0 → E0 E5 (E5 is never
    // rewritten), so type-5 edges count the weight-1 choices.
    let h = hemls(&square_of(0), &["Edge0 -> Edge0 Edge0 Weight 3 -> Edge0 Edge5 Weight 1"], 90.0, false);
    let s = settings(11, 1.0);
    let mut applications = 0usize;
    let mut on_step = |k: u32, m: &Map| {
        if k < 11 {
            applications += m.edge_kinds().iter().filter(|&&t| t == 0).count();
        }
    };
    let g = grow_with(&h, &s, &Environment::default(), &mut Rng::from_seed(2024), &mut on_step).unwrap();
    let fives = g.map.edge_kinds().iter().filter(|&&t| t == 5).count();
    let freq = fives as f64 / applications as f64;
    assert!(applications > 1000, "{applications}");
    assert!((freq - 0.25).abs() < 0.04, "weight-1 frequency {freq} over {applications} applications");

    let run = |seed: u64| grow(&h, &s, &Environment::default(), &mut Rng::from_seed(seed)).unwrap().map;
    let (a, b, c) = (run(5), run(5), run(6));
    assert_eq!(a.edge_kinds(), b.edge_kinds());
    assert_eq!(a.positions(), b.positions());
    assert_ne!(a.edge_kinds(), c.edge_kinds());
}

#[test]
fn context_rules_see_neighbours_and_take_precedence() {
    // Sides: s0 = P0→P1 (E0), s1 = P1→P2 (E1), s2 = P2→P3 (E0), s3 = P3→P0 (E0).
    let axiom = "Edge0 + Edge1 + Edge0 + Edge0";
    let count = |rules: &[&str]| grow_checked(&hemls(axiom, rules, 90.0, false), &settings(1, 1.0)).unwrap().map;
    // Left context: only s2 starts next to an E1.
    let ends = |m: &Map| (0..m.edge_count()).map(|e| m.edge_ends(e)).collect::<Vec<_>>();
    let m = count(&["Edge1 < Edge0 -> Edge0 Edge0"]);
    assert_eq!(ends(&m), vec![(0, 1), (1, 2), (3, 0), (2, 4), (4, 3)]);
    // Right context: only s0 ends next to an E1.
    let m = count(&["Edge0 > Edge1 -> Edge0 Edge0"]);
    assert_eq!(ends(&m), vec![(1, 2), (2, 3), (3, 0), (0, 4), (4, 1)]);
    // Both: nothing has E1 on both ends.
    assert_eq!(count(&["Edge1 < Edge0 > Edge1 -> Edge0 Edge0"]).vertex_count(), 4);
    // A context rule wins over an earlier context-free one: s2 gets 2
    // pieces, s0 and s3 get 3.
    let m = count(&["Edge0 -> Edge0 Edge0 Edge0", "Edge1 < Edge0 -> Edge0 Edge0"]);
    assert_eq!(m.vertex_count(), 4 + 2 + 1 + 2);
    // The same with Sync.
    let h = hemls(axiom, &["Edge0 -> Edge0 Edge0 Edge0", "Edge1 < Edge0 -> Edge0 Edge0"], 90.0, true);
    assert_eq!(grow_checked(&h, &settings(1, 1.0)).unwrap().map.vertex_count(), 9);
}

#[test]
fn timed_rules_count_ages() {
    let h = hemls(&square_of(0), &["Edge0_i -> Edge0_i+1 Edge0_i+1 If i < 2"], 90.0, false);
    let g = grow_checked(&h, &settings(4, 1.0)).unwrap();
    let edges: Vec<usize> = g.steps.iter().map(|s| s.edges).collect();
    assert_eq!(edges, vec![4, 8, 16, 16, 16]);
    assert!(g.map.edge_ages().iter().all(|&a| a == 2));

    let h = hemls(&square_of(0), &["Edge0_i -> Edge0_i-1 Edge0_i Edge0_i+1"], 90.0, false);
    let g = grow_checked(&h, &settings(2, 1.0)).unwrap();
    let mut hist = [0usize; 3];
    for &a in g.map.edge_ages() {
        hist[a as usize] += 1;
    }
    assert_eq!(hist, [20, 12, 4]);
    // Plain EdgeN resets the age.
    let h = hemls(&square_of(0), &["Edge0_i -> Edge0_i+1 Edge0 If i = 0"], 90.0, false);
    let g = grow_checked(&h, &settings(3, 1.0)).unwrap();
    assert_eq!(g.steps.iter().map(|s| s.edges).collect::<Vec<_>>(), vec![4, 8, 12, 16]);
}

#[test]
fn limits_stop_runaway_growth_quickly() {
    let limits = GrowthLimits { max_vertices: 1000, ..GrowthLimits::default() };
    let s = Settings { limits, ..settings(20, 1.5) };
    let err = grow(&four_sided_tiles(), &s, &Environment::default(), &mut Rng::from_seed(1)).unwrap_err();
    assert_eq!(err, GrowError::Limit { what: "vertices", limit: 1000, step: 5 });
    let msg = err.to_string();
    assert!(msg.contains("raise max_vertices in the [limits] table of the --env file"), "{msg}");

    let limits = GrowthLimits { max_faces: 100, ..GrowthLimits::default() };
    let s = Settings { limits, ..settings(20, 1.5) };
    let err = grow(&four_sided_tiles(), &s, &Environment::default(), &mut Rng::from_seed(1)).unwrap_err();
    assert_eq!(err, GrowError::Limit { what: "faces", limit: 100, step: 4 });

    // Default limits: the tiles stop at step 11 ((2¹¹+1)² > 2,000,000 vertices).
    let start = std::time::Instant::now();
    let err = grow(&four_sided_tiles(), &settings(20, 1.5), &Environment::default(), &mut Rng::from_seed(1));
    assert_eq!(err.unwrap_err(), GrowError::Limit { what: "vertices", limit: 2_000_000, step: 11 });
    let t = start.elapsed();
    assert!(t.as_secs_f64() < 5.0, "took {t:?}");
}

#[test]
fn bad_successors_are_rule_errors() {
    let check = |rules: &[&str], want: &str| {
        let h = hemls(&square_of(0), rules, 90.0, false);
        match grow(&h, &settings(1, 1.0), &Environment::default(), &mut Rng::from_seed(1)) {
            Err(GrowError::Rule { rule, kind, message, .. }) => {
                assert_eq!((rule, kind), (rules.len() - 1, 0));
                assert!(message.contains(want), "{message}");
            }
            other => panic!("expected a rule error, got {other:?}"),
        }
    };
    check(&["Edge0 -> [ + Edge1 ]"], "draws no edge");
    check(&["Edge1 -> Edge1", "Edge0 -> + Edge0 + Edge0 + Edge0 + Edge0"], "ends where it starts");
    check(&["Edge0 -> Edge0 - - Edge0"], "ends where it starts"); // 180° back
    let err = GrowError::Rule { rule: 0, kind: 3, span: Default::default(), message: "x".into() };
    assert_eq!(err.to_string(), "rule 1 (for Edge3): x");
    // Too few axiom sides.
    let h = hemls("Edge0 + Edge0", &[], 90.0, false);
    assert!(matches!(
        grow(&h, &settings(1, 1.0), &Environment::default(), &mut Rng::from_seed(1)),
        Err(GrowError::Invalid { .. })
    ));
}

#[test]
fn overflowing_coordinates_are_reported() {
    let h = hemls(&square_of(0), &["Edge0 -> Edge0 Edge0"], 90.0, false);
    let err = grow(&h, &settings(3, 1e200), &Environment::default(), &mut Rng::from_seed(1)).unwrap_err();
    assert_eq!(err, GrowError::NonFinite { step: 2 });
}

#[test]
fn branches_into_the_outer_face_or_along_the_edge_never_join() {
    // Every branch points outward or along its edge: nothing joins.
    let h = hemls(&square_of(0), &["Edge0 -> Edge0 [ - Edge1 ] [ Edge1 ] Edge0"], 90.0, false);
    let g = grow_checked(&h, &settings(3, 1.5)).unwrap();
    assert_eq!(g.map.face_count(), 1);
    assert_eq!(g.map.vertex_count(), 32);
}

#[test]
fn surfaces_carry_faces_and_typed_edges() {
    let g = grow_checked(&three_sided_tiles(), &settings(2, 1.5)).unwrap();
    let s = g.map.to_surface(TagId::default());
    assert_eq!(s.euler_characteristic(), 1);
    assert_eq!((s.positions.len(), s.edges.len(), s.face_count()), (15, 30, 16));
    for f in s.faces() {
        let p: Vec<_> = f.iter().map(|&v| s.positions[v as usize]).collect();
        assert!((p[1] - p[0]).cross(p[2] - p[1]).z > 0.0, "faces are counter-clockwise seen from +z");
    }
    assert!(s.edges.iter().all(|e| e.kind < 3));
}

// ---- property test ----

fn turn_of(i: u8) -> Turn {
    [Turn::Right, Turn::Left, Turn::PitchDown, Turn::PitchUp, Turn::RollLeft, Turn::RollRight][i as usize % 6]
}

fn inverse(t: Turn) -> Turn {
    match t {
        Turn::Right => Turn::Left,
        Turn::Left => Turn::Right,
        Turn::PitchDown => Turn::PitchUp,
        Turn::PitchUp => Turn::PitchDown,
        Turn::RollLeft => Turn::RollRight,
        Turn::RollRight => Turn::RollLeft,
    }
}

fn sym(kind: u8, rev: bool, age: u8) -> EdgeSym {
    EdgeSym {
        kind: kind as u32 % 3,
        reversed: rev,
        age: [Age::Zero, Age::Same, Age::Plus1, Age::Minus1][age as usize % 4],
    }
}

/// A successor from random parts: main-line edges with turns before them
/// (balanced at the end), and branches at random points.
fn successor(parts: &[(u8, u8, bool, u8, Vec<u8>)], flat: bool) -> Successor {
    let mut items = Vec::new();
    let mut open: Vec<Turn> = Vec::new();
    for (i, (turn, kind, rev, branch_kind, branch_turns)) in parts.iter().enumerate() {
        let t = turn_of(if flat { turn % 2 } else { *turn });
        if turn % 3 != 0 {
            items.push(Item::Turn(t));
            open.push(t);
        }
        items.push(Item::Edge(sym(*kind, *rev, i as u8)));
        // None, one branch, or a mirrored pair (the joinable kind).
        let mut turns: Vec<Turn> = branch_turns.iter().map(|&b| turn_of(if flat { b % 2 } else { b })).collect();
        let edge = sym(*branch_kind / 4, false, 0);
        match branch_kind % 4 {
            0 => {}
            1 => items.push(Item::Branch(Branch { turns, edge })),
            _ => {
                if turns.is_empty() {
                    turns.push(Turn::Right);
                }
                let mirror = turns
                    .iter()
                    .map(|&t| match t {
                        Turn::Right | Turn::Left | Turn::PitchDown | Turn::PitchUp => inverse(t),
                        roll => roll,
                    })
                    .collect();
                items.push(Item::Branch(Branch { turns, edge }));
                items.push(Item::Branch(Branch { turns: mirror, edge }));
            }
        }
    }
    for t in open.into_iter().rev() {
        items.push(Item::Turn(inverse(t)));
    }
    Successor { items, weight: 1.0 }
}

type Part = (u8, u8, bool, u8, Vec<u8>);

fn arb_part() -> impl Strategy<Value = Part> {
    (any::<u8>(), any::<u8>(), any::<bool>(), any::<u8>(), prop::collection::vec(any::<u8>(), 0..3))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn random_grammars_grow_into_discs(
        sides in prop::collection::vec((0u32..3, any::<bool>()), 3..6),
        rules in prop::collection::vec((0u32..3, prop::collection::vec(prop::collection::vec(arb_part(), 1..4), 1..3), 0u8..4), 1..5),
        angle in prop::sample::select(vec![30.0, 45.0, 60.0, 72.0, 90.0, 120.0]),
        sync in any::<bool>(),
        flat in any::<bool>(),
        steps in 1u32..5,
        scale in 0.5f64..2.0,
        branch_angle in prop::sample::select(vec![15.0, 30.0, 45.0, 60.0, 90.0]),
    ) {
        let h = Hemls {
            name: "random".into(),
            axiom: sides.iter().map(|&(kind, reversed)| AxiomSide { kind, reversed }).collect(),
            rules: rules.iter().enumerate().map(|(i, (kind, succs, ctx))| Rule {
                pred: Predecessor {
                    // The first three rules cover every type.
                    kind: if i < 3 { i as u32 } else { *kind },
                    timed: false,
                    left: (*ctx == 1).then_some((kind + 1) % 3),
                    right: (*ctx == 2).then_some((kind + 2) % 3),
                },
                condition: None,
                successors: succs.iter().map(|p| successor(p, flat)).collect(),
                span: Default::default(),
            }).collect(),
            angle,
            sync,
            branch_angle: Some(branch_angle),
        };
        let limits = GrowthLimits { max_vertices: 20_000, max_edges: 40_000, max_faces: 20_000 };
        let s = Settings { limits, ..settings(steps, scale) };
        let mut bad = Vec::new();
        let r = grow_with(&h, &s, &Environment::default(), &mut Rng::from_seed(3), &mut |k, m: &Map| {
            if let Err(e) = m.validate() {
                bad.push(format!("step {k}: {e}"));
            }
            if !m.positions().iter().all(|p| p.is_finite()) {
                bad.push(format!("step {k}: non-finite position"));
            }
        });
        prop_assert!(bad.is_empty(), "{:?}", bad);
        match r {
            Ok(g) => {
                prop_assert_eq!(g.map.euler_characteristic(), 1);
                let surf = g.map.to_surface(TagId::default());
                prop_assert_eq!(surf.euler_characteristic(), 1);
            }
            Err(GrowError::Limit { .. }) | Err(GrowError::Rule { .. }) => {}
            Err(e) => prop_assert!(false, "unexpected error {e}"),
        }
    }
}

#[test]
fn a_face_with_thousands_of_branches_joins_quickly() {
    // A 64-gon whose every edge sends a branch inward: after 10 steps the
    // single seed face has received tens of thousands of branches, most of
    // them mutually anti-parallel within a 90° cone (the tree path of the
    // joiner; quadratic pair tests would take minutes).
    let axiom = vec!["Edge0"; 64].join(" + ");
    let mut h = hemls(&axiom, &["Edge0 -> Edge0 [ + Edge0 ] Edge0"], 90.0, false);
    h.branch_angle = Some(90.0);
    let t = std::time::Instant::now();
    let g = grow_checked(&h, &settings(10, 1.5)).unwrap();
    assert!(t.elapsed().as_secs_f64() < 10.0, "took {:?}", t.elapsed());
    assert!(g.map.face_count() > 1000, "{}", g.map.face_count());
}
