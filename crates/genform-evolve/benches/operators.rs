//! Reproduction throughput on 100-gene genomes: crossover and mutation
//! alone, and a whole GA generation with a trivial objective (children/s).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use genform_core::{Limits, Rng};
use genform_evolve::fixtures::{ShipToy, ship};
use genform_evolve::operators::{LengthBounds, MutationMix, crossover, initial, mutate};
use genform_evolve::{Ga, GaConfig};
use std::hint::black_box;

fn operators(c: &mut Criterion) {
    let graph = ship();
    let limits = Limits::default();
    let parents: Vec<_> = (0..16).map(|i| initial(&graph, &limits, [100, 100], &mut Rng::stream(1, &[i]))).collect();
    let bounds = LengthBounds { min: 4, max: 200 };
    let mut group = c.benchmark_group("reproduction_100_genes");

    group.throughput(Throughput::Elements(2));
    let mut i = 0u64;
    group.bench_function("crossover", |b| {
        b.iter(|| {
            i += 1;
            let (p1, p2) = (&parents[i as usize % 16], &parents[(i as usize * 7 + 3) % 16]);
            black_box(crossover([p1, p2], &graph, &limits, &bounds, 3, &mut Rng::stream(2, &[i])))
        })
    });

    group.throughput(Throughput::Elements(1));
    let mix = MutationMix::default();
    group.bench_function("clone_and_mutate", |b| {
        b.iter(|| {
            i += 1;
            let mut g = parents[i as usize % 16].clone();
            black_box(mutate(&mut g, &graph, &limits, &mix, &mut Rng::stream(3, &[i])));
            g
        })
    });

    // A whole generation: selection, reproduction of 120 children, a trivial
    // evaluation, sorting and statistics.
    let config = GaConfig { initial_length: [100, 100], min_length: 4, max_length: 200, ..GaConfig::default() };
    let objective = ShipToy { target: 100 };
    let mut ga = Ga::new(&graph, &limits, config, 4).unwrap();
    ga.initialize(&objective);
    group.throughput(Throughput::Elements(120));
    group.bench_function("ga_generation_150", |b| b.iter(|| black_box(ga.step(&objective).max)));
    group.finish();
}

criterion_group!(benches, operators);
criterion_main!(benches);
