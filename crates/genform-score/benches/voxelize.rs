//! Voxelize-and-count of spaceship-like scenes on the reference grid
//! (100×200×100 over x, y ∈ [−5, 5], z ∈ [−2, 18]): the fast voxelizer
//! against the per-voxel oracle in the same run.
//!
//! Run with `cargo bench -p genform-score --bench voxelize`.

use criterion::{Criterion, criterion_group, criterion_main};
use genform_core::Rng;
use genform_core::scene::{Instance, Primitive, Scene};
use genform_score::{Grid, VolumeScorer, VolumeTarget, VoxelSet, voxelize};
use glam::{Affine3A, Quat, Vec3};
use std::hint::black_box;

/// `n` boxes of sizes 0.3–1.5 along z ∈ [0, 8], half of them mirrored in x
/// (the spaceship grammar's wings); `rotated` turns each by a random angle.
fn ships(n: usize, seed: u64, rotated: bool) -> Scene {
    let mut rng = Rng::stream(seed, &[1]);
    let mut s = Scene::new();
    let tag = s.tag("hull");
    for i in 0..n {
        let mut size =
            Vec3::new(rng.uniform(0.3, 1.5) as f32, rng.uniform(0.3, 1.5) as f32, rng.uniform(0.3, 1.5) as f32);
        if i % 2 == 1 {
            size.x = -size.x;
        }
        let at = Vec3::new(rng.uniform(-2.5, 2.5) as f32, rng.uniform(-0.5, 1.0) as f32, rng.uniform(0.0, 8.0) as f32);
        let rot = if rotated {
            Quat::from_euler(glam::EulerRot::XYZ, rng.uniform(-0.5, 0.5) as f32, rng.uniform(-3.0, 3.0) as f32, 0.0)
        } else {
            Quat::IDENTITY
        };
        s.instances.push(Instance {
            transform: Affine3A::from_scale_rotation_translation(size, rot, at),
            primitive: Primitive::Box,
            tag,
        });
    }
    s
}

/// A spaceship-like scene: a chain of `n` body segments along +z whose
/// sizes compound (each a factor 0.6–1.5 of the previous per axis, so some
/// grow large), with mirrored wing chains and top stacks scaled relative to
/// their segment, all axis-aligned like the spaceship grammar's boxes.
fn compounding_ship(n: usize, seed: u64) -> Scene {
    let mut rng = Rng::stream(seed, &[2]);
    let mut s = Scene::new();
    let tag = s.tag("hull");
    let f = |rng: &mut Rng, lo: f32, hi: f32| rng.uniform(f64::from(lo), f64::from(hi)) as f32;
    let push = |s: &mut Scene, size: Vec3, at: Vec3| {
        for mirror in [false, true] {
            if mirror && at.x == 0.0 {
                break;
            }
            let (size, at) =
                if mirror { (size * Vec3::new(-1.0, 1.0, 1.0), at * Vec3::new(-1.0, 1.0, 1.0)) } else { (size, at) };
            let transform = Affine3A::from_scale_rotation_translation(size, Quat::IDENTITY, at);
            s.instances.push(Instance { transform, primitive: Primitive::Box, tag });
        }
    };
    let (mut size, mut z) = (Vec3::ONE, -1.0f32);
    for _ in 0..n {
        size *= Vec3::new(f(&mut rng, 0.6, 1.5), f(&mut rng, 0.6, 1.5), f(&mut rng, 0.6, 1.5));
        size = size.min(Vec3::splat(8.0));
        let body = Vec3::new(0.0, 0.0, z + size.z / 2.0);
        push(&mut s, size, body);
        if rng.uniform(0.0, 1.0) < 0.5 {
            // A wing chain to +x, mirrored to −x.
            let (mut ws, mut x) =
                (size * Vec3::new(f(&mut rng, 0.3, 1.2), f(&mut rng, 0.2, 0.5), f(&mut rng, 0.2, 1.0)), size.x / 2.0);
            for _ in 0..1 + rng.index(4) {
                push(&mut s, ws, Vec3::new(x + ws.x / 2.0, body.y, body.z + ws.z * f(&mut rng, -0.5, 0.5)));
                x += ws.x;
                ws *= Vec3::new(f(&mut rng, 0.6, 1.2), f(&mut rng, 0.9, 1.0), f(&mut rng, 0.7, 1.2));
            }
        }
        if rng.uniform(0.0, 1.0) < 0.33 {
            // A top stack.
            let (mut ts, mut y) =
                (size * Vec3::new(f(&mut rng, 0.3, 0.8), f(&mut rng, 0.1, 0.2), f(&mut rng, 0.3, 0.8)), size.y / 2.0);
            for _ in 0..1 + rng.index(3) {
                push(&mut s, ts, Vec3::new(0.0, y + ts.y / 2.0, body.z));
                y += ts.y;
                ts *= Vec3::new(f(&mut rng, 0.6, 1.1), f(&mut rng, 0.8, 1.1), f(&mut rng, 0.6, 1.1));
            }
        }
        z += size.z;
    }
    s
}

fn bench(c: &mut Criterion) {
    let grid = Grid::new(Vec3::new(-5.0, -5.0, -2.0), Vec3::new(5.0, 5.0, 18.0), [100, 200, 100]).unwrap();
    let target: VoxelSet = voxelize::voxelize(&grid, &ships(30, 7, false)).occupancy;
    let scorer = VolumeScorer::new(grid, vec![VolumeTarget::new(target)]).unwrap();
    let scenes: Vec<Scene> = (0..16).map(|s| ships(40, s, false)).collect();
    let rotated: Vec<Scene> = (0..16).map(|s| ships(40, s, true)).collect();
    let mut scratch = scorer.scratch();
    let mut g = c.benchmark_group("voxelize+count 40 boxes, 100x200x100");
    g.bench_function("fast axis-aligned", |b| {
        let mut i = 0;
        b.iter(|| {
            i = (i + 1) % scenes.len();
            black_box(scorer.counts(&scenes[i], &mut scratch))
        })
    });
    g.bench_function("fast rotated", |b| {
        let mut i = 0;
        b.iter(|| {
            i = (i + 1) % rotated.len();
            black_box(scorer.counts(&rotated[i], &mut scratch))
        })
    });
    let compounding: Vec<Scene> = (0..16).map(|s| compounding_ship(12, s)).collect();
    g.bench_function("fast compounding ship", |b| {
        let mut i = 0;
        b.iter(|| {
            i = (i + 1) % compounding.len();
            black_box(scorer.counts(&compounding[i], &mut scratch))
        })
    });
    g.sample_size(10);
    g.bench_function("oracle axis-aligned", |b| {
        let mut i = 0;
        b.iter(|| {
            i = (i + 1) % scenes.len();
            black_box(scorer.counts_of(&voxelize::oracle::voxelize(&grid, &scenes[i])))
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
