use super::*;
use crate::fixtures::{HalfInvalidToy, PrefixToy, SevensToy, TargetToy};
use crate::objective::{FnObjective, Objective, SensiblePlan};
use crate::optimizer::{Individual, Optimizer};
use crate::run::{Stop, StopReason, run};
use crate::stats::GenerationStats;
use genform_core::Rng;
use std::collections::HashSet;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

/// Best fitness of `algorithm` after `evaluations` objective calls (the run
/// may pass the count by less than one generation; random search's
/// generations are the larger, so the comparison never favours GE).
fn best_after<O: Objective<Codons>>(
    algorithm: CodonAlgorithm,
    objective: &O,
    config: &GeConfig,
    seed: u64,
    evaluations: u64,
) -> f64 {
    let cancel = AtomicBool::new(false);
    let stop = Stop { generations: None, budget: None, evaluations: Some(evaluations), cancel: &cancel };
    let mut opt = AnyCodonOptimizer::new(algorithm, config, seed).unwrap();
    let summary = run(&mut opt, objective, &stop, |_, _| {}).unwrap();
    assert_eq!(summary.reason, StopReason::Evaluations);
    opt.best().map_or(f64::NEG_INFINITY, |b| b.fitness)
}

/// Per seed (GE best, random best) at 2500 evaluations (50 generations of 50).
fn compare<O: Objective<Codons>>(objective: &O) -> Vec<(f64, f64)> {
    let config = GeConfig::default();
    (1..=5)
        .map(|seed| {
            (
                best_after(CodonAlgorithm::Ge, objective, &config, seed, 2500),
                best_after(CodonAlgorithm::Random, objective, &config, seed, 2500),
            )
        })
        .collect()
}

#[test]
fn ge_beats_random_search_on_sevens() {
    let results = compare(&SevensToy);
    for &(ge, random) in &results {
        // Measured: GE 17–19, random 8–11.
        assert!(ge >= random + 5.0, "{results:?}");
        assert!(ge >= 15.0, "{results:?}");
    }
}

#[test]
fn ge_beats_random_search_on_a_target_sequence() {
    let target = TargetToy { target: vec![212, 187, 632, 832, 800, 517, 338, 39, 954, 1] };
    let results = compare(&target);
    for &(ge, random) in &results {
        // Fitness is minus a distance: GE's is under 60 % of random search's
        // (measured: 25–46 %).
        assert!(ge > 0.6 * random, "{results:?}");
    }
}

#[test]
fn ge_beats_random_search_when_half_the_genomes_are_invalid() {
    let results = compare(&HalfInvalidToy);
    for &(ge, random) in &results {
        assert!(ge >= random + 5.0, "{results:?}");
    }
}

#[test]
fn invalid_parents_are_not_chosen() {
    // Children inherit their first codon from a parent unless mutation
    // redraws it (1 %), so if invalid parents were chosen about half the
    // children would be invalid; selection leaves only mutation's share.
    let mut ge = Ge::new(GeConfig::default(), 9).unwrap();
    let initial = ge.step(&HalfInvalidToy);
    assert!((15..=35).contains(&initial.invalid), "{}", initial.invalid);
    let later: usize = (0..10).map(|_| ge.step(&HalfInvalidToy).invalid).sum();
    assert!(later <= 10, "{later} invalid in 10 generations");
    assert!(ge.population().iter().rev().skip_while(|i| !i.is_valid()).all(Individual::is_valid), "invalid sort last");
}

#[test]
fn elitism_keeps_the_best_monotone() {
    let config = GeConfig { population: 20, elitism: 1, ..GeConfig::default() };
    let mut ge = Ge::new(config, 3).unwrap();
    let target = TargetToy { target: vec![500; 8] };
    let mut last = f64::NEG_INFINITY;
    for g in 0..30 {
        let s = ge.step(&target);
        assert_eq!(s.generation, g);
        assert!(s.max >= last, "generation {g}: {} < {last}", s.max);
        last = s.max;
        assert_eq!(ge.best().unwrap().fitness, s.max);
        assert_eq!(ge.population()[0], *ge.best().unwrap());
        assert_eq!(ge.population().len(), 20);
        assert!(ge.population().windows(2).all(|w| w[0].fitness >= w[1].fitness));
    }
}

#[test]
fn lengths_stay_within_the_cap_and_codons_within_range() {
    // Rewarding length drives genomes to the cap.
    let config =
        GeConfig { population: 30, initial_length: [5, 20], max_length: 60, codon_range: 17, ..GeConfig::default() };
    let mut ge = Ge::new(config, 2).unwrap();
    let longer = FnObjective(|c: &Codons| c.len() as f64);
    let mut s = ge.step(&longer);
    assert!((5..=20).contains(&s.len_min) && s.len_max <= 20);
    for _ in 0..40 {
        s = ge.step(&longer);
        assert!(s.len_min >= 1 && s.len_max <= 60, "{s:?}");
        assert!(ge.population().iter().all(|i| i.genome.iter().all(|&c| c < 17)));
    }
    assert_eq!((s.max, s.best_len), (60.0, 60));
}

#[test]
fn unchanged_children_reuse_their_parents_fitness() {
    let config = GeConfig { population: 10, crossover_rate: 0.0, mutation_rate: 0.0, ..GeConfig::default() };
    let mut ge = Ge::new(config, 1).unwrap();
    assert_eq!(ge.step(&SevensToy).evaluations, 10);
    let s = ge.step(&SevensToy);
    assert_eq!((s.evaluations, s.total_evaluations, s.reproduction.copies), (0, 10, 9));

    let config = GeConfig { population: 10, crossover_rate: 1.0, mutation_rate: 0.5, ..GeConfig::default() };
    let mut ge = Ge::new(config, 1).unwrap();
    ge.step(&SevensToy);
    let s = ge.step(&SevensToy);
    assert_eq!((s.evaluations, s.reproduction.crossovers, s.reproduction.mutations.alter), (9, 5, 9));
}

fn without_times(mut s: GenerationStats) -> GenerationStats {
    s.eval_time = Duration::ZERO;
    s.reproduction_time = Duration::ZERO;
    s
}

/// 16 generations of `config` with `seed` on [`PrefixToy`], on 1 and on 2
/// threads: each run's final population (genomes, fitness bits) and stats.
#[allow(clippy::type_complexity)]
fn on_one_and_two_threads(config: &GeConfig, seed: u64) -> Vec<(Vec<(Codons, u64)>, Vec<GenerationStats>)> {
    [1, 2]
        .map(|threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let mut ge = Ge::new(config.clone(), seed).unwrap();
                let stats: Vec<_> = (0..=15).map(|_| without_times(ge.step(&PrefixToy))).collect();
                (ge.population().iter().map(|i| (i.genome.clone(), i.fitness.to_bits())).collect::<Vec<_>>(), stats)
            })
        })
        .into_iter()
        .collect()
}

#[test]
fn same_seed_same_run_at_one_and_two_threads() {
    let objective = HalfInvalidToy;
    let config = GeConfig { population: 31, elitism: 2, ..GeConfig::default() };
    let runs: Vec<_> = [1, 2]
        .map(|threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let mut ge = Ge::new(config.clone(), 77).unwrap();
                let mut random = CodonRandom::new(CodonRandomConfig::like(&config), 77).unwrap();
                let mut stats = Vec::new();
                for _ in 0..=10 {
                    stats.push(without_times(ge.step(&objective)));
                    stats.push(without_times(random.step(&objective)));
                }
                (ge.population().to_vec(), random.population().to_vec(), stats)
            })
        })
        .into_iter()
        .collect();
    // NaN ≠ NaN: compare fitness by bits.
    let key = |p: &[Individual<Codons>]| p.iter().map(|i| (i.genome.clone(), i.fitness.to_bits())).collect::<Vec<_>>();
    assert_eq!(key(&runs[0].0), key(&runs[1].0));
    assert_eq!(key(&runs[0].1), key(&runs[1].1));
    assert_eq!(format!("{:?}", runs[0].2), format!("{:?}", runs[1].2));
    assert_eq!(runs[0].2.len(), 22);
    // A different seed gives a different run.
    let mut other = Ge::new(config, 78).unwrap();
    other.step(&objective);
    assert_ne!(key(other.population()), key(&runs[0].0));
}

#[test]
fn both_codon_algorithms_run_through_the_driver() {
    let cancel = AtomicBool::new(false);
    let stop = Stop { generations: Some(5), budget: None, evaluations: None, cancel: &cancel };
    for algorithm in CodonAlgorithm::ALL {
        let mut opt = AnyCodonOptimizer::new(algorithm, &GeConfig::default(), 1).unwrap();
        let mut seen = Vec::new();
        let summary = run(&mut opt, &SevensToy, &stop, |s, o| {
            assert_eq!(s.generation, o.generation());
            seen.push(s.generation);
        })
        .unwrap();
        assert_eq!(seen, [0, 1, 2, 3, 4, 5], "{algorithm}");
        assert_eq!(summary.reason, StopReason::Generations);
        assert!(opt.best().is_some_and(|b| b.fitness.is_finite()));
    }
    assert_eq!(CodonAlgorithm::Ge.to_string(), "ge");
    let bad = GeConfig { elitism: 60, ..GeConfig::default() };
    assert!(AnyCodonOptimizer::new(CodonAlgorithm::Ge, &bad, 1).is_err());
}

#[test]
fn effective_operators_and_novel_children_repeat_at_one_and_two_threads() {
    let config = GeConfig { population: 31, elitism: 2, mutation_rate: 0.05, ..GeConfig::default() };
    let runs = on_one_and_two_threads(&config, 5);
    assert_eq!(runs[0].0, runs[1].0);
    assert_eq!(format!("{:?}", runs[0].1), format!("{:?}", runs[1].1));
    let dup: u64 = runs[0].1.iter().map(|s| s.reproduction.duplicates).sum();
    let replaced: u64 = runs[0].1.iter().map(|s| s.reproduction.duplicates_replaced).sum();
    assert!(dup > 0 && replaced > 0, "duplicates {dup}, replaced {replaced}");
}

#[test]
fn novel_children_never_evaluate_a_prefix_twice() {
    // Counting evaluations per expressed prefix: every evaluated child
    // reads something no earlier evaluation read (within a generation the
    // same prefix may be drawn twice only after 8 failed tries, which this
    // toy with 16 codons per prefix never exhausts).
    struct Counting(std::sync::Mutex<std::collections::HashMap<Vec<u32>, u32>>);
    impl Objective<Codons> for Counting {
        type Scratch = ();
        fn scratch(&self) {}
        fn evaluate(&self, codons: &Codons, s: &mut ()) -> f64 {
            let e = PrefixToy.expressed(codons, s).unwrap();
            *self.0.lock().unwrap().entry(codons[..e].to_vec()).or_default() += 1;
            PrefixToy.evaluate(codons, s)
        }
        fn expressed(&self, codons: &Codons, s: &mut ()) -> Option<usize> {
            PrefixToy.expressed(codons, s)
        }
    }
    let objective = Counting(Default::default());
    let config = GeConfig { population: 40, crossover_rate: 0.9, mutation_rate: 0.01, ..GeConfig::default() };
    let mut ge = Ge::new(config.clone(), 3).unwrap();
    ge.step(&objective);
    objective.0.lock().unwrap().clear();
    for _ in 0..20 {
        ge.step(&objective);
    }
    let counts = objective.0.lock().unwrap();
    assert!(counts.len() > 300, "{} distinct prefixes", counts.len());
    assert!(counts.values().all(|&n| n == 1), "{:?}", counts.values().filter(|&&n| n > 1).count());
    // Without it, low mutation and cuts that copy a parent's prefix make
    // many repeats.
    let objective = Counting(Default::default());
    let mut ge = Ge::new(GeConfig { novel_children: false, ..config }, 3).unwrap();
    for _ in 0..21 {
        ge.step(&objective);
    }
    assert!(objective.0.lock().unwrap().values().any(|&n| n > 1));
}

#[test]
fn distinct_parents_leave_copies_of_one_score_out_of_selection() {
    // Every genome scores the same: only the first member may be a parent,
    // so without variation every child is a copy of it.
    let flat = FnObjective(|_: &Codons| 1.0);
    let config = GeConfig {
        population: 12,
        crossover_rate: 0.0,
        mutation_rate: 0.0,
        novel_children: false,
        distinct_parents: true,
        ..GeConfig::default()
    };
    let mut ge = Ge::new(config.clone(), 4).unwrap();
    ge.step(&flat);
    let first = ge.population()[0].genome.clone();
    ge.step(&flat);
    assert!(ge.population().iter().all(|i| i.genome == first));
    let mut ge = Ge::new(GeConfig { distinct_parents: false, ..config }, 4).unwrap();
    ge.step(&flat);
    ge.step(&flat);
    assert!(ge.population().iter().any(|i| i.genome != ge.population()[0].genome));
}

/// A toy with phenotypes and subtrees: the genome is read as 4 blocks,
/// each a head codon `h` and the `h mod 3` codons after it (a "subtree");
/// the phenotype is every read codon mod 5, and the fitness how many read
/// codons are 0 mod 5. Counts evaluations per phenotype.
struct Blocks(std::sync::Mutex<std::collections::HashMap<Vec<u32>, u32>>);

impl Blocks {
    /// The blocks' spans, or `None` when the genome is too short.
    fn spans(codons: &Codons) -> Option<Vec<crate::CodonSpan>> {
        let mut spans = Vec::new();
        let mut at = 0;
        for _ in 0..4 {
            let end = at + 1 + (*codons.get(at)? % 3) as usize;
            if end > codons.len() {
                return None;
            }
            spans.push(crate::CodonSpan { start: at, end });
            at = end;
        }
        Some(spans)
    }

    fn phenotype(codons: &Codons) -> Option<Vec<u32>> {
        let end = Self::spans(codons)?.last()?.end;
        Some(codons[..end].iter().map(|c| c % 5).collect())
    }
}

impl Objective<Codons> for Blocks {
    type Scratch = ();
    fn scratch(&self) {}
    fn evaluate(&self, codons: &Codons, _: &mut ()) -> f64 {
        let Some(p) = Self::phenotype(codons) else { return f64::NAN };
        *self.0.lock().unwrap().entry(p.clone()).or_default() += 1;
        p.iter().filter(|&&c| c == 0).count() as f64
    }
    fn expressed(&self, codons: &Codons, _: &mut ()) -> Option<usize> {
        Some(Self::spans(codons).and_then(|s| s.last().map(|s| s.end)).unwrap_or(codons.len()))
    }
    fn phenotype_key(&self, codons: &Codons, _: &mut ()) -> Option<u64> {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        Self::phenotype(codons)?.hash(&mut h);
        Some(h.finish())
    }
    fn subtrees(&self, codons: &Codons, _: &mut (), out: &mut Vec<crate::CodonSpan>) {
        out.clear();
        out.extend(Self::spans(codons).unwrap_or_default());
    }
}

#[test]
fn novel_children_by_phenotype_never_grow_one_phenotype_twice() {
    // Codons read mod 5 from 0..1000: point mutations often keep the
    // phenotype, which the codon key does not notice.
    let config = GeConfig {
        population: 30,
        initial_length: [12, 20],
        codon_range: 1000,
        mutation_rate: 0.1,
        ..GeConfig::default()
    };
    let repeats = |novel_key| {
        let objective = Blocks(Default::default());
        let mut ge = Ge::new(GeConfig { novel_key, ..config.clone() }, 7).unwrap();
        ge.step(&objective);
        objective.0.lock().unwrap().clear();
        for _ in 0..15 {
            ge.step(&objective);
        }
        let counts = objective.0.lock().unwrap();
        (counts.len(), counts.values().filter(|&&n| n > 1).count())
    };
    let (distinct, repeated) = repeats(NovelKey::Phenotype);
    assert!(distinct > 200 && repeated == 0, "{distinct} phenotypes, {repeated} grown twice");
    let (_, repeated) = repeats(NovelKey::Codons);
    assert!(repeated > 10, "the codon key re-grows phenotypes: {repeated}");
}

#[test]
fn subtree_mutation_regrows_one_block_and_keeps_the_others_read_alike() {
    let config = GeConfig {
        population: 40,
        elitism: 0,
        initial_length: [12, 20],
        crossover_rate: 0.0,
        mutation_rate: 0.0,
        novel_children: false,
        subtree_mutation: 1.0,
        ..GeConfig::default()
    };
    let objective = Blocks(Default::default());
    let mut ge = Ge::new(config.clone(), 3).unwrap();
    ge.step(&objective);
    let parents: Vec<Codons> = ge.population().iter().map(|i| i.genome.clone()).collect();
    let stats = ge.step(&objective);
    assert!(stats.reproduction.mutations.regrow > 20, "{:?}", stats.reproduction.mutations);
    let read = |g: &Codons| {
        Blocks::spans(g).map(|s| s.iter().map(|t| g[t.start..t.end].to_vec()).collect::<Vec<_>>()).unwrap_or_default()
    };
    let mut one_block = 0;
    for child in ge.population() {
        // Some parent's blocks differ from the child's in exactly one place.
        let c = read(&child.genome);
        if parents.iter().any(|p| {
            let p = read(p);
            p.len() == 4 && c.len() == 4 && p.iter().zip(&c).filter(|(a, b)| a != b).count() == 1
        }) {
            one_block += 1;
        }
    }
    assert!(one_block >= 25, "{one_block} of 40 children differ from a parent in one block");
    // The same run at one and four threads.
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut ge = Ge::new(GeConfig { subtree_mutation: 0.5, mutation_rate: 0.05, ..config.clone() }, 9).unwrap();
            for _ in 0..8 {
                ge.step(&objective);
            }
            ge.population().iter().map(|i| (i.genome.clone(), i.fitness.to_bits())).collect::<Vec<_>>()
        })
    };
    assert_eq!(run(1), run(4));
}

#[test]
fn restarts_replace_all_but_the_elites_after_a_stall_and_keep_the_best() {
    // A flat objective never improves: a restart is due every
    // `restart_after + 1` generations, and it replaces every member but the
    // elites by fresh genomes (none descends from the old population).
    let flat = FnObjective(|c: &Codons| if c.is_empty() { f64::NAN } else { 1.0 });
    let config = GeConfig { population: 20, elitism: 2, restart_after: 3, ..GeConfig::default() };
    let mut ge = Ge::new(config.clone(), 4).unwrap();
    ge.step(&flat);
    let mut before = ge.population().to_vec();
    for generation in 1..=12 {
        ge.step(&flat);
        let now = ge.population();
        let restarted = generation % 4 == 0;
        assert_eq!(ge.restarts(), generation / 4, "generation {generation}");
        if restarted {
            assert_eq!(now[..2], before[..2], "the elites stay");
            let old: HashSet<&Codons> = before.iter().map(|i| &i.genome).collect();
            assert!(now[2..].iter().all(|i| !old.contains(&i.genome)), "fresh genomes");
        }
        before = now.to_vec();
    }
    // An improving run never restarts: SevensToy's best rises every few generations early on.
    let mut improving = Ge::new(GeConfig { restart_after: 50, ..GeConfig::default() }, 1).unwrap();
    let mut best = f64::NEG_INFINITY;
    for _ in 0..40 {
        improving.step(&SevensToy);
        let b = improving.best().unwrap().fitness;
        assert!(b >= best, "the best is never lost");
        best = b;
    }
    assert_eq!(improving.restarts(), 0);
    assert!(
        GeConfig { local_search: 1.5, ..GeConfig::default() }
            .validate()
            .unwrap_err()
            .to_string()
            .contains("local_search")
    );
}

#[test]
fn local_search_children_are_the_best_with_a_few_read_codons_redrawn() {
    // Every child is local (share 1), novelty off so they are seen as made:
    // each differs from the first member in 1..=3 codons, all inside the
    // codons PrefixToy reads, and the unread tail is the first member's.
    let config = GeConfig {
        population: 30,
        elitism: 1,
        local_search: 1.0,
        novel_children: false,
        distinct_parents: false,
        ..GeConfig::default()
    };
    let mut ge = Ge::new(config.clone(), 3).unwrap();
    ge.step(&PrefixToy);
    for _ in 0..5 {
        let first = ge.population()[0].clone();
        let reads = PrefixToy.expressed(&first.genome, &mut ()).unwrap();
        let stats = ge.step(&PrefixToy);
        assert_eq!(stats.reproduction.crossovers, 0, "no crossover when every child is local");
        for child in ge.population() {
            if child.genome == first.genome {
                continue;
            }
            assert_eq!(child.genome.len(), first.genome.len());
            let changed: Vec<usize> = (0..child.genome.len()).filter(|&i| child.genome[i] != first.genome[i]).collect();
            assert!((1..=3).contains(&changed.len()), "{changed:?}");
            assert!(changed.iter().all(|&i| i < reads), "{changed:?} outside the {reads} read codons");
        }
    }
    // Repeats at any thread count, with the EA's children alongside.
    let config = GeConfig { local_search: 0.3, restart_after: 2, ..config };
    let runs = on_one_and_two_threads(&config, 8);
    assert_eq!(runs[0].0, runs[1].0);
    assert_eq!(format!("{:?}", runs[0].1), format!("{:?}", runs[1].1));
}

/// A toy that writes its own initial genomes: genome `index` is 10 codons,
/// the first drawn from 0..4 (the phenotype key), then `index` and the
/// plan's depth, codon range and length cap; fitness is the first codon.
struct Writes;

impl Objective<Codons> for Writes {
    type Scratch = ();
    fn scratch(&self) {}
    fn evaluate(&self, codons: &Codons, _: &mut ()) -> f64 {
        codons.first().map_or(f64::NAN, |&c| f64::from(c))
    }
    fn expressed(&self, codons: &Codons, _: &mut ()) -> Option<usize> {
        Some(codons.len().min(1))
    }
    fn phenotype_key(&self, codons: &Codons, _: &mut ()) -> Option<u64> {
        codons.first().map(|&c| u64::from(c))
    }
    fn sensible_genome(&self, index: usize, plan: SensiblePlan, rng: &mut Rng, _: &mut ()) -> Option<Codons> {
        let head = rng.below(4) as u32;
        let mut g = vec![head, index as u32, plan.max_depth, plan.codon_range, plan.max_length as u32];
        g.resize(10, 0);
        Some(g)
    }
}

#[test]
fn sensible_init_takes_the_objectives_genomes_with_distinct_phenotypes_first() {
    let config = GeConfig {
        population: 6,
        initial_length: [3, 5],
        max_length: 40,
        codon_range: 50,
        init: Init::Sensible,
        init_depth: 7,
        ..GeConfig::default()
    };
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut ge = Ge::new(config.clone(), 3).unwrap();
            ge.step(&Writes);
            let mut g: Vec<Codons> = ge.population().iter().map(|i| i.genome.clone()).collect();
            g.sort_by_key(|c| c[1]);
            g
        })
    };
    let genomes = run(1);
    assert_eq!(genomes, run(2));
    for (i, g) in genomes.iter().enumerate() {
        // Written by the objective for index i, with the plan's limits.
        assert_eq!(g[1..5], [i as u32, 7, 50, 40], "{g:?}");
    }
    // Four phenotypes exist: the first four genomes take one each (a
    // repeated key is drawn again), the last two must repeat one.
    let heads: HashSet<u32> = genomes[..4].iter().map(|g| g[0]).collect();
    assert_eq!(heads.len(), 4, "{genomes:?}");
    // An objective that writes none: random codons, exactly as `init = "random"`.
    let random = GeConfig { init: Init::Random, ..config.clone() };
    let (mut a, mut b) = (Ge::new(config, 3).unwrap(), Ge::new(random, 3).unwrap());
    a.step(&PrefixToy);
    b.step(&PrefixToy);
    let genomes = |ge: &Ge| ge.population().iter().map(|i| i.genome.clone()).collect::<Vec<_>>();
    assert_eq!(genomes(&a), genomes(&b));
    assert!(a.population().iter().all(|i| (3..=5).contains(&i.genome.len())));
}
