//! Tests of the building operations through the whole pipeline: `lot`,
//! `extrude`, `comp(f)`, `shape`, splits and repeats on polygon scopes,
//! floating sizes and roofs.

use super::*;
use genform_core::Primitive;
use glam::Vec3;

fn grammar(src: &str) -> ShapeGrammar {
    let file = SourceFile::new("t.sg", src);
    match compile(&file, &NoAssets) {
        Ok((g, _)) => g,
        Err(d) => panic!("{}", d.short()),
    }
}

fn try_scene(src: &str) -> Result<Scene, ExpressError> {
    let g = grammar(src);
    let limits = g.limits();
    let s = g.sample(&mut Rng::from_seed(1), &limits)?;
    let mut scene = Scene::new();
    g.express(&s.genome, &limits, &mut scene).map(|()| scene)
}

fn scene(src: &str) -> Scene {
    try_scene(src).unwrap_or_else(|e| panic!("{e}"))
}

/// Area of a planar polygon in 3D.
fn area(p: &[Vec3]) -> f32 {
    let mut n = Vec3::ZERO;
    for i in 0..p.len() {
        n += p[i].cross(p[(i + 1) % p.len()]);
    }
    n.length() / 2.0
}

/// Outward unit normal of a planar polygon (counter-clockwise seen from it).
fn normal(p: &[Vec3]) -> Vec3 {
    let mut n = Vec3::ZERO;
    for i in 0..p.len() {
        n += p[i].cross(p[(i + 1) % p.len()]);
    }
    n.normalize()
}

/// Volume of mesh instance `k` in world units (divergence theorem).
fn world_volume(s: &Scene, k: usize) -> f32 {
    let Primitive::Mesh(m) = s.instances[k].primitive else { panic!("{:?}", s.instances[k].primitive) };
    let (mesh, t) = (&s.meshes[m as usize], s.instances[k].transform);
    mesh.triangles
        .iter()
        .map(|tri| {
            let [a, b, c] = tri.map(|i| t.transform_point3(mesh.positions[i as usize]));
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-4
}

#[test]
fn a_lot_is_a_polygon_on_the_ground() {
    let s = scene("A { lot(4, 2); shape; }");
    assert_eq!(s.polygons.len(), 1);
    let p = &s.polygons[0].points;
    assert_eq!(p.len(), 4);
    assert!((area(p) - 8.0).abs() < 1e-5);
    assert!(close(normal(p), Vec3::Y), "{:?}", normal(p));
    assert!(p.iter().all(|q| q.y == 0.0 && q.x.abs() <= 2.0 && q.z.abs() <= 1.0));
}

#[test]
fn a_rectangular_mass_is_a_box_standing_on_the_lot() {
    let s = scene("A { lot(4, 2); extrude(3); shape; }");
    assert_eq!(s.instances.len(), 1);
    assert_eq!(s.instances[0].primitive, Primitive::Box);
    let t = s.instances[0].transform;
    assert!(close(t.translation.into(), Vec3::new(0.0, 1.5, 0.0)));
    assert!(close(t.transform_vector3(Vec3::ONE).abs(), Vec3::new(4.0, 3.0, 2.0)));
}

#[test]
fn an_l_shaped_lot_extrudes_to_a_closed_prism() {
    // (x, z) corners of an L: 3 × 3 minus the 1 × 1... area 8, height 2.
    let s = scene("A { lot(0, 0, 3, 0, 3, 2, 1, 2, 1, 3, 0, 3); extrude(2); shape; }");
    assert_eq!(s.instances.len(), 1);
    let Primitive::Mesh(m) = s.instances[0].primitive else { panic!("{:?}", s.instances[0].primitive) };
    let mesh = &s.meshes[m as usize];
    let vol = world_volume(&s, 0);
    assert!((vol - 2.0 * 7.0).abs() < 1e-3, "{vol}");
    // 6 walls, 2 caps of 4 triangles each.
    assert_eq!(mesh.triangles.len(), 6 * 2 + 2 * 4);
}

#[test]
fn clockwise_and_crossing_lots() {
    // A clockwise outline is turned round: the lot still faces up.
    let s = scene("A { lot(0, 0, 0, 2, 2, 2, 2, 0); shape; }");
    assert!(close(normal(&s.polygons[0].points), Vec3::Y));
    let e = try_scene("A { lot(0, 0, 1, 1, 1, 0, 0, 1); shape; }").unwrap_err().to_string();
    assert!(e.contains("t.sg:1:5") && e.contains("crosses itself"), "{e}");
    let e = try_scene("A { lot(0, 2); }").unwrap_err().to_string();
    assert!(e.contains("positive width and depth"), "{e}");
}

#[test]
fn comp_hands_each_face_its_orientation() {
    let src = "A { lot(4, 2); extrude(3);
        comp(f) { front: { tag(\"front\"); shape; } | back: { tag(\"back\"); shape; }
                | left, right: { tag(\"lr\"); shape; } | top: { tag(\"top\"); shape; }
                | bottom: { tag(\"bottom\"); shape; } } }";
    let s = scene(src);
    assert_eq!(s.polygons.len(), 6);
    let by_tag = |t: &str| -> Vec<&Vec<Vec3>> {
        let id = s.tags.iter().position(|n| n == t).unwrap() as u32;
        s.polygons.iter().filter(|p| p.tag == id).map(|p| &p.points).collect()
    };
    let front = by_tag("front");
    assert_eq!(front.len(), 1);
    assert!(close(normal(front[0]), Vec3::Z));
    assert!((area(front[0]) - 12.0).abs() < 1e-4);
    assert!(close(normal(by_tag("back")[0]), -Vec3::Z));
    let lr = by_tag("lr");
    assert_eq!(lr.len(), 2);
    assert!(lr.iter().all(|p| (area(p) - 6.0).abs() < 1e-4 && normal(p).x.abs() > 0.999));
    let top = by_tag("top");
    assert!(close(normal(top[0]), Vec3::Y) && (area(top[0]) - 8.0).abs() < 1e-4);
    assert!(top[0].iter().all(|p| (p.y - 3.0).abs() < 1e-5));
    assert!(close(normal(by_tag("bottom")[0]), -Vec3::Y));
}

#[test]
fn comp_follows_a_rotated_scope_and_first_match_wins() {
    // Rotated 90° about y, the scope's front (+z) looks along world +x.
    let src = "A { rotate(y, 90); lot(4, 2); extrude(3);
        comp(f) { front: { tag(\"front\"); shape; } | side: { tag(\"side\"); shape; } } }";
    let s = scene(src);
    assert_eq!(s.polygons.len(), 4);
    let front = s.tags.iter().position(|n| n == "front").unwrap() as u32;
    let f: Vec<_> = s.polygons.iter().filter(|p| p.tag == front).collect();
    assert_eq!(f.len(), 1);
    assert!(close(normal(&f[0].points), Vec3::X), "{:?}", normal(&f[0].points));
}

#[test]
fn face_scopes_run_x_along_the_bottom_edge_and_y_up() {
    // On the front face a box at the scope's +x, +y corner sits at the
    // mass's right top front corner.
    let s =
        scene("A { lot(4, 2); extrude(3); comp(f) { front: { translate(sx / 2, sy / 2, 0); size(0, 0, 0); box; } } }");
    assert!(close(s.instances[0].transform.translation.into(), Vec3::new(2.0, 3.0, 1.0)));
    assert_eq!((s.instances.len(), s.polygons.len()), (1, 0));
}

#[test]
fn floating_splits_fill_the_face_exactly() {
    // 10 wide: absolute 1, floating 2 and 3 stretched by 9 / 5.
    let s = scene("A { lot(10, 2); extrude(3); comp(f) { front: { split(x) { 1: shape | ~2: shape | ~3: shape } } } }");
    let w: Vec<f32> = s.polygons.iter().map(|p| area(&p.points) / 3.0).collect();
    assert_eq!(w.len(), 3);
    assert!((w[0] - 1.0).abs() < 1e-5 && (w[1] - 3.6).abs() < 1e-5 && (w[2] - 5.4).abs() < 1e-5, "{w:?}");
    // With a relative piece the floating ones keep their size.
    let s = scene("A { lot(10, 2); extrude(3); comp(f) { front: { split(x) { ~2: shape | 1r: shape } } } }");
    let w: Vec<f32> = s.polygons.iter().map(|p| area(&p.points) / 3.0).collect();
    assert!((w[0] - 2.0).abs() < 1e-5 && (w[1] - 8.0).abs() < 1e-5, "{w:?}");
}

#[test]
fn floors_and_tiles_of_a_facade() {
    // 10 × 7 front: floors of ~3 → 2 floors of 3.5; tiles of ~3 → 3 of 10/3.
    let s = scene("A { lot(10, 4); extrude(7); comp(f) { front: { repeat(y, ~3) { repeat(x, ~3) { shape; } } } } }");
    assert_eq!(s.polygons.len(), 6);
    let total: f32 = s.polygons.iter().map(|p| area(&p.points)).sum();
    assert!((total - 70.0).abs() < 1e-3);
    assert!(s.polygons.iter().all(|p| (area(&p.points) - 3.5 * 10.0 / 3.0).abs() < 1e-4));
}

#[test]
fn splitting_an_l_lot_keeps_its_area() {
    let s = scene("A { lot(0, 0, 3, 0, 3, 2, 1, 2, 1, 3, 0, 3); split(x) { 1: shape | 1: shape | 1: shape } }");
    let total: f32 = s.polygons.iter().map(|p| area(&p.points)).sum();
    assert!((total - 7.0).abs() < 1e-4, "{total}");
    // Pieces beyond the polygon are empty and emit nothing.
    let s = scene("A { lot(2, 2); split(x) { 2: shape | 5: shape } }");
    assert_eq!(s.polygons.len(), 1);
}

#[test]
fn setbacks_stack_masses_on_inset_top_faces() {
    let src = "A { lot(10, 6); extrude(4); shape;
        comp(f) { top: { split(x) { 1: {} | 1r: { split(y) { 1: {} | 1r: { extrude(2); shape; } | 1: {} } } | 1: {} } } } }";
    let s = scene(src);
    assert_eq!(s.instances.len(), 2);
    let t = s.instances[1].transform;
    assert!(close(t.translation.into(), Vec3::new(0.0, 5.0, 0.0)), "{:?}", t.translation);
    assert!(close(t.transform_vector3(Vec3::ONE).abs(), Vec3::new(8.0, 2.0, 4.0)));
}

#[test]
fn roofs_sit_on_the_top_face() {
    for (op, peak) in
        [("roof_gable(45)", 3.0), ("roof_hip(45)", 3.0), ("roof_pyramid(45)", 3.0), ("roof_shed(45)", 6.0)]
    {
        let s = scene(&format!("A {{ lot(10, 6); extrude(4); comp(f) {{ top: {op} }} }}"));
        assert_eq!(s.instances.len(), 1, "{op}");
        let Primitive::Mesh(m) = s.instances[0].primitive else { panic!() };
        let t = s.instances[0].transform;
        let ys: Vec<f32> = s.meshes[m as usize].positions.iter().map(|p| t.transform_point3(*p).y).collect();
        let (lo, hi) = ys.iter().fold((f32::MAX, f32::MIN), |(a, b), y| (a.min(*y), b.max(*y)));
        assert!((lo - 4.0).abs() < 1e-4 && (hi - 4.0 - peak).abs() < 1e-4, "{op}: {lo} {hi}");
    }
}

#[test]
fn taper_raises_a_pyramid_on_the_top_face() {
    // On the 10 × 6 top face of a 4 high mass: apex 5 above it, over the
    // face's centre; volume 10 · 6 · 5 / 3.
    let s = scene("A { lot(10, 6); extrude(4); comp(f) { top: taper(5) } }");
    let Primitive::Mesh(m) = s.instances[0].primitive else { panic!() };
    let t = s.instances[0].transform;
    let mesh = &s.meshes[m as usize];
    let top = mesh
        .positions
        .iter()
        .map(|p| t.transform_point3(*p))
        .fold(Vec3::splat(f32::MIN), |a, p| if p.y > a.y { p } else { a });
    assert!(close(top, Vec3::new(0.0, 9.0, 0.0)), "{top}");
    let vol = world_volume(&s, 0);
    assert!((vol - 100.0).abs() < 1e-3, "{vol}");
}

#[test]
fn comp_v_gives_each_corner_its_scope_classed_by_where_it_points() {
    // A column on every corner of a 4 × 2 lot, centred on the corner.
    let s = scene("A { lot(4, 2); comp(v) { all: { size(0.4, 0.4, 3); box; } } }");
    let mut at: Vec<(i32, i32)> = s
        .instances
        .iter()
        .map(|i| {
            let c = i.transform.translation;
            ((c.x * 10.0).round() as i32, (c.z * 10.0).round() as i32)
        })
        .collect();
    at.sort();
    assert_eq!(at, [(-20, -10), (-20, 10), (20, -10), (20, 10)]);
    // Each column is 0.4 wide, 3 high, and stands in the lot's plane.
    for i in &s.instances {
        let (scale, _, t) = i.transform.to_scale_rotation_translation();
        let mut dims = scale.abs().to_array();
        dims.sort_by(f32::total_cmp);
        assert!(
            (dims[0] - 0.4).abs() < 1e-5 && (dims[1] - 0.4).abs() < 1e-5 && (dims[2] - 3.0).abs() < 1e-5,
            "{scale}"
        );
        assert!(t.y.abs() < 1e-5, "{t}");
    }
    // An L's six corners, each classed by its outward bisector (the
    // reflex one's points into the notch); diagonal ones count as front or
    // back, as a wall at 45° does: the four at z ≥ 2, the two at z = 0.
    let l = |arm: &str| {
        let src = format!(
            "A {{ lot(0, 0, 3, 0, 3, 2, 1, 2, 1, 3, 0, 3); comp(v) {{ {arm}: {{ size(0.2, 0.2, 1); box; }} }} }}"
        );
        scene(&src).instances.iter().map(|i| i.transform.translation.z).collect::<Vec<f32>>()
    };
    assert_eq!(l("all").len(), 6);
    assert!(l("front").len() == 4 && l("back").len() == 2 && l("left").is_empty(), "{:?} {:?}", l("front"), l("back"));
}

#[test]
fn polygons_emitted_on_emitted_surfaces_are_lifted_off_them() {
    // A 4 × 2 lot extruded 3 and emitted; its top face emitted on it, and
    // an inset of that face on the face: 5 mm, then 10 mm above the roof
    // of the mass, instead of in its plane (where they would z-fight).
    let s = scene("A { lot(4, 2); extrude(3); shape; comp(f) { top: { shape; offset(-0.5) { inside: shape } } } }");
    let heights: Vec<f32> = s.polygons.iter().map(|p| p.points.iter().map(|q| q.y).fold(f32::MIN, f32::max)).collect();
    assert_eq!(heights.len(), 2);
    assert!((heights[0] - 3.005).abs() < 1e-5 && (heights[1] - 3.010).abs() < 1e-5, "{heights:?}");
    // On a mass never emitted, its faces lie in its planes.
    let s = scene("A { lot(4, 2); extrude(3); comp(f) { top: shape } }");
    assert!(s.polygons[0].points.iter().all(|q| (q.y - 3.0).abs() < 1e-6), "{:?}", s.polygons[0].points);
    // A wall of an emitted mass: lifted outwards, along its normal.
    let s = scene("A { lot(4, 2); extrude(3); shape; comp(f) { front: shape } }");
    let z: Vec<f32> = s.polygons[0].points.iter().map(|q| q.z).collect();
    assert!(z.iter().all(|z| (z.abs() - 1.005).abs() < 1e-5), "{z:?}");
}

#[test]
fn what_is_left_out_is_noted_with_its_place_and_reason() {
    // An inset past the middle leaves `inside` nothing: noted once per
    // run, however often it happens, with the place and the inset.
    let s = scene("A { lot(4, 2); offset(-1.5) { inside: { extrude(1); shape; } | border: shape } }");
    assert_eq!(s.notes.len(), 1, "{:?}", s.notes);
    let (text, n) = &s.notes[0];
    assert!(text.starts_with("t.sg:1:") && text.contains("`offset(-1.5)` leaves nothing inside") && *n == 1, "{text}");
    // An inset that leaves something, or no `inside` arm: nothing to note.
    assert!(scene("A { lot(4, 2); offset(-0.5) { inside: { extrude(1); shape; } | border: shape } }").notes.is_empty());
    assert!(scene("A { lot(4, 2); offset(-1.5) { border: shape } }").notes.is_empty());
    // A roof on a piece with no area: noted, not silently missing.
    let s = scene("A { lot(4, 2); split(x) { 0: { roof_hip(30); } | 1r: { roof_hip(30); } } }");
    assert!(s.notes.iter().any(|(t, _)| t.contains("`roof_hip`: the polygon has no area here")), "{:?}", s.notes);
}

#[test]
fn hostile_building_operations_fail_clearly() {
    let cases = [
        ("A { extrude(2); }", "needs a polygon scope"),
        ("A { lot(2, 2); extrude(-1); }", "must be ≥ 0"),
        ("A { lot(2, 2); roof_hip(95); }", "between 0 and 90"),
        ("A { roof_gable(30); }", "needs a polygon scope"),
        ("A { lot(2, 2); comp(f) { top: shape } }", "needs a mass"),
        ("A { lot(0, 0, 5, 0, 5, 1, 1, 1, 1, 5, 0, 5); roof_pyramid(30); }", "does not see every edge"),
        ("A { taper(3); }", "needs a polygon scope"),
        ("A { lot(2, 2); taper(-1); }", "must be ≥ 0"),
    ];
    for (src, want) in cases {
        let e = try_scene(src).unwrap_err().to_string();
        assert!(e.contains(want) && e.contains("t.sg:1:"), "{src}: {e}");
    }
    // The same L takes a hip or a gable roof (through its straight skeleton).
    assert_eq!(scene("A { lot(0, 0, 3, 0, 3, 2, 1, 2, 1, 3, 0, 3); roof_hip(30); }").meshes.len(), 1);
    assert_eq!(scene("A { lot(0, 0, 3, 0, 3, 2, 1, 2, 1, 3, 0, 3); roof_gable(30); }").meshes.len(), 1);
    // A shed takes any footprint; a pyramid one whose centre sees it whole.
    assert_eq!(scene("A { lot(0, 0, 3, 0, 3, 2, 1, 2, 1, 3, 0, 3); roof_shed(30); }").meshes.len(), 1);
    assert_eq!(scene("A { lot(0, 0, 2, 0, 2, 1, 1, 1, 1, 2, 0, 2); roof_pyramid(30); }").meshes.len(), 1);
    // A zero extrusion is an empty mass: nothing, and no faces.
    let s = scene("A { lot(2, 2); extrude(0); shape; comp(f) { all: shape } }");
    assert!(s.is_empty());
}

#[test]
fn building_parameters_are_genes() {
    let g = grammar("A { param w: uniform(4, 8); param h: int(2, 5); lot(w, 6); extrude(3 * h); shape; }");
    let mut heights = std::collections::BTreeSet::new();
    for seed in 0..20 {
        let limits = g.limits();
        let s = g.sample(&mut Rng::from_seed(seed), &limits).unwrap();
        let mut scene = Scene::new();
        g.express(&s.genome, &limits, &mut scene).unwrap();
        let size = scene.instances[0].transform.transform_vector3(Vec3::ONE);
        heights.insert((size.y * 10.0).round() as i32);
    }
    assert!(heights.len() > 1 && heights.iter().all(|h| [60, 90, 120, 150].contains(h)), "{heights:?}");
}

/// The areas of the polygons tagged `tag`, in emission order.
fn tagged_areas(src: &str, tag: &str) -> Vec<f32> {
    let s = scene(src);
    let id = s.tags.iter().position(|t| t == tag).map(|i| i as u32);
    s.polygons.iter().filter(|p| Some(p.tag) == id).map(|p| area(&p.points)).collect()
}

fn sum(v: &[f32]) -> f32 {
    v.iter().sum()
}

#[test]
fn offset_insets_and_borders_partition_the_polygon() {
    let src = "A { lot(10, 6); offset(-1) { inside: { tag(\"in\"); shape; } | border: { tag(\"b\"); shape; } } }";
    let inside = tagged_areas(src, "in");
    let border = tagged_areas(src, "b");
    assert_eq!(inside.len(), 1);
    assert!((inside[0] - 32.0).abs() < 1e-4, "{inside:?}");
    assert_eq!(border.len(), 4);
    assert!((sum(&border) - 28.0).abs() < 1e-4, "{border:?}");
    // Only the front border (the street side, +z): a trapezoid 10 → 8 wide.
    let front = tagged_areas("A { lot(10, 6); offset(-1) { front: { tag(\"f\"); shape; } } }", "f");
    assert_eq!(front.len(), 1);
    assert!((front[0] - 9.0).abs() < 1e-4);
    // An L of arms 2 wide: an inset by 1 consumes it; by 0.5 it is an L of
    // arms 1 wide, 5 and 4 long beyond the corner square.
    let l = "lot(0, 0, 6, 0, 6, 2, 2, 2, 2, 6, 0, 6)";
    assert!(tagged_areas(&format!("A {{ {l}; offset(-1) {{ inside: {{ tag(\"in\"); shape; }} }} }}"), "in").is_empty());
    let half = tagged_areas(&format!("A {{ {l}; offset(-0.5) {{ inside: {{ tag(\"in\"); shape; }} }} }}"), "in");
    assert!((sum(&half) - (5.0 + 4.0)).abs() < 1e-4, "{half:?}");
    // A dumbbell's neck closes: two pieces.
    let db = "lot(0, 0, 6, 0, 6, 2, 10, 2, 10, 0, 16, 0, 16, 6, 10, 6, 10, 4, 6, 4, 6, 6, 0, 6)";
    let two = tagged_areas(&format!("A {{ {db}; offset(-1.5) {{ inside: {{ tag(\"in\"); shape; }} }} }}"), "in");
    assert_eq!(two.len(), 2);
    assert!((sum(&two) - 18.0).abs() < 1e-4);
    // Growing: the original inside, a mitred ring outside.
    let grow = "A { lot(10, 6); offset(1) { inside: { tag(\"in\"); shape; } | border: { tag(\"b\"); shape; } } }";
    assert!((sum(&tagged_areas(grow, "in")) - 60.0).abs() < 1e-4);
    assert!((sum(&tagged_areas(grow, "b")) - (12.0 * 8.0 - 60.0)).abs() < 1e-4);
}

#[test]
fn setbacks_strips_and_remainder() {
    let src = "A { lot(10, 6); setback(2) { front: { tag(\"s\"); shape; } | remainder: { tag(\"r\"); shape; } } }";
    assert_eq!(tagged_areas(src, "s"), [20.0]);
    assert_eq!(tagged_areas(src, "r"), [40.0]);
    // The strip lies on the street side (+z).
    let s = scene(src);
    let z: f32 = s.polygons[0].points.iter().map(|p| p.z).sum::<f32>() / s.polygons[0].points.len() as f32;
    assert!(z > 1.9 && z < 2.1, "{z}");
    // Two strips meeting at a corner are cut along its bisector.
    let two =
        "A { lot(10, 6); setback(2) { front, left: { tag(\"s\"); shape; } | remainder: { tag(\"r\"); shape; } } }";
    let strips = tagged_areas(two, "s");
    assert_eq!(strips.len(), 2);
    assert!((sum(&strips) - (60.0 - 8.0 * 4.0)).abs() < 1e-4, "{strips:?}");
    assert!((strips[0] - (20.0 - 2.0)).abs() < 1e-4, "{strips:?}");
    assert!((sum(&tagged_areas(two, "r")) - 32.0).abs() < 1e-4);
    // A setback deeper than the lot leaves no remainder.
    assert!(
        tagged_areas("A { lot(10, 6); setback(7) { all: shape | remainder: { tag(\"r\"); shape; } } }", "r").is_empty()
    );
}

#[test]
fn setbacks_by_side_cut_their_corners_from_corner_to_corner() {
    // A 10 × 8 lot set back 3 at the front, 2 at the back and 1 at the
    // sides: the remainder is 8 × 3; the front strip a trapezoid from the
    // 10 m edge to the remainder's 8 m one, 3 deep (27), the back one 2
    // deep (18), each side strip 1 wide from 8 m down to 3 m (5.5).
    let src = "A { lot(10, 8); setback(1, front = 3, back = 2) { front: { tag(\"f\"); shape; } | back: { tag(\"b\"); shape; } \
               | side: { tag(\"s\"); shape; } | remainder: { tag(\"r\"); shape; } } }";
    let near = |got: Vec<f32>, want: &[f32]| {
        assert_eq!(got.len(), want.len(), "{got:?}");
        assert!(got.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-4), "{got:?} vs {want:?}");
    };
    near(tagged_areas(src, "r"), &[24.0]);
    near(tagged_areas(src, "f"), &[27.0]);
    near(tagged_areas(src, "b"), &[18.0]);
    near(tagged_areas(src, "s"), &[5.5, 5.5]);
    // Without named sides, as before: one distance for all.
    let same =
        "A { lot(10, 8); setback(1, front = 1) { all: { tag(\"s\"); shape; } | remainder: { tag(\"r\"); shape; } } }";
    near(tagged_areas(same, "r"), &[48.0]);
}

#[test]
fn setbacks_per_edge_index_take_one_distance_per_written_edge() {
    // `lot(w, d)` lists front, right, back, left: the same 10 × 8 lot set
    // back as the test above by edge index gives the same pieces.
    let src = "A { lot(10, 8); setback(0, edges = [3, 1, 2, 1]) { front: { tag(\"f\"); shape; } \
               | back: { tag(\"b\"); shape; } | side: { tag(\"s\"); shape; } | remainder: { tag(\"r\"); shape; } } }";
    let near = |got: Vec<f32>, want: &[f32]| {
        assert_eq!(got.len(), want.len(), "{got:?}");
        assert!(got.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-4), "{got:?} vs {want:?}");
    };
    near(tagged_areas(src, "r"), &[24.0]);
    near(tagged_areas(src, "f"), &[27.0]);
    near(tagged_areas(src, "s"), &[5.5, 5.5]);
    // A 3 × 2 lot written counter-clockwise in (x, z) with a straight
    // corner at (2, 0): indices follow the writing (edge 2 is x = 3), and
    // a strip beside edges of no depth runs to their lines (1 × 2).
    let lot = "lot(0, 0, 2, 0, 3, 0, 3, 2, 0, 2)";
    let one = format!(
        "A {{ {lot}; setback(0, edges = [0, 0, 1, 0, 0]) {{ all: {{ tag(\"s\"); shape; }} | remainder: {{ tag(\"r\"); shape; }} }} }}"
    );
    near(tagged_areas(&one, "s"), &[2.0]);
    near(tagged_areas(&one, "r"), &[4.0]);
    let s = scene(&one);
    let strip = s.polygons.iter().find(|p| (area(&p.points) - 2.0).abs() < 1e-4).unwrap();
    assert!(
        strip.points.iter().all(|q| q.x > 0.5 - 1e-4),
        "the strip lies at x = 3 (centred: 1.5): {:?}",
        strip.points
    );
    // Roof edge indices follow the writing too: edge 0 of this pentagon
    // runs along x (stored reversed, its edge 0 would be the sloping
    // (5, 9)–(0, 6)), so the ridge does.
    let s = scene("A { lot(0, 0, 10, 0, 10, 6, 5, 9, 0, 6); roof_gable(40, ridge = 0); }");
    let p = world_points(&s, 0);
    let top = p.iter().map(|q| q.y).fold(f32::MIN, f32::max);
    let ridge: Vec<_> = p.iter().filter(|q| q.y > top - 1e-4).collect();
    assert!(ridge.iter().all(|q| (q.z - ridge[0].z).abs() < 1e-4), "{ridge:?}");
    assert!(ridge.iter().any(|q| (q.x - ridge[0].x).abs() > 1.0), "{ridge:?}");
    // A list of the wrong length, or a bad distance, says so.
    for (src, want) in [
        ("A { lot(2, 2); setback(0, edges = [1, 1, 1]) { all: shape } }", "lists 3 distances, the polygon has 4 edges"),
        ("A { lot(2, 2); setback(0, edges = [1, -1, 1, 1]) { all: shape } }", "must be ≥ 0"),
    ] {
        let e = try_scene(src).unwrap_err().to_string();
        assert!(e.contains(want) && e.contains("t.sg:1:"), "{src}: {e}");
    }
}

#[test]
fn split_area_cuts_by_area_not_length() {
    let near = |got: Vec<f32>, want: &[f32]| {
        assert_eq!(got.len(), want.len(), "{got:?}");
        assert!(got.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-3), "{got:?} vs {want:?}");
    };
    // A 10 × 6 lot: 15 m², the rest, 15 m².
    let rect = "A { lot(10, 6); splitArea(x) { 15: { tag(\"a\"); shape; } | ~1: { tag(\"b\"); shape; } | 15: { tag(\"a\"); shape; } } }";
    near(tagged_areas(rect, "a"), &[15.0, 15.0]);
    near(tagged_areas(rect, "b"), &[30.0]);
    // A right triangle of legs 10 (50 m²) in halves: the cut stands at
    // 10 − √50 from the right angle, not at 5.
    let tri = "A { lot(0, 0, 10, 0, 0, 10); splitArea(x) { 1r: { tag(\"a\"); shape; } | 1r: { tag(\"b\"); shape; } } }";
    near(tagged_areas(tri, "a"), &[25.0]);
    near(tagged_areas(tri, "b"), &[25.0]);
    // The same triangle given clockwise.
    let cw = "A { lot(0, 0, 0, 10, 10, 0); splitArea(x) { 1r: { tag(\"a\"); shape; } | 1r: { tag(\"b\"); shape; } } }";
    near(tagged_areas(cw, "a"), &[25.0]);
    // Only a polygon scope can be divided by area.
    let e = try_scene("A { splitArea(x) { 1r: box } }").unwrap_err().to_string();
    assert!(e.contains("`splitArea` divides a polygon scope") && e.contains("t.sg:1:5"), "{e}");
}

#[test]
fn l_u_and_o_shapes() {
    let shape = |op: &str| {
        let src = format!(
            "A {{ lot(10, 6); {op} {{ shape: {{ tag(\"s\"); shape; }} | remainder: {{ tag(\"r\"); shape; }} }} }}"
        );
        (tagged_areas(&src, "s"), tagged_areas(&src, "r"))
    };
    let (s, r) = shape("shapeL(2, 3)");
    assert_eq!((s.len(), r.len()), (1, 1));
    assert!((s[0] - (20.0 + 12.0)).abs() < 1e-4 && (r[0] - 28.0).abs() < 1e-4, "{s:?} {r:?}");
    let (s, r) = shape("shapeU(2, 3, 1)");
    assert!((s[0] - 36.0).abs() < 1e-4 && (r[0] - 24.0).abs() < 1e-4, "{s:?} {r:?}");
    let (s, r) = shape("shapeO(1, 1, 1, 1)");
    assert_eq!(s.len(), 4);
    assert!((sum(&s) - 28.0).abs() < 1e-4 && (r[0] - 32.0).abs() < 1e-4, "{s:?} {r:?}");
    // Widths past the lot: the whole lot is the shape.
    let (s, r) = shape("shapeL(9, 1)");
    assert!(r.is_empty() && (s[0] - 60.0).abs() < 1e-4);
    // Mass them: an L-shaped block with a hip roof stays closed.
    let s = scene("A { lot(10, 6); shapeL(2, 3) { shape: { extrude(3); shape; comp(f) { top: roof_hip(30) } } } }");
    assert_eq!(s.meshes.len(), 2);
}

#[test]
fn comp_e_places_a_scope_on_every_edge() {
    let s = scene("A { lot(10, 6); comp(e) { front: { size(1, 1, 1); box; } | side: { size(0.5, 0.5, 0.5); box; } } }");
    assert_eq!(s.instances.len(), 4);
    let front = s.instances[0].transform.translation;
    assert!(close(Vec3::from(front), Vec3::new(0.0, 0.0, 3.0)), "{front}");
    // An L has six edges.
    let l = scene("A { lot(0, 0, 6, 0, 6, 2, 2, 2, 2, 6, 0, 6); comp(e) { all: { size(1, 1, 1); box; } } }");
    assert_eq!(l.instances.len(), 6);
}

#[test]
fn hostile_component_splits_fail_clearly() {
    let cases = [
        ("A { offset(-1) { inside: shape } }", "needs a polygon scope"),
        ("A { lot(2, 2); setback(-1) { front: shape } }", "must be ≥ 0"),
        ("A { lot(2, 2); shapeL(-1, 1) { shape: shape } }", "must be ≥ 0"),
        ("A { lot(0, 0, 3, 0, 3, 2, 1, 2, 1, 3, 0, 3); shapeU(1, 1, 1) { shape: shape } }", "rectangular"),
    ];
    for (src, want) in cases {
        let e = try_scene(src).unwrap_err().to_string();
        assert!(e.contains(want) && e.contains("t.sg:1:"), "{src}: {e}");
    }
    // Grown past a concave corner the ring stays whole: a T's stem.
    let t = "A { lot(0, 0, 6, 0, 6, 1, 3.5, 1, 3.5, 5, 2.5, 5, 2.5, 1, 0, 1); offset(1) { border: { tag(\"b\"); shape; } } }";
    let ring = tagged_areas(t, "b");
    assert_eq!(ring.len(), 8);
    // The grown outline: 8 × 3 base with a 3 × 4 stem, less the T itself.
    assert!((sum(&ring) - (8.0 * 3.0 + 3.0 * 4.0 - (6.0 + 4.0))).abs() < 1e-4, "{ring:?}");
    // An inset past the inradius leaves nothing, without error.
    assert!(scene("A { lot(2, 2); offset(-5) { inside: shape } }").is_empty());
}

proptest::proptest! {
    /// Random star-shaped lots (mostly concave) under every polygon
    /// operation with random distances: an error or finite geometry, never
    /// a panic or NaN.
    #[test]
    fn polygon_operations_on_random_lots_stay_finite(
        radii in proptest::collection::vec(0.5f64..12.0, 3..14),
        d in -6.0f64..6.0,
        w in proptest::collection::vec(-1.0f64..15.0, 4),
        op in 0usize..6,
    ) {
        let k = radii.len();
        let corners: Vec<String> = radii
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let a = std::f64::consts::TAU * i as f64 / k as f64;
                format!("{:.4}, {:.4}", r * a.cos(), r * a.sin())
            })
            .collect();
        let arms = "{ extrude(2); shape; comp(f) { top: roof_hip(40, 0.2) } }";
        let body = match op {
            0 => format!("offset({d}) {{ inside: {arms} | border: {{ extrude(1); shape; }} }}"),
            1 => format!("setback({d}) {{ front, left: shape | remainder: {arms} }}"),
            2 => format!("comp(e) {{ all: {{ size(sx, 0.3, 0.3); box; }} }} roof_hip(30, {});", d.abs()),
            3 => format!("shapeL({}, {}) {{ shape: {arms} | remainder: shape }}", w[0], w[1]),
            4 => format!("shapeU({}, {}, {}) {{ shape: {arms} | remainder: shape }}", w[0], w[1], w[2]),
            _ => format!("shapeO({}, {}, {}, {}) {{ shape: shape | remainder: {arms} }}", w[0], w[1], w[2], w[3]),
        };
        // L, U and O shapes need a rectangle.
        let lot = if op >= 3 { format!("{:.3}, {:.3}", radii[0] + 1.0, radii[1] + 1.0) } else { corners.join(", ") };
        let src = format!("A {{ lot({lot}); {body} }}");
        let file = SourceFile::new("t.sg", src.as_str());
        let (g, _) = compile(&file, &NoAssets).map_err(|e| proptest::test_runner::TestCaseError::fail(e.short()))?;
        let limits = g.limits();
        let s = match g.sample(&mut Rng::from_seed(1), &limits) {
            Ok(s) => s,
            // A clear error (a negative width, a ring that folds over) is allowed.
            Err(e) => {
                let e = e.to_string();
                proptest::prop_assert!(e.contains("t.sg:1:"), "{src}: {e}");
                return Ok(());
            }
        };
        let mut scene = Scene::new();
        let r = g.express(&s.genome, &limits, &mut scene);
        if r.is_ok() {
            for p in &scene.polygons {
                proptest::prop_assert!(p.points.iter().all(|q| q.is_finite()), "{src}");
            }
            for m in &scene.meshes {
                proptest::prop_assert!(m.positions.iter().all(|q| q.is_finite()), "{src}");
            }
            for i in &scene.instances {
                proptest::prop_assert!(i.transform.is_finite(), "{src}");
            }
        }
    }
}

/// World vertices of mesh instance `k`.
fn world_points(s: &Scene, k: usize) -> Vec<Vec3> {
    let Primitive::Mesh(m) = s.instances[k].primitive else { panic!("{:?}", s.instances[k].primitive) };
    let t = s.instances[k].transform;
    s.meshes[m as usize].positions.iter().map(|p| t.transform_point3(*p)).collect()
}

/// Four terraced houses 6 m wide along the street (world +z) and 10 m
/// deep, with gable roofs `roof` on their top faces.
fn terrace(roof: &str) -> Scene {
    scene(&format!(
        "A {{ lot(24, 10); split(x) {{ 6: H | 6: H | 6: H | 6: H }} }}
         H {{ extrude(6); comp(f) {{ side: {{ tag(\"wall\"); shape; }} | top: {{ tag(\"roof\"); {roof} }} }} }}"
    ))
}

#[test]
fn terraced_gables_turn_their_ridge_to_the_street() {
    for roof in [
        "roof_gable(40, 0.5, ridge = front, ends = 0, gables = \"wall\");",
        "roof_gable(40, ridge = 0, overhang = [0.5, 0, 0.5, 0], gables = \"wall\");",
        "roof_gable(40, overhang = 0.5, ridge = back, ends = 0, gables = \"wall\");",
    ] {
        let s = terrace(roof);
        let tag = |name: &str| s.tags.iter().position(|t| t == name).unwrap() as u32;
        let (roof_tag, wall_tag) = (tag("roof"), tag("wall"));
        let roofs: Vec<usize> = (0..s.instances.len()).filter(|&k| s.instances[k].tag == roof_tag).collect();
        assert_eq!(roofs.len(), 4, "{roof}");
        for &k in &roofs {
            let p = world_points(&s, k);
            let cx = p.iter().map(|q| q.x).sum::<f32>() / p.len() as f32;
            let x0 = -12.0 + 6.0 * ((cx + 12.0) / 6.0).floor();
            // No overhang at the party walls, 0.5 at the street and back.
            assert!(p.iter().all(|q| q.x >= x0 - 1e-4 && q.x <= x0 + 6.0 + 1e-4), "{roof}: {p:?}");
            let (zlo, zhi) = p.iter().fold((f32::MAX, f32::MIN), |(a, b), q| (a.min(q.z), b.max(q.z)));
            assert!((zlo + 5.5).abs() < 1e-4 && (zhi - 5.5).abs() < 1e-4, "{roof}: {zlo} {zhi}");
            // The ridge: the highest points, a segment along the street.
            let top = p.iter().map(|q| q.y).fold(f32::MIN, f32::max);
            let ridge: Vec<Vec3> = p.iter().copied().filter(|q| q.y > top - 1e-4).collect();
            let (rlo, rhi) = ridge.iter().fold((f32::MAX, f32::MIN), |(a, b), q| (a.min(q.x), b.max(q.x)));
            assert!(ridge.iter().all(|q| q.z.abs() < 1e-4), "{roof}: {ridge:?}");
            assert!((rlo - x0).abs() < 1e-4 && (rhi - x0 - 6.0).abs() < 1e-4, "{roof}: {ridge:?}");
            assert!((top - 6.0 - 5.5 * 40f32.to_radians().tan()).abs() < 1e-3, "{roof}: {top}");
        }
        // The gable triangles: walls in the party-wall planes, within the
        // façades, on top of the mass.
        let gables: Vec<usize> = (0..s.instances.len())
            .filter(|&k| s.instances[k].tag == wall_tag && matches!(s.instances[k].primitive, Primitive::Mesh(_)))
            .collect();
        assert_eq!(gables.len(), 4, "{roof}");
        for &k in &gables {
            let p = world_points(&s, k);
            let cx = p.iter().map(|q| q.x).sum::<f32>() / p.len() as f32;
            let x0 = -12.0 + 6.0 * ((cx + 12.0) / 6.0).floor();
            assert!(p.iter().all(|q| q.z.abs() <= 5.0 + 1e-4 && q.y >= 6.0 - 1e-4), "{roof}: {p:?}");
            let Primitive::Mesh(m) = s.instances[k].primitive else { unreachable!() };
            let mut area = 0.0;
            for t in &s.meshes[m as usize].triangles {
                let [a, b, c] = t.map(|i| p[i as usize]);
                // Each triangle in a party wall's plane.
                assert!([a, b, c].iter().all(|q| (q.x - a.x).abs() < 1e-4), "{roof}: {a} {b} {c}");
                assert!((a.x - x0).abs() < 1e-4 || (a.x - x0 - 6.0).abs() < 1e-4, "{roof}: {a} {x0}");
                area += (b - a).cross(c - a).length() / 2.0;
            }
            // The gables over the two 10 m walls: the roof rises from the
            // eaves 0.5 m out, so each is 0.5 tan 40° high at the façades
            // and 5.5 tan 40° at the ridge: 10 · 3 tan 40° each.
            assert!((area - 60.0 * 40f32.to_radians().tan()).abs() < 1e-3, "{roof}: {area}");
        }
        // The roof and its gables together close the solid: a prism of
        // 6 m over a triangle 11 m wide per house.
        let vol: f32 = roofs.iter().chain(&gables).map(|&k| world_volume(&s, k)).sum();
        let want = 4.0 * 6.0 * 11.0 * 5.5 * 40f32.to_radians().tan() / 2.0;
        assert!((vol - want).abs() < 1e-2, "{roof}: {vol} {want}");
    }
}

#[test]
fn roof_ridge_overhangs_and_gables() {
    // Without a ridge the 6 × 10 plot's ridge runs along its depth.
    let s = terrace("roof_gable(40);");
    let p = world_points(&s, s.instances.iter().position(|i| matches!(i.primitive, Primitive::Mesh(_))).unwrap());
    let top = p.iter().map(|q| q.y).fold(f32::MIN, f32::max);
    let ridge: Vec<&Vec3> = p.iter().filter(|q| q.y > top - 1e-4).collect();
    assert!(ridge.iter().any(|q| q.z > 4.9) && ridge.iter().any(|q| q.z < -4.9), "{ridge:?}");
    // A shed with its eaves at the back edge rises towards the front.
    let s = scene("A { lot(10, 6); extrude(4); comp(f) { top: roof_shed(45, ridge = back) } }");
    let p = world_points(&s, 0);
    let top = p.iter().map(|q| q.y).fold(f32::MIN, f32::max);
    assert!((top - 10.0).abs() < 1e-4 && p.iter().filter(|q| q.y > top - 1e-4).all(|q| (q.z - 3.0).abs() < 1e-4));
    // A hip roof with one overhang per edge.
    let s = scene("A { lot(10, 6); roof_hip(45, overhang = [1, 0, 0, 0]); }");
    let p = world_points(&s, 0);
    let (zlo, zhi) = p.iter().fold((f32::MAX, f32::MIN), |(a, b), q| (a.min(q.z), b.max(q.z)));
    assert!((zhi - 4.0).abs() < 1e-4 && (zlo + 3.0).abs() < 1e-4, "{zlo} {zhi}");
    // Errors.
    for (src, msg) in [
        ("A { lot(2, 2); roof_gable(30, ridge = 4); }", "from 0 to 3"),
        ("A { lot(2, 2); roof_gable(30, overhang = [1, 2]); }", "2 values, the polygon 4 edges"),
    ] {
        let e = try_scene(src).err().unwrap().to_string();
        assert!(e.contains(msg), "{src}: {e}");
    }
    for (src, msg) in [
        ("A { lot(2, 2); roof_hip(30, ridge = front); }", "takes no argument `ridge`"),
        ("A { lot(2, 2); roof_gable(30, 1, overhang = 2); }", "given twice"),
        ("A { lot(2, 2); roof_gable(30, gables = 1); }", "takes a quoted tag"),
        ("A { lot(2, 2); extrude(width = 2); }", "no named arguments"),
    ] {
        let file = SourceFile::new("t.sg", src);
        let e = match compile(&file, &NoAssets) {
            Ok(_) => panic!("{src} compiled"),
            Err(d) => d.short(),
        };
        assert!(e.contains(msg), "{src}: {e}");
    }
}

#[test]
fn taper_with_a_top_scale_raises_a_frustum() {
    // On the 10 × 6 top face: a frustum 5 high, its top 5 × 3 over the
    // centre; volume h/3 · (A + √(A·a) + a) = 5/3 · (60 + 30 + 15).
    let s = scene("A { lot(10, 6); extrude(4); comp(f) { top: taper(5, 0.5) } }");
    let p = world_points(&s, 0);
    let top: Vec<&Vec3> = p.iter().filter(|q| (q.y - 9.0).abs() < 1e-4).collect();
    assert_eq!(top.len(), 4);
    assert!(top.iter().all(|q| (q.x.abs() - 2.5).abs() < 1e-4 && (q.z.abs() - 1.5).abs() < 1e-4), "{top:?}");
    let vol = world_volume(&s, 0);
    assert!((vol - 175.0).abs() < 1e-3, "{vol}");
    let e = try_scene("A { lot(2, 2); taper(1, 2); }").err().unwrap().to_string();
    assert!(e.contains("from 0 to 1"), "{e}");
}

#[test]
fn a_roofs_faces_are_scopes_for_comp_arms() {
    // A 10 × 6 gable house: the slopes tiled, the gables as wall, the
    // underside left out; each face a polygon in its own plane.
    let s = scene(
        "A { lot(10, 6); extrude(3); comp(f) { top: { roof_gable(45) { top: { tag(\"tiles\"); shape; } \
         | side: { tag(\"gable\"); shape; } | bottom: { } } } } }",
    );
    let tag = |name: &str| s.tags.iter().position(|t| t == name).unwrap() as u32;
    assert!(s.instances.is_empty(), "the roof itself is not drawn: {:?}", s.instances);
    let of = |t: u32| s.polygons.iter().filter(|p| p.tag == t).collect::<Vec<_>>();
    let (tiles, gables) = (of(tag("tiles")), of(tag("gable")));
    assert_eq!((tiles.len(), gables.len(), s.polygons.len()), (2, 2, 4));
    // Slopes 10 long and 3/cos 45° up; gables 6 wide and 3 high.
    for p in &tiles {
        assert!((area(&p.points) - 10.0 * 3.0 * 2f32.sqrt()).abs() < 1e-3, "{:?}", p.points);
        let n = normal(&p.points);
        assert!((n.y - 45f32.to_radians().cos()).abs() < 1e-4, "{n}");
    }
    for p in &gables {
        assert!((area(&p.points) - 9.0).abs() < 1e-3, "{:?}", p.points);
        assert!(normal(&p.points).y.abs() < 1e-4 && p.points.iter().all(|q| q.y >= 3.0 - 1e-4));
    }
}

#[test]
fn gable_faces_end_at_the_walls_corners_under_overhanging_eaves() {
    // Eaves 0.5 out over the street and the back, none at the gable ends:
    // each gable face is the 6 m wall's width; the overhang's ends are
    // `verge` faces of their own.
    let s = scene(
        "A { lot(10, 6); roof_gable(45, 0.5, ridge = front, ends = 0) { side: { tag(\"gable\"); shape; } \
         | verge: { tag(\"verge\"); shape; } } }",
    );
    let tag = |name: &str| s.tags.iter().position(|t| t == name).unwrap() as u32;
    let gables: Vec<_> = s.polygons.iter().filter(|p| p.tag == tag("gable")).collect();
    assert_eq!(gables.len(), 2);
    for p in &gables {
        let (lo, hi) = p.points.iter().fold((f32::MAX, f32::MIN), |(a, b), q| (a.min(q.z), b.max(q.z)));
        assert!((lo + 3.0).abs() < 1e-4 && (hi - 3.0).abs() < 1e-4, "{:?}", p.points);
        // A pentagon: 0.5 tan 45° high at the façades, 3.5 at the ridge.
        assert!((area(&p.points) - (6.0 * 0.5 + 6.0 * 3.0 / 2.0)).abs() < 1e-3, "{} {:?}", area(&p.points), p.points);
    }
    let verges: Vec<_> = s.polygons.iter().filter(|p| p.tag == tag("verge")).collect();
    assert_eq!(verges.len(), 4, "a small triangle at each end of each eave");
    assert!(verges.iter().all(|p| (area(&p.points) - 0.125).abs() < 1e-4));
}

#[test]
fn a_roof_slope_is_selected_by_the_side_it_faces_and_split_like_a_wall() {
    // Dormer windows on the street-side slope only: x along the eaves,
    // y up the slope.
    let s = scene(
        "A { lot(12, 8); roof_gable(40, ridge = front) { front: { split(x) { ~3: { tag(\"tile\"); shape; } \
         | 2: { tag(\"dormer\"); shape; } | ~3: { tag(\"tile\"); shape; } } } | top: { tag(\"tile\"); shape; } } }",
    );
    let tag = |name: &str| s.tags.iter().position(|t| t == name).unwrap() as u32;
    let dormers: Vec<_> = s.polygons.iter().filter(|p| p.tag == tag("dormer")).collect();
    assert_eq!(dormers.len(), 1);
    let xs = dormers[0].points.iter().map(|q| q.x);
    let (lo, hi) = xs.fold((f32::MAX, f32::MIN), |(a, b), x| (a.min(x), b.max(x)));
    assert!((lo + 1.0).abs() < 1e-4 && (hi - 1.0).abs() < 1e-4, "2 m along the eaves, centred: {lo} {hi}");
    for p in &dormers {
        // On the slope facing the street (+z in the world, the lot's front).
        let n = normal(&p.points);
        assert!(n.z > 0.5 && n.y > 0.5, "{n}");
    }
    let back: Vec<_> = s.polygons.iter().filter(|p| normal(&p.points).z < -0.5).collect();
    assert_eq!(back.len(), 1, "the back slope is one tiled face");
}

#[test]
fn a_taper_has_faces_too() {
    let s = scene("A { lot(4, 4); taper(3, 0.5) { top: { tag(\"t\"); shape; } | bottom: { tag(\"b\"); shape; } } }");
    // A frustum: four sides and the top look up, the base down.
    assert_eq!(s.polygons.len(), 6);
    let up = s.polygons.iter().filter(|p| normal(&p.points).y > 0.0).count();
    assert_eq!(up, 5);
}

#[test]
fn index_selectors_take_pieces_by_their_place_in_the_list() {
    // A box's faces: walls in the footprint's order (front first), then
    // top and bottom. `0` takes the front wall, `4` the top, `all` the rest.
    let s = scene(
        "A { lot(4, 2); extrude(3); comp(f) { 0: { tag(\"a\"); shape; } | 4: { tag(\"t\"); shape; } \
         | all: { tag(\"b\"); shape; } } }",
    );
    let tag = |name: &str| s.tags.iter().position(|t| t == name).unwrap() as u32;
    let by = |t: u32| s.polygons.iter().filter(|p| p.tag == t).collect::<Vec<_>>();
    let (a, t, b) = (by(tag("a")), by(tag("t")), by(tag("b")));
    assert_eq!((a.len(), t.len(), b.len()), (1, 1, 4), "{:?}", s.polygons.len());
    assert!(normal(&a[0].points).z > 0.99, "the front wall faces the street (+z)");
    assert!(normal(&t[0].points).y > 0.99);
    // Several indices in one arm, on a polygon's edges.
    let e = scene("A { lot(4, 2); comp(e) { 1, 3: { tag(\"s\"); box; } } }");
    assert_eq!(e.instances.len(), 2);
    // Out of range or not whole: an error at the selector.
    for src in ["A { lot(4, 2); comp(e) { 64: box } }", "A { lot(4, 2); comp(e) { 1.5: box } }"] {
        let file = SourceFile::new("t.sg", src);
        let Err(e) = compile(&file, &NoAssets) else { panic!("{src}: no error") };
        let e = e.short();
        assert!(e.contains("index selector is a whole number from 0 to 63"), "{e}");
    }
}

#[test]
fn a_footprint_turns_so_that_its_street_edge_is_its_front() {
    // A 10 × 6 lot turned 30°, its short edge 1 facing the street: that
    // edge, and only it, is `front`, and `lot.street` reads the distance.
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let corners: Vec<[f64; 2]> = [[0.0, 0.0], [10.0, 0.0], [10.0, 6.0], [0.0, 6.0]]
        .iter()
        .map(|&[x, z]| [x * c - z * s, x * s + z * c])
        .collect();
    let g = grammar("A { comp(e) { front: { tag(\"f\"); size(sx, 0.1, lot.street); box; } } }");
    let props = LotProps { street_edge: 1.0, street: 4.0, ..LotProps::default() };
    for (edge, want) in [(1usize, 6.0f32), (0, 10.0), (3, 6.0)] {
        let g = g.on_footprint_with(&corners, LotProps { street_edge: edge as f64, ..props }).unwrap();
        let limits = g.limits();
        let sample = g.sample(&mut Rng::from_seed(1), &limits).unwrap();
        let mut scene = Scene::new();
        g.express(&sample.genome, &limits, &mut scene).unwrap();
        assert_eq!(scene.instances.len(), 1, "edge {edge}: one front edge");
        let t = scene.instances[0].transform;
        let mid = {
            let (a, b) = (corners[edge], corners[(edge + 1) % 4]);
            Vec3::new(((a[0] + b[0]) / 2.0) as f32, 0.0, ((a[1] + b[1]) / 2.0) as f32)
        };
        assert!((t.translation.x - mid.x).abs() < 1e-4 && (t.translation.z - mid.z).abs() < 1e-4, "edge {edge}: {t:?}");
        // The box: as long as the edge, `lot.street` (4) deep.
        assert!((t.matrix3.x_axis.length() - want).abs() < 1e-4, "edge {edge}: {t:?}");
        assert!((t.matrix3.z_axis.length() - 4.0).abs() < 1e-4, "edge {edge}: {t:?}");
    }
}

#[test]
fn lot_street_values_are_minus_one_off_a_street() {
    // Run on no footprint (or one with no street near), both read −1.
    let s = scene("A { size(lot.street + 2, lot.street_edge + 3, 1); box; }");
    let t = s.instances[0].transform;
    assert!((t.matrix3.x_axis.length() - 1.0).abs() < 1e-6 && (t.matrix3.y_axis.length() - 2.0).abs() < 1e-6);
}

#[test]
fn setbacks_on_concave_lots_partition_them_and_keep_to_their_edges() {
    // An L (area 8.5) and a U (area 20): strips and remainder tile the lot,
    // and a strip never takes in an arm beyond its edge's reach.
    for (lot, total) in [
        ("lot(0, 0, 4, 0, 4, 1.5, 1, 1.5, 1, 4, 0, 4)", 8.5f32),
        ("lot(0, 0, 6, 0, 6, 4, 4, 4, 4, 2, 2, 2, 2, 4, 0, 4)", 20.0),
    ] {
        for arms in ["front", "all", "back, left"] {
            let src = format!(
                "A {{ {lot}; setback(0.5) {{ {arms}: {{ tag(\"s\"); shape; }} | remainder: {{ tag(\"r\"); shape; }} }} }}"
            );
            let (s, r) = (tagged_areas(&src, "s"), tagged_areas(&src, "r"));
            assert!((sum(&s) + sum(&r) - total).abs() < 1e-3, "{lot} {arms}: {s:?} + {r:?}");
            // Every strip is a band at most 0.5 deep: its area at most its
            // outline's half-perimeter × 0.5 (a far arm would break this).
            let scene = scene(&src);
            let tag = scene.tags.iter().position(|t| t == "s").unwrap() as u32;
            for p in scene.polygons.iter().filter(|p| p.tag == tag) {
                let perim: f32 =
                    (0..p.points.len()).map(|i| (p.points[(i + 1) % p.points.len()] - p.points[i]).length()).sum();
                assert!(area(&p.points) <= 0.5 * perim / 2.0 + 1e-4, "{lot} {arms}: {:?}", p.points);
            }
        }
    }
}

#[test]
fn a_border_grown_past_a_narrow_notch_closes_it() {
    // A 5 × 4 lot with a notch 1 wide and 3 deep (area 17): grown by 1,
    // mitred corners would cross in the notch; the outside wavefront
    // closes it instead. The border fills the notch (3) and the 1 m band
    // around the 5 × 4 box with its corners mitred (2·(5 + 4) + 4 = 22):
    // 25 in all, each edge's piece its own class.
    let src = "A { lot(0, 0, 5, 0, 5, 4, 3, 4, 3, 1, 2, 1, 2, 4, 0, 4); \
               offset(1) { inside: { tag(\"i\"); shape; } | border: { tag(\"b\"); shape; } } }";
    let (inside, border) = (tagged_areas(src, "i"), tagged_areas(src, "b"));
    assert!((sum(&inside) - 17.0).abs() < 1e-3, "{inside:?}");
    assert!((sum(&border) - 25.0).abs() < 1e-2, "{border:?}");
    assert!(border.len() >= 4, "{border:?}");
}
