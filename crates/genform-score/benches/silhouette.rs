//! Image scoring: the fast silhouette rasterizer against the per-pixel
//! oracle on 40 random boxes at 800×600, seen through the tree-sketch camera
//! (reference §1.9), plus 40 mixed primitives (frusta and spheres) on the
//! fast path.
//!
//! Run: `cargo bench -p genform-score --bench silhouette`.

use criterion::{Criterion, criterion_group, criterion_main};
use genform_core::Rng;
use genform_core::camera::Camera;
use genform_core::scene::{Instance, Primitive, Scene};
use genform_score::image::oracle;
use genform_score::{ImageScorer, ImageTarget};
use glam::{Affine3A, Quat, Vec3};
use std::hint::black_box;

fn scorer() -> ImageScorer {
    #[allow(clippy::approx_constant)] // the reference's φ, not quite −π/2
    let camera =
        Camera { fov_deg: 60.0, phi: -1.5708, theta: 0.0, radius: 9.4716, look_at: Vec3::new(-0.680994, 3.2558, 0.0) };
    // A disc of target pixels in the middle, like the sketch's crown.
    let (w, h) = (800u32, 600u32);
    let weights: Vec<f32> = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32 - 420.0, (i / w) as f32 - 280.0);
            if x * x + y * y < 200.0 * 200.0 { 1.0 } else { -1.0 }
        })
        .collect();
    let target = ImageTarget::from_weights(w, h, &weights).expect("valid weights");
    ImageScorer::new(camera, w, h, target).expect("valid scorer")
}

/// 40 instances of `kinds` with random size (0.2–1.2), rotation and
/// position in the tree's region.
fn scene(seed: u64, kinds: &[Primitive]) -> Scene {
    let mut rng = Rng::from_seed(seed);
    let mut s = Scene::new();
    let tag = s.tag("part");
    for i in 0..40 {
        let mut u = |lo: f64, hi: f64| rng.uniform(lo, hi) as f32;
        let size = Vec3::new(u(0.2, 1.2), u(0.2, 1.2), u(0.2, 1.2));
        let axis = Vec3::new(u(-1.0, 1.0), u(-1.0, 1.0), u(-1.0, 1.0)).normalize_or(Vec3::Y);
        let rot = Quat::from_axis_angle(axis, u(0.0, std::f64::consts::TAU));
        let pos = Vec3::new(u(-3.0, 2.0), u(0.0, 6.0), u(-2.0, 2.0));
        s.instances.push(Instance {
            transform: Affine3A::from_scale_rotation_translation(size, rot, pos),
            primitive: kinds[i % kinds.len()],
            tag,
        });
    }
    s
}

fn bench(c: &mut Criterion) {
    let scorer = scorer();
    let boxes = scene(7, &[Primitive::Box]);
    let mixed = scene(8, &[Primitive::Frustum { top: 0.58 }, Primitive::Sphere]);
    let mut scratch = scorer.scratch();
    // Same answer from both before timing them.
    assert_eq!(scorer.counts(&boxes, &mut scratch), oracle::counts(&scorer, &boxes));

    let mut g = c.benchmark_group("silhouette_800x600");
    g.bench_function("fast_40_boxes", |b| b.iter(|| scorer.counts(black_box(&boxes), &mut scratch)));
    g.bench_function("fast_40_frusta_spheres", |b| b.iter(|| scorer.counts(black_box(&mixed), &mut scratch)));
    g.sample_size(10);
    g.bench_function("oracle_40_boxes", |b| b.iter(|| oracle::counts(&scorer, black_box(&boxes))));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
