//! Derivations steered by a GE codon genome ([`CodonSource`]): the same
//! codons grow the same graph, other codons another one, and running out
//! of codons still ends the derivation.

use genform_core::SourceFile;
use genform_core::codons::CodonSource;
use genform_graph::{Derivation, GraphGrammar, Stop};

fn load(name: &str) -> GraphGrammar {
    let path = format!("{}/../../examples/graph/{name}.gg.yaml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    match genform_graph::compile(&SourceFile::new(path, text)) {
        Ok((g, _)) => g,
        Err(d) => panic!("{}", d.short()),
    }
}

/// A genome of `n` codons in 0..1000 from a small LCG.
fn genome(seed: u32, n: usize) -> Vec<u32> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (s >> 8) % 1000
        })
        .collect()
}

/// Derives `g` from `codons`; also returns the source.
fn derive<'a>(g: &GraphGrammar, codons: &'a [u32], max_wraps: u32) -> (Derivation, CodonSource<'a>) {
    let mut c = CodonSource::new(codons, 1000, max_wraps);
    let d = g.derive(&mut c, None, genform_graph::DEFAULT_MAX_ELEMENTS).unwrap();
    (d, c)
}

/// The graph as text: labels, positions and attributes of every element.
fn text(d: &Derivation) -> String {
    d.graph.to_yaml()
}

#[test]
fn the_same_codons_grow_the_same_tree() {
    let g = load("tree");
    let codons = genome(1, 2000);
    let (a, ca) = derive(&g, &codons, 2);
    let (b, cb) = derive(&g, &codons, 2);
    assert!(text(&a) == text(&b));
    assert_eq!((ca.used(), ca.wraps()), (cb.used(), cb.wraps()));
    assert!(ca.used() > 200 && !ca.exhausted(), "used {}", ca.used());
    // The grammar's own limits still shape it: 200 steps, 803 elements.
    assert_eq!((a.steps, a.graph.element_count()), (200, 803));
}

#[test]
fn other_codons_grow_another_tree() {
    let g = load("tree");
    let (a, _) = derive(&g, &genome(1, 2000), 2);
    let (b, _) = derive(&g, &genome(2, 2000), 2);
    assert!(text(&a) != text(&b));
    // Only the branch angles changed: the element count is the grammar's.
    assert_eq!(a.graph.element_count(), b.graph.element_count());
}

#[test]
fn koch_codons_choose_the_bumps_of_the_unfinished_generation() {
    // Oldest-match rewriting: the codons pick which of the oldest edges is
    // bumped next. After 3 + 12 + 48 = 63 steps three generations are
    // complete whatever the codons; at 192 steps the fourth is not, and
    // the codons decide which of its edges have their bumps.
    let g = load("koch");
    let points = |codons: &[u32], steps: usize| {
        let mut c = CodonSource::new(codons, 1000, 2);
        let d = g.derive(&mut c, Some(steps), genform_graph::DEFAULT_MAX_ELEMENTS).unwrap();
        assert!(!c.exhausted());
        let mut p: Vec<[i64; 2]> = d.graph.vertices().map(|v| v.pos().map(|x| (x * 1e6).round() as i64)).collect();
        p.sort();
        p
    };
    let (a, b) = (genome(1, 2000), genome(7, 2000));
    assert!(points(&a, 63) == points(&b, 63));
    assert!(points(&a, 192) == points(&a, 192));
    assert!(points(&a, 192) != points(&b, 192));
    assert_eq!(points(&a, 192).len(), 579);
}

#[test]
fn exhausted_codons_still_finish() {
    let g = load("tree");
    for codons in [&[][..], &[500, 501, 502][..]] {
        let (d, c) = derive(&g, codons, 1);
        assert!(c.exhausted());
        assert_eq!(c.used(), 2 * codons.len());
        assert_eq!((d.steps, d.stats.stop), (200, Stop::StepLimit));
        assert!(d.graph.vertices().all(|v| v.pos().iter().all(|x| x.is_finite())));
    }
    let (a, _) = derive(&g, &[], 0);
    let (b, _) = derive(&g, &[], 0);
    assert!(text(&a) == text(&b));
}
