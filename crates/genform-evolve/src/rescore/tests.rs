use super::*;
use crate::algorithm::{Algorithm, AnyOptimizer, Settings};
use crate::config::{GaConfig, HybridConfig, MhConfig, SmcConfig};
use crate::fixtures::{HalfInvalidToy, SevensToy, ShipToy, ship, ship_ids};
use crate::ga::Ga;
use crate::ge::{AnyCodonOptimizer, CodonAlgorithm, Codons, GeConfig};
use crate::hybrid::{Horizon, Hybrid};
use crate::map_elites::{DescriptorAxis, MapElitesConfig};
use crate::mcmc::Mh;
use crate::objective::FnObjective;
use genform_core::Limits;
use std::fmt::Debug;

/// A steerable toy: `weight` × [`ShipToy`] with `target`, invalid (NaN)
/// when `invalid_every` divides the length; descriptors are the length
/// and the number of wings (for MAP-Elites).
#[derive(Clone, Copy, Debug)]
struct Steered {
    target: usize,
    weight: f64,
    invalid_every: usize,
}

/// The objective runs start with.
const BEFORE: Steered = Steered { target: 10, weight: 1.0, invalid_every: 0 };
/// The objective after steering: another target, another scale, some invalid.
const AFTER: Steered = Steered { target: 30, weight: 3.0, invalid_every: 7 };

impl Objective for Steered {
    type Scratch = ();

    fn scratch(&self) {}

    fn evaluate(&self, genome: &Genome, _: &mut ()) -> f64 {
        if self.invalid_every > 0 && genome.len().is_multiple_of(self.invalid_every) {
            return f64::NAN;
        }
        self.weight * ShipToy { target: self.target }.evaluate(genome, &mut ())
    }

    fn evaluate_described(&self, genome: &Genome, s: &mut (), d: &mut [f64; 2]) -> f64 {
        let wings = genome.iter().filter(|g| g.symbol() == ship_ids::WING).count();
        *d = [genome.len() as f64, wings as f64];
        self.evaluate(genome, s)
    }
}

fn settings() -> Settings {
    Settings {
        ga: GaConfig {
            population: 20,
            elitism: Some(4),
            initial_length: [5, 15],
            max_length: 40,
            ..GaConfig::default()
        },
        mh: MhConfig { chains: 8, initial_length: [5, 15], max_length: 40, ..MhConfig::default() },
        smc: SmcConfig { particles: 30, max_length: 40, ..SmcConfig::default() },
        hybrid: HybridConfig { stagnation: 5, polish_after: 0.5 },
        map_elites: MapElitesConfig {
            initial: 20,
            batch: 16,
            descriptors: [DescriptorAxis::new("length", 6, [0.0, 40.0]), DescriptorAxis::new("wings", 4, [0.0, 8.0])],
            ..MapElitesConfig::default()
        },
    }
}

fn any(algorithm: Algorithm) -> AnyOptimizer {
    let horizon = Horizon { generations: Some(40), ..Horizon::default() };
    AnyOptimizer::new(algorithm, &ship(), &Limits::default(), &settings(), 3, horizon).unwrap()
}

fn fresh<G, O: Objective<G>>(objective: &O, genome: &G) -> f64 {
    objective.evaluate(genome, &mut objective.scratch())
}

/// Equal values, NaN equal to NaN.
fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// Re-scores `opt` under `new` and checks what [`Rescore`] promises: the
/// evaluations are counted, every value in the population and in `stored`
/// (what else the optimizer keeps) is a fresh evaluation under `new`, the
/// population is sorted best first, and the best is the best valid of the
/// re-scored population, `stored` and old best. Returns the evaluations.
fn rescored<G: Clone + PartialEq + Debug, P: Rescore<G>, O: Objective<G>>(
    opt: &mut P,
    new: &O,
    stored: impl Fn(&P) -> Vec<Individual<G>>,
) -> u64 {
    let old_best = opt.best().cloned().expect("a best before steering");
    let before = opt.evaluations();
    let made = opt.rescore(new);
    assert!(made > 0);
    assert_eq!(opt.evaluations(), before + made, "re-scoring evaluations count");
    let kept: Vec<Individual<G>> = opt.population().iter().cloned().chain(stored(opt)).collect();
    for i in &kept {
        assert!(same(i.fitness, fresh(new, &i.genome)), "stale fitness {} of {:?}", i.fitness, i.genome);
    }
    let pop = opt.population();
    assert!(
        pop.windows(2).all(|w| !w[1].is_valid() || (w[0].is_valid() && w[0].fitness >= w[1].fitness)),
        "sorted best first"
    );
    let expected = kept
        .iter()
        .map(|i| i.fitness)
        .chain([fresh(new, &old_best.genome)])
        .filter(|f| f.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    let best = opt.best().expect("some individual stays valid");
    assert_eq!(best.fitness, expected, "the best is the best of the re-scored");
    assert!(same(best.fitness, fresh(new, &best.genome)));
    made
}

/// Population, best and evaluations, NaN-safe, for determinism checks.
type Fingerprint<G> = (Vec<(G, u64)>, Option<(G, u64)>, u64);

fn fingerprint<G: Clone, P: Optimizer<G>>(opt: &P) -> Fingerprint<G> {
    let pop = opt.population().iter().map(|i| (i.genome.clone(), i.fitness.to_bits())).collect();
    (pop, opt.best().map(|b| (b.genome.clone(), b.fitness.to_bits())), opt.evaluations())
}

#[test]
fn every_tree_algorithm_rescores_what_it_stores() {
    for algorithm in Algorithm::ALL {
        let mut opt = any(algorithm);
        for _ in 0..8 {
            opt.step(&BEFORE);
        }
        let stale = opt.best().unwrap().fitness;
        rescored(&mut opt, &AFTER, |_| Vec::new());
        assert!(opt.best().unwrap().fitness != stale, "{algorithm}: the best is on the new scale");
        // The run goes on under the new objective.
        let stats = opt.step(&AFTER);
        assert_eq!(stats.total_evaluations, opt.evaluations(), "{algorithm}");
        assert!(same(opt.best().unwrap().fitness, fresh(&AFTER, &opt.best().unwrap().genome)), "{algorithm}");
    }
}

#[test]
fn nothing_is_rescored_before_generation_zero() {
    for algorithm in Algorithm::ALL {
        let mut opt = any(algorithm);
        assert_eq!(opt.rescore(&AFTER), 0, "{algorithm}");
        assert_eq!(opt.evaluations(), 0);
    }
    let mut ge = AnyCodonOptimizer::new(CodonAlgorithm::Ge, &GeConfig::default(), 1).unwrap();
    assert_eq!(ge.rescore(&SevensToy), 0);
}

#[test]
fn rescoring_is_the_same_at_one_and_four_threads() {
    for algorithm in Algorithm::ALL {
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let mut opt = any(algorithm);
                for _ in 0..6 {
                    opt.step(&BEFORE);
                }
                opt.rescore(&AFTER);
                let rescored = fingerprint(&opt);
                for _ in 0..4 {
                    opt.step(&AFTER);
                }
                (rescored, fingerprint(&opt))
            })
        };
        assert!(run(1) == run(4), "{algorithm} differs between 1 and 4 threads");
    }
}

#[test]
fn the_ga_rescores_its_champions_and_restarts_its_stall_count() {
    let config = GaConfig { restart_after: 2, restart_tolerance: 0.5, ..settings().ga };
    let mut ga = Ga::new(&ship(), &Limits::default(), config, 5).unwrap();
    for _ in 0..200 {
        if !ga.champions().is_empty() {
            break;
        }
        ga.step(&BEFORE);
    }
    assert!(!ga.champions().is_empty(), "a restart happened");
    rescored(&mut ga, &AFTER, |ga| ga.champions().to_vec());
    // Two stalled generations were due for a restart on the old scale;
    // after re-scoring the epoch counts from the new top.
    let restarts = ga.restarts();
    ga.step(&AFTER);
    assert_eq!(ga.restarts(), restarts, "no restart right after re-scoring");
}

#[test]
fn mh_rescales_an_automatic_ladder_and_keeps_a_set_one() {
    let scaled = FnObjective(|g: &Genome| 10.0 * BEFORE.evaluate(g, &mut ()));
    for temperature in [None, Some(2.0)] {
        let config = MhConfig { temperature, ..settings().mh };
        let mut mh = Mh::new(&ship(), &Limits::default(), config, 2).unwrap();
        for _ in 0..5 {
            mh.step(&BEFORE);
        }
        let betas = mh.betas().to_vec();
        rescored(&mut mh, &scaled, |mh| mh.chains().to_vec());
        let ratios: Vec<f64> = mh.betas().iter().zip(&betas).map(|(a, b)| a / b).collect();
        let expected = if temperature.is_none() { 0.1 } else { 1.0 };
        assert!(ratios.iter().all(|r| (r - expected).abs() < 1e-12), "{temperature:?}: {ratios:?}");
    }
}

#[test]
fn map_elites_keeps_cells_and_drops_elites_that_became_invalid() {
    let mut opt = any(Algorithm::MapElites);
    for _ in 0..10 {
        opt.step(&BEFORE);
    }
    let AnyOptimizer::MapElites(me) = &mut opt else { unreachable!() };
    let cells: Vec<([usize; 2], Genome)> = me.elites().map(|e| (e.cell, e.individual.genome.clone())).collect();
    rescored(me, &AFTER, |me| me.elites().map(|e| e.individual.clone()).collect());
    let kept: Vec<([usize; 2], Genome)> = me.elites().map(|e| (e.cell, e.individual.genome.clone())).collect();
    let cells_before = cells.len();
    let expected: Vec<_> = cells.into_iter().filter(|(_, g)| fresh(&AFTER, g).is_finite()).collect();
    assert!(kept == expected, "the same elites in the same cells, less the invalid ones");
    assert!(kept.len() < cells_before, "some elites became invalid: {} of {cells_before} kept", kept.len());
    assert_eq!(me.population().len(), me.filled());
    assert!(me.population().iter().all(|i| i.is_valid()));
}

#[test]
fn the_hybrid_rescores_in_every_phase() {
    let mut h = match any(Algorithm::Hybrid) {
        AnyOptimizer::Hybrid(h) => h,
        _ => unreachable!(),
    };
    let mut seen: Vec<&'static str> = Vec::new();
    for _ in 0..200 {
        if seen.len() == 3 {
            break;
        }
        h.step(&BEFORE);
        let phase = h.phase().name();
        if !seen.contains(&phase) {
            seen.push(phase);
            let mut copy: Hybrid = (*h).clone();
            rescored(&mut copy, &AFTER, |_| Vec::new());
        }
    }
    assert_eq!(seen, ["sosmc", "ga", "mh"]);
}

#[test]
fn codon_optimizers_rescore_population_and_best() {
    let config = GeConfig { population: 30, elitism: 5, ..GeConfig::default() };
    for algorithm in CodonAlgorithm::ALL {
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let mut opt = AnyCodonOptimizer::new(algorithm, &config, 4).unwrap();
                for _ in 0..6 {
                    opt.step(&SevensToy);
                }
                let made = rescored(&mut opt, &HalfInvalidToy, |_| Vec::<Individual<Codons>>::new());
                assert!(made <= 31, "{algorithm}: at most the population and the best");
                opt.step(&HalfInvalidToy);
                fingerprint(&opt)
            })
        };
        assert!(run(1) == run(4), "{algorithm} differs between 1 and 4 threads");
    }
}

#[test]
fn equal_neighbours_are_evaluated_once() {
    let calls = std::sync::atomic::AtomicU64::new(0);
    let counting = FnObjective(|c: &Codons| {
        calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        c[0] as f64
    });
    let mut individuals: Vec<Individual<Codons>> =
        [1, 1, 1, 2, 1].iter().map(|&c| Individual { genome: vec![c], fitness: 0.0 }).collect();
    assert_eq!(reevaluate(&counting, &mut individuals), 3);
    assert_eq!(calls.into_inner(), 3);
    let values: Vec<f64> = individuals.iter().map(|i| i.fitness).collect();
    assert_eq!(values, [1.0, 1.0, 1.0, 2.0, 1.0]);
}
