//! End-to-end evaluation throughput of `genform evolve` (derive + voxelize
//! or rasterize + score) on each example scene the issue sets a goal for:
//! `spaceship_volume`, `city_volume`, `tree_avoid`, `tree_volume` and
//! `tree_sketch`. Each scene is evaluated on a GA generation-0 population
//! (its own population size and initial genome lengths) with 1 and 2
//! threads; throughput is in evaluations. Derivation alone is measured too,
//! so that the scoring share can be read off. The spaceship also runs a
//! full GA run (population 150, 130 generations). Everything goes through
//! the library's scene handle ([`genform_app::OpenScene`]), as `evolve`
//! does. (The per-voxel reference voxelizer is genform-score's `voxelize`
//! bench.)

use criterion::{
    BenchmarkGroup, Criterion, SamplingMode, Throughput, criterion_group, criterion_main, measurement::WallTime,
};
use genform_app::OpenScene;
use genform_core::{Genome, Scene};
use genform_evolve::{Ga, Objective};
use rayon::prelude::*;
use std::path::Path;
use std::sync::atomic::AtomicBool;

/// The scenes with an evaluation-speed goal (issue #18).
const SCENES: [&str; 5] = ["spaceship_volume", "city_volume", "tree_avoid", "tree_volume", "tree_sketch"];

struct Setup {
    open: OpenScene,
    population: Vec<Genome>,
}

impl Setup {
    fn generator(&self) -> &dyn genform_core::Generator {
        self.open.tree().unwrap().0.generator.as_ref()
    }

    fn limits(&self) -> genform_core::Limits {
        self.open.tree().unwrap().1
    }
}

fn setup(scene: &str) -> Setup {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../examples/scenes/{scene}.toml"));
    let open = OpenScene::open(genform_app::Scene::load(&path, &[]).unwrap(), Default::default()).unwrap();
    let (loaded, limits) = open.tree().unwrap();
    let ga = &open.scene.optimizers.ga;
    // A GA's generation-0 population: lengths as the experiment uses them.
    let graph = loaded.generator.graph();
    let population = (0..ga.population as u64)
        .map(|i| {
            let mut rng = genform_core::Rng::stream(1, &[i]);
            genform_evolve::operators::initial(graph, &limits, ga.initial_length, &mut rng)
        })
        .collect();
    Setup { open, population }
}

/// Evaluates the whole population on 1 and 2 threads, and derives it alone.
fn evaluate(g: &mut BenchmarkGroup<WallTime>, s: &Setup) {
    let objective = s.open.objective().unwrap();
    g.throughput(Throughput::Elements(s.population.len() as u64));
    // Flat sampling with few samples keeps the slow scenes (seconds per
    // population) to a bounded run time.
    g.sampling_mode(SamplingMode::Flat).sample_size(10);
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        g.bench_function(format!("evaluate/fast/{threads}-thread"), |b| {
            b.iter(|| {
                // Unrelated generation-0 genomes: nothing from the previous
                // iteration may be replayed.
                s.open.scorer().clear_caches();
                pool.install(|| {
                    s.population
                        .par_iter()
                        .map_init(|| objective.scratch(), |scratch, genome| objective.evaluate(genome, scratch))
                        .sum::<f64>()
                })
            })
        });
    }
    g.bench_function("derive/1-thread", |b| {
        let mut scene = Scene::new();
        b.iter(|| {
            let mut n = 0;
            for genome in &s.population {
                scene.clear();
                if s.generator().express(genome, &s.limits(), &mut scene).is_ok() {
                    n += scene.instances.len();
                }
            }
            n
        })
    });
}

/// Evaluations per second of a whole GA run (`[ga]` of the scene, seed 1,
/// `generations` generations, 2 threads, caches emptied first): what a
/// user's `evolve` gets, where children share most of their models with
/// their parents.
fn ga_run(g: &mut BenchmarkGroup<WallTime>, s: &Setup, generations: usize) {
    let objective = s.open.objective().unwrap();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let run = || {
        s.open.scorer().clear_caches();
        pool.install(|| {
            let mut ga = Ga::new(s.generator().graph(), &s.limits(), s.open.scene.optimizers.ga.clone(), 1).unwrap();
            let cancel = AtomicBool::new(false);
            let stop = genform_evolve::Stop {
                generations: Some(generations),
                budget: None,
                evaluations: None,
                cancel: &cancel,
            };
            genform_evolve::run(&mut ga, &objective, &stop, |_, _| {}).unwrap();
            ga.evaluations()
        })
    };
    g.throughput(Throughput::Elements(run()));
    g.sampling_mode(SamplingMode::Flat).sample_size(10);
    g.bench_function(format!("ga_run/{generations}-generations/2-thread"), |b| b.iter(run));
}

fn bench(c: &mut Criterion) {
    for name in SCENES {
        let s = setup(name);
        let mut g = c.benchmark_group(name);
        evaluate(&mut g, &s);
        if name.starts_with("tree_") {
            ga_run(&mut g, &s, 30);
        }
        if name != "spaceship_volume" {
            g.finish();
            continue;
        }
        g.finish();

        let objective = s.open.objective().unwrap();
        let mut g = c.benchmark_group("spaceship_volume_ga");
        g.sample_size(10);
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        g.bench_function("full_run/150x130/2-thread", |b| {
            b.iter(|| {
                pool.install(|| {
                    let mut ga =
                        Ga::new(s.generator().graph(), &s.limits(), s.open.scene.optimizers.ga.clone(), 7).unwrap();
                    let cancel = AtomicBool::new(false);
                    let stop = genform_evolve::Stop {
                        generations: Some(130),
                        budget: None,
                        evaluations: None,
                        cancel: &cancel,
                    };
                    genform_evolve::run(&mut ga, &objective, &stop, |_, _| {}).unwrap();
                    ga.best().unwrap().fitness
                })
            })
        });
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
