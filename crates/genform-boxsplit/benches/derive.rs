//! Box-split derivation throughput on one core, in cells of the derivation
//! box per second (deriving, observing and painting the result grid):
//!
//! - `castle_256x64x256`: `examples/boxsplit/castle.bsg` in an empty world.
//! - `bridge_256x48x64`: `examples/boxsplit/bridge.bsg` over a synthetic
//!   valley with a river (piers of 1×1 columns every sixth block).
//! - `column_field_128x64x128`: a support column under every cell of the
//!   top layer, each growing down block by block to rolling terrain (the
//!   paper's column rule; one rule application and one observer per block).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use genform_boxsplit::{BoxGrammar, DeriveOptions, compile};
use genform_core::{BlockGrid, BlockState, Rng, SourceFile};
use glam::IVec3;
use std::hint::black_box;

fn load(name: &str) -> BoxGrammar {
    let path = format!("{}/../../examples/boxsplit/{name}.bsg", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("example");
    compile(&SourceFile::new(format!("{name}.bsg"), text)).map(|(g, _)| g).expect("compiles")
}

/// Terrain of `size` with ground height `h(x, z)`: stone, grass on top,
/// water up to `water`.
fn terrain(size: IVec3, water: i32, h: impl Fn(i32, i32) -> i32) -> BlockGrid {
    let mut g = BlockGrid::new(IVec3::ZERO, size.as_uvec3());
    let (air, stone, grass, wet) = (
        g.intern(&BlockState::air()),
        g.intern(&BlockState::new("stone")),
        g.intern(&BlockState::new("grass_block")),
        g.intern(&BlockState::new("water")),
    );
    for y in 0..size.y {
        for z in 0..size.z {
            for x in 0..size.x {
                let ground = h(x, z);
                let c = if y + 1 < ground {
                    stone
                } else if y + 1 == ground {
                    grass
                } else if y < water {
                    wet
                } else {
                    air
                };
                let i = g.index(IVec3::new(x, y, z)).unwrap();
                g.cells[i] = c;
            }
        }
    }
    g
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("derive");
    group.sample_size(10);
    let opts = DeriveOptions::default();

    let castle = load("castle");
    let size = IVec3::new(256, 64, 256);
    group.throughput(Throughput::Elements((size.x * size.y * size.z) as u64));
    group.bench_function("castle_256x64x256", |b| {
        b.iter(|| black_box(castle.derive(None, IVec3::ZERO, size, &mut Rng::from_seed(1), &opts).unwrap()))
    });

    let bridge = load("bridge");
    let size = IVec3::new(256, 48, 64);
    let valley = terrain(size, 8, |x, z| 4 + ((x - 128).abs() / 3) + ((z as f32 * 0.3).sin() * 2.0) as i32);
    group.throughput(Throughput::Elements((size.x * size.y * size.z) as u64));
    group.bench_function("bridge_256x48x64", |b| {
        b.iter(|| black_box(bridge.derive(Some(&valley), IVec3::ZERO, size, &mut Rng::from_seed(1), &opts).unwrap()))
    });

    let field = compile(&SourceFile::new(
        "field.bsg",
        "limits applications = 10000000;\n\
         Field { split y [-1, 1] { Under, fill oak_planks } }\n\
         Under { split x [1] repeat { Row } }\n\
         Row { split z [1] repeat { Column } }\n\
         Column { when FULL(SOLID) { skip } else { split y [-1, 1] { Column, fill stone_bricks } } }\n",
    ))
    .map(|(g, _)| g)
    .expect("compiles");
    let size = IVec3::new(128, 64, 128);
    let hills = terrain(size, 0, |x, z| 8 + ((x as f32 * 0.1).sin() * (z as f32 * 0.07).cos() * 6.0 + 6.0) as i32);
    group.throughput(Throughput::Elements((size.x * size.y * size.z) as u64));
    group.bench_function("column_field_128x64x128", |b| {
        b.iter(|| black_box(field.derive(Some(&hills), IVec3::ZERO, size, &mut Rng::from_seed(1), &opts).unwrap()))
    });
    group.finish();

    // Counts behind the throughputs, for the report.
    for (name, g, world, size) in [
        ("castle", &castle, None, IVec3::new(256, 64, 256)),
        ("bridge", &bridge, Some(&valley), IVec3::new(256, 48, 64)),
        ("column_field", &field, Some(&hills), IVec3::new(128, 64, 128)),
    ] {
        let d = g.derive(world, IVec3::ZERO, size, &mut Rng::from_seed(1), &opts).unwrap();
        println!("{name}: {:?}", d.stats);
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
