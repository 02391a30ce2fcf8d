use super::*;
use genform_core::scene::{Instance, Mesh, Polygon, Primitive};
use glam::{Affine3A, Mat3, Vec3};
use proptest::prelude::*;
use std::sync::Arc;

/// Eye at (0, 0, −10) looking along +z with fov 90°: on a 64×48 image a
/// point (x, y, z) lands at pixel (32 + 24·x/(z+10), 24 − 24·y/(z+10)).
fn head_on() -> Camera {
    Camera { fov_deg: 90.0, phi: -std::f32::consts::FRAC_PI_2, theta: 0.0, radius: 10.0, look_at: Vec3::ZERO }
}

fn flat_target(w: u32, h: u32, f: impl Fn(u32, u32) -> f32) -> ImageTarget {
    let weights: Vec<f32> = (0..h).flat_map(|y| (0..w).map(move |x| (x, y))).map(|(x, y)| f(x, y)).collect();
    ImageTarget::from_weights(w, h, &weights).unwrap()
}

fn instance(primitive: Primitive, transform: Affine3A) -> Instance {
    Instance { transform, primitive, tag: 0 }
}

fn scene_of(instances: Vec<Instance>) -> Scene {
    Scene { instances, ..Scene::default() }
}

/// Fast and oracle coverage must be identical; on failure, say where.
fn check_against_oracle(scorer: &ImageScorer, scene: &Scene) {
    let mut scratch = scorer.scratch();
    let fast = scorer.coverage(scene, &mut scratch);
    let slow = oracle::coverage(scorer, scene);
    let diff = fast.differences(&slow);
    assert!(
        diff.is_empty(),
        "{} pixels differ, first {:?}; fast {fast:?}, oracle {slow:?}",
        diff.len(),
        &diff[..diff.len().min(8)]
    );
    // The counts path (which drains the mask) agrees too, twice in a row.
    let expect = oracle::counts(scorer, scene);
    for _ in 0..2 {
        let c = scorer.counts(scene, &mut scratch);
        assert!((c.good - expect.good).abs() < 1e-6 && (c.bad - expect.bad).abs() < 1e-6, "{c:?} vs {expect:?}");
        assert_eq!(c.target, expect.target);
    }
    assert!(scratch.mask.is_clear());
}

#[test]
fn head_on_box_covers_a_known_rectangle() {
    // Box x ∈ [−1, 2], y ∈ [−0.5, 1], z ∈ [2, 3]: its front face, at depth
    // 12, spans pixels x ∈ [30, 36), y ∈ [22, 25); the back face lies inside.
    let t = Affine3A::from_scale_rotation_translation(
        Vec3::new(3.0, 1.5, 1.0),
        glam::Quat::IDENTITY,
        Vec3::new(0.5, 0.25, 2.5),
    );
    let scene = scene_of(vec![instance(Primitive::Box, t)]);
    // Target: the left half of the image.
    let target = flat_target(64, 48, |x, _| if x < 33 { 1.0 } else { -1.0 });
    let scorer = ImageScorer::new(head_on(), 64, 48, target).unwrap();
    let cov = scorer.coverage(&scene, &mut scorer.scratch());
    for y in 0..48 {
        for x in 0..64 {
            assert_eq!(cov.get(x, y), (30..36).contains(&x) && (22..25).contains(&y), "pixel ({x}, {y})");
        }
    }
    let c = scorer.counts(&scene, &mut scorer.scratch());
    assert_eq!((c.good, c.bad, c.target, c.overlap, c.outside), (9.0, 9.0, 33.0 * 48.0, 0.0, 0.0));
    check_against_oracle(&scorer, &scene);
}

#[test]
fn tree_sketch_trunk_lands_on_the_sketched_trunk() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/scenes/targets/tree_target_sketch1.png");
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("reading {path}: {e}"));
    let target = ImageTarget::from_png(&bytes, PngMode::Dark).unwrap();
    assert_eq!((target.width(), target.height()), (800, 600));
    #[allow(clippy::approx_constant)] // the reference's φ, not quite −π/2
    let camera =
        Camera { fov_deg: 60.0, phi: -1.5708, theta: 0.0, radius: 9.4716, look_at: Vec3::new(-0.680994, 3.2558, 0.0) };
    let scorer = ImageScorer::new(camera, 800, 600, target).unwrap();
    // The v2 trunk: the reference frustum (top radius 0.29 of 0.5) scaled
    // (0.8, 1.8, 0.8), standing on y ∈ [−0.8, 1].
    let trunk = |x: f32| {
        let t = Affine3A::from_translation(Vec3::new(x, 0.1, 0.0)) * Affine3A::from_scale(Vec3::new(0.8, 1.8, 0.8));
        scene_of(vec![instance(Primitive::Frustum { top: 0.58 }, t)])
    };
    let mut scratch = scorer.scratch();
    let c = scorer.counts(&trunk(0.0), &mut scratch);
    let precision = c.good / (c.good + c.bad);
    assert!(c.good > 2500.0 && precision > 0.9, "{c:?}");
    // Bottom center of the picture.
    let cov = scorer.coverage(&trunk(0.0), &mut scratch);
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    for y in 0..600 {
        for x in 0..800 {
            if cov.get(x, y) {
                xs.push(x);
                ys.push(y);
            }
        }
    }
    let mid = (xs.iter().min().unwrap() + xs.iter().max().unwrap()) / 2;
    assert!((425..445).contains(&mid), "trunk center column {mid}");
    assert!(*ys.iter().max().unwrap() > 500 && *ys.iter().min().unwrap() > 400, "rows {:?}", (ys[0], ys.last()));
    // A camera frame mirrored left-right would put the origin where x =
    // −1.36 lands in this one: off the trunk.
    let c = scorer.counts(&trunk(-1.36), &mut scratch);
    assert!(c.good / (c.good + c.bad) < 0.3, "{c:?}");
}

#[test]
fn near_plane_crossing_and_behind_the_camera() {
    let scorer = ImageScorer::new(head_on(), 64, 48, flat_target(64, 48, |_, _| 1.0)).unwrap();
    // A long box through the eye (z from −12 to 8): clipped at the near
    // plane; its visible part covers the middle of the image.
    let through = Affine3A::from_scale_rotation_translation(
        Vec3::new(1.0, 1.0, 20.0),
        glam::Quat::IDENTITY,
        Vec3::new(0.0, 0.0, -2.0),
    );
    let scene = scene_of(vec![instance(Primitive::Box, through)]);
    let cov = scorer.coverage(&scene, &mut scorer.scratch());
    assert!(cov.get(32, 24) && cov.count() > 100, "{cov:?}");
    check_against_oracle(&scorer, &scene);
    // Entirely behind the eye: nothing.
    let behind = Affine3A::from_translation(Vec3::new(0.0, 0.0, -15.0));
    let scene = scene_of(vec![instance(Primitive::Sphere, behind)]);
    assert_eq!(scorer.coverage(&scene, &mut scorer.scratch()).count(), 0);
    // Beyond zfar (100): nothing, unless the range is widened.
    let far = scene_of(vec![instance(
        Primitive::Box,
        Affine3A::from_scale(Vec3::splat(30.0)) * Affine3A::from_translation(Vec3::Z * 5.0),
    )]);
    assert_eq!(scorer.coverage(&far, &mut scorer.scratch()).count(), 0);
    let wide = scorer.clone().with_depth_range(0.1, 300.0).unwrap();
    assert!(wide.coverage(&far, &mut wide.scratch()).count() > 0);
}

#[test]
fn odd_transforms_cover_nothing_or_stay_exact() {
    let scorer = ImageScorer::new(head_on(), 64, 48, flat_target(64, 48, |x, _| x as f32 - 20.0)).unwrap();
    let nan = Affine3A::from_translation(Vec3::new(f32::NAN, 0.0, 0.0));
    let inf = Affine3A::from_scale(Vec3::new(f32::INFINITY, 1.0, 1.0));
    let flat = Affine3A::from_scale(Vec3::new(2.0, 0.0, 1.0));
    let point = Affine3A::from_scale(Vec3::ZERO);
    let huge = Affine3A::from_scale(Vec3::splat(1e30));
    let mirrored = Affine3A::from_mat3(Mat3::from_cols(Vec3::new(-1.0, 0.3, 0.0), Vec3::Y, Vec3::new(0.2, 0.0, -2.0)));
    let broken = Arc::new(Mesh {
        name: "broken".into(),
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(f32::NAN, 0.0, 0.0), Vec3::Y],
        triangles: vec![[0, 1, 3], [0, 1, 2], [0, 7, 1]],
    });
    let mut scene = scene_of(vec![
        instance(Primitive::Box, nan),
        instance(Primitive::Sphere, inf),
        instance(Primitive::Box, flat),
        instance(Primitive::Frustum { top: 0.5 }, point),
        instance(Primitive::TaperedBox { top: f32::NAN }, huge),
        instance(Primitive::TaperedBox { top: 0.0 }, mirrored),
        instance(Primitive::Mesh(0), Affine3A::IDENTITY),
        instance(Primitive::Mesh(5), Affine3A::IDENTITY),
    ]);
    scene.meshes.push(broken);
    scene.polygons.push(Polygon {
        points: vec![Vec3::new(-3.0, -3.0, 1.0), Vec3::new(-2.0, -3.0, 1.0), Vec3::new(-2.5, -2.0, 1.0)],
        tag: 0,
    });
    let c = scorer.counts(&scene, &mut scorer.scratch());
    assert!(c.good.is_finite() && c.bad.is_finite() && c.good > 0.0, "{c:?}");
    check_against_oracle(&scorer, &scene);
}

#[test]
fn sizes_must_match_and_scratches_adapt() {
    let err = ImageScorer::new(head_on(), 64, 48, flat_target(32, 24, |_, _| 1.0)).unwrap_err();
    assert_eq!(err.to_string(), "the target image is 32×24 but the scorer renders 64×48");
    assert!(matches!(
        ImageScorer::new(head_on(), 0, 48, flat_target(1, 1, |_, _| 1.0)),
        Err(ImageError::BadSize { .. })
    ));
    let bad_fov = Camera { fov_deg: 180.0, ..head_on() };
    assert!(matches!(
        ImageScorer::new(bad_fov, 64, 48, flat_target(64, 48, |_, _| 1.0)),
        Err(ImageError::BadCamera(_))
    ));
    let nan_cam = Camera { radius: f32::NAN, ..head_on() };
    assert!(matches!(
        ImageScorer::new(nan_cam, 64, 48, flat_target(64, 48, |_, _| 1.0)),
        Err(ImageError::BadCamera(_))
    ));
    let s = ImageScorer::new(head_on(), 64, 48, flat_target(64, 48, |_, _| 1.0)).unwrap();
    assert!(s.clone().with_depth_range(1.0, 0.5).is_err());
    // A scratch of another scorer is refitted, not misused.
    let small = ImageScorer::new(head_on(), 16, 12, flat_target(16, 12, |_, _| 1.0)).unwrap();
    let scene = scene_of(vec![instance(Primitive::Sphere, Affine3A::from_scale(Vec3::splat(4.0)))]);
    let mut scratch = small.scratch();
    assert_eq!(s.counts(&scene, &mut scratch), s.counts(&scene, &mut s.scratch()));
}

#[test]
fn pfm_weights_and_preview() {
    // 4×2 weights, file rows bottom-up: bottom row [−1, −1, −1, −1], top
    // row [2, 0, 0, 0.5].
    let mut bytes = b"Pf\n4 2\n-1.0\n".to_vec();
    for v in [-1.0f32, -1.0, -1.0, -1.0, 2.0, 0.0, 0.0, 0.5] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    let target = ImageTarget::from_pfm(&bytes).unwrap();
    assert_eq!((target.weight(0, 0), target.weight(3, 0), target.weight(0, 1)), (2.0, 0.5, -1.0));
    assert_eq!(target.total_positive(), 2.5);
    // A camera that sees a huge box everywhere: everything is covered.
    let scorer = ImageScorer::new(head_on(), 4, 2, target).unwrap();
    let scene = scene_of(vec![instance(Primitive::Box, Affine3A::from_scale(Vec3::new(100.0, 100.0, 1.0)))]);
    let c = scorer.counts(&scene, &mut scorer.scratch());
    assert_eq!((c.good, c.bad, c.target), (2.5, 4.0, 2.5));
    let (rgba, w, h) = scorer.silhouette(&scene);
    assert_eq!((w, h, rgba.len()), (4, 2, 32));
    assert_eq!(&rgba[..4], &[0, 150, 60, 255], "covered target is green");
    assert_eq!(&rgba[4..8], &[90, 90, 90, 255], "covered don't-care is grey");
    assert_eq!(&rgba[16..20], &[215, 40, 40, 255], "covered avoid is red");
    let (rgba, _, _) = scorer.silhouette(&Scene::new());
    assert_eq!(&rgba[..4], &[190, 190, 190, 255]);
}

/// A random affine map: entries in ±1.5 (reflections and shears included),
/// sometimes with a flattened axis, placed around the camera's target (some
/// through the near plane or behind the eye).
fn transform() -> impl Strategy<Value = Affine3A> {
    (prop::array::uniform9(-1.5f32..1.5), prop::array::uniform3(-6.0f32..6.0), 0..6u8).prop_map(|(m, t, flat)| {
        let mut m = Mat3::from_cols_array(&m);
        if flat < 3 {
            *m.col_mut(flat as usize) = Vec3::ZERO;
        }
        Affine3A::from_mat3_translation(m, Vec3::new(t[0], t[1], t[2] * 2.0))
    })
}

fn primitive() -> impl Strategy<Value = Primitive> {
    prop_oneof![
        Just(Primitive::Box),
        Just(Primitive::Sphere),
        (0.0f32..1.5).prop_map(|top| Primitive::Frustum { top }),
        (0.0f32..1.5).prop_map(|top| Primitive::TaperedBox { top }),
        Just(Primitive::Mesh(0)),
    ]
}

fn camera() -> impl Strategy<Value = Camera> {
    (-3.2f32..3.2, -1.7f32..1.7, 4.0f32..12.0, 30.0f32..90.0).prop_map(|(phi, theta, radius, fov_deg)| Camera {
        fov_deg,
        phi,
        theta,
        radius,
        look_at: Vec3::new(0.2, -0.1, 0.3),
    })
}

/// An open mesh (a fan of skewed triangles) for `Primitive::Mesh(0)`.
fn asset() -> Arc<Mesh> {
    Arc::new(Mesh {
        name: "fan".into(),
        positions: vec![Vec3::ZERO, Vec3::new(1.0, 0.2, 0.0), Vec3::new(0.3, 1.0, 0.5), Vec3::new(-0.8, 0.4, -0.3)],
        triangles: vec![[0, 1, 2], [0, 2, 3], [1, 3, 2]],
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn fast_path_equals_the_oracle(
        cam in camera(),
        parts in prop::collection::vec((primitive(), transform()), 1..12),
    ) {
        let target = flat_target(64, 48, |x, y| if (x / 8 + y / 8) % 2 == 0 { 1.0 } else { -1.0 });
        let scorer = ImageScorer::new(cam, 64, 48, target).unwrap();
        let mut scene = scene_of(parts.into_iter().map(|(p, t)| instance(p, t)).collect());
        scene.meshes.push(asset());
        check_against_oracle(&scorer, &scene);
    }
}

/// Closed assets: the tree grammars' trunk and leaf, the reference cube
/// and the tessellated built-in primitives (as meshes).
fn closed_assets() -> Vec<Arc<Mesh>> {
    let obj = |name, text| Arc::new(Mesh::from_obj(name, text).unwrap());
    let tess = genform_core::scene::Tessellation { radial: 9, rings: 6 };
    let unit = |p| Arc::new(genform_core::scene::unit_mesh(p, tess));
    vec![
        obj("trunk", include_str!("../../tests/data/trunk.obj")),
        obj("leaf", include_str!("../../tests/data/leaf_low_poly.obj")),
        obj("cube", include_str!("../../tests/data/cube.obj")),
        unit(Primitive::Sphere),
        unit(Primitive::Frustum { top: 0.3 }),
    ]
}

#[test]
fn closed_surfaces_are_recognised() {
    assert!(closed_assets().iter().all(|m| edge_table::is_closed(m)));
    assert!(!edge_table::is_closed(&asset()));
    // One triangle turned over, or one missing, opens the cube.
    let mut cube = (*closed_assets()[2]).clone();
    cube.triangles[3].swap(0, 1);
    assert!(!edge_table::is_closed(&cube));
    cube.triangles.remove(3);
    assert!(!edge_table::is_closed(&cube));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Closed mesh assets fill only their positively wound triangles when
    /// nothing is clipped; coverage stays the oracle's (all triangles).
    #[test]
    fn closed_meshes_equal_the_oracle(
        cam in camera(),
        parts in prop::collection::vec((0usize..5, transform(), 0.2f32..1.0), 1..8),
    ) {
        let target = flat_target(64, 48, |x, y| if (x / 8 + y / 8) % 2 == 0 { 1.0 } else { -1.0 });
        let scorer = ImageScorer::new(cam, 64, 48, target).unwrap();
        let assets = closed_assets();
        // Smaller shapes, so that most need no clipping.
        let instances = parts
            .into_iter()
            .map(|(m, t, s)| instance(Primitive::Mesh(m as u32), Affine3A::from_scale(Vec3::splat(s)) * t))
            .collect();
        let mut scene = scene_of(instances);
        scene.meshes = assets;
        check_against_oracle(&scorer, &scene);
    }
}

/// Tree-like placements on the tree_sketch camera and image size: many
/// large leaves and trunks, all on screen (the culled path).
#[test]
fn tree_assets_match_the_oracle_at_full_size() {
    let cam = Camera {
        fov_deg: 60.0,
        phi: -std::f32::consts::FRAC_PI_2,
        theta: 0.0,
        radius: 9.4716,
        look_at: Vec3::new(-0.68, 3.26, 0.0),
    };
    let target = flat_target(200, 150, |x, _| if x % 3 == 0 { 1.0 } else { -1.0 });
    let scorer = ImageScorer::new(cam, 200, 150, target).unwrap();
    let mut rng = genform_core::Rng::stream(3, &[]);
    let mut instances = Vec::new();
    for n in 0..40 {
        let mut u = || rng.next_f64() as f32;
        let size = Vec3::new(0.2 + u(), 0.3 + 1.5 * u(), 0.2 + u());
        let r = glam::Quat::from_rotation_y(7.0 * u()) * glam::Quat::from_rotation_z(1.5 * u());
        let at = Vec3::new(4.0 * u() - 2.7, 6.0 * u() + 0.3, 2.0 * u() - 1.0);
        instances.push(instance(Primitive::Mesh(n % 2), Affine3A::from_scale_rotation_translation(size, r, at)));
    }
    let mut scene = scene_of(instances);
    scene.meshes = closed_assets();
    let mut scratch = scorer.scratch();
    assert!(scorer.coverage(&scene, &mut scratch).count() > 2000);
    check_against_oracle(&scorer, &scene);
}

/// Trees on the tree_sketch camera (`seed` places them; `stretch` scales
/// the trunk asset's own vertices: same mesh id, other content).
fn sketch_forest(seed: u64, stretch: f32) -> Scene {
    let mut rng = genform_core::Rng::stream(seed, &[]);
    let mut instances = Vec::new();
    for n in 0..30 {
        let mut u = || rng.next_f64() as f32;
        let size = Vec3::new(0.2 + u(), 0.3 + 1.5 * u(), 0.2 + u());
        let r = glam::Quat::from_rotation_y(7.0 * u()) * glam::Quat::from_rotation_z(1.5 * u());
        let at = Vec3::new(4.0 * u() - 2.7, 6.0 * u() + 0.3, 2.0 * u() - 1.0);
        let primitive = if n == 7 { Primitive::Box } else { Primitive::Mesh(n as u32 % 2) };
        instances.push(instance(primitive, Affine3A::from_scale_rotation_translation(size, r, at)));
    }
    let mut scene = scene_of(instances);
    scene.meshes = closed_assets();
    let mut trunk = (*scene.meshes[0]).clone();
    trunk.positions.iter_mut().for_each(|p| p.y *= stretch);
    scene.meshes[0] = Arc::new(trunk);
    scene
}

fn sketch_scorer(look_x: f32) -> ImageScorer {
    let cam = Camera {
        fov_deg: 60.0,
        phi: -std::f32::consts::FRAC_PI_2,
        theta: 0.0,
        radius: 9.4716,
        look_at: Vec3::new(look_x, 3.26, 0.0),
    };
    let target = flat_target(200, 150, |x, _| if x % 3 == 0 { 1.0 } else { -1.0 });
    ImageScorer::new(cam, 200, 150, target).unwrap()
}

/// Scenes that share mesh instances, and one whose trunk asset has other
/// vertices under the same id, go through one cached scratch in turn: the
/// coverage and counts equal a cacheless scratch's, instances were
/// replayed, and a scratch moved to another camera of the same image size
/// forgets the first camera's spans.
#[test]
fn replayed_instances_cover_like_rasterized_ones() {
    let scorer = sketch_scorer(-0.68);
    let a = sketch_forest(1, 1.0);
    let mut b = sketch_forest(2, 1.0);
    b.instances.truncate(15);
    b.instances.extend(a.instances[..15].iter().rev().cloned());
    let stretched = sketch_forest(1, 1.4);
    let mut cached = scorer.scratch();
    for (n, scene) in [&a, &b, &a, &stretched, &a, &b, &stretched, &a].into_iter().enumerate() {
        let mut fresh = ImageScratch::new(200, 150, scorer.tessellation());
        let want = scorer.coverage(scene, &mut fresh);
        assert_eq!(scorer.coverage(scene, &mut cached).differences(&want), Vec::new(), "scene {n}");
        assert_eq!(scorer.counts(scene, &mut cached), scorer.counts(scene, &mut fresh), "scene {n}");
    }
    assert!(cached.cache_hits() >= 40, "{} instances replayed", cached.cache_hits());
    let other = sketch_scorer(0.4);
    let mut fresh = ImageScratch::new(200, 150, other.tessellation());
    assert_eq!(other.counts(&a, &mut cached), other.counts(&a, &mut fresh));
    let hits = cached.cache_hits();
    other.counts(&a, &mut cached);
    assert_eq!(cached.cache_hits(), hits, "the other camera's spans are recorded anew first");
}
