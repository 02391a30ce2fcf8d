//! Spaceship derivation + Scene build throughput at fixed genome lengths,
//! and GLB/OBJ write throughput of the resulting scenes.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use genform_core::genome::Link;
use genform_core::{Generator, GeneratorGraph, Genome, Limits, Rng, Scene, SourceFile};
use std::hint::black_box;

fn example(name: &str) -> genform_shape::ShapeGrammar {
    let path = format!("{}/../../examples/shape/{name}.sg", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("the example");
    let file = SourceFile::new(format!("{name}.sg"), text);
    genform_shape::compile(&file, &genform_shape::NoAssets).map(|(g, _)| g).expect("the example compiles")
}

fn spaceship() -> genform_shape::ShapeGrammar {
    example("spaceship")
}

/// Whole derivations of the building examples (16 sampled genomes each):
/// the L house's straight-skeleton hip roof, the office block's offsets,
/// setback and U shape.
fn buildings(c: &mut Criterion) {
    let mut group = c.benchmark_group("buildings_express");
    for name in ["l_house", "office_block", "polygon_operations"] {
        let g = example(name);
        let limits = g.limits();
        let genomes: Vec<Genome> =
            (0..16).map(|s| g.sample(&mut Rng::from_seed(s), &limits).expect("samples").genome).collect();
        group.throughput(Throughput::Elements(genomes.len() as u64));
        group.bench_function(name, |b| {
            let mut scene = Scene::new();
            b.iter(|| {
                for genome in &genomes {
                    scene.clear();
                    g.express(black_box(genome), &limits, &mut scene).unwrap();
                }
                black_box(scene.meshes.len())
            })
        });
    }
    group.finish();
}

/// A genome of exactly `len` genes: the root plus repeated grows at
/// uniformly chosen empty links (the GA's initialisation).
fn genome_of_len(graph: &GeneratorGraph, len: usize, seed: u64) -> Genome {
    let mut rng = Rng::from_seed(seed);
    let mut params = Vec::new();
    graph.draw_params(graph.root, &mut rng, &mut params);
    let mut g = Genome::with_root(graph, graph.root, &params);
    let mut open = Vec::new();
    while g.len() < len {
        open.clear();
        for gene in g.iter() {
            open.extend(gene.links().enumerate().filter(|(_, l)| *l == Link::Empty).map(|(i, _)| (gene.pos, i)));
        }
        let (p, link) = open[rng.index(open.len())];
        let spec = graph.symbol(g.gene(p).symbol());
        let target = spec.slots[spec.slot_of_link(link).unwrap().0].target;
        params.clear();
        graph.draw_params(target, &mut rng, &mut params);
        g.grow(p, link, target, &params, graph.symbol(target).link_len());
    }
    g
}

fn bench(c: &mut Criterion) {
    let ship = spaceship();
    let limits = Limits::default();
    let mut group = c.benchmark_group("spaceship_express");
    for len in [40usize, 100] {
        let genomes: Vec<Genome> = (0..16).map(|s| genome_of_len(ship.graph(), len, s)).collect();
        group.throughput(Throughput::Elements((len * genomes.len()) as u64));
        group.bench_with_input(BenchmarkId::new("genes", len), &genomes, |b, genomes| {
            let mut scene = Scene::new();
            b.iter(|| {
                for g in genomes {
                    scene.clear();
                    ship.express(black_box(g), &limits, &mut scene).unwrap();
                }
                black_box(scene.instances.len())
            })
        });
    }
    group.finish();

    let mut scene = Scene::new();
    ship.express(&genome_of_len(ship.graph(), 100, 1), &limits, &mut scene).unwrap();
    let tess = Default::default();
    let mut group = c.benchmark_group("export_spaceship_100_genes");
    // Instanced (one node per primitive): the layout the figures in
    // docs/benchmarks.md were measured with; `auto` merges this ship.
    let instanced = genform_export::Granularity::Instanced;
    let glb = genform_export::write_glb_with(&scene, tess, instanced);
    group.throughput(Throughput::Bytes(glb.len() as u64));
    group.bench_function("glb", |b| {
        b.iter(|| black_box(genform_export::write_glb_with(black_box(&scene), tess, instanced)))
    });
    let merged = genform_export::Granularity::Merged;
    group.bench_function("glb_merged", |b| {
        b.iter(|| black_box(genform_export::write_glb_with(black_box(&scene), tess, merged)))
    });
    let obj = genform_export::write_obj(&scene, tess);
    group.throughput(Throughput::Bytes(obj.len() as u64));
    group.bench_function("obj", |b| b.iter(|| black_box(genform_export::write_obj(black_box(&scene), tess))));
    group.finish();
}

criterion_group!(benches, bench, buildings);
criterion_main!(benches);
