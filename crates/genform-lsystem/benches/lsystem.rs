//! L-system throughput on one core: modules written per second by
//! deterministic rewriting (ABOP Fig. 1.24e, n = 9), parametric rewriting
//! (row of trees, n = 12), context-sensitive rewriting (Hogeweg, n = 30),
//! turtle interpretation into a Scene, expressing a genome of the evolvable
//! tree, and printing a derived string (`--string-out`): a `.ls` one with
//! genform's numbers and an L-Py file's with Python's (`6.0`, `1e-05`).
//! Throughput counts every module written by every step, or the bytes
//! printed.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use genform_core::{Generator, Rng, Scene, SourceFile};
use genform_lsystem::{LSystem, LsGenerator};
use std::hint::black_box;
use std::sync::Arc;

fn load(name: &str) -> LSystem {
    let path = format!("{}/../../examples/lsystem/{name}.ls", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("example");
    genform_lsystem::compile(&SourceFile::new(format!("{name}.ls"), text)).map(|(s, _)| s).expect("compiles")
}

/// Modules written over `steps` steps.
fn written(s: &LSystem, steps: u32) -> u64 {
    let mut total = 0u64;
    s.derive_limited(steps, &mut Rng::from_seed(0), usize::MAX, |_, m| total += m.len() as u64).unwrap();
    total
}

fn rewriting(c: &mut Criterion) {
    let mut g = c.benchmark_group("rewrite");
    for (name, steps, label) in [
        ("abop_1_24e", 9, "deterministic_fig1_24e_n9"),
        ("abop_1_24e", 12, "deterministic_fig1_24e_n12"),
        ("row_of_trees", 12, "parametric_row_of_trees_n12"),
        ("hogeweg", 30, "context_hogeweg_n30"),
    ] {
        let s = load(name);
        g.throughput(Throughput::Elements(written(&s, steps)));
        g.bench_function(label, |b| {
            b.iter(|| black_box(s.derive_limited(steps, &mut Rng::from_seed(0), usize::MAX, |_, _| {}).unwrap()))
        });
    }
    g.finish();
}

fn turtle(c: &mut Criterion) {
    let mut g = c.benchmark_group("turtle");
    for (name, steps) in [("abop_1_24e", 9), ("bush_3d", 7)] {
        let s = load(name);
        let m = s.derive_limited(steps, &mut Rng::from_seed(0), usize::MAX, |_, _| {}).unwrap();
        g.throughput(Throughput::Elements(m.len() as u64));
        let mut scene = Scene::new();
        g.bench_function(format!("{name}_n{steps}"), |b| {
            b.iter(|| {
                scene.clear();
                black_box(s.interpret(&m, &mut Rng::from_seed(0), usize::MAX, &mut scene).unwrap())
            })
        });
    }
    g.finish();
}

fn express(c: &mut Criterion) {
    let generator = LsGenerator::new(Arc::new(load("evolvable_tree"))).unwrap();
    let limits = generator.limits();
    let genomes: Vec<_> = (0..64).map(|k| generator.sample(&mut Rng::from_seed(k), &limits).unwrap().genome).collect();
    let genes: usize = genomes.iter().map(|g| g.len()).sum();
    let mut g = c.benchmark_group("generator");
    g.throughput(Throughput::Elements(genes as u64));
    let mut scene = Scene::new();
    g.bench_function("evolvable_tree_express_64_genomes", |b| {
        b.iter(|| {
            for genome in &genomes {
                scene.clear();
                generator.express(genome, &limits, &mut scene).unwrap();
            }
            black_box(scene.instances.len())
        })
    });
    g.finish();
}

fn strings(c: &mut Criterion) {
    let mut g = c.benchmark_group("string");
    let lpy = {
        let path = format!("{}/tests/lpy/02b-subdivision-circle.lpy", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(&path).expect("L-Py file");
        genform_lsystem::compile_lpy(&SourceFile::new("02b-subdivision-circle.lpy", text)).expect("reads").0
    };
    for (name, s, steps) in [("row_of_trees_n12_ls", load("row_of_trees"), 12), ("subdivision_circle_lpy_n10", lpy, 10)]
    {
        let m = s.derive_limited(steps, &mut Rng::from_seed(0), usize::MAX, |_, _| {}).unwrap();
        g.throughput(Throughput::Bytes(m.display(&s.alphabet, true).len() as u64));
        g.bench_function(name, |b| {
            b.iter(|| {
                let mut bytes = 0;
                m.display_pieces(&s.alphabet, true, |piece| {
                    bytes += piece.len();
                    Ok::<(), ()>(())
                })
                .unwrap();
                black_box(bytes)
            })
        });
    }
    g.finish();
}

criterion_group!(benches, rewriting, turtle, express, strings);
criterion_main!(benches);
