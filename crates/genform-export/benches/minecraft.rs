//! Minecraft I/O: writing a 64×64×64 structure into the real fastanvil
//! region (throughput in blocks/s and in region bytes/s), reading that
//! region's terrain, writing the structure as a schematic, and greedy
//! meshing of a 256×64×256 castle.
//!
//! Run: `cargo bench -p genform-export --bench minecraft`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use genform_core::blocks::{BlockGrid, BlockState};
use genform_export::minecraft::{self, RegionFile, SchemVersion};
use glam::{IVec3, UVec3};
use std::hint::black_box;

fn fixture() -> RegionFile {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/terrain/fastanvil-1.19.4/r.0.0.mca");
    RegionFile { x: 0, z: 0, bytes: std::fs::read(path).expect("the terrain fixture") }
}

/// A castle-like structure: outer walls with crenellations, corner towers,
/// floors every 8 blocks, windows, stairs on the roofs and air inside.
fn castle(origin: IVec3, size: UVec3) -> BlockGrid {
    let mut g = BlockGrid::new(origin, size);
    let states = [
        "stone_bricks",
        "mossy_stone_bricks",
        "cracked_stone_bricks",
        "glass_pane[east=true,north=false,south=false,waterlogged=false,west=true]",
        "oak_planks",
        "stone_brick_stairs[facing=north,half=bottom,shape=straight,waterlogged=false]",
        "air",
        "torch",
    ]
    .map(|s| g.intern(&BlockState::parse(s).expect("valid block")));
    let (sx, sy, sz) = (size.x as i32, size.y as i32, size.z as i32);
    let mut i = 0;
    for y in 0..sy {
        for z in 0..sz {
            for x in 0..sx {
                let wall = x % 32 == 0 || z % 32 == 0 || x == sx - 1 || z == sz - 1;
                let tower = (x % 64 < 6) && (z % 64 < 6);
                let floor = y % 8 == 0;
                let c = if y == sy - 1 {
                    if wall && (x + z) % 2 == 0 {
                        states[0]
                    } else if wall {
                        states[6]
                    } else {
                        states[5]
                    }
                } else if wall || tower {
                    if y % 8 == 4 && (x + z) % 4 == 1 {
                        states[3]
                    } else {
                        states[((x * 7 + y * 3 + z * 5) % 11).min(2) as usize]
                    }
                } else if floor {
                    states[4]
                } else if y % 8 == 1 && (x * 13 + z * 7) % 61 == 0 {
                    states[7]
                } else {
                    states[6]
                };
                g.cells[i] = c;
                i += 1;
            }
        }
    }
    g
}

fn bench(c: &mut Criterion) {
    let region = fixture();
    let structure = castle(IVec3::new(8, 50, 8), UVec3::splat(64));
    let blocks = structure.volume() as u64;

    let mut g = c.benchmark_group("region_write_64cubed");
    g.sample_size(20);
    g.throughput(Throughput::Elements(blocks));
    g.bench_function("blocks", |b| b.iter(|| minecraft::write_region(black_box(&region), &structure).unwrap()));
    g.throughput(Throughput::Bytes(region.bytes.len() as u64));
    g.bench_function("region_bytes", |b| b.iter(|| minecraft::write_region(black_box(&region), &structure).unwrap()));
    g.finish();

    let mut g = c.benchmark_group("read_terrain");
    g.sample_size(10);
    let (lo, hi) = (IVec3::new(0, -64, 0), IVec3::new(240, 320, 240));
    g.throughput(Throughput::Elements(240 * 384 * 240));
    g.bench_function("fastanvil_full_area", |b| {
        b.iter(|| minecraft::read_terrain(std::slice::from_ref(black_box(&region)), lo, hi).unwrap())
    });
    g.finish();

    let mut g = c.benchmark_group("schem_write_64cubed");
    g.throughput(Throughput::Elements(blocks));
    g.bench_function("v2", |b| b.iter(|| minecraft::write_schem(black_box(&structure), SchemVersion::V2, 3955)));
    g.bench_function("litematic", |b| b.iter(|| minecraft::write_litematic(black_box(&structure), 3955, "castle")));
    g.finish();

    let big = castle(IVec3::ZERO, UVec3::new(256, 64, 256));
    let mut g = c.benchmark_group("greedy_mesh");
    g.sample_size(10);
    g.throughput(Throughput::Elements(big.volume() as u64));
    g.bench_function("castle_256x64x256", |b| b.iter(|| minecraft::mesh_blocks(black_box(&big))));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
