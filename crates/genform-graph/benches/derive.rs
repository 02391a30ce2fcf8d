//! Graph-grammar derivations on one core, at the paper's step counts, with
//! the peer implementation's median times (shared/reference/graph-grammar.md)
//! for comparison: Koch 192 steps (7.62 s), tree 200 steps (4.15 s), façade
//! (8.92 s), square tiling (10.5–12 s), circular pattern (0.06 s). Koch at
//! 2,000 and 20,000 steps shows that a step's cost does not grow with the
//! graph (throughput = steps per second).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use genform_core::{Rng, SourceFile};
use genform_graph::GraphGrammar;
use std::hint::black_box;

fn load(name: &str) -> GraphGrammar {
    let path = format!("{}/../../examples/graph/{name}.gg.yaml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("example");
    genform_graph::compile(&SourceFile::new(path, text)).map(|(g, _)| g).expect("compiles")
}

fn examples(c: &mut Criterion) {
    let mut g = c.benchmark_group("derive");
    for (name, steps) in [
        ("koch", Some(192)),
        ("tree", Some(200)),
        ("facade", None),
        ("square_pattern", None),
        ("circle_pattern", None),
        ("koch", Some(2_000)),
        ("koch", Some(20_000)),
    ] {
        let grammar = load(name);
        let done = grammar.derive(&mut Rng::from_seed(1), steps, 1_000_000).unwrap().steps;
        g.throughput(Throughput::Elements(done as u64));
        let label = format!("{name}_{done}_steps");
        g.bench_function(label, |b| {
            b.iter(|| black_box(grammar.derive(&mut Rng::from_seed(1), steps, 1_000_000).unwrap()))
        });
    }
    // The same derivations starting from the graph the last one returned
    // (`derive_reusing`): what a loop deriving again and again pays,
    // without the allocation and page faults of a fresh graph each time.
    for steps in [2_000, 20_000] {
        let grammar = load("koch");
        g.throughput(Throughput::Elements(steps as u64));
        let mut previous = None;
        g.bench_function(format!("koch_{steps}_steps_reusing"), |b| {
            b.iter(|| {
                let d = grammar.derive_reusing(&mut Rng::from_seed(1), Some(steps), 1_000_000, previous.take());
                let d = black_box(d.unwrap());
                previous = Some(d.graph);
            })
        });
    }
    g.finish();
}

fn compile_and_draw(c: &mut Criterion) {
    let path = format!("{}/../../examples/graph/facade.gg.yaml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("example");
    let file = SourceFile::new("facade.gg.yaml", text);
    c.bench_function("compile_facade", |b| b.iter(|| black_box(genform_graph::compile(&file).unwrap())));
    let koch = load("koch").derive(&mut Rng::from_seed(1), Some(192), 1_000_000).unwrap().graph;
    c.bench_function("koch_192_to_scene", |b| b.iter(|| black_box(koch.to_scene())));
    c.bench_function("koch_192_to_yaml", |b| b.iter(|| black_box(koch.to_yaml())));
    // A drawing far larger than the caches (1.2 M elements, 600 k drawn).
    let big = load("koch").derive(&mut Rng::from_seed(1), Some(200_000), 2_000_000).unwrap().graph;
    let mut g = c.benchmark_group("draw_large");
    g.sample_size(10);
    g.bench_function("koch_200000_to_scene", |b| b.iter(|| black_box(big.to_scene())));
    g.finish();
}

criterion_group!(benches, examples, compile_and_draw);
criterion_main!(benches);
