use super::*;
use crate::fixtures::{ship, ship_ids::*};
use genform_core::Rng;
use genform_core::genome::Link;
use proptest::prelude::*;

const LIMITS: Limits = Limits { max_genes: 60, max_depth: 8, max_primitives: 1000 };

/// A valid ship genome of roughly `len` genes, with some links closed and
/// some subtrees cut so every link state occurs.
fn random_genome(seed: u64, len: usize) -> Genome {
    let graph = ship();
    let mut rng = Rng::stream(seed, &[1]);
    let mut g = initial(&graph, &LIMITS, [len, len], &mut rng);
    let positions: Vec<GenePos> = g.iter().map(|x| x.pos).collect();
    for p in positions {
        if g.gene(p).link_len() > 0 && rng.bernoulli(0.1) {
            let link = rng.index(g.gene(p).link_len());
            g.set_closed(p, link, true);
        }
    }
    if rng.bernoulli(0.3) {
        cut(&mut g, &graph, &mut rng);
    }
    g
}

fn child_at(g: &Genome, at: Connection) -> Option<GenePos> {
    match g.gene(at.parent).link(at.link) {
        Link::Child(c) => Some(c),
        _ => None,
    }
}

/// Every gene as (symbol, parameter bits), sorted.
fn genes(gs: &[&Genome]) -> Vec<(u32, Vec<u64>)> {
    let mut v: Vec<_> =
        gs.iter().flat_map(|g| g.iter().map(|x| (x.symbol(), x.params().map(f64::to_bits).collect()))).collect();
    v.sort();
    v
}

fn slot_prob(graph: &GeneratorGraph, g: &Genome, at: Connection) -> f64 {
    let spec = graph.symbol(g.gene(at.parent).symbol());
    spec.slots[spec.slot_of_link(at.link).unwrap().0].prob
}

/// Whether every empty link of a `p = 1` slot is explained by a limit.
fn mandatory_complete(graph: &GeneratorGraph, g: &Genome, limits: &Limits) -> bool {
    g.iter().all(|x| {
        let spec = graph.symbol(x.symbol());
        x.links().enumerate().all(|(i, l)| {
            let p = spec.slots[spec.slot_of_link(i).unwrap().0].prob;
            p < 1.0 || l != Link::Empty || g.depth(x.pos) >= limits.max_depth || g.len() >= limits.max_genes
        })
    })
}

fn within_limits(g: &Genome, limits: &Limits) -> bool {
    g.len() <= limits.max_genes && g.iter().all(|x| g.depth(x.pos) <= limits.max_depth)
}

#[test]
fn initial_individuals_have_the_mandatory_closure_and_target_length() {
    let graph = ship();
    let limits = Limits { max_genes: 1000, max_depth: 100, max_primitives: 1000 };
    let mut lens = Vec::new();
    for seed in 0..100 {
        let g = initial(&graph, &limits, [20, 30], &mut Rng::stream(seed, &[]));
        g.validate(&graph).unwrap();
        let body = child_at(&g, Connection { parent: GenePos(0), link: 0 }).expect("S → Body is always grown");
        assert_eq!(g.gene(body).symbol(), BODY);
        assert!(mandatory_complete(&graph, &g, &limits));
        // The last grow may add a Wing with its mandatory Tip: one past the target.
        assert!((20..=31).contains(&g.len()), "{}", g.len());
        lens.push(g.len());
    }
    assert!(lens.iter().any(|&n| n <= 22) && lens.iter().any(|&n| n >= 29), "lengths spread over [20, 30]: {lens:?}");
}

#[test]
fn grow_picks_links_in_proportion_to_slot_probability() {
    // S → Body only: Body's empty links are next (0.6), wing × 2 (0.5 each),
    // top (0.3) and ghost (0).
    let graph = ship();
    let base = initial(&graph, &LIMITS, [1, 1], &mut Rng::from_seed(0));
    assert_eq!(base.len(), 2);
    let n = 6000;
    let mut counts = [0usize; 5];
    for i in 0..n {
        let mut g = base.clone();
        let out = grow(&mut g, &graph, &LIMITS, &mut Rng::stream(3, &[i])).unwrap();
        counts[out.at.link] += 1;
        let expect_added = if (1..=2).contains(&out.at.link) { 2 } else { 1 };
        assert_eq!(out.added, expect_added, "a Wing comes with its Tip");
    }
    assert_eq!(counts[4], 0, "p = 0 slots never grow");
    let p_top = counts[3] as f64 / n as f64;
    let p_wing = (counts[1] + counts[2]) as f64 / n as f64;
    assert!((p_top - 0.3 / 1.9).abs() < 0.015, "top {p_top}");
    assert!((p_wing - 1.0 / 1.9).abs() < 0.02, "wing {p_wing}");
}

#[test]
fn grow_respects_gene_and_depth_limits() {
    let graph = ship();
    let limits = Limits { max_genes: 1000, max_depth: 3, max_primitives: 0 };
    let mut g = initial(&graph, &limits, [1, 1], &mut Rng::from_seed(1));
    let mut rng = Rng::from_seed(2);
    while grow(&mut g, &graph, &limits, &mut rng).is_some() {}
    // Saturated: every growable link below depth 3 is full; nothing deeper.
    assert!(within_limits(&g, &limits));
    assert!(g.iter().any(|x| g.depth(x.pos) == 3));
    let limits = Limits { max_genes: 7, ..limits };
    let mut g = initial(&graph, &limits, [1, 1], &mut Rng::from_seed(1));
    while grow(&mut g, &graph, &limits, &mut rng).is_some() {}
    assert_eq!(g.len(), 7);
}

#[test]
fn cut_follows_one_minus_slot_probability_and_spares_mandatory_genes() {
    let graph = ship();
    let mut base = Genome::with_root(&graph, S, &[]);
    let body = base.grow(GenePos(0), 0, BODY, &[1.0; 3], 5);
    let next = base.grow(body, 0, BODY, &[1.0; 3], 5);
    base.grow(body, 3, TOP, &[1.0], 0);
    let wing = base.grow(next, 1, WING, &[1.0, 2.0], 2);
    base.grow(wing, 0, TIP, &[1.0], 0);
    base.validate(&graph).unwrap();
    // Cuttable: next Body (1 − 0.6), Top (0.7), Wing (0.5); never S's Body or the Tip.
    let n = 6000;
    let mut counts = std::collections::HashMap::new();
    for i in 0..n {
        let mut g = base.clone();
        let out = cut(&mut g, &graph, &mut Rng::stream(5, &[i])).unwrap();
        *counts.entry((out.symbol, out.removed)).or_insert(0usize) += 1;
    }
    assert_eq!(counts.len(), 3, "{counts:?}");
    let p_top = counts[&(TOP, 1)] as f64 / n as f64;
    let p_next = counts[&(BODY, 3)] as f64 / n as f64;
    assert!((p_top - 0.7 / 1.6).abs() < 0.02, "top {p_top}");
    assert!((p_next - 0.4 / 1.6).abs() < 0.02, "next {p_next}");

    let mut only_mandatory = Genome::with_root(&graph, S, &[]);
    only_mandatory.grow(GenePos(0), 0, BODY, &[1.0; 3], 5);
    assert_eq!(cut(&mut only_mandatory, &graph, &mut Rng::from_seed(0)), None);
    assert_eq!(only_mandatory.len(), 2);
}

#[test]
fn crossover_fails_without_a_compatible_connection() {
    let graph = ship();
    let mut p1 = Genome::with_root(&graph, S, &[]);
    p1.grow(GenePos(0), 0, BODY, &[1.0; 3], 5);
    // A root whose mandatory link is empty offers no connection: an empty
    // p = 1 link would strip child 1 of its Body.
    let p2 = Genome::with_root(&graph, S, &[]);
    let out = crossover([&p1, &p2], &graph, &LIMITS, &LengthBounds::ANY, 3, &mut Rng::from_seed(0));
    assert_eq!(out, CrossoverOutcome { crossed: None, retries: 3 });
}

#[test]
fn crossover_length_bounds_make_it_retry() {
    let graph = ship();
    let p1 = initial(&graph, &LIMITS, [30, 30], &mut Rng::from_seed(7));
    let p2 = initial(&graph, &LIMITS, [5, 5], &mut Rng::from_seed(8));
    let bounds = LengthBounds { min: 4, max: 12 };
    let mut retried = 0;
    for i in 0..200 {
        let out = crossover([&p1, &p2], &graph, &LIMITS, &bounds, 3, &mut Rng::stream(9, &[i]));
        retried += out.retries;
        if let Some(c) = out.crossed {
            assert!(c.children.iter().all(|g| bounds.contains(g.len())));
        }
    }
    assert!(retried > 0);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn grow_keeps_genomes_valid(seed in any::<u64>(), len in 1usize..40) {
        let graph = ship();
        let mut g = random_genome(seed, len);
        let before = g.len();
        let mut rng = Rng::stream(seed, &[2]);
        if let Some(out) = grow(&mut g, &graph, &LIMITS, &mut rng) {
            g.validate(&graph).unwrap();
            prop_assert_eq!(g.len(), before + out.added);
            prop_assert!(slot_prob(&graph, &g, out.at) > 0.0);
            prop_assert_eq!(child_at(&g, out.at), Some(out.pos));
            prop_assert!(within_limits(&g, &LIMITS));
            // The new gene's mandatory links are filled unless a limit stopped them.
            let closed = g.gene(out.pos).symbol() != WING || g.gene(out.pos).link(0) != Link::Empty;
            prop_assert!(closed || g.len() == LIMITS.max_genes || g.depth(out.pos) == LIMITS.max_depth);
        } else {
            prop_assert_eq!(g.len(), before);
        }
    }

    #[test]
    fn cut_keeps_genomes_valid_and_spares_mandatory_genes(seed in any::<u64>(), len in 1usize..40) {
        let graph = ship();
        let mut g = random_genome(seed, len);
        let before = g.clone();
        if let Some(out) = cut(&mut g, &graph, &mut Rng::stream(seed, &[3])) {
            g.validate(&graph).unwrap();
            prop_assert!(slot_prob(&graph, &before, out.at) < 1.0);
            let victim = child_at(&before, out.at).unwrap();
            prop_assert_eq!(before.gene(victim).symbol(), out.symbol);
            prop_assert_eq!(out.removed, before.subtree_len(victim));
            prop_assert_eq!(g.len(), before.len() - out.removed);
            prop_assert_eq!(child_at(&g, out.at), None);
        } else {
            prop_assert_eq!(g, before);
        }
    }

    #[test]
    fn alter_redraws_one_genes_parameters(seed in any::<u64>(), len in 1usize..40) {
        let graph = ship();
        let mut g = random_genome(seed, len);
        let before = g.clone();
        let pos = alter(&mut g, &graph, &mut Rng::stream(seed, &[4])).unwrap();
        g.validate(&graph).unwrap();
        prop_assert_eq!(g.len(), before.len());
        for (a, b) in g.iter().zip(before.iter()) {
            prop_assert_eq!(a.symbol(), b.symbol());
            prop_assert_eq!(a.links().collect::<Vec<_>>(), b.links().collect::<Vec<_>>());
            if a.pos != pos {
                prop_assert_eq!(a.params().collect::<Vec<_>>(), b.params().collect::<Vec<_>>());
            }
        }
        prop_assert!(g.gene(pos).param_len() > 0);
    }

    #[test]
    fn mutate_falls_back_to_an_operator_that_applies(seed in any::<u64>()) {
        let graph = ship();
        // Only mandatory genes: cut cannot apply, so a cut-only mix must fail
        // and a cut-heavy one must fall back to grow or alter.
        let mut g = initial(&graph, &LIMITS, [1, 1], &mut Rng::from_seed(seed));
        let cut_only = MutationMix { alter: 0.0, grow: 0.0, cut: 1.0, drift: 0.0, regrow: 0.0, ..MutationMix::default() };
        prop_assert_eq!(mutate(&mut g.clone(), &graph, &LIMITS, &cut_only, &mut Rng::from_seed(seed)), None);
        let mix = MutationMix { alter: 1.0, grow: 1.0, cut: 100.0, drift: 0.0, regrow: 0.0, ..MutationMix::default() };
        let kind = mutate(&mut g, &graph, &LIMITS, &mix, &mut Rng::from_seed(seed)).unwrap();
        prop_assert!(kind != MutationKind::Cut);
        g.validate(&graph).unwrap();
    }

    #[test]
    fn crossover_exchanges_subtrees_on_one_edge(
        s1 in any::<u64>(), s2 in any::<u64>(), l1 in 2usize..40, l2 in 1usize..40, max in 10usize..60,
    ) {
        let graph = ship();
        let (p1, p2) = (random_genome(s1, l1), random_genome(s2, l2));
        let bounds = LengthBounds { min: 3, max };
        let out = crossover([&p1, &p2], &graph, &LIMITS, &bounds, 3, &mut Rng::stream(s1 ^ s2, &[5]));
        prop_assert!(out.retries <= 3);
        let Some(Crossed { children: [c1, c2], points: [a1, a2] }) = out.crossed else {
            prop_assert_eq!(out.retries, 3);
            return Ok(());
        };
        prop_assert!(out.retries < 3);
        for c in [&c1, &c2] {
            c.validate(&graph).unwrap();
            prop_assert!(bounds.contains(c.len()) && within_limits(c, &LIMITS));
        }
        // Same edge: same parent symbol, same slot.
        let sym = p1.gene(a1.parent).symbol();
        prop_assert_eq!(p2.gene(a2.parent).symbol(), sym);
        let spec = graph.symbol(sym);
        prop_assert_eq!(spec.slot_of_link(a1.link).unwrap().0, spec.slot_of_link(a2.link).unwrap().0);
        // Parent 1's point held a gene; the subtrees moved across intact.
        let e1 = child_at(&p1, a1).unwrap();
        let e2 = child_at(&p2, a2);
        prop_assert_eq!(child_at(&c2, a2).map(|c| c2.subtree_text(c)), Some(p1.subtree_text(e1)));
        prop_assert_eq!(child_at(&c1, a1).map(|c| c1.subtree_text(c)), e2.map(|e| p2.subtree_text(e)));
        prop_assert_eq!(p2.gene(a2.parent).link(a2.link) == Link::Closed, false);
        // Nothing is created or lost.
        prop_assert_eq!(genes(&[&p1, &p2]), genes(&[&c1, &c2]));
        // Mandatory children survive: parents whose p = 1 links are all full
        // give children whose p = 1 links are all full.
        let unlimited = Limits { max_genes: usize::MAX, max_depth: usize::MAX, ..LIMITS };
        if mandatory_complete(&graph, &p1, &unlimited) && mandatory_complete(&graph, &p2, &unlimited) {
            prop_assert!(mandatory_complete(&graph, &c1, &unlimited) && mandatory_complete(&graph, &c2, &unlimited));
        }
    }
}

mod drift_and_reference {
    use super::super::drift::reflect;
    use super::super::{drift, reference_grow, reference_initial};
    use crate::fixtures::ship;
    use genform_core::genome::Link;
    use genform_core::graph::Distribution;
    use genform_core::{Genome, Limits, Rng};

    const LIMITS: Limits = Limits { max_genes: 10_000, max_depth: 50, max_primitives: 1000 };

    fn structure(g: &Genome) -> Vec<(u32, Vec<Link>)> {
        g.iter().map(|x| (x.symbol(), x.links().collect())).collect()
    }

    #[test]
    fn reflect_folds_values_into_the_bounds() {
        assert_eq!(reflect(0.3, 0.0, 1.0), 0.3);
        assert!((reflect(1.2, 0.0, 1.0) - 0.8).abs() < 1e-12);
        assert!((reflect(-0.25, 0.0, 1.0) - 0.25).abs() < 1e-12);
        assert!((reflect(2.5, 0.0, 1.0) - 0.5).abs() < 1e-12, "several widths away");
        assert_eq!(reflect(5.0, 2.0, 2.0), 2.0, "a point mass");
        assert_eq!(reflect(-3.0, 0.0, f64::INFINITY), 3.0, "one infinite bound");
        assert_eq!(reflect(-3.0, f64::NEG_INFINITY, f64::INFINITY), -3.0);
    }

    #[test]
    fn drift_moves_one_gene_s_parameters_a_little_within_their_ranges_and_keeps_the_structure() {
        let graph = ship();
        for seed in 0..200u64 {
            let g0 = super::super::initial(&graph, &LIMITS, [5, 30], &mut Rng::from_seed(seed));
            let mut g = g0.clone();
            let pos = drift(&mut g, &graph, 0.1, &mut Rng::stream(seed, &[1])).expect("ship genes have parameters");
            assert_eq!(structure(&g), structure(&g0), "seed {seed}: drift changed the structure");
            g.validate(&graph).unwrap();
            let mut changed = 0;
            for (a, b) in g0.iter().zip(g.iter()) {
                let spec = graph.symbol(a.symbol());
                for ((d, x), y) in spec.components().zip(a.params()).zip(b.params()) {
                    if x != y {
                        assert_eq!(a.pos, pos, "only the chosen gene changes");
                        changed += 1;
                    }
                    assert!(d.contains(y), "seed {seed}: {y} outside {d:?}");
                    if let Distribution::Uniform { min, max } = d {
                        // 8 standard deviations: a redraw would pass this often.
                        assert!((x - y).abs() <= 0.8 * (max - min) + 1e-12, "seed {seed}: a jump, not a drift");
                    }
                }
            }
            // A Tip has only a choice, which is redrawn and may come out the same.
            let discrete_only = graph.symbol(g.gene(pos).symbol()).name == "Tip";
            assert!(changed > 0 || discrete_only, "seed {seed}: nothing moved");
            let mut again = g0.clone();
            drift(&mut again, &graph, 0.1, &mut Rng::stream(seed, &[1]));
            assert!(again == g, "same stream, same result");
        }
    }

    #[test]
    fn drift_steps_scale_with_drift_scale() {
        let graph = ship();
        let mean_step = |scale: f64| {
            let mut total = 0.0;
            let mut n = 0.0;
            for seed in 0..300u64 {
                let g0 = super::super::initial(&graph, &LIMITS, [10, 10], &mut Rng::from_seed(seed));
                let mut g = g0.clone();
                drift(&mut g, &graph, scale, &mut Rng::stream(seed, &[2]));
                for (a, b) in g0.iter().zip(g.iter()) {
                    let spec = graph.symbol(a.symbol());
                    for ((d, x), y) in spec.components().zip(a.params()).zip(b.params()) {
                        if matches!(d, Distribution::Uniform { .. }) && x != y {
                            total += (x - y).abs();
                            n += 1.0;
                        }
                    }
                }
            }
            total / n
        };
        assert!(mean_step(0.02) * 3.0 < mean_step(0.2));
    }

    #[test]
    fn reference_grow_ignores_probabilities_never_picks_the_last_free_link_and_adds_no_closure() {
        let graph = ship();
        let mut picked = [0usize; 5];
        for seed in 0..200u64 {
            let g = reference_initial(&graph, &LIMITS, [20, 20], &mut Rng::from_seed(seed));
            assert_eq!(g.len(), 20, "root plus 19 grows");
            g.validate(&graph).unwrap();
            assert!(reference_initial(&graph, &LIMITS, [20, 20], &mut Rng::from_seed(seed)) == g, "deterministic");
            // S plus one Body: only the Body can grow; its free links are
            // next (0), wing (1, 2) and top (3); ghost (4) has p = 0.
            let mut g = reference_initial(&graph, &LIMITS, [2, 2], &mut Rng::from_seed(seed));
            assert_eq!(g.len(), 2);
            let pos = reference_grow(&mut g, &graph, &LIMITS, &mut Rng::stream(seed, &[3])).unwrap();
            assert_eq!(g.len(), 3, "no mandatory closure");
            picked[g.gene(pos).parent().unwrap().1] += 1;
        }
        assert_eq!((picked[3], picked[4]), (0, 0), "the last free link and p = 0 slots are never picked");
        assert!(picked[..3].iter().all(|&n| n > 30), "the others about equally often: {picked:?}");
    }
}

/// Root parameters — what an L-system's ranged constants become (a real in
/// `[0, 90]`, whole numbers in `1..5`, a flag in `0..1`) — stay inside
/// their ranges, and whole ones whole, through any chain of mutations and
/// crossovers.
mod root_parameters {
    use super::*;
    use genform_core::graph::Distribution;

    fn graph_with_root_parameters() -> GeneratorGraph {
        let mut graph = ship();
        graph.symbols[S as usize].params = vec![
            genform_core::ParamSpec {
                name: "angle".into(),
                components: vec![Distribution::Uniform { min: 0.0, max: 90.0 }],
            },
            genform_core::ParamSpec { name: "n".into(), components: vec![Distribution::IntRange { min: 1, max: 5 }] },
            genform_core::ParamSpec {
                name: "leafy".into(),
                components: vec![Distribution::IntRange { min: 0, max: 1 }],
            },
        ];
        graph
    }

    fn root_in_range(graph: &GeneratorGraph, g: &Genome) -> Result<(), TestCaseError> {
        let root = g.root().unwrap();
        let values: Vec<f64> = g.gene(root).params().collect();
        prop_assert_eq!(values.len(), 3);
        for (d, v) in graph.symbol(graph.root).components().zip(&values) {
            prop_assert!(d.contains(*v), "{} outside {:?}", v, d);
            if matches!(d, Distribution::IntRange { .. }) {
                prop_assert_eq!(v.fract(), 0.0);
            }
        }
        Ok(())
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        #[test]
        fn stay_in_range_through_mutation_and_crossover(seed in any::<u64>(), steps in 1usize..40) {
            let graph = graph_with_root_parameters();
            let mut rng = Rng::from_seed(seed);
            let mut a = initial(&graph, &LIMITS, [3, 20], &mut rng);
            let mut b = initial(&graph, &LIMITS, [3, 20], &mut rng);
            let bounds = LengthBounds { min: 1, max: LIMITS.max_genes + 1 };
            // Drift-heavy, so the reals are reflected at their bounds often.
            let mix = MutationMix { drift: 60.0, drift_scale: 0.5, ..MutationMix::default() };
            for _ in 0..steps {
                mutate(&mut a, &graph, &LIMITS, &mix, &mut rng);
                if let Some(Crossed { children: [c1, c2], .. }) =
                    crossover([&a, &b], &graph, &LIMITS, &bounds, 3, &mut rng).crossed
                {
                    (a, b) = (c1, c2);
                }
                a.validate(&graph).unwrap();
                root_in_range(&graph, &a)?;
                root_in_range(&graph, &b)?;
            }
        }
    }
}
