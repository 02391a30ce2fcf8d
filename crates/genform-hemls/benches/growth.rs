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

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use genform_core::Rng;
use genform_hemls::grammar;
use genform_hemls::settings; // `testkit` names `crate::grammar` and `crate::settings`
use genform_hemls::{Environment, grow};
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

criterion_group!(benches, tiles, six_steps);
criterion_main!(benches);
