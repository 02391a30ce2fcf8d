use super::*;
use crate::config::SelectionPair;
use crate::fixtures::{ShipToy, ship};
use crate::objective::FnObjective;
use crate::random::RandomSearch;
use crate::selection::Selection;
use crate::{RandomConfig, operators::MutationMix};
use genform_core::Genome;
use std::sync::atomic::{AtomicU64, Ordering};

const LIMITS: Limits = Limits { max_genes: 10_000, max_depth: 50, max_primitives: 1000 };

fn small() -> GaConfig {
    GaConfig {
        population: 30,
        elitism: Some(6),
        initial_length: [10, 30],
        min_length: 4,
        max_length: 60,
        ..GaConfig::default()
    }
}

fn ga(config: GaConfig, seed: u64) -> Ga {
    Ga::new(&ship(), &LIMITS, config, seed).unwrap()
}

/// Population fingerprint: genomes and fitness bit patterns.
fn snapshot(ga: &Ga) -> Vec<(Genome, u64)> {
    ga.population().iter().map(|i| (i.genome.clone(), i.fitness.to_bits())).collect()
}

fn fitness_columns(s: &GenerationStats) -> [u64; 6] {
    [s.max.to_bits(), s.avg.to_bits(), s.min.to_bits(), s.len_avg.to_bits(), s.evaluations, s.invalid as u64]
}

#[test]
fn best_fitness_never_drops_with_elitism() {
    let objective = ShipToy { target: 17 };
    let mut ga = ga(GaConfig { elitism: Some(1), ..small() }, 3);
    let mut last = f64::NEG_INFINITY;
    for g in 0..25 {
        let stats = ga.step(&objective);
        assert_eq!(stats.generation, g);
        assert!(stats.max >= last, "generation {g}: {} < {last}", stats.max);
        assert_eq!(ga.best().unwrap().fitness, stats.max);
        last = stats.max;
    }
    assert!(last > ga.population()[29].fitness, "the search makes progress and keeps diversity");
}

#[test]
fn same_seed_same_result_at_any_thread_count() {
    let objective = ShipToy { target: 17 };
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut ga = ga(small(), 11);
            let stats: Vec<_> = (0..6).map(|_| fitness_columns(&ga.step(&objective))).collect();
            (snapshot(&ga), stats)
        })
    };
    let (pop1, stats1) = run(1);
    let (pop3, stats3) = run(3);
    assert_eq!(stats1, stats3);
    assert!(pop1 == pop3, "populations differ between 1 and 3 threads");
    let mut other = ga(small(), 12);
    for _ in 0..6 {
        other.step(&objective);
    }
    assert!(snapshot(&other) != pop1, "another seed gives another population");
}

#[test]
fn elites_are_not_re_evaluated() {
    let calls = AtomicU64::new(0);
    let objective = FnObjective(|g: &Genome| {
        calls.fetch_add(1, Ordering::Relaxed);
        g.len() as f64
    });
    let mut ga = ga(small(), 5);
    let first = ga.step(&objective);
    assert_eq!(first.evaluations, 30);
    for _ in 0..5 {
        let s = ga.step(&objective);
        // Elites and unchanged parent copies keep their cached fitness.
        assert_eq!(s.evaluations + s.reproduction.copies, 24);
        assert_eq!(s.total_evaluations, ga.evaluations());
    }
    assert_eq!(calls.load(Ordering::Relaxed), ga.evaluations());
}

#[test]
fn children_stay_within_the_length_bounds() {
    let config = GaConfig { min_length: 8, max_length: 25, initial_length: [8, 20], ..small() };
    let mut ga = ga(config, 9);
    let objective = FnObjective(|g: &Genome| g.len() as f64); // pushes towards the upper bound
    let mut stats = Vec::new();
    for _ in 0..10 {
        stats.push(ga.step(&objective));
        assert!(ga.population().iter().all(|i| (8..25).contains(&i.genome.len())));
        ga.population().iter().for_each(|i| i.genome.validate(&ship()).unwrap());
    }
    let last = stats.last().unwrap();
    assert_eq!(last.len_max, 24);
    assert!(stats.iter().map(|s| s.reproduction.crossovers).sum::<u64>() > 0);
    assert!(stats.iter().map(|s| s.reproduction.mutations.grow + s.reproduction.mutations.cut).sum::<u64>() > 0);
}

#[test]
fn invalid_individuals_sort_last_and_stay_out_of_statistics() {
    // Odd lengths cannot be "expressed".
    let objective = FnObjective(|g: &Genome| if g.len() % 2 == 1 { f64::NAN } else { -(g.len() as f64) });
    let mut ga = ga(small(), 2);
    for _ in 0..5 {
        let s = ga.step(&objective);
        let pop = ga.population();
        let valid = pop.iter().filter(|i| i.is_valid()).count();
        assert_eq!(s.invalid, pop.len() - valid);
        assert!(pop[..valid].iter().all(|i| i.is_valid()) && pop[valid..].iter().all(|i| !i.is_valid()));
        assert!(s.max.is_finite() && s.min.is_finite() && s.avg.is_finite());
        assert!(ga.best().unwrap().is_valid());
    }
    let all_invalid = FnObjective(|_: &Genome| f64::NEG_INFINITY);
    let mut ga2 = super::Ga::new(&ship(), &LIMITS, small(), 1).unwrap();
    for _ in 0..3 {
        let s = ga2.step(&all_invalid);
        assert_eq!(s.invalid, 30);
        assert!(s.max.is_nan());
    }
    assert!(ga2.best().is_none());
}

#[test]
fn ga_beats_random_search_at_equal_evaluations() {
    let objective = ShipToy { target: 25 };
    let config = GaConfig { population: 40, elitism: Some(8), initial_length: [15, 35], ..GaConfig::default() };
    let (mut ga_wins, runs) = (0, 4);
    for seed in 0..runs {
        let mut ga = Ga::new(&ship(), &LIMITS, config.clone(), seed).unwrap();
        while ga.evaluations() < 1000 {
            ga.step(&objective);
        }
        let mut rs = RandomSearch::new(&ship(), &LIMITS, RandomConfig::like(&config), seed).unwrap();
        while rs.evaluations() < ga.evaluations() {
            rs.step(&objective);
        }
        let (g, r) = (ga.best().unwrap().fitness, crate::Optimizer::best(&rs).unwrap().fitness);
        if g > r {
            ga_wins += 1;
        }
    }
    assert_eq!(ga_wins, runs, "the GA must beat random search in every run");
}

#[test]
fn selection_and_mix_settings_are_used() {
    // Pure alter never changes lengths or structure.
    let config = GaConfig {
        mutation_rate: 1.0,
        mutation: MutationMix { alter: 1.0, grow: 0.0, cut: 0.0, drift: 0.0, regrow: 0.0, ..MutationMix::default() },
        selection: SelectionPair { first: Selection::Random, second: Selection::Random },
        ..small()
    };
    let mut ga = ga(config, 4);
    let objective = ShipToy { target: 17 };
    let lens = |ga: &Ga| {
        let mut v: Vec<usize> = ga.population().iter().map(|i| i.genome.len()).collect();
        v.sort();
        v
    };
    ga.step(&objective);
    let initial = lens(&ga);
    let s = ga.step(&objective);
    assert_eq!(s.reproduction.mutations.alter, 24);
    assert_eq!(s.reproduction.crossovers, 0);
    assert!(lens(&ga).iter().all(|n| initial.contains(n)));
}

fn thesis_small() -> GaConfig {
    small().with_preset(crate::GaPreset::Thesis)
}

#[test]
fn default_and_thesis_presets_are_deterministic_at_any_thread_count() {
    let objective = ShipToy { target: 17 };
    let configs = [
        small(),
        GaConfig { tune_after: 0, mutation_rate: 0.5, ..small() },
        thesis_small(),
        GaConfig { initialization: crate::Initialization::Reference, ..small() },
    ];
    for config in configs {
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let mut ga = ga(config.clone(), 21);
                let stats: Vec<_> = (0..8)
                    .map(|_| {
                        let s = ga.step(&objective);
                        (fitness_columns(&s), s.reproduction, s.distinct)
                    })
                    .collect();
                (snapshot(&ga), stats)
            })
        };
        let (pop1, stats1) = run(1);
        let (pop3, stats3) = run(3);
        assert_eq!(stats1, stats3, "{config:?}");
        assert!(pop1 == pop3, "populations differ between 1 and 3 threads: {config:?}");
    }
}

#[test]
fn the_thesis_preset_makes_no_drift_and_keeps_duplicates() {
    let objective = ShipToy { target: 17 };
    let mut ga = ga(GaConfig { mutation_rate: 1.0, ..thesis_small() }, 8);
    assert_eq!((ga.config().mutation.drift, ga.config().avoid_duplicates), (0.0, false));
    let stats: Vec<_> = (0..15).map(|_| ga.step(&objective)).collect();
    assert_eq!(stats.iter().map(|s| s.reproduction.mutations.drift).sum::<u64>(), 0);
    assert_eq!(stats.iter().map(|s| s.reproduction.duplicates_replaced).sum::<u64>(), 0);
}

#[test]
fn duplicates_are_replaced_and_the_population_stays_more_diverse() {
    // Pure crossover converges fast and then repeats its parents.
    let objective = ShipToy { target: 17 };
    let base = GaConfig { mutation_rate: 0.0, tune_after: 0, ..small() };
    let run = |config: GaConfig| {
        let mut ga = ga(config, 6);
        let stats: Vec<_> = (0..30).map(|_| ga.step(&objective)).collect();
        let distinct: usize = stats[10..].iter().map(|s| s.distinct.unwrap()).sum();
        let found: u64 = stats.iter().map(|s| s.reproduction.duplicates).sum();
        let replaced: u64 = stats.iter().map(|s| s.reproduction.duplicates_replaced).sum();
        (distinct, found, replaced)
    };
    let (with, found, replaced) = run(base.clone());
    let (without, found_off, replaced_off) = run(GaConfig { avoid_duplicates: false, ..base });
    assert!(found > 0 && replaced > 0 && replaced <= found, "{found} {replaced}");
    assert!(found_off > 0 && replaced_off == 0);
    assert!(with > without, "distinct genomes: {with} with duplicate avoidance, {without} without");
}

#[test]
fn operator_tallies_cover_every_evaluated_child() {
    let objective = ShipToy { target: 17 };
    let mut ga = ga(GaConfig { mutation_rate: 0.5, tune_after: 0, ..small() }, 13);
    ga.step(&objective);
    let mut improved = 0;
    for _ in 0..20 {
        let s = ga.step(&objective);
        let o = s.reproduction.operators;
        let tallies = [o.crossover, o.alter, o.grow, o.cut, o.drift];
        assert_eq!(tallies.iter().map(|t| t.children).sum::<u64>(), s.evaluations);
        assert_eq!(s.evaluations + s.reproduction.copies, 24);
        assert!(tallies.iter().all(|t| t.improved <= t.children));
        improved += tallies.iter().map(|t| t.improved).sum::<u64>();
        assert!(o.drift.children > 0, "the default GA drifts");
    }
    assert!(improved > 0);
}

#[test]
fn reference_initialization_builds_root_plus_grows_without_closure() {
    let objective = ShipToy { target: 17 };
    let config = GaConfig { initialization: crate::Initialization::Reference, initial_length: [12, 12], ..small() };
    let mut ga = ga(config, 3);
    ga.step(&objective);
    assert!(ga.population().iter().all(|i| i.genome.len() == 12));
    // Without the closure some Wing lacks its mandatory Tip in some genome.
    let graph = ship();
    let open_tip = ga.population().iter().any(|i| {
        i.genome
            .iter()
            .any(|g| graph.symbol(g.symbol()).name == "Wing" && g.link(0) == genform_core::genome::Link::Empty)
    });
    assert!(open_tip);
}

#[test]
fn drift_starts_after_tune_after_generations_without_a_new_best() {
    // A flat objective never improves: generations 1–3 stagnate, and drift
    // starts with generation 4.
    let flat = FnObjective(|_: &Genome| 1.0);
    let mut late = ga(GaConfig { mutation_rate: 1.0, tune_after: 3, ..small() }, 17);
    let drifts: Vec<u64> = (0..8).map(|_| late.step(&flat).reproduction.mutations.drift).collect();
    assert_eq!(drifts[..4], [0, 0, 0, 0], "{drifts:?}");
    assert!(drifts[4..].iter().all(|&d| d > 0), "{drifts:?}");
    // tune_after = 0 drifts from the first generation.
    let mut eager = ga(GaConfig { mutation_rate: 1.0, tune_after: 0, ..small() }, 17);
    eager.step(&flat);
    assert!(eager.step(&flat).reproduction.mutations.drift > 0);
}

#[test]
fn a_stalled_ga_restarts_from_fresh_individuals_and_keeps_the_best_seen() {
    // A flat objective never improves, so every epoch stalls after
    // `restart_after` generations: generations 4, 8, … are restarts.
    let flat = FnObjective(|g: &Genome| -((g.len() as f64 - 17.0).abs()));
    let config = GaConfig { restart_after: 3, tune_after: 2, ..small() };
    let mut stalling = ga(config, 19);
    stalling.step(&flat);
    let mut best = f64::NEG_INFINITY;
    let mut restarts = Vec::new();
    for _ in 0..40 {
        let before = stalling.restarts();
        let s = stalling.step(&flat);
        if stalling.restarts() > before {
            restarts.push(s.generation);
            // Every member but the kept ones (none) is new and evaluated.
            assert_eq!(s.evaluations, 30);
            assert_eq!(s.reproduction, Default::default());
        }
        let b = stalling.best().unwrap().fitness;
        assert!(b >= best, "the best seen never drops");
        best = b;
        assert!(stalling.population()[0].fitness <= b);
    }
    assert!(restarts.len() >= 2, "restarts at {restarts:?}");
    assert_eq!(stalling.champions().len(), restarts.len(), "one champion per finished epoch");
    let top = stalling.champions().iter().map(|c| c.fitness).fold(f64::NEG_INFINITY, f64::max);
    assert!(top <= best && stalling.champions().iter().all(|c| c.is_valid()));
    assert!(restarts.windows(2).all(|w| w[1] - w[0] > 3), "{restarts:?}");
    // The restarted population is not the old one: it starts from the prior.
    let mut fresh = ga(GaConfig { restart_after: 1, restart_keep: 2, ..small() }, 5);
    let objective = FnObjective(|_: &Genome| 1.0);
    fresh.step(&objective);
    fresh.step(&objective);
    let old = snapshot(&fresh);
    let s = fresh.step(&objective);
    assert_eq!(fresh.restarts(), 1);
    assert_eq!(s.evaluations, 28, "restart_keep members keep their fitness");
    assert_eq!(snapshot(&fresh)[..2], old[..2]);
    assert!(snapshot(&fresh)[2..].iter().all(|m| !old.contains(m)));
}

#[test]
fn restarts_are_deterministic_at_any_thread_count_and_off_in_the_thesis_preset() {
    let objective = ShipToy { target: 17 };
    let config = GaConfig { restart_after: 4, restart_tolerance: 0.01, tune_after: 2, ..small() };
    let run = |config: GaConfig, threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut ga = ga(config, 23);
            let stats: Vec<_> = (0..40).map(|_| fitness_columns(&ga.step(&objective))).collect();
            (snapshot(&ga), stats, ga.restarts(), ga.best().unwrap().fitness.to_bits())
        })
    };
    let one = run(config.clone(), 1);
    assert!(one.2 > 0, "the toy stalls within 40 generations");
    let four = run(config.clone(), 4);
    assert!(one == four, "results differ between 1 and 4 threads");
    let thesis = run(config.with_preset(crate::GaPreset::Thesis), 1);
    assert_eq!(thesis.2, 0, "the thesis GA never restarts");
}
