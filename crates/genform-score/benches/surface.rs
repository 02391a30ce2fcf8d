//! Surface measures and scoring of a bumpy four-sided-tile grid after 6
//! steps (65² = 4225 vertices, 8320 edges).
//!
//! Run with `cargo bench -p genform-score --bench surface`.

use criterion::{Criterion, criterion_group, criterion_main};
use genform_core::scene::Scene;
use genform_core::{Surface, SurfaceEdge};
use genform_score::{SurfaceCriterion, SurfaceMeasures, SurfaceObjective, SurfaceScorer};
use glam::Vec3;
use std::hint::black_box;

fn grid(m: usize) -> Scene {
    let at = |i: usize, j: usize| (j * (m + 1) + i) as u32;
    let mut s = Surface::new(0);
    for j in 0..=m {
        for i in 0..=m {
            let (x, y) = (i as f32 / m as f32 - 0.5, j as f32 / m as f32 - 0.5);
            s.positions.push(Vec3::new(x, y, (7.0 * x).sin() * (5.0 * y).cos()));
            if i < m {
                s.edges.push(SurfaceEdge { a: at(i, j), b: at(i + 1, j), kind: 0 });
            }
            if j < m {
                s.edges.push(SurfaceEdge { a: at(i, j), b: at(i, j + 1), kind: 1 });
            }
        }
    }
    Scene { surfaces: vec![s], ..Scene::new() }
}

fn bench(c: &mut Criterion) {
    let scene = grid(64);
    let objective = SurfaceCriterion::ALL.into_iter().fold(SurfaceObjective::default(), |o, k| o.with(k, 1.0, 1.0));
    let scorer = SurfaceScorer::new(objective).unwrap();
    let mut g = c.benchmark_group("surface 65x65 grid");
    g.bench_function("measures", |b| b.iter(|| black_box(SurfaceMeasures::of(black_box(&scene)))));
    g.bench_function("measures+score", |b| b.iter(|| black_box(scorer.fitness(black_box(&scene)))));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
