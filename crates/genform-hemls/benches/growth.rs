//! HEMLS growth throughput on one core (the whole growth: seed, every step's
//! grow, rewrite and join phases):
//!
//! - `tiles/n`: the four-sided tiles for n = 5..9 steps (4ⁿ quads; the goal
//!   is n = 8, 65,536 quads, in ≤ 50 ms, and time roughly linear in the
//!   element count).
//! - `six_steps/<env>/…`: six steps of the three-sided tiles (Sync) and of
//!   the Koch snowflake in a given environment; [`six_steps_in`] takes the
//!   environment so that an environment variant can be added next to the
//!   empty one.
//! - `env/tiles4_six_steps/…`: six steps of the four-sided tiles (4,096
//!   quads) with no environment and with five attractors, gravity and a
//!   sphere boundary the sheet slides over (the goal: the environment costs
//!   at most 2× the bare growth).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use genform_core::Rng;
use genform_hemls::grammar;
use genform_hemls::settings; // `testkit` names `crate::grammar` and `crate::settings`
use genform_hemls::{Axis, Boundary, Charge, Environment, Gravity, Settings, grow};
use glam::DVec3;
use std::hint::black_box;

#[path = "../src/testkit.rs"]
mod testkit;

fn tiles(c: &mut Criterion) {
    let mut group = c.benchmark_group("tiles");
    group.sample_size(10);
    let h = testkit::four_sided_tiles();
    let env = Environment::default();
    for n in 5..=9u32 {
        let s = testkit::settings(n, 1.5);
        group.throughput(Throughput::Elements(4u64.pow(n)));
        group.bench_function(format!("n{n}"), |b| {
            b.iter(|| {
                let g = grow(black_box(&h), &s, &env, &mut Rng::from_seed(1)).unwrap();
                assert_eq!(g.map.face_count(), 4usize.pow(n));
                g
            })
        });
    }
    group.finish();
}

/// Six growth steps of the three-sided tiles and the Koch snowflake in
/// `env`, reported under `six_steps/<label>/…`.
pub fn six_steps_in(c: &mut Criterion, label: &str, env: &Environment) {
    let mut group = c.benchmark_group(format!("six_steps/{label}"));
    group.sample_size(10);
    let s = testkit::settings(6, 1.5);
    for (name, h) in [("three_sided_tiles", testkit::three_sided_tiles()), ("koch", testkit::koch())] {
        group.bench_function(name, |b| b.iter(|| grow(black_box(&h), &s, env, &mut Rng::from_seed(1)).unwrap()));
    }
    group.finish();
}

fn six_steps(c: &mut Criterion) {
    six_steps_in(c, "no_env", &Environment::default());
}

/// Five attractors around the sheet, gravity pulling it down and a sphere
/// under it that its middle slides over.
pub fn busy_environment() -> Environment {
    let mut env = Environment::new()
        .with_gravity(Gravity::new(Axis::Z, -0.3))
        .with_boundary(Boundary::sphere(SPHERE_CENTER, SPHERE_RADIUS));
    for (x, y) in [(4.0, 4.0), (-4.0, 4.0), (-4.0, -4.0), (4.0, -4.0), (6.0, 0.0)] {
        env = env.with_charge(Charge::attractor(DVec3::new(x, y, 1.0)).with_strength(0.5));
    }
    env
}

const SPHERE_CENTER: DVec3 = DVec3::new(0.0, 0.0, -2.2);
const SPHERE_RADIUS: f64 = 2.0;

fn environment(c: &mut Criterion) {
    let mut group = c.benchmark_group("env/tiles4_six_steps");
    group.sample_size(10);
    let h = testkit::four_sided_tiles();
    // About a fixed centre, so that the scale does not lift the sagging
    // sheet's middle off the sphere.
    let s = Settings { fixed_center: true, ..testkit::settings(6, 1.5) };
    // The benchmark means something only if the sheet reaches the sphere.
    let g = grow(&h, &s, &busy_environment(), &mut Rng::from_seed(1)).unwrap();
    let on_sphere = g.map.positions().iter().filter(|p| (**p - SPHERE_CENTER).length() < SPHERE_RADIUS + 1e-2);
    assert!(on_sphere.count() >= 10, "the sheet must slide over the sphere");
    for (name, env) in [("none", Environment::default()), ("charges_gravity_sphere", busy_environment())] {
        group.throughput(Throughput::Elements(4u64.pow(6)));
        group.bench_function(name, |b| {
            b.iter(|| {
                let g = grow(black_box(&h), &s, &env, &mut Rng::from_seed(1)).unwrap();
                assert_eq!(g.map.face_count(), 4usize.pow(6));
                g
            })
        });
    }
    group.finish();
    six_steps_in(c, "charges_gravity_sphere", &busy_environment());
}

criterion_group!(benches, tiles, six_steps, environment);
criterion_main!(benches);
