use super::*;
use crate::chi2;
use crate::config::GeneChoice;
use crate::fixtures::{ShipToy, ship};
use crate::objective::FnObjective;
use genform_core::genome::{GenePos, Link};
use genform_core::{Distribution, ParamSpec, SlotSpec, SymbolSpec};
use std::collections::HashMap;

/// `S → a: A (p 0.6)`; `A(k ∈ {0: 1, 1: 3}) → next: A (p 0.4), leaf: B (p 0.5)`;
/// `B(c ∈ {0: 1, 1: 1})`. With depth ≤ 3 the support has 115 trees.
fn tiny() -> GeneratorGraph {
    let choice = |name: &str, weights: Vec<f64>| ParamSpec {
        name: name.into(),
        components: vec![Distribution::Choice { values: (0..weights.len()).map(|v| v as f64).collect(), weights }],
    };
    let slot = |name: &str, target, prob| SlotSpec { name: name.into(), target, prob, max_count: 1 };
    GeneratorGraph {
        name: "tiny".into(),
        root: 0,
        symbols: vec![
            SymbolSpec { name: "S".into(), params: vec![], slots: vec![slot("a", 1, 0.6)], emits_geometry: false },
            SymbolSpec {
                name: "A".into(),
                params: vec![choice("k", vec![1.0, 3.0])],
                slots: vec![slot("next", 1, 0.4), slot("leaf", 2, 0.5)],
                emits_geometry: true,
            },
            SymbolSpec {
                name: "B".into(),
                params: vec![choice("c", vec![1.0, 1.0])],
                slots: vec![],
                emits_geometry: true,
            },
        ],
    }
}

const DEPTH: usize = 3;

/// Every tree of the support with its prior probability (unnormalized:
/// the truncated prior divides by their sum). Keys match [`key`].
fn enumerate_a(depth: usize) -> Vec<(String, f64)> {
    let mut out = Vec::new();
    let nexts: Vec<(String, f64)> = if depth < DEPTH {
        let mut v = vec![("-".to_string(), 0.6)];
        v.extend(enumerate_a(depth + 1).into_iter().map(|(k, p)| (k, 0.4 * p)));
        v
    } else {
        vec![("-".to_string(), 0.6)]
    };
    let leaves: Vec<(String, f64)> = if depth < DEPTH {
        vec![("-".into(), 0.5), ("B0".into(), 0.25), ("B1".into(), 0.25)]
    } else {
        vec![("-".into(), 0.5)]
    };
    for (k, pk) in [(0, 0.25), (1, 0.75)] {
        for (n, pn) in &nexts {
            for (l, pl) in &leaves {
                out.push((format!("A{k}({n},{l})"), pk * pn * pl));
            }
        }
    }
    out
}

fn support() -> Vec<(String, f64)> {
    let mut all = vec![("S(-)".to_string(), 0.4)];
    all.extend(enumerate_a(1).into_iter().map(|(k, p)| (format!("S({k})"), 0.6 * p)));
    let total: f64 = all.iter().map(|(_, p)| p).sum();
    all.into_iter().map(|(k, p)| (k, p / total)).collect()
}

fn key(g: &Genome, pos: GenePos) -> String {
    let gene = g.gene(pos);
    let sub = |i: usize| match gene.link(i) {
        Link::Child(c) => key(g, c),
        _ => "-".to_string(),
    };
    match gene.symbol() {
        0 => format!("S({})", sub(0)),
        1 => format!("A{}({},{})", gene.param(0), sub(0), sub(1)),
        _ => format!("B{}", gene.param(0)),
    }
}

/// A fitness on tree keys: 0.9 per `B` leaf, −0.6 per `A` with `k = 1`.
fn tilt(key: &str) -> f64 {
    0.9 * key.matches('B').count() as f64 - 0.6 * key.matches("A1").count() as f64
}

/// Runs chains at temperature 1 and tests the visited trees against
/// `prior · exp(fitness)` (the prior itself when `tilted` is false).
fn samples_the_target(config: MhConfig, seed: u64, tilted: bool) {
    let limits = Limits { max_genes: 1000, max_depth: DEPTH, max_primitives: 1000 };
    let fitness = move |k: &str| if tilted { tilt(k) } else { 0.0 };
    let mut mh = Mh::new(&tiny(), &limits, config, seed).unwrap();
    let objective = FnObjective(move |g: &Genome| fitness(&key(g, GenePos(0))));
    let support = support();
    assert_eq!(support.len(), 115);
    let index: HashMap<&str, usize> = support.iter().enumerate().map(|(i, (k, _))| (k.as_str(), i)).collect();
    let mut counts = vec![0u64; support.len()];
    let mut moves = MoveCounts::default();
    for g in 0..20_000 {
        moves += mh.step(&objective).moves;
        if g >= 200 && g % 10 == 0 {
            for c in mh.chains() {
                let k = key(&c.genome, GenePos(0));
                counts[*index.get(k.as_str()).unwrap_or_else(|| panic!("{k} is outside the support"))] += 1;
            }
        }
    }
    let weights: Vec<f64> = support.iter().map(|(k, p)| p * fitness(k).exp()).collect();
    let total: f64 = weights.iter().sum();
    let expected: Vec<f64> = weights.iter().map(|w| w / total).collect();
    chi2::assert_fits("visited trees vs target", &counts, &expected);
    assert!(moves.jumps_accepted > 0 && moves.swaps_accepted > 0, "{moves:?}");
    assert_eq!(moves.diffusions_accepted > 0, mh.config.jump < 1.0, "{moves:?}");
    assert_eq!(moves.delayed_accepted > 0, mh.config.delayed_rejection, "{moves:?}");
}

fn temperature_one() -> MhConfig {
    MhConfig {
        chains: 24,
        initial_length: [1, 6],
        min_length: 1,
        max_length: 1000,
        temperature: Some(1.0),
        ladder: 1.0,
        anneal: 1.0,
        ..MhConfig::default()
    }
}

#[test]
fn flat_fitness_samples_the_prior_with_level_choice_and_delayed_rejection() {
    samples_the_target(temperature_one(), 11, false);
}

#[test]
fn flat_fitness_samples_the_prior_with_uniform_choice() {
    let config =
        MhConfig { gene_choice: GeneChoice::Uniform, delayed_rejection: false, jump: 0.7, ..temperature_one() };
    samples_the_target(config, 12, false);
}

#[test]
fn jumps_with_delayed_rejection_sample_a_tilted_prior() {
    samples_the_target(MhConfig { jump: 1.0, ..temperature_one() }, 13, true);
}

#[test]
fn all_moves_sample_a_tilted_prior() {
    samples_the_target(temperature_one(), 14, true);
}

#[test]
fn the_support_enumeration_matches_prior_sampling() {
    // Guards the test's own reference distribution: forward samples from
    // the graph's prior, kept when inside the depth bound, fit it too.
    let unlimited = Limits { max_genes: 1000, max_depth: 100, max_primitives: 1000 };
    let support = support();
    let index: HashMap<&str, usize> = support.iter().enumerate().map(|(i, (k, _))| (k.as_str(), i)).collect();
    let mut counts = vec![0u64; support.len()];
    let mut rng = Rng::from_seed(5);
    let mut kept = 0;
    while kept < 20_000 {
        let s = genform_core::generator::sample_prior(&tiny(), &mut rng, &unlimited).genome;
        if let Some(&i) = index.get(key(&s, GenePos(0)).as_str()) {
            counts[i] += 1;
            kept += 1;
        }
    }
    chi2::assert_fits("prior samples vs enumeration", &counts, &support.iter().map(|(_, p)| *p).collect::<Vec<_>>());
}

#[test]
fn choice_probabilities_match_the_choices() {
    let g = ship();
    let limits = Limits::default();
    let x = crate::operators::initial(&g, &limits, [12, 12], &mut Rng::from_seed(3));
    for (eligible, choice) in [
        (Eligible::Nonterminals, GeneChoice::Level),
        (Eligible::Parameters, GeneChoice::Level),
        (Eligible::Nonterminals, GeneChoice::Uniform),
    ] {
        let mut freq: HashMap<GenePos, u64> = HashMap::new();
        let mut rng = Rng::from_seed(9);
        for _ in 0..40_000 {
            *freq.entry(moves::choose(&x, eligible, choice, &mut rng).unwrap()).or_default() += 1;
        }
        let positions: Vec<GenePos> = freq.keys().copied().collect();
        let observed: Vec<u64> = positions.iter().map(|p| freq[p]).collect();
        let expected: Vec<f64> = positions.iter().map(|&p| moves::ln_choice(&x, eligible, choice, p).exp()).collect();
        assert!((expected.iter().sum::<f64>() - 1.0).abs() < 1e-9, "{eligible:?} {choice:?}");
        chi2::assert_fits("gene choice", &observed, &expected);
    }
}

#[test]
fn jumps_keep_the_parameters_of_genes_that_stay() {
    let g = ship();
    let limits = Limits::default();
    let mut rng = Rng::from_seed(4);
    let x = crate::operators::initial(&g, &limits, [20, 20], &mut rng);
    let v = GenePos(0);
    let before = moves::paths_below(&x, v);
    let mut shared = 0;
    for _ in 0..50 {
        let Some(y) = moves::jump(&x, v, &g, &limits, &mut rng) else { continue };
        y.validate(&g).unwrap();
        for (path, pos) in moves::paths_below(&y, v) {
            if let Some(&old) = before.get(&path) {
                shared += 1;
                assert_eq!(x.gene(old).params().collect::<Vec<_>>(), y.gene(pos).params().collect::<Vec<_>>());
            }
        }
    }
    assert!(shared > 50, "jumps should keep many genes, kept {shared}");
}

#[test]
fn jumps_beyond_the_limits_are_outside_the_support() {
    let g = ship();
    let limits = Limits { max_genes: 6, max_depth: 3, max_primitives: 100 };
    let x = Genome::with_root(&g, 0, &[]);
    let mut rng = Rng::from_seed(1);
    let mut outside = 0;
    for _ in 0..200 {
        match moves::jump(&x, GenePos(0), &g, &limits, &mut rng) {
            Some(y) => assert!(y.len() <= 6 && y.iter().all(|gene| y.depth(gene.pos) <= 3)),
            None => outside += 1,
        }
    }
    assert!(outside > 0);
}

#[test]
fn drift_stays_in_range_or_reports_leaving_it() {
    let g = ship();
    let mut rng = Rng::from_seed(2);
    let x = crate::operators::initial(&g, &Limits::default(), [10, 10], &mut rng);
    let body = x.iter().find(|gene| gene.symbol() == crate::fixtures::ship_ids::BODY).unwrap().pos;
    for _ in 0..200 {
        let mut y = x.clone();
        let ln = moves::diffuse(&mut y, body, &g, Some(0.5), &mut rng);
        if ln == f64::NEG_INFINITY {
            assert_eq!(y, x, "a rejected drift leaves the genome alone");
        } else {
            assert_eq!(ln, 0.0, "uniform prior: ratio 1 inside");
            assert!(y.gene(body).params().all(|v| (0.5..=1.5).contains(&v)));
        }
    }
}

#[test]
fn improves_a_toy_objective_and_is_deterministic_across_threads() {
    let config = MhConfig { chains: 12, initial_length: [5, 20], max_length: 60, ..MhConfig::default() };
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let mut mh = Mh::new(&ship(), &Limits::default(), config.clone(), 21).unwrap();
        let stats: Vec<GenerationStats> = pool.install(|| (0..150).map(|_| mh.step(&ShipToy { target: 20 })).collect());
        (mh, stats)
    };
    let (a, stats) = run(1);
    let (b, _) = run(3);
    assert_eq!(a.chains(), b.chains());
    assert_eq!(a.best(), b.best());
    let first = stats[0].max;
    let best = a.best().unwrap().fitness;
    assert!(best > first + 0.5, "best {best} vs initial {first}");
    assert_eq!(a.evaluations(), stats.iter().map(|s| s.evaluations).sum::<u64>());
    assert!(a.betas().windows(2).all(|w| w[0] > w[1]), "coldest first");
    assert!((a.betas()[0] / a.betas()[11] - TALTON).abs() < 1e-6);
}

const TALTON: f64 = crate::config::TALTON_LADDER;

#[test]
fn swaps_move_better_states_to_colder_chains() {
    let g = ship();
    let limits = Limits::default();
    let config = MhConfig { chains: 2, temperature: Some(0.01), ladder: 100.0, anneal: 1.0, ..MhConfig::default() };
    let ind = |fitness| Individual { genome: Genome::with_root(&g, 0, &[]), fitness };
    let mut mh = Mh::from_states(&g, &limits, config, 0, vec![ind(1.0), ind(5.0)]).unwrap();
    let mut counts = MoveCounts::default();
    mh.swap(0, &mut counts);
    assert_eq!(counts.swaps_accepted, 1);
    assert_eq!(mh.chains()[0].fitness, 5.0);
}

#[test]
fn acceptance_helpers() {
    assert_eq!(tempered(2.0, 1.0, 0.5), 1.0);
    assert_eq!(tempered(f64::INFINITY, 1.0, 1.0), 0.0);
    assert_eq!(tempered(1.0, f64::NAN, 0.0), f64::NEG_INFINITY);
    assert_eq!(tempered(1.0, 0.0, f64::NEG_INFINITY), f64::INFINITY);
    assert!((ln_reject(0.5f64.ln()) - 0.5f64.ln()).abs() < 1e-12);
    assert_eq!(ln_reject(0.0), f64::NEG_INFINITY);
    let mut rng = Rng::from_seed(0);
    let accepted = (0..10_000).filter(|_| accept(0.25f64.ln(), &mut rng)).count();
    assert!((2300..2700).contains(&accepted), "{accepted}");
}

#[test]
fn invalid_settings_are_named() {
    let e = Mh::new(&ship(), &Limits::default(), MhConfig { jump: 2.0, ..MhConfig::default() }, 0).unwrap_err();
    assert_eq!(e.to_string(), "jump must be in [0, 1], got 2");
    let e = Mh::new(&ship(), &Limits::default(), MhConfig { anneal: 0.9, ..MhConfig::default() }, 0).unwrap_err();
    assert!(e.to_string().contains("anneal must be finite and ≥ 1"));
}
