use super::*;
use crate::chi2;
use crate::config::Weighting;
use crate::fixtures::{ShipToy, ship};
use genform_core::{Distribution, ParamSpec, SlotSpec, SymbolSpec};

/// `R → a, b, c: G (p 1 each)`; `G → x: G (p 0.5)`, `G` emits geometry.
fn fan() -> GeneratorGraph {
    let slot = |name: &str, target, prob| SlotSpec { name: name.into(), target, prob, max_count: 1 };
    GeneratorGraph {
        name: "fan".into(),
        root: 0,
        symbols: vec![
            SymbolSpec {
                name: "R".into(),
                params: vec![],
                slots: vec![slot("a", 1, 1.0), slot("b", 1, 1.0), slot("c", 1, 1.0)],
                emits_geometry: false,
            },
            SymbolSpec {
                name: "G".into(),
                params: vec![ParamSpec {
                    name: "w".into(),
                    components: vec![Distribution::Uniform { min: 0.0, max: 1.0 }],
                }],
                slots: vec![slot("x", 1, 0.5)],
                emits_geometry: true,
            },
        ],
    }
}

#[test]
fn sosmc_grows_a_uniformly_chosen_open_link() {
    let g = fan();
    let limits = Limits::default();
    // After one step from the root: one of a, b, c. Then the open links
    // are two of the root's and the new gene's one; each is picked with
    // probability 1/3 whichever state was reached.
    let mut first = [0u64; 3];
    let mut second = [0u64; 3];
    for seed in 0..6000 {
        let mut rng = Rng::from_seed(seed);
        let mut genome = Genome::with_root(&g, 0, &[]);
        assert!(advance(&mut genome, &g, &limits, Order::Stochastic, &mut rng));
        assert_eq!(genome.len(), 2, "stops at the first geometric gene");
        first[genome.iter().nth(1).unwrap().parent().unwrap().1] += 1;
        let open = open_links(&genome);
        assert_eq!(open.len(), 3);
        let picked = next_open(&genome, Order::Stochastic, &mut rng).unwrap();
        second[open.iter().position(|o| *o == picked).unwrap()] += 1;
    }
    chi2::assert_fits("first link", &first, &[1.0 / 3.0; 3]);
    chi2::assert_fits("second link", &second, &[1.0 / 3.0; 3]);
}

#[test]
fn smc_follows_depth_first_program_order() {
    let g = fan();
    let limits = Limits::default();
    let mut rng = Rng::from_seed(3);
    let mut genome = Genome::with_root(&g, 0, &[]);
    advance(&mut genome, &g, &limits, Order::Fixed, &mut rng);
    // The root's first link, then always the newest gene's open link.
    assert_eq!(genome.iter().nth(1).unwrap().parent(), Some((GenePos(0), 0)));
    while !is_complete(&genome) {
        let open = open_links(&genome);
        let latest = open.iter().map(|(p, _)| *p).max().unwrap();
        let first_of_latest = *open.iter().find(|(p, _)| *p == latest).unwrap();
        assert_eq!(next_open(&genome, Order::Fixed, &mut rng.clone()), Some(first_of_latest));
        advance(&mut genome, &g, &limits, Order::Fixed, &mut rng);
    }
    genome.validate(&g).unwrap();
}

#[test]
fn skipped_slots_are_closed_and_never_expressed() {
    let g = ship();
    let limits = Limits { max_genes: 30, max_depth: 6, max_primitives: 1000 };
    for seed in 0..50 {
        let mut rng = Rng::from_seed(seed);
        let mut genome = Genome::with_root(&g, 0, &[]);
        while advance(&mut genome, &g, &limits, Order::Stochastic, &mut rng) {}
        assert!(is_complete(&genome));
        genome.validate(&g).unwrap();
        assert!(genome.len() <= 30);
        // p = 0 slots are never expressed; p = 1 slots always are (within limits).
        for gene in genome.iter() {
            let spec = g.symbol(gene.symbol());
            for (i, l) in gene.links().enumerate() {
                let (slot, _) = spec.slot_of_link(i).unwrap();
                if spec.slots[slot].prob == 0.0 {
                    assert_eq!(l, Link::Closed);
                }
            }
        }
        let reopened = reopen(&genome);
        assert!(reopened.iter().all(|gene| gene.links().all(|l| l != Link::Closed)));
        assert_eq!(reopened.len(), genome.len());
    }
}

#[test]
fn particles_grow_improve_and_restart_deterministically() {
    let config = SmcConfig { particles: 40, max_length: 40, ..SmcConfig::default() };
    let run = |order, threads| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let mut smc = Smc::new(&ship(), &Limits::default(), config.clone(), order, 5).unwrap();
        let stats: Vec<GenerationStats> =
            pool.install(|| (0..120).map(|_| smc.step(&ShipToy { target: 20 })).collect());
        (smc, stats)
    };
    for order in [Order::Fixed, Order::Stochastic] {
        let (a, stats) = run(order, 1);
        let (b, _) = run(order, 3);
        assert_eq!(a.population(), b.population());
        assert_eq!(a.best(), b.best());
        assert!(a.sweeps() > 1, "{order:?}: 120 steps finish a sweep of ≤ 40-gene particles");
        assert_eq!(stats[0].generation, 0);
        assert_eq!(stats.last().unwrap().generation, 119);
        assert!(stats.iter().all(|s| s.ess.is_some_and(|e| (1.0..=40.0 + 1e-9).contains(&e))));
        assert!(a.population().windows(2).all(|w| w[0].fitness >= w[1].fitness || !w[1].fitness.is_finite()));
        let best = a.best().unwrap().fitness;
        assert!(best > stats[0].max + 1.0, "{order:?}: best {best} vs first step {}", stats[0].max);
        assert_eq!(a.evaluations(), stats.iter().map(|s| s.evaluations).sum::<u64>());
    }
}

#[test]
fn shifted_weighting_runs_too() {
    let config = SmcConfig { particles: 20, weight: Weighting::Shifted, max_length: 30, ..SmcConfig::default() };
    let mut smc = Smc::new(&ship(), &Limits::default(), config, Order::Stochastic, 1).unwrap();
    for _ in 0..30 {
        smc.step(&ShipToy { target: 10 });
    }
    assert!(smc.best().is_some());
    let e = Smc::new(&ship(), &Limits::default(), SmcConfig { particles: 0, ..SmcConfig::default() }, Order::Fixed, 0);
    assert!(e.is_err());
}
