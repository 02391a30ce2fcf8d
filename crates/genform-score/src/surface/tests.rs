//! Golden values of the reference (§9 "Fitness values"), hand checks, an
//! oracle from the paper's formulas, and the scorer's combination.

use super::*;
use genform_core::scene::Scene;
use genform_core::{Surface, SurfaceEdge};
use glam::Vec3;
use proptest::prelude::*;

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * b.abs().max(1.0)
}

fn edge(a: usize, b: usize, kind: u32) -> SurfaceEdge {
    SurfaceEdge { a: a as u32, b: b as u32, kind }
}

fn scene_of(surfaces: Vec<Surface>) -> Scene {
    Scene { surfaces, ..Scene::new() }
}

/// The flat four-sided-tile surface after `n` steps from the unit square
/// centred at the origin, scale `s` per step: a (2ⁿ+1)² grid of side sⁿ.
fn four_sided_tiles(n: u32, s: f64) -> Surface {
    let m = 1usize << n;
    let side = s.powi(n as i32);
    let d = side / m as f64;
    let at = |i: usize, j: usize| j * (m + 1) + i;
    let mut surf = Surface::new(0);
    for j in 0..=m {
        for i in 0..=m {
            surf.positions.push(Vec3::new(
                (-0.5 * side + i as f64 * d) as f32,
                (-0.5 * side + j as f64 * d) as f32,
                0.0,
            ));
        }
    }
    for j in 0..=m {
        for i in 0..=m {
            if i < m {
                surf.edges.push(edge(at(i, j), at(i + 1, j), 0));
            }
            if j < m {
                surf.edges.push(edge(at(i, j), at(i, j + 1), 1));
            }
            if i < m && j < m {
                surf.push_face(&[at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)].map(|v| v as u32));
            }
        }
    }
    surf
}

/// The flat three-sided-tile surface after `n` steps: the equilateral
/// triangle of side sⁿ cut into 4ⁿ triangles; vertex (j, k) is the j-th of
/// row k (rows hold 2ⁿ+1−k vertices).
fn three_sided_tiles(n: u32, s: f64) -> Surface {
    let m = 1usize << n;
    let d = s.powi(n as i32) / m as f64;
    let h = d * 3f64.sqrt() / 2.0;
    let row_start = |k: usize| (0..k).map(|r| m + 1 - r).sum::<usize>();
    let at = |j: usize, k: usize| row_start(k) + j;
    let mut surf = Surface::new(0);
    for k in 0..=m {
        for j in 0..=m - k {
            surf.positions.push(Vec3::new(((j as f64 + k as f64 / 2.0) * d) as f32, (k as f64 * h) as f32, 0.0));
        }
    }
    for k in 0..m {
        for j in 0..m - k {
            surf.edges.push(edge(at(j, k), at(j + 1, k), 0));
            surf.edges.push(edge(at(j, k), at(j, k + 1), 1));
            surf.edges.push(edge(at(j + 1, k), at(j, k + 1), 2));
            surf.push_face(&[at(j, k), at(j + 1, k), at(j, k + 1)].map(|v| v as u32));
            if j + 1 < m - k {
                surf.push_face(&[at(j + 1, k), at(j + 1, k + 1), at(j, k + 1)].map(|v| v as u32));
            }
        }
    }
    surf
}

/// Vertices only (no edges, no faces).
fn points(ps: &[(f32, f32, f32)]) -> Surface {
    let mut surf = Surface::new(0);
    surf.positions.extend(ps.iter().map(|&(x, y, z)| Vec3::new(x, y, z)));
    surf
}

/// The unit square seed centred at the origin.
fn unit_square() -> Surface {
    let mut surf = points(&[(-0.5, -0.5, 0.0), (0.5, -0.5, 0.0), (0.5, 0.5, 0.0), (-0.5, 0.5, 0.0)]);
    surf.edges = vec![edge(0, 1, 0), edge(1, 2, 1), edge(2, 3, 0), edge(3, 0, 1)];
    surf.push_face(&[0, 1, 2, 3]);
    surf
}

#[test]
fn four_sided_tiles_golden_values() {
    let subdivisions = [1.0, 0.75, 0.625, 0.5625, 0.53125];
    for n in 0..=4u32 {
        let surf = four_sided_tiles(n, 1.5);
        let k = 1usize << n;
        assert_eq!(surf.positions.len(), (k + 1) * (k + 1));
        assert_eq!(surf.edges.len(), 2 * k * (k + 1));
        assert_eq!((surf.face_count(), surf.euler_characteristic()), (k * k, 1));
        let m = SurfaceMeasures::of(&scene_of(vec![surf]));
        assert!(close(m.size, 2.0 * 1.5f64.powi(n as i32), 1e-7), "n = {n}: size {}", m.size);
        assert_eq!((m.smoothness, m.undulation), (0.0, 0.0), "n = {n}");
        assert_eq!(m.subdivisions, subdivisions[n as usize], "n = {n}");
        assert_eq!(m.subdivisions, (k + 1) as f64 / (2 * k) as f64);
        assert_eq!(m.symmetry, 1.0, "n = {n}");
        assert_eq!(m.soft_boundary, 0.0);
    }
    assert_eq!(SurfaceMeasures::of(&scene_of(vec![four_sided_tiles(4, 1.5)])).size, 10.125);
}

#[test]
fn three_sided_tiles_golden_values() {
    let subdivisions = [1.0, 0.6667, 0.5, 0.4167, 0.375];
    for n in 0..=4u32 {
        let surf = three_sided_tiles(n, 1.5);
        let k = 1usize << n;
        assert_eq!(surf.positions.len(), (k + 1) * (k + 2) / 2);
        assert_eq!(2 * surf.edges.len(), 3 * k * (k + 1), "3·2ⁿ⁻¹(2ⁿ+1) edges");
        assert_eq!((surf.face_count(), surf.euler_characteristic()), (k * k, 1));
        let m = SurfaceMeasures::of(&scene_of(vec![surf]));
        let side = 1.5f64.powi(n as i32);
        assert!(close(m.size, (1.0 + 3f64.sqrt() / 2.0) * side, 1e-6), "n = {n}: size {}", m.size);
        assert!(close(m.subdivisions, (k + 2) as f64 / (3 * k) as f64, 1e-15), "n = {n}");
        assert!((m.subdivisions - subdivisions[n as usize]).abs() < 5e-5, "n = {n}");
        assert_eq!((m.smoothness, m.undulation), (0.0, 0.0));
        // Mirror-symmetric about the vertical centre line (sym = 1); about
        // the horizontal one, rows k < 2ⁿ/2 (2ⁿ+1−k nodes each) lie below and
        // rows k > 2ⁿ/2 above.
        let row = |r: usize| (k + 1 - r) as f64;
        let below: f64 = (0..=k).filter(|&r| 2 * r < k).map(row).sum();
        let above: f64 = (0..=k).filter(|&r| 2 * r > k).map(row).sum();
        assert!(close(m.symmetry, 0.5 * (1.0 + above / below), 1e-15), "n = {n}: {}", m.symmetry);
    }
    // n = 0: 2 nodes below, 1 above the horizontal line; 1:1 about the vertical.
    assert_eq!(SurfaceMeasures::of(&scene_of(vec![three_sided_tiles(0, 1.0)])).symmetry, 0.75);
}

#[test]
fn hand_check_lifting_one_seed_vertex() {
    let h = 0.25;
    let mut surf = unit_square();
    surf.positions[2].z = h;
    let m = SurfaceMeasures::of(&scene_of(vec![surf]));
    assert_eq!(m.smoothness, 2.0 * f64::from(h), "two incident edges");
    assert_eq!(m.undulation, f64::from(h));
    assert_eq!((m.size, m.subdivisions, m.symmetry), (2.0, 1.0, 1.0));
    assert_eq!((m.vertices, m.edges), (4, 4));
}

#[test]
fn symmetry_of_lopsided_point_sets() {
    // x ∈ {0, 0, 1, 2, 4}: centre 2, 3 nodes left, 1 right (one on the
    // line) → 1/3. y ∈ {0, 1, 0, 3, 4}: centre 2, 3 below, 2 above → 2/3.
    let lopsided = points(&[(0.0, 0.0, 0.0), (0.0, 1.0, 0.0), (1.0, 0.0, 0.0), (2.0, 3.0, 0.0), (4.0, 4.0, 0.0)]);
    let m = SurfaceMeasures::of(&scene_of(vec![lopsided]));
    assert!(close(m.symmetry, 0.5 * (1.0 / 3.0 + 2.0 / 3.0), 1e-15));
    assert_eq!((m.size, m.subdivisions, m.smoothness), (8.0, 1.0, 0.0), "no edges: subdivisions 1");
    // All nodes on the vertical line: sym about it is 1; y ∈ {0, 1, 5}
    // around 2.5 splits 2 : 1.
    let on_a_line = points(&[(3.0, 0.0, 0.0), (3.0, 1.0, 0.0), (3.0, 5.0, 0.0)]);
    assert_eq!(SurfaceMeasures::of(&scene_of(vec![on_a_line])).symmetry, 0.75);
    // A single node is on both lines.
    assert_eq!(SurfaceMeasures::of(&scene_of(vec![points(&[(7.0, -2.0, 1.0)])])).symmetry, 1.0);
}

#[test]
fn nodes_a_few_ulps_off_the_line_count_as_on_it() {
    // The grid's middle column moved right by 4 ulps of the extent, as
    // rounding in growth would: still symmetric. By 1e-3 of it: not.
    for (nudge, symmetric) in [(4.0 * f32::EPSILON, true), (1e-3, false)] {
        let mut surf = four_sided_tiles(2, 1.5);
        surf.positions.iter_mut().filter(|p| p.x == 0.0).for_each(|p| p.x = nudge * 2.25);
        let sym = SurfaceMeasures::of(&scene_of(vec![surf])).symmetry;
        // Off the line, the 5 middle nodes join the 10 on the right: 10 : 15.
        assert_eq!(sym, if symmetric { 1.0 } else { 0.5 * (1.0 + 10.0 / 15.0) }, "nudge {nudge:?}");
    }
    // Same far from the origin, where an ulp is larger.
    let mut surf = four_sided_tiles(2, 1.5);
    for p in &mut surf.positions {
        p.x += 1000.0;
        if p.x == 1000.0 {
            p.x = f32::from_bits(1000f32.to_bits() + 2);
        }
    }
    assert_eq!(SurfaceMeasures::of(&scene_of(vec![surf])).symmetry, 1.0);
}

#[test]
fn surfaces_of_a_scene_are_measured_together_with_soft_boundary_counts() {
    let mut a = unit_square();
    a.outside_soft = 3;
    let mut b = four_sided_tiles(1, 1.0);
    for p in &mut b.positions {
        *p += Vec3::new(3.0, 0.0, 2.0);
    }
    b.outside_soft = 2;
    let m = SurfaceMeasures::of(&scene_of(vec![a, b]));
    assert_eq!((m.vertices, m.edges), (4 + 9, 4 + 12));
    assert_eq!(m.soft_boundary, 5.0);
    assert_eq!(m.soft_boundary_fraction(), 5.0 / 13.0);
    assert_eq!(m.size, 4.0 + 1.0, "x from −0.5 to 3.5, y from −0.5 to 0.5");
    assert_eq!(m.undulation, 2.0);
    assert_eq!(m.subdivisions, 13.0 / 16.0);
    assert_eq!(m.smoothness, 0.0, "each surface is flat; no edge joins them");
}

#[test]
fn empty_scenes_have_finite_measures() {
    let want = SurfaceMeasures {
        size: 0.0,
        smoothness: 0.0,
        soft_boundary: 0.0,
        subdivisions: 1.0,
        symmetry: 1.0,
        undulation: 0.0,
        vertices: 0,
        edges: 0,
    };
    for scene in [Scene::new(), scene_of(vec![Surface::new(0), Surface::default()])] {
        let m = SurfaceMeasures::of(&scene);
        assert_eq!(m, want);
        assert!(m.is_finite());
        assert_eq!(m.soft_boundary_fraction(), 0.0);
        let scorer = SurfaceScorer::new(all_six(&want, 1.0)).unwrap();
        assert_eq!(scorer.fitness(&scene), 6.0);
        let scorer = SurfaceScorer::new(SurfaceObjective::default().with(SurfaceCriterion::Size, 10.0, 1.0)).unwrap();
        assert_eq!(scorer.fitness(&scene), 0.5, "size 0 against 10: error 1");
    }
}

#[test]
fn broken_geometry_scores_zero_on_the_criteria_it_touches() {
    let mut surf = unit_square();
    surf.positions[1].x = f32::NAN;
    surf.positions[2].z = f32::INFINITY;
    let m = SurfaceMeasures::of(&scene_of(vec![surf]));
    assert!(!m.is_finite());
    assert!(m.size.is_nan() && m.symmetry.is_nan() && !m.smoothness.is_finite());
    assert_eq!(m.subdivisions, 1.0);
    let objective = SurfaceObjective::default()
        .with(SurfaceCriterion::Size, 2.0, 1.0)
        .with(SurfaceCriterion::Smoothness, 0.0, 1.0)
        .with(SurfaceCriterion::Subdivisions, 1.0, 3.0);
    let score = SurfaceScorer::new(objective).unwrap().score(&m);
    assert_eq!(score.fitness(), 3.0);
    let errors: Vec<f64> = score.components().iter().map(|c| c.error).collect();
    assert_eq!(errors, [f64::INFINITY, f64::INFINITY, 0.0]);
}

#[test]
fn criterion_names_round_trip() {
    for c in SurfaceCriterion::ALL {
        assert_eq!(SurfaceCriterion::from_name(c.name()), Some(c));
    }
    assert_eq!(SurfaceCriterion::from_name("softness"), None);
}

/// An objective aiming at exactly the measures `m`, every weight `w`.
fn all_six(m: &SurfaceMeasures, w: f64) -> SurfaceObjective {
    SurfaceCriterion::ALL.into_iter().fold(SurfaceObjective::default(), |o, c| o.with(c, m.get(c), w))
}

#[test]
fn targets_met_give_the_best_fitness() {
    let mut surf = four_sided_tiles(4, 1.5);
    surf.positions[7].z = 0.5;
    surf.outside_soft = 4;
    let m = SurfaceMeasures::of(&scene_of(vec![surf]));
    let mut objective = all_six(&m, 1.0);
    objective.symmetry.weight = 2.5;
    let scorer = SurfaceScorer::new(objective).unwrap();
    assert_eq!(scorer.best(), 7.5);
    let score = scorer.score(&m);
    assert_eq!(score.fitness(), 7.5);
    assert_eq!(score.components().len(), 6);
    for c in score.components() {
        assert_eq!((c.error, c.contribution), (0.0, c.weight), "{}", c.name());
        assert_eq!(c.measure, c.target);
    }
}

#[test]
fn errors_and_weights_by_hand() {
    // n = 4, s = 1.5: size 10.125, subdivisions 0.53125.
    let scene = scene_of(vec![four_sided_tiles(4, 1.5)]);
    let objective = SurfaceObjective::default().with(SurfaceCriterion::Size, 10.0, 1.0).with(
        SurfaceCriterion::Subdivisions,
        0.5,
        2.0,
    );
    let score = SurfaceScorer::new(objective).unwrap().score_scene(&scene);
    let [size, sub] = score.components() else { panic!("two weighted criteria") };
    assert_eq!((size.name(), size.measure, size.error), ("size", 10.125, 0.0125));
    assert_eq!((sub.name(), sub.measure, sub.error), ("subdivisions", 0.53125, 0.0625));
    assert!(close(size.contribution, 1.0 / 1.0125, 1e-15));
    assert!(close(sub.contribution, 2.0 / 1.0625, 1e-15));
    assert_eq!(score.fitness(), size.contribution + sub.contribution);
    // Each weight scales its own criterion only.
    let mut heavier = objective;
    heavier.size.weight = 3.0;
    let score3 = SurfaceScorer::new(heavier).unwrap().score_scene(&scene);
    assert!(close(score3.components()[0].contribution, 3.0 * size.contribution, 1e-15));
    assert_eq!(score3.components()[1], *sub);
}

#[test]
fn zero_weight_criteria_are_skipped() {
    let scene = scene_of(vec![four_sided_tiles(2, 1.0)]);
    let base = SurfaceObjective::default().with(SurfaceCriterion::Symmetry, 1.0, 1.0);
    // Undulation is far off its target, but with weight 0 it does not count.
    let skipped = base.with(SurfaceCriterion::Undulation, 50.0, 0.0);
    let score = SurfaceScorer::new(skipped).unwrap().score_scene(&scene);
    assert_eq!(score.components().iter().map(|c| c.name()).collect::<Vec<_>>(), ["symmetry"]);
    assert_eq!(score.fitness(), 1.0);
    assert_eq!(score.to_string(), "fitness 1.000000: symmetry 1.000000 (target 1, error 0.000000, +1.000000)");
}

#[test]
fn the_floor_sets_the_error_scale_of_targets_near_zero() {
    let mut surf = unit_square();
    surf.positions[0].z = 0.25;
    let scene = scene_of(vec![surf]);
    let mut objective = SurfaceObjective::default().with(SurfaceCriterion::Smoothness, 0.0, 1.0);
    // Smoothness 0.5 against 0: default floor 1 → error 0.5.
    assert_eq!(SurfaceScorer::new(objective).unwrap().fitness(&scene), 1.0 / 1.5);
    objective.smoothness.floor = Some(0.1);
    assert!(close(SurfaceScorer::new(objective).unwrap().fitness(&scene), 1.0 / 6.0, 1e-15));
    // A target above the floor makes it relative: 0.5 against 2 → 0.75.
    objective.smoothness.target = 2.0;
    assert_eq!(SurfaceScorer::new(objective).unwrap().fitness(&scene), 1.0 / 1.75);
}

#[test]
fn closer_to_the_target_scores_higher_on_either_side() {
    let scorer = SurfaceScorer::new(SurfaceObjective::default().with(SurfaceCriterion::Size, 2.6, 1.0)).unwrap();
    // Grids of side 1.5ⁿ: sizes 2, 3, 4.5, 6.75, … around the target 2.6.
    let f: Vec<f64> = (0..6).map(|n| scorer.fitness(&scene_of(vec![four_sided_tiles(n, 1.5)]))).collect();
    assert!(f[1] > f[0], "3 is closer to 2.6 than 2: {f:?}");
    assert!(f.windows(2).skip(1).all(|w| w[0] > w[1]), "{f:?}");
    assert!(f.iter().all(|&v| v > 0.0 && v < 1.0));
}

#[test]
fn invalid_objectives_are_rejected_with_the_criterion_named() {
    assert_eq!(SurfaceScorer::new(SurfaceObjective::default()).unwrap_err(), SurfaceError::NoCriteria);
    let ok = SurfaceObjective::default().with(SurfaceCriterion::Size, 10.0, 1.0);
    let err = SurfaceScorer::new(ok.with(SurfaceCriterion::Symmetry, 1.0, -1.0)).unwrap_err();
    assert_eq!(err, SurfaceError::BadWeight { criterion: "symmetry", weight: -1.0 });
    assert!(err.to_string().contains("`symmetry`"), "{err}");
    assert!(matches!(
        SurfaceScorer::new(ok.with(SurfaceCriterion::Undulation, f64::NAN, 1.0)),
        Err(SurfaceError::BadTarget { criterion: "undulation", .. })
    ));
    // Checked even when the weight is 0: a typo should not pass silently.
    assert!(matches!(
        SurfaceScorer::new(ok.with(SurfaceCriterion::Smoothness, f64::INFINITY, 0.0)),
        Err(SurfaceError::BadTarget { criterion: "smoothness", .. })
    ));
    let mut zero_floor = ok;
    zero_floor.size.floor = Some(0.0);
    assert_eq!(SurfaceScorer::new(zero_floor).unwrap_err(), SurfaceError::BadFloor { criterion: "size", floor: 0.0 });
}

#[derive(serde::Deserialize, serde::Serialize, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
struct Config {
    surface: SurfaceObjective,
}

#[test]
fn surface_tables_parse_from_toml() {
    let text = "[surface]\n\
                size = { target = 10, weight = 1 }\n\
                symmetry = { target = 1 }\n\
                smoothness = { target = 0, weight = 0.5, floor = 0.1 }\n";
    let c: Config = toml::from_str(text).unwrap();
    let want = SurfaceObjective::default()
        .with(SurfaceCriterion::Size, 10.0, 1.0)
        .with(SurfaceCriterion::Symmetry, 1.0, 1.0)
        .with(SurfaceCriterion::Smoothness, 0.0, 0.5);
    let mut want = want;
    want.smoothness.floor = Some(0.1);
    assert_eq!(c.surface, want);
    assert_eq!(c.surface.undulation.weight, 0.0, "left out: skipped");
    let back: Config = toml::from_str(&toml::to_string(&c).unwrap()).unwrap();
    assert_eq!(back, c);
    for (bad, key) in [
        ("[surface]\nsise = { target = 10 }\n", "sise"),
        ("[surface]\nsize = { target = 10, wieght = 2 }\n", "wieght"),
        ("[surface]\nsize = { weight = 2 }\n", "target"),
    ] {
        let err = toml::from_str::<Config>(bad).unwrap_err().to_string();
        assert!(err.contains(key), "{bad}: {err}");
    }
}

/// A hand-computed surface: the 2 × 1 rectangle with a node in the middle of
/// its bottom side, the top right corner lifted by 0.5 and a chord from the
/// middle node to it; 2 nodes outside a soft boundary.
///
/// ```text
///  v4 (0,1,0) ──────── v3 (2,1,½)
///   │                 ╱ │
///  v0 (0,0,0) ── v1 (1,0,0) ── v2 (2,0,0)
/// ```
///
/// By hand: size = 2 + 1 = 3; smoothness = ½ (v2v3) + ½ (v3v4) + ½ (v1v3)
/// = 1.5; soft boundary = 2; subdivisions = 5 nodes / 6 edges; symmetry:
/// about x = 1 two nodes each side (v1 on the line) → 1, about y = ½ three
/// below, two above → ⅔, so (1 + ⅔)/2 = ⅚; undulation = ½.
fn hand_surface() -> Scene {
    let mut surf = points(&[(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (2.0, 0.0, 0.0), (2.0, 1.0, 0.5), (0.0, 1.0, 0.0)]);
    surf.edges = vec![edge(0, 1, 0), edge(1, 2, 0), edge(2, 3, 1), edge(3, 4, 0), edge(4, 0, 1), edge(1, 3, 2)];
    surf.push_face(&[0, 1, 3, 4]);
    surf.push_face(&[1, 2, 3]);
    surf.outside_soft = 2;
    scene_of(vec![surf])
}

/// Each criterion alone in the paper form on [`hand_surface`]: the measure
/// by hand, its error `|F − T| / max(|T|, ε)` and the fitness `−w·e`.
#[test]
fn paper_form_scores_each_criterion_by_hand() {
    let scene = hand_surface();
    let m = SurfaceMeasures::of(&scene);
    // (criterion, measure by hand, target, weight, error by hand)
    let cases = [
        (SurfaceCriterion::Size, 3.0, 4.0, 2.0, 0.25),
        (SurfaceCriterion::Smoothness, 1.5, 0.0, 1.0, 1.5), // floor 1
        (SurfaceCriterion::SoftBoundary, 2.0, 0.0, 0.5, 2.0), // floor 1
        (SurfaceCriterion::Subdivisions, 5.0 / 6.0, 0.5, 3.0, 2.0 / 3.0),
        (SurfaceCriterion::Symmetry, 5.0 / 6.0, 1.0, 1.0, 1.0 / 6.0),
        (SurfaceCriterion::Undulation, 0.5, 1.0, 1.0, 0.5),
    ];
    let mut all = SurfaceObjective { form: SurfaceForm::Paper, ..SurfaceObjective::default() };
    let mut total = 0.0;
    for (c, measure, target, weight, error) in cases {
        assert!(close(m.get(c), measure, 1e-15), "{}: {} by hand {measure}", c.name(), m.get(c));
        let objective =
            SurfaceObjective { form: SurfaceForm::Paper, ..SurfaceObjective::default() }.with(c, target, weight);
        let scorer = SurfaceScorer::new(objective).unwrap();
        assert_eq!(scorer.best(), 0.0);
        let score = scorer.score_scene(&scene);
        let [part] = score.components() else { panic!("one weighted criterion") };
        assert!(close(part.error, error, 1e-15), "{}: error {} by hand {error}", c.name(), part.error);
        assert!(close(score.fitness(), -weight * error, 1e-15), "{}: {}", c.name(), score.fitness());
        assert_eq!(score.fitness(), part.contribution);
        // The bounded form of the same goal, for contrast: w / (1 + e).
        let bounded = SurfaceScorer::new(SurfaceObjective { form: SurfaceForm::Bounded, ..objective }).unwrap();
        assert!(close(bounded.fitness(&scene), weight / (1.0 + error), 1e-15), "{}", c.name());
        all = all.with(c, target, weight);
        total -= weight * error;
    }
    // All six together: the weighted sum of the six.
    let score = SurfaceScorer::new(all).unwrap().score_scene(&scene);
    assert_eq!(score.components().len(), 6);
    assert!(close(score.fitness(), total, 1e-15), "{} vs {total}", score.fitness());
    assert!(close(total, -(0.5 + 1.5 + 1.0 + 2.0 + 1.0 / 6.0 + 0.5), 1e-15));
    assert!(score.to_string().contains("size 3.000000 (target 4, error 0.250000, -0.500000)"), "{score}");
}

#[test]
fn paper_form_is_zero_on_target_linear_off_it_and_minus_infinity_when_broken() {
    let scene = scene_of(vec![four_sided_tiles(4, 1.5)]);
    let m = SurfaceMeasures::of(&scene);
    let mut on_target = all_six(&m, 1.5);
    on_target.form = SurfaceForm::Paper;
    assert_eq!(SurfaceScorer::new(on_target).unwrap().score(&m).fitness(), 0.0);
    // Linear: size 2, 3, 4.5, … against 10 costs w·(10 − size)/10 until it passes 10.
    let objective = SurfaceObjective { form: SurfaceForm::Paper, ..SurfaceObjective::default() }.with(
        SurfaceCriterion::Size,
        10.0,
        2.0,
    );
    let scorer = SurfaceScorer::new(objective).unwrap();
    for n in 0..6 {
        let size = 2.0 * 1.5f64.powi(n);
        let f = scorer.fitness(&scene_of(vec![four_sided_tiles(n as u32, 1.5)]));
        assert!(close(f, -2.0 * (size - 10.0).abs() / 10.0, 1e-6), "n = {n}: {f}");
    }
    // Far off, the paper form keeps its slope where the bounded one flattens:
    // sizes 400 and 800 against 10 (errors 39 and 79, weight 2) differ by 80
    // in the paper form but by 2/40 − 2/80 = 0.025 in the bounded one.
    let at = |size: f64, form| {
        let o = SurfaceObjective { form, ..SurfaceObjective::default() }.with(SurfaceCriterion::Size, 10.0, 2.0);
        SurfaceScorer::new(o).unwrap().score(&SurfaceMeasures { size, ..m }).fitness()
    };
    assert!(close(at(400.0, SurfaceForm::Paper) - at(800.0, SurfaceForm::Paper), 80.0, 1e-12));
    assert!(close(at(400.0, SurfaceForm::Bounded) - at(800.0, SurfaceForm::Bounded), 0.025, 1e-12));
    // Broken geometry has an infinite error: −∞, the invalid individuals' rank.
    let mut surf = unit_square();
    surf.positions[1].x = f32::NAN;
    let broken = SurfaceMeasures::of(&scene_of(vec![surf]));
    let o = SurfaceObjective { form: SurfaceForm::Paper, ..SurfaceObjective::default() }
        .with(SurfaceCriterion::Size, 2.0, 1.0)
        .with(SurfaceCriterion::Subdivisions, 1.0, 1.0);
    assert_eq!(SurfaceScorer::new(o).unwrap().score(&broken).fitness(), f64::NEG_INFINITY);
}

#[test]
fn forms_parse_by_name_and_unknown_forms_list_the_valid_ones() {
    for f in SurfaceForm::ALL {
        assert_eq!(SurfaceForm::from_name(f.name()), Some(f));
    }
    assert_eq!(SurfaceForm::default(), SurfaceForm::Bounded);
    let c: Config = toml::from_str("[surface]\nform = \"paper\"\nsize = { target = 10 }\n").unwrap();
    assert_eq!(c.surface.form, SurfaceForm::Paper);
    assert!(toml::to_string(&c).unwrap().contains("form = \"paper\""));
    let c: Config = toml::from_str("[surface]\nsize = { target = 10 }\n").unwrap();
    assert_eq!(c.surface.form, SurfaceForm::Bounded);
    assert!(!toml::to_string(&c).unwrap().contains("form"), "the default stays unwritten");
    let err = toml::from_str::<Config>("[surface]\nform = \"papr\"\nsize = { target = 10 }\n").unwrap_err().to_string();
    assert!(err.contains("papr") && err.contains("`bounded`") && err.contains("`paper`"), "{err}");
}

/// The paper's formulas over all node pairs and neighbour lists.
fn oracle(ps: &[Vec3], edges: &[(usize, usize)]) -> (f64, f64, f64) {
    let d = |f: fn(&Vec3) -> f32| {
        ps.iter().flat_map(|a| ps.iter().map(move |b| (f64::from(f(a)) - f64::from(f(b))).abs())).fold(0.0, f64::max)
    };
    let mut neighbours = vec![Vec::new(); ps.len()];
    for &(a, b) in edges {
        neighbours[a].push(b);
        neighbours[b].push(a);
    }
    let z = |i: usize| f64::from(ps[i].z);
    let smooth: f64 =
        0.5 * (0..ps.len()).map(|i| neighbours[i].iter().map(|&j| (z(i) - z(j)).abs()).sum::<f64>()).sum::<f64>();
    (d(|p| p.x) + d(|p| p.y), smooth, d(|p| p.z))
}

fn coord() -> impl Strategy<Value = f32> {
    (-400i32..400).prop_map(|v| v as f32 / 16.0)
}

proptest! {
    #[test]
    fn measures_match_the_paper_formulas(
        ps in prop::collection::vec((coord(), coord(), coord()), 1..24),
        raw_edges in prop::collection::vec((0usize..1000, 0usize..1000), 0..40),
    ) {
        let ps: Vec<Vec3> = ps.into_iter().map(|(x, y, z)| Vec3::new(x, y, z)).collect();
        let edges: Vec<(usize, usize)> = raw_edges.iter().map(|&(a, b)| (a % ps.len(), b % ps.len())).collect();
        // Split between two surfaces to check they are measured together.
        let cut = ps.len() / 2;
        let mut one = Surface::new(0);
        let mut two = Surface::new(0);
        one.positions.extend_from_slice(&ps[..cut]);
        two.positions.extend_from_slice(&ps[cut..]);
        let mut joined = Vec::new();
        for &(a, b) in &edges {
            if a < cut && b < cut {
                one.edges.push(edge(a, b, 0));
                joined.push((a, b));
            } else if a >= cut && b >= cut {
                two.edges.push(edge(a - cut, b - cut, 0));
                joined.push((a, b));
            }
        }
        let m = SurfaceMeasures::of(&scene_of(vec![one, two]));
        let (size, smooth, und) = oracle(&ps, &joined);
        prop_assert_eq!(m.size, size);
        prop_assert_eq!(m.undulation, und);
        // Coordinates are multiples of 1/16 below 25: every sum is exact.
        prop_assert_eq!(m.smoothness, smooth);
        prop_assert!((0.0..=1.0).contains(&m.symmetry));
        prop_assert_eq!((m.vertices, m.edges), (ps.len(), joined.len()));
    }

    #[test]
    fn point_sets_mirrored_in_both_axes_are_symmetric(
        ps in prop::collection::vec((coord(), coord()), 1..20),
        shift in (coord(), coord()),
    ) {
        let mut surf = Surface::new(0);
        for (x, y) in ps {
            for (sx, sy) in [(1.0, 1.0), (-1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)] {
                surf.positions.push(Vec3::new(sx * x + shift.0, sy * y + shift.1, 0.0));
            }
        }
        prop_assert_eq!(SurfaceMeasures::of(&scene_of(vec![surf])).symmetry, 1.0);
    }
}
