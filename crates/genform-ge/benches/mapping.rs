//! Mapping throughput on one core, in codons read per second: standard GE
//! over `arith.bnf` (the golden-trace grammar) and `lsys.bnf` with random
//! genomes, and Genr8's EA grammar with every extension and repair on.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use genform_core::{Rng, SourceFile};
use genform_ge::{Bnf, MapOptions, Mapper};
use std::hint::black_box;

fn load(name: &str) -> Bnf {
    let path = format!("{}/../../examples/ge/{name}.bnf", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("example grammar");
    genform_ge::compile(&SourceFile::new(format!("{name}.bnf"), text)).map(|(b, _)| b).expect("compiles")
}

/// `count` genomes with lengths in `lo..=hi` and codons below `codon_max`.
fn genomes(seed: u64, count: usize, lo: u64, hi: u64, codon_max: u64) -> Vec<Vec<u32>> {
    let mut rng = Rng::from_seed(seed);
    (0..count)
        .map(|_| {
            let len = lo + rng.below(hi - lo + 1);
            (0..len).map(|_| rng.below(codon_max) as u32).collect()
        })
        .collect()
}

fn bench(c: &mut Criterion, label: &str, bnf: &Bnf, options: MapOptions, pop: &[Vec<u32>]) {
    let mut mapper = Mapper::new(bnf, options).expect("options");
    let codons: usize = pop.iter().map(|g| mapper.map(g).used_codons).sum();
    let valid = pop.iter().filter(|g| mapper.map(g).valid()).count();
    eprintln!("{label}: {} genomes, {codons} codons read, {valid} valid", pop.len());
    let mut group = c.benchmark_group("map");
    group.throughput(Throughput::Elements(codons as u64));
    group.bench_function(label, |b| {
        b.iter(|| {
            let mut total = 0usize;
            for g in pop {
                let out = mapper.map(black_box(g));
                total += out.used_codons + mapper.phenotype().map_or(0, str::len);
            }
            black_box(total)
        })
    });
    group.finish();
}

fn mapping(c: &mut Criterion) {
    let arith = load("arith");
    // Long genomes with wrapping, so deep derivations dominate rather than
    // the per-genome reset.
    bench(c, "arith_wraps4", &arith, MapOptions::standard(4, None), &genomes(1, 1000, 50, 200, 256));
    bench(c, "arith_traces_settings", &arith, MapOptions::standard(0, None), &genomes(2, 1000, 8, 40, 256));
    bench(c, "lsys_wraps2", &load("lsys"), MapOptions::standard(2, None), &genomes(3, 1000, 4, 30, 256));
    bench(c, "genr8_repair", &load("genr8"), MapOptions::genr8(), &genomes(4, 1000, 50, 200, 1000));
}

criterion_group!(benches, mapping);
criterion_main!(benches);
