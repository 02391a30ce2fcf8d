//! End-to-end evaluation throughput of `genform evolve` on the
//! `spaceship_volume` scene (100×200×100 grid): derive + voxelize + score,
//! with the fast voxelizer on 1 and 2 threads, against the per-voxel
//! reference voxelizer in the same run, and the wall time of a full GA run
//! (population 150, 130 generations).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use genform_cli::objective::{SceneObjective, Scorers};
use genform_cli::scene_config::SceneConfig;
use genform_cli::{grammar, targets};
use genform_core::{Genome, Scene};
use genform_evolve::{Ga, Objective};
use rayon::prelude::*;
use std::path::Path;
use std::sync::atomic::AtomicBool;

struct Setup {
    generator: Box<dyn genform_core::Generator>,
    limits: genform_core::Limits,
    scorers: Scorers,
    config: SceneConfig,
    population: Vec<Genome>,
}

fn setup() -> Setup {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/spaceship_volume.toml");
    let config = SceneConfig::load(&path).unwrap().config;
    let loaded = grammar::load(&config.grammar).unwrap();
    let scorers = targets::build(&config).unwrap();
    // A GA's generation-0 population: lengths as the experiment uses them.
    let graph = loaded.generator.graph();
    let population = (0..config.ga.population as u64)
        .map(|i| {
            let mut rng = genform_core::Rng::stream(1, &[i]);
            genform_evolve::operators::initial(graph, &loaded.limits, config.ga.initial_length, &mut rng)
        })
        .collect();
    Setup { limits: loaded.limits, generator: loaded.generator, scorers, config, population }
}

fn bench(c: &mut Criterion) {
    let s = setup();
    let objective = SceneObjective { generator: s.generator.as_ref(), limits: s.limits, scorers: &s.scorers };
    let n = s.population.len() as u64;
    let mut g = c.benchmark_group("spaceship_volume");
    g.throughput(Throughput::Elements(n));
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        g.bench_function(format!("evaluate/fast/{threads}-thread"), |b| {
            b.iter(|| {
                pool.install(|| {
                    s.population
                        .par_iter()
                        .map_init(|| objective.scratch(), |scratch, genome| objective.evaluate(genome, scratch))
                        .sum::<f64>()
                })
            })
        });
    }
    // The same derivations scored through the per-voxel reference voxelizer.
    let volume = s.scorers.volume.as_ref().unwrap();
    g.sample_size(10);
    g.bench_function("evaluate/oracle/1-thread", |b| {
        let mut scene = Scene::new();
        b.iter(|| {
            let mut total = 0.0;
            for genome in &s.population {
                scene.clear();
                s.generator.express(genome, &s.limits, &mut scene).unwrap();
                let v = genform_score::voxelize::oracle::voxelize(volume.grid(), &scene);
                total += s.scorers.fitness.eval(&volume.counts_of(&v), genome.len());
            }
            total
        })
    });
    g.finish();

    let mut g = c.benchmark_group("spaceship_volume_ga");
    g.sample_size(10);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    g.bench_function("full_run/150x130/2-thread", |b| {
        b.iter(|| {
            pool.install(|| {
                let mut ga = Ga::new(s.generator.graph(), &s.limits, s.config.ga.clone(), 7).unwrap();
                let cancel = AtomicBool::new(false);
                let stop =
                    genform_evolve::Stop { generations: Some(130), budget: None, evaluations: None, cancel: &cancel };
                genform_evolve::run(&mut ga, &objective, &stop, |_, _| {}).unwrap();
                ga.best().unwrap().fitness
            })
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
