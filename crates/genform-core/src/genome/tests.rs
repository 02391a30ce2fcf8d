use super::*;
use crate::graph::tests::tiny;
use crate::rng::Rng;
use proptest::prelude::*;

/// Grows a random valid genome for the tiny graph: `steps` grow operations
/// at uniformly chosen empty links.
fn random_genome(seed: u64, steps: usize) -> Genome {
    let graph = tiny();
    let mut rng = Rng::from_seed(seed);
    let mut g = Genome::with_root(&graph, 0, &[]);
    let mut params = Vec::new();
    let mut open = Vec::new();
    for _ in 0..steps {
        open.clear();
        for gene in g.iter() {
            for (i, l) in gene.links().enumerate() {
                if l == Link::Empty {
                    open.push((gene.pos, i));
                }
            }
        }
        if open.is_empty() {
            break;
        }
        let (p, link) = open[rng.index(open.len())];
        let spec = graph.symbol(g.gene(p).symbol());
        let (slot, _) = spec.slot_of_link(link).unwrap();
        let target = spec.slots[slot].target;
        params.clear();
        graph.draw_params(target, &mut rng, &mut params);
        g.grow(p, link, target, &params, graph.symbol(target).link_len());
        if rng.bernoulli(0.1) {
            let last = g.iter().last().unwrap().pos;
            if g.gene(last).link_len() > 0 {
                g.set_closed(last, 0, true);
            }
        }
    }
    g
}

#[test]
fn grow_appends_and_links() {
    let graph = tiny();
    let mut g = Genome::with_root(&graph, 0, &[]);
    let a = g.grow(GenePos(0), 0, 1, &[1.0, 1.0, 1.0, 2.0], 3);
    let b = g.grow(a, 2, 2, &[1.0], 0);
    assert_eq!(g.len(), 3);
    assert_eq!(g.gene(GenePos(0)).link(0), Link::Child(a));
    assert_eq!(g.gene(a).link(2), Link::Child(b));
    assert_eq!(g.gene(b).parent(), Some((a, 2)));
    assert_eq!(g.depth(b), 2);
    g.validate(&graph).unwrap();
}

#[test]
fn cut_removes_subtree_and_clears_link() {
    let graph = tiny();
    let mut g = Genome::with_root(&graph, 0, &[]);
    let a = g.grow(GenePos(0), 0, 1, &[1.0, 1.0, 1.0, 2.0], 3);
    let a2 = g.grow(a, 0, 1, &[1.0, 1.0, 1.0, 3.0], 3);
    let _b = g.grow(a, 2, 2, &[1.0], 0);
    let _b2 = g.grow(a2, 2, 2, &[0.0], 0);
    assert_eq!(g.cut(a2), 2);
    assert_eq!(g.len(), 3);
    g.validate(&graph).unwrap();
    assert_eq!(g.gene(a).link(0), Link::Empty);
    assert_eq!(g.subtree_text(GenePos(0)), "0[](1[1.0, 1.0, 1.0, 2.0](_,_,2[1.0](),),)");
}

#[test]
fn validate_rejects_out_of_range_and_wrong_child() {
    let graph = tiny();
    let mut g = Genome::with_root(&graph, 0, &[]);
    let a = g.grow(GenePos(0), 0, 1, &[1.0, 1.0, 9.0, 2.0], 3);
    let e = g.validate(&graph).unwrap_err();
    assert!(e.to_string().contains("size[2]` = 9"), "{e}");
    g.set_param(a, 2, 1.0);
    g.validate(&graph).unwrap();
    g.grow(a, 0, 2, &[1.0], 0);
    let e = g.validate(&graph).unwrap_err();
    assert!(matches!(e, GenomeError::WrongChild { .. }), "{e}");
}

#[test]
fn json_rejects_bad_files_with_reasons() {
    let graph = tiny();
    let cases = [
        (r#"{"format":"x","version":1,"generator":"t","genes":[]}"#, "not a genome file"),
        (r#"{"format":"genform-genome","version":1,"generator":"t","genes":[]}"#, "empty"),
        (r#"{"format":"genform-genome","version":1,"generator":"t","genes":[{"symbol":"Q"}]}"#, "unknown symbol `Q`"),
        (
            r#"{"format":"genform-genome","version":1,"generator":"t","genes":[{"symbol":"S"},{"symbol":"B","parent":0,"slot":"a","params":{"kind":1}}]}"#,
            "holds `A`, not `B`",
        ),
        (
            r#"{"format":"genform-genome","version":1,"generator":"t","genes":[{"symbol":"S"},{"symbol":"A","parent":0,"slot":"a","params":{"size":[1,1],"k":1}}]}"#,
            "needs 3 value(s)",
        ),
        (
            r#"{"format":"genform-genome","version":1,"generator":"t","genes":[{"symbol":"S"},{"symbol":"A","parent":0,"slot":"a","params":{"size":[1,1,1],"k":7}}]}"#,
            "outside int(1, 3)",
        ),
        (
            r#"{"format":"genform-genome","version":1,"generator":"t","genes":[{"symbol":"A","params":{"size":[1,1,1],"k":1}}]}"#,
            "starts with `S`",
        ),
    ];
    for (text, want) in cases {
        let e = Genome::from_json(text, &graph).unwrap_err().to_string();
        assert!(e.contains(want), "{text}\n→ {e}\nwanted {want}");
    }
}

proptest! {
    #[test]
    fn random_genomes_are_valid_and_roundtrip_json(seed in any::<u64>(), steps in 0usize..40) {
        let graph = tiny();
        let g = random_genome(seed, steps);
        g.validate(&graph).unwrap();
        let text = g.to_json(&graph);
        let back = Genome::from_json(&text, &graph).unwrap();
        prop_assert_eq!(&back, &g);
    }

    #[test]
    fn cut_keeps_links_consistent(seed in any::<u64>(), steps in 1usize..40, pick in any::<prop::sample::Index>()) {
        let graph = tiny();
        let mut g = random_genome(seed, steps);
        let positions: Vec<GenePos> = g.iter().map(|x| x.pos).collect();
        let victim = positions[pick.index(positions.len())];
        let expect_removed = g.subtree_len(victim);
        let before = g.len();
        let removed = g.cut(victim);
        prop_assert_eq!(removed, expect_removed);
        prop_assert_eq!(g.len(), before - removed);
        if victim.0 == 0 {
            prop_assert!(g.is_empty());
        } else {
            g.validate(&graph).unwrap();
        }
    }

    #[test]
    fn graft_copies_subtree_exactly(seed in any::<u64>(), seed2 in any::<u64>(), steps in 1usize..30, pick in any::<prop::sample::Index>()) {
        let graph = tiny();
        let src = random_genome(seed, steps);
        // Pick an `A` gene from src and graft it into an empty `next` or `a` link of dst.
        let a_genes: Vec<GenePos> = src.iter().filter(|x| x.symbol() == 1).map(|x| x.pos).collect();
        prop_assume!(!a_genes.is_empty());
        let from = a_genes[pick.index(a_genes.len())];
        let mut dst = random_genome(seed2, steps);
        let slot_owner = dst.iter().find(|x| x.symbol() == 1 && x.link(1) == Link::Empty).map(|x| x.pos);
        let (parent, link) = match slot_owner {
            Some(p) => (p, 1),
            None => {
                let root = dst.root().unwrap();
                if let Link::Child(c) = dst.gene(root).link(0) { dst.cut(c); }
                (root, 0)
            }
        };
        let before = dst.len();
        let at = dst.graft(&src, from, parent, link);
        dst.validate(&graph).unwrap();
        prop_assert_eq!(dst.len(), before + src.subtree_len(from));
        prop_assert_eq!(dst.subtree_text(at), src.subtree_text(from));
    }
}
