//! The growth environment: the charge law and gravity, boundary slide /
//! stop / soft behaviour on every shape, settling, and preview guides.

use genform_core::scene::{Primitive, Tessellation, unit_mesh};
use genform_core::{GuideKind, Mesh, Scene};
use genform_hemls::env::skin;
use genform_hemls::{Axis, Behaviour, Boundary, Charge, Environment, Gravity, Keep, Shape};
use glam::{DVec3, Vec3};
use proptest::prelude::*;

fn env_with(b: Boundary) -> Environment {
    Environment::new().with_boundary(b)
}

/// The closed, outward-wound cube mesh `[-h, h]³` around `center`.
fn cube_mesh(center: Vec3, h: f32) -> Mesh {
    let mut m = unit_mesh(Primitive::Box, Tessellation::default());
    for p in &mut m.positions {
        *p = *p * (2.0 * h) + center;
    }
    m
}

fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).length() <= tol
}

#[test]
fn attractor_law_matches_genr8_numbers() {
    let p = DVec3::new(1.0, -1.0, 0.5);
    let q = p + DVec3::new(0.0, 0.0, 2.0);
    let a = Environment::new().with_charge(Charge::attractor(q));
    assert!(close(a.displacement(p), DVec3::new(0.0, 0.0, 0.25), 1e-15), "{}", a.displacement(p));
    let r = Environment::new().with_charge(Charge::repeller(q));
    assert!(close(r.displacement(p), DVec3::new(0.0, 0.0, -0.25), 1e-15), "{}", r.displacement(p));
    // Explicit c and e: 3 / 2³.
    let c = Environment::new().with_charge(Charge::attractor(q).with_strength(3.0).with_exponent(3.0));
    assert!(close(c.displacement(p), DVec3::new(0.0, 0.0, 0.375), 1e-15));
}

#[test]
fn gravity_moves_every_point_by_the_same_amount() {
    let env = Environment::new().with_gravity(Gravity::new(Axis::Z, -0.1));
    for p in [DVec3::ZERO, DVec3::new(5.0, -3.0, 100.0), DVec3::splat(-1e6)] {
        assert_eq!(env.displacement(p), DVec3::new(0.0, 0.0, -0.1));
    }
    let up_x = Environment::new().with_gravity(Gravity::new(Axis::X, 0.5));
    assert_eq!(up_x.displacement(DVec3::ONE), DVec3::new(0.5, 0.0, 0.0));
}

#[test]
fn displacement_sums_all_charges_and_gravity() {
    let env = Environment::new()
        .with_charge(Charge::attractor(DVec3::new(2.0, 0.0, 0.0)))
        .with_charge(Charge::repeller(DVec3::new(0.0, -2.0, 0.0)))
        .with_gravity(Gravity::new(Axis::Z, -0.1));
    assert!(close(env.displacement(DVec3::ZERO), DVec3::new(0.25, 0.25, -0.1), 1e-15));
}

#[test]
fn a_charge_on_the_vertex_gives_a_finite_bounded_move() {
    let q = DVec3::new(0.3, 0.4, 0.5);
    let env = Environment::new().with_charge(Charge::repeller(q)).with_charge(Charge::attractor(q));
    assert_eq!(env.displacement(q), DVec3::ZERO);
    let bound = 1.0 / env.min_distance.powi(2);
    for off in [1e-300, 1e-12, 1e-6, 1e-3] {
        let p = q + DVec3::new(off, 0.0, 0.0);
        let r = Environment::new().with_charge(Charge::repeller(q)).displacement(p);
        assert!(r.is_finite() && r.length() <= bound * (1.0 + 1e-12), "{off}: {r}");
        // An attractor never pulls past its own position.
        let a = Environment::new().with_charge(Charge::attractor(q)).displacement(p);
        assert!(a.is_finite() && (p + a - q).x >= 0.0, "{off}: {a}");
    }
}

#[test]
fn the_empty_environment_changes_nothing() {
    let env = Environment::new();
    assert!(env.is_empty());
    let (a, b) = (DVec3::new(1.0, 2.0, 3.0), DVec3::new(-4.0, 5.0, 0.5));
    assert_eq!(env.displacement(a), DVec3::ZERO);
    assert_eq!(env.constrain(a, b), b);
    assert_eq!(env.settle(a), a);
    assert!(!env.is_outside_soft(a));
    assert!(!env_with(Boundary::sphere(DVec3::ZERO, 1.0).with_behaviour(Behaviour::Soft)).is_empty());
}

#[test]
fn sphere_slide_goes_round_and_stop_stays_at_the_hit() {
    let sphere = Boundary::sphere(DVec3::ZERO, 1.0);
    // Straight down onto the top: slide has no tangential part left.
    let (from, to) = (DVec3::new(0.0, 0.0, 3.0), DVec3::new(0.0, 0.0, -3.0));
    for behaviour in [Behaviour::Slide, Behaviour::Stop] {
        let end = env_with(sphere.clone().with_behaviour(behaviour)).constrain(from, to);
        assert!(close(end, DVec3::new(0.0, 0.0, 1.0), 1e-5), "{behaviour:?}: {end}");
        assert!(end.length() > 1.0, "{behaviour:?}: {end}");
    }
    // A slanted move: stop keeps the hit, slide keeps the sideways part.
    let (from, to) = (DVec3::new(0.0, 0.0, 2.0), DVec3::new(1.0, 0.0, 0.0));
    let stop = env_with(sphere.clone().with_behaviour(Behaviour::Stop)).constrain(from, to);
    let slide = env_with(sphere.clone()).constrain(from, to);
    assert!((stop.length() - 1.0).abs() < 1e-5 && stop.length() > 1.0, "{stop}");
    assert!(slide.length() > 1.0 && slide.x > stop.x + 0.1, "slide {slide} stop {stop}");
    // The slide ends on the tangent plane at the hit point.
    let n = stop.normalize();
    assert!(((slide - stop).dot(n)).abs() < 1e-5, "{slide} {stop}");
}

#[test]
fn sphere_enclosure_keeps_points_in() {
    let env = env_with(Boundary::sphere(DVec3::ZERO, 2.0).with_keep(Keep::Inside));
    let end = env.constrain(DVec3::ZERO, DVec3::new(5.0, 0.0, 0.0));
    assert!(end.length() < 2.0 && end.length() > 2.0 - 1e-4, "{end}");
    // A move from outside that passes through is stopped where it would leave.
    let end = env.constrain(DVec3::new(-5.0, 0.0, 0.0), DVec3::new(5.0, 0.0, 0.0));
    assert!(end.length() < 2.0 && end.x > 1.9, "{end}");
    // Outside moving further out: no crossing, nothing changes.
    let far = DVec3::new(6.0, 1.0, 0.0);
    assert_eq!(env.constrain(DVec3::new(5.0, 0.0, 0.0), far), far);
}

proptest! {
    /// Whatever the move, a slide or stop off a sphere obstacle never ends
    /// inside it, and a move that stays clear is not changed.
    #[test]
    fn sphere_obstacle_never_ends_inside(
        dir in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0),
        dist in 1.0001f64..4.0,
        to in (-4.0f64..4.0, -4.0f64..4.0, -4.0f64..4.0),
        r in 0.1f64..3.0,
        stop in any::<bool>(),
    ) {
        let c = DVec3::new(0.5, -0.25, 1.0);
        let dir = DVec3::new(dir.0, dir.1, dir.2).try_normalize().unwrap_or(DVec3::X);
        let from = c + dir * r * dist;
        let to = c + DVec3::new(to.0, to.1, to.2) * r;
        let behaviour = if stop { Behaviour::Stop } else { Behaviour::Slide };
        let env = env_with(Boundary::sphere(c, r).with_behaviour(behaviour));
        let end = env.constrain(from, to);
        prop_assert!(end.is_finite());
        prop_assert!((end - c).length() >= r, "ended inside: {} from {} to {}", end, from, to);
        prop_assert!((end - from).length() <= (to - from).length() + 1e-9);
        // A segment that never comes near the sphere is untouched.
        let seg = to - from;
        let t = ((c - from).dot(seg) / seg.length_squared()).clamp(0.0, 1.0);
        if (from + seg * t - c).length() > r * 1.001 {
            prop_assert_eq!(end, to);
        }
    }

    /// Slides inside a sphere enclosure never end outside it.
    #[test]
    fn sphere_enclosure_never_ends_outside(
        from in (-0.57f64..0.57, -0.57f64..0.57, -0.57f64..0.57),
        to in (-4.0f64..4.0, -4.0f64..4.0, -4.0f64..4.0),
    ) {
        let env = env_with(Boundary::sphere(DVec3::ZERO, 1.0).with_keep(Keep::Inside));
        let end = env.constrain(DVec3::new(from.0, from.1, from.2), DVec3::new(to.0, to.1, to.2));
        prop_assert!(end.length() <= 1.0, "{}", end);
    }

    /// A closed cube mesh behaves like the box primitive it tessellates, for
    /// both sides and both hard behaviours, on random segments.
    #[test]
    fn cube_mesh_matches_the_box_primitive(
        from in (-3.0f64..3.0, -3.0f64..3.0, -3.0f64..3.0),
        to in (-3.0f64..3.0, -3.0f64..3.0, -3.0f64..3.0),
        inside in any::<bool>(),
        stop in any::<bool>(),
    ) {
        let keep = if inside { Keep::Inside } else { Keep::Outside };
        let behaviour = if stop { Behaviour::Stop } else { Behaviour::Slide };
        let center = Vec3::new(0.25, -0.5, 0.125);
        let h = 1.25;
        let primitive = env_with(
            Boundary::cuboid(center.as_dvec3() - h as f64, center.as_dvec3() + h as f64)
                .with_behaviour(behaviour)
                .with_keep(keep),
        );
        let mesh = env_with(Boundary::mesh(&cube_mesh(center, h)).unwrap().with_behaviour(behaviour).with_keep(keep));
        let (from, to) = (DVec3::new(from.0, from.1, from.2), DVec3::new(to.0, to.1, to.2));
        let (a, b) = (primitive.constrain(from, to), mesh.constrain(from, to));
        prop_assert!(close(a, b, 1e-6), "box {} mesh {} ({} → {})", a, b, from, to);
        for p in [from, to] {
            // Equal up to the skin (at an edge the box clamps each axis,
            // the mesh steps along the edge's pseudo-normal).
            prop_assert!(close(primitive.settle(p), mesh.settle(p), 1e-5));
        }
    }

    /// Settling always lands on the allowed side of spheres, boxes and a
    /// closed mesh, and leaves allowed points alone.
    #[test]
    fn settle_always_lands_on_the_allowed_side(
        p in (-3.0f64..3.0, -3.0f64..3.0, -3.0f64..3.0),
        inside in any::<bool>(),
    ) {
        let keep = if inside { Keep::Inside } else { Keep::Outside };
        let p = DVec3::new(p.0, p.1, p.2);
        for b in [
            Boundary::sphere(DVec3::new(0.1, 0.2, 0.3), 1.5),
            Boundary::cuboid(DVec3::splat(-1.0), DVec3::new(1.0, 2.0, 0.5)),
            Boundary::plane(DVec3::ZERO, DVec3::new(1.0, 1.0, 1.0)).unwrap(),
            Boundary::mesh(&cube_mesh(Vec3::ZERO, 1.0)).unwrap(),
        ] {
            let b = b.with_keep(keep);
            let q = env_with(b.clone()).settle(p);
            prop_assert!(!b.is_wrong_side(q), "{:?}: {} → {}", b.shape, p, q);
            if !b.is_wrong_side(p) {
                prop_assert_eq!(q, p);
            } else {
                // The nearest allowed point: never further than the
                // farthest surface point of these shapes from the cube.
                prop_assert!((q - p).length() <= 6.0);
            }
        }
    }
}

#[test]
fn plane_keeps_the_side_its_normal_points_to() {
    let plane = Boundary::plane(DVec3::ZERO, DVec3::new(0.0, 0.0, 2.0)).unwrap();
    let (from, to) = (DVec3::new(0.0, 0.0, 1.0), DVec3::new(2.0, 0.0, -1.0));
    let slide = env_with(plane.clone()).constrain(from, to);
    assert!(close(slide, DVec3::new(2.0, 0.0, 0.0), 1e-5) && slide.z >= 0.0, "{slide}");
    let stop = env_with(plane.clone().with_behaviour(Behaviour::Stop)).constrain(from, to);
    assert!(close(stop, DVec3::new(1.0, 0.0, 0.0), 1e-5) && stop.z >= 0.0, "{stop}");
    // Moving up and away is free; with keep = inside, down is free and up stops.
    assert_eq!(env_with(plane.clone()).constrain(to, from), from);
    let below = env_with(plane.clone().with_keep(Keep::Inside));
    assert_eq!(below.constrain(DVec3::new(0.0, 0.0, -1.0), DVec3::new(0.0, 0.0, -3.0)), DVec3::new(0.0, 0.0, -3.0));
    let up = below.constrain(DVec3::new(0.0, 0.0, -1.0), DVec3::new(0.0, 0.0, 1.0));
    assert!(up.z <= 0.0 && up.z > -1e-5, "{up}");
    // Parallel moves on the plane itself stay there, zero moves stay put.
    let on = DVec3::new(1.0, 1.0, 0.0);
    assert_eq!(env_with(plane.clone()).constrain(DVec3::ZERO, on), on);
    assert_eq!(env_with(plane).constrain(on, on), on);
    assert!(Boundary::plane(DVec3::ZERO, DVec3::ZERO).is_none());
}

#[test]
fn box_obstacle_and_enclosure() {
    let (lo, hi) = (DVec3::splat(-1.0), DVec3::splat(1.0));
    let enclosure = env_with(Boundary::cuboid(lo, hi).with_keep(Keep::Inside));
    let end = enclosure.constrain(DVec3::ZERO, DVec3::new(3.0, 0.5, 0.0));
    assert!(close(end, DVec3::new(1.0, 0.5, 0.0), 1e-5) && end.x < 1.0, "{end}");
    // Into a corner: the slide along x = 1 hits y = 1 and stops there.
    let end = enclosure.constrain(DVec3::ZERO, DVec3::new(3.0, 3.0, 0.0));
    assert!(end.x < 1.0 && end.y < 1.0 && end.x > 0.99 && end.y > 0.99, "{end}");
    let obstacle = env_with(Boundary::cuboid(lo, hi));
    let end = obstacle.constrain(DVec3::new(-3.0, 0.0, 0.0), DVec3::new(3.0, 0.2, 0.0));
    assert!(end.x < -1.0 && end.x > -1.0 - 1e-4 && (end.y - 0.2).abs() < 1e-5, "{end}");
    let stop = env_with(Boundary::cuboid(lo, hi).with_behaviour(Behaviour::Stop));
    let end = stop.constrain(DVec3::new(0.0, 0.0, 3.0), DVec3::new(0.0, 0.5, -1.0));
    assert!(end.z > 1.0 && end.z < 1.0 + 1e-4 && (end.y - 0.25).abs() < 1e-4, "{end}");
}

#[test]
fn settle_projects_points_out_to_the_nearest_allowed_point() {
    let sphere = env_with(Boundary::sphere(DVec3::ZERO, 1.0));
    let s = sphere.settle(DVec3::new(0.0, 0.5, 0.0));
    assert!(close(s, DVec3::new(0.0, 1.0, 0.0), 1e-5) && s.y > 1.0, "{s}");
    // The centre has no nearest direction: it leaves upwards.
    assert!(close(sphere.settle(DVec3::ZERO), DVec3::Z, 1e-5));
    let enclosure = env_with(Boundary::sphere(DVec3::ZERO, 1.0).with_keep(Keep::Inside));
    let s = enclosure.settle(DVec3::new(0.0, 3.0, 0.0));
    assert!(close(s, DVec3::Y, 1e-5) && s.y < 1.0, "{s}");
    let boxed = env_with(Boundary::cuboid(DVec3::splat(-1.0), DVec3::splat(1.0)));
    let s = boxed.settle(DVec3::new(0.9, 0.1, -0.2));
    assert!(close(s, DVec3::new(1.0, 0.1, -0.2), 1e-5) && s.x > 1.0, "{s}");
    let cube = env_with(Boundary::mesh(&cube_mesh(Vec3::ZERO, 1.0)).unwrap());
    let s = cube.settle(DVec3::new(0.1, 0.2, 0.95));
    assert!(close(s, DVec3::new(0.1, 0.2, 1.0), 1e-5) && s.z > 1.0, "{s}");
    // Points on the allowed side and soft boundaries are left alone.
    let p = DVec3::new(0.0, 0.0, 2.0);
    assert_eq!(sphere.settle(p), p);
    let soft = env_with(Boundary::sphere(DVec3::ZERO, 1.0).with_behaviour(Behaviour::Soft));
    assert_eq!(soft.settle(DVec3::ZERO), DVec3::ZERO);
    // The clearance is the documented skin.
    assert!((s.z - 1.0 - skin(DVec3::new(0.1, 0.2, 0.95))).abs() < 1e-9);
}

#[test]
fn soft_boundaries_never_change_a_move_but_report_the_wrong_side() {
    let shapes = [
        Boundary::sphere(DVec3::ZERO, 1.0),
        Boundary::cuboid(DVec3::splat(-1.0), DVec3::splat(1.0)),
        Boundary::plane(DVec3::ZERO, DVec3::Z).unwrap(),
        Boundary::mesh(&cube_mesh(Vec3::ZERO, 1.0)).unwrap(),
    ];
    for b in shapes {
        let env = env_with(b.clone().with_behaviour(Behaviour::Soft));
        let (from, to) = (DVec3::new(0.2, 0.1, 3.0), DVec3::new(-0.1, 0.3, -3.0));
        assert_eq!(env.constrain(from, to), to, "{:?}", b.shape);
        assert!(env.has_soft_boundaries() && !env.has_hard_boundaries());
        assert!(env.is_outside_soft(DVec3::new(0.0, 0.0, -0.5)), "{:?}", b.shape);
        assert!(!env.is_outside_soft(DVec3::new(0.0, 0.0, 3.0)), "{:?}", b.shape);
        let inside = env_with(b.with_behaviour(Behaviour::Soft).with_keep(Keep::Inside));
        assert!(!inside.is_outside_soft(DVec3::new(0.0, 0.0, -0.5)));
        assert!(inside.is_outside_soft(DVec3::new(0.0, 0.0, 3.0)));
    }
    // Hard boundaries are not counted.
    assert!(!env_with(Boundary::sphere(DVec3::ZERO, 1.0)).is_outside_soft(DVec3::ZERO));
}

/// A square sheet `[-2, 2]²` at height `z`, facing +z.
fn sheet(z: f32) -> Mesh {
    let positions = vec![
        Vec3::new(-2.0, -2.0, z),
        Vec3::new(2.0, -2.0, z),
        Vec3::new(2.0, 2.0, z),
        Vec3::new(-2.0, 2.0, z),
        Vec3::new(0.0, 0.0, z),
    ];
    let triangles = vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
    Mesh { name: "sheet".into(), positions, triangles }
}

#[test]
fn open_mesh_keeps_the_side_its_normals_face() {
    let b = Boundary::mesh(&sheet(0.0)).unwrap();
    let Shape::Mesh(m) = &b.shape else { unreachable!() };
    assert!(!m.is_closed());
    let env = env_with(b.clone().with_behaviour(Behaviour::Stop));
    // Through the middle vertex and through an inner edge: both stopped.
    for x in [0.0, 1.0, 0.3] {
        let end = env.constrain(DVec3::new(x, x * 0.5_f64.min(x), 1.0), DVec3::new(x, 0.0, -1.0));
        assert!(end.z > 0.0 && end.z < 1e-4, "{x}: {end}");
    }
    // Beside the sheet: free. From below going up: free (back to front).
    let beside = DVec3::new(3.0, 0.0, -1.0);
    assert_eq!(env.constrain(DVec3::new(3.0, 0.0, 1.0), beside), beside);
    assert_eq!(env.constrain(DVec3::new(0.5, 0.5, -1.0), DVec3::new(0.5, 0.5, 1.0)), DVec3::new(0.5, 0.5, 1.0));
    // Behind the sheet is the wrong side; beyond its rim is not.
    assert!(b.is_wrong_side(DVec3::new(0.5, -0.5, -1.0)));
    assert!(b.is_wrong_side(DVec3::new(0.0, 0.0, -0.1)));
    assert!(!b.is_wrong_side(DVec3::new(0.5, -0.5, 1.0)));
    assert!(!b.is_wrong_side(DVec3::new(3.0, 0.0, -1.0)));
    let s = env.settle(DVec3::new(0.5, -0.5, -1.0));
    assert!(close(s, DVec3::new(0.5, -0.5, 0.0), 1e-5) && s.z > 0.0, "{s}");
}

#[test]
fn degenerate_input_gives_no_nan() {
    // A sheet with extra zero-area triangles: three collinear points, and a
    // repeated index.
    let mut m = sheet(0.0);
    m.positions.extend([Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.5, 0.0, 0.0)]);
    m.triangles.extend([[4, 5, 6], [4, 4, 5]]);
    let b = Boundary::mesh(&m).unwrap();
    let env = env_with(b.clone());
    let points = [DVec3::ZERO, DVec3::new(0.5, 0.0, 0.0), DVec3::new(0.25, 0.0, 1.0), DVec3::new(2.0, 2.0, 0.0)];
    for &from in &points {
        for &to in &points {
            for e in
                [&env, &env_with(Boundary::sphere(DVec3::ZERO, 0.0)), &env_with(Boundary::sphere(DVec3::ZERO, 1.0))]
            {
                let end = e.constrain(from, to);
                assert!(end.is_finite(), "{from} → {to}: {end}");
                assert!(e.settle(from).is_finite());
            }
        }
    }
    // A move lying in the sheet's plane (parallel to every triangle).
    let along = env.constrain(DVec3::new(-3.0, 0.1, 0.0), DVec3::new(3.0, 0.1, 0.0));
    assert!(along.is_finite());
    // Non-finite input is passed through, never turned into something else.
    assert!(env.constrain(DVec3::ZERO, DVec3::NAN).is_nan());
}

#[test]
fn bad_meshes_are_rejected_with_reasons() {
    let flat =
        Mesh { name: "flat".into(), positions: vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0], triangles: vec![[0, 1, 2]] };
    assert!(Boundary::mesh(&flat).unwrap_err().contains("no triangle with an area"));
    let missing = Mesh { name: "m".into(), positions: vec![Vec3::ZERO], triangles: vec![[0, 1, 2]] };
    assert!(Boundary::mesh(&missing).unwrap_err().contains("missing vertex"));
    let nan = Mesh { name: "n".into(), positions: vec![Vec3::NAN, Vec3::X, Vec3::Y], triangles: vec![[0, 1, 2]] };
    assert!(Boundary::mesh(&nan).unwrap_err().contains("not finite"));
    let mut twisted = sheet(0.0);
    twisted.triangles[1] = [2, 1, 4];
    assert!(Boundary::mesh(&twisted).unwrap_err().contains("consistently wound"));
}

#[test]
fn an_inward_wound_closed_mesh_is_turned_outward() {
    let mut m = cube_mesh(Vec3::ZERO, 1.0);
    for t in &mut m.triangles {
        t.swap(1, 2);
    }
    let env = env_with(Boundary::mesh(&m).unwrap());
    let end = env.constrain(DVec3::new(0.0, 0.0, 3.0), DVec3::ZERO);
    assert!(end.z > 1.0 && end.z < 1.0 + 1e-4, "{end}");
}

#[test]
fn mesh_sphere_agrees_with_the_sphere_primitive_and_is_fast() {
    // A finely tessellated unit sphere (80 rings × 160 segments).
    let mut m = unit_mesh(Primitive::Sphere, Tessellation { radial: 160, rings: 80 });
    for p in &mut m.positions {
        *p *= 2.0;
    }
    let b = Boundary::mesh(&m).unwrap();
    let Shape::Mesh(mb) = &b.shape else { unreachable!() };
    assert!(mb.is_closed() && mb.triangle_count() > 25_000);
    let env = env_with(b.with_behaviour(Behaviour::Stop));
    let start = std::time::Instant::now();
    let mut n = 0;
    for i in 0..40 {
        for j in 0..50 {
            let (th, ph) = (std::f64::consts::PI * (i as f64 + 0.5) / 40.0, std::f64::consts::TAU * j as f64 / 50.0);
            let dir = DVec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
            let end = env.constrain(dir * 3.0, DVec3::ZERO);
            // The polyhedron lies within 0.1% of the sphere here.
            assert!((end.length() - 1.0).abs() < 2e-3, "{dir}: {end}");
            assert!(env.settle(dir * 0.5).length() > 0.99);
            n += 1;
        }
    }
    // O(log triangles) per query: 2000 moves and settles take far below a
    // second even unoptimised (a linear scan would be ~50M triangle tests).
    assert!(start.elapsed().as_secs_f64() < 5.0, "{n} queries took {:?}", start.elapsed());
}

#[test]
fn guides_show_boundaries_and_charges() {
    let env = Environment::new()
        .with_charge(Charge::attractor(DVec3::new(0.0, 0.0, 3.0)))
        .with_charge(Charge::repeller(DVec3::new(1.0, 0.0, -1.0)))
        .with_boundary(Boundary::sphere(DVec3::new(0.0, 0.0, -2.0), 1.5))
        .with_boundary(Boundary::cuboid(DVec3::splat(-4.0), DVec3::splat(4.0)).with_keep(Keep::Inside))
        .with_boundary(Boundary::plane(DVec3::new(0.0, 0.0, -5.0), DVec3::Z).unwrap())
        .with_boundary(Boundary::mesh(&cube_mesh(Vec3::X, 0.5)).unwrap().with_behaviour(Behaviour::Soft));
    let mut scene = Scene::new();
    env.guides(&mut scene);
    assert_eq!(scene.guides.len(), 6);
    let tag = |name: &str| scene.tags.iter().position(|t| t == name).unwrap() as u32;
    let (boundary, attractor, repeller) = (tag("boundary"), tag("attractor"), tag("repeller"));
    let meshes: Vec<_> = scene
        .guides
        .iter()
        .filter_map(|g| match &g.kind {
            GuideKind::Mesh(m) => {
                assert_eq!(g.tag, boundary);
                Some(m.bounds().unwrap())
            }
            GuideKind::Point { .. } => None,
        })
        .collect();
    assert_eq!(meshes.len(), 4);
    let (lo, hi) = meshes[0];
    assert!((lo - Vec3::new(-1.5, -1.5, -3.5)).abs().max_element() < 1e-3 && (hi.z + 0.5).abs() < 1e-3);
    assert_eq!(meshes[1], (Vec3::splat(-4.0), Vec3::splat(4.0)));
    assert!((meshes[2].1.x - meshes[2].0.x - 10.0).abs() < 1e-4 || (meshes[2].1.y - meshes[2].0.y) > 7.0);
    assert_eq!(meshes[2].0.z, -5.0);
    assert_eq!(meshes[3], (Vec3::new(0.5, -0.5, -0.5), Vec3::new(1.5, 0.5, 0.5)));
    let points: Vec<_> = scene
        .guides
        .iter()
        .filter_map(|g| match g.kind {
            GuideKind::Point { at, .. } => Some((at, g.tag)),
            _ => None,
        })
        .collect();
    assert_eq!(points, vec![(Vec3::new(0.0, 0.0, 3.0), attractor), (Vec3::new(1.0, 0.0, -1.0), repeller)]);
}
