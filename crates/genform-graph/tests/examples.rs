//! The shipped examples against the paper's and the reference's figures.

use genform_core::{Rng, SourceFile};
use genform_graph::{Derivation, GraphGrammar, Stop};

fn load(name: &str) -> GraphGrammar {
    let path = format!("{}/../../examples/graph/{name}.gg.yaml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    match genform_graph::compile(&SourceFile::new(path, text)) {
        Ok((g, warnings)) => {
            assert!(warnings.items.is_empty(), "{}", warnings.short());
            g
        }
        Err(d) => panic!("{}", d.short()),
    }
}

fn run(g: &GraphGrammar, seed: u64) -> Derivation {
    g.derive(&mut Rng::from_seed(seed), None, genform_graph::DEFAULT_MAX_ELEMENTS).unwrap()
}

fn labels(d: &Derivation, label: &str) -> (usize, usize) {
    let v = d.graph.vertices().filter(|v| v.label() == label).count();
    let e = d.graph.edges().filter(|e| e.label() == label).count();
    (v, e)
}

#[test]
fn koch_snowflake_has_the_papers_1158_elements() {
    let g = load("koch");
    for seed in [1, 2] {
        let d = run(&g, seed);
        assert_eq!((d.steps, d.stats.stop), (192, Stop::StepLimit));
        assert_eq!((d.graph.vertex_count(), d.graph.edge_count()), (579, 579));
        // The bumps (1/3 of their side high) stick out of the 90-wide base.
        let xs: Vec<f64> = d.graph.vertices().map(|v| v.pos()[0]).collect();
        let (lo, hi) = xs.iter().fold((f64::MAX, f64::MIN), |(l, h), x| (l.min(*x), h.max(*x)));
        assert!(lo < -3.0 && hi > 93.0, "{lo} {hi}");
    }
}

#[test]
fn koch_at_twenty_thousand_steps() {
    let g = load("koch");
    let d = g.derive(&mut Rng::from_seed(1), Some(20_000), 1_000_000).unwrap();
    assert_eq!(d.graph.element_count(), 6 + 6 * 20_000);
}

#[test]
fn tree_has_803_elements_after_200_steps() {
    let g = load("tree");
    for seed in [1, 2, 3] {
        let d = run(&g, seed);
        assert_eq!((d.steps, d.graph.element_count()), (200, 803));
        // The trunk stops after 11 sections.
        let trunk = labels(&d, "trunk").1 + labels(&d, "trunk_tip").1;
        assert!(trunk <= 11, "{trunk}");
        assert_eq!(d.stats.applications.iter().sum::<usize>(), 200);
    }
}

#[test]
fn circle_pattern_takes_1_plus_3n_steps() {
    let g = load("circle_pattern");
    let mut ns = Vec::new();
    for seed in 0..20 {
        let d = run(&g, seed);
        let n = labels(&d, "petal").1;
        assert!((5..=15).contains(&n), "{n}");
        assert_eq!((d.steps, d.graph.element_count(), d.stats.stop), (1 + 3 * n, 2 + 2 * n, Stop::NoMatch));
        ns.push(n);
    }
    ns.sort_unstable();
    ns.dedup();
    assert!(ns.len() > 4, "petal counts vary: {ns:?}");
}

#[test]
fn square_pattern_fills_sixteen_cells() {
    let g = load("square_pattern");
    for seed in [1, 2] {
        let d = run(&g, seed);
        let (h, v) = (labels(&d, "hcell").1, labels(&d, "vcell").1);
        assert_eq!((h, v), (8, 8), "a checkerboard of directions");
        let stripes = labels(&d, "stripe").1;
        assert!((16..=64).contains(&stripes), "{stripes}");
        assert_eq!(d.stats.stop, Stop::NoMatch);
        // Every stripe lies inside the square.
        for v in d.graph.vertices() {
            let [x, y] = v.pos();
            assert!((0.0..=40.0).contains(&x) && (0.0..=40.0).contains(&y));
        }
    }
}

#[test]
fn facade_has_a_door_and_fifteen_windows() {
    let g = load("facade");
    for seed in [1, 2] {
        let d = run(&g, seed);
        assert_eq!((d.steps, d.graph.element_count()), (78, 193));
        assert_eq!(labels(&d, "door").1, 1);
        assert_eq!(labels(&d, "done").1, 15, "every window got its blind");
        assert_eq!(labels(&d, "sill").1, 15);
        assert_eq!(labels(&d, "blind").1, 15);
    }
}
