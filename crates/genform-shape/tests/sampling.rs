//! Prior sampling follows the grammar: slot and alternative frequencies
//! match their probabilities (within 3σ), links the program never reaches
//! stay empty, and the front end never panics on arbitrary input.

use genform_core::genome::{GenePos, Link};
use genform_core::{Generator, Limits, Rng, Scene, SourceFile};
use genform_shape::{NoAssets, ShapeGrammar};
use proptest::prelude::*;

fn grammar(src: &str) -> ShapeGrammar {
    match genform_shape::compile(&SourceFile::new("t.sg", src), &NoAssets) {
        Ok((g, _)) => g,
        Err(d) => panic!("{}", d.short()),
    }
}

fn within_3_sigma(hits: usize, n: usize, p: f64) {
    let f = hits as f64 / n as f64;
    let sigma = (p * (1.0 - p) / n as f64).sqrt();
    assert!((f - p).abs() < 3.0 * sigma, "frequency {f}, expected {p} ± {}", 3.0 * sigma);
}

const N: usize = 4000;

#[test]
fn slot_links_are_expressed_with_their_probability() {
    let g = grammar("S { slot a: A p 0.3 x 2; slot b: B p 0.8; a; a; b; } A { box; } B { sphere; }");
    let (mut a, mut b) = (0, 0);
    for seed in 0..N as u64 {
        let s = g.sample(&mut Rng::stream(21, &[seed]), &Limits::default()).unwrap();
        let root = s.genome.gene(GenePos(0));
        a += (0..2).filter(|&l| matches!(root.link(l), Link::Child(_))).count();
        b += matches!(root.link(2), Link::Child(_)) as usize;
    }
    within_3_sigma(a, 2 * N, 0.3);
    within_3_sigma(b, N, 0.8);
}

#[test]
fn alternatives_are_chosen_by_weight() {
    let g = grammar("S { alt { 2: { box; } 1: { sphere; } 1: { cone; } } }");
    let mut counts = [0usize; 3];
    for seed in 0..N as u64 {
        let s = g.sample(&mut Rng::stream(22, &[seed]), &Limits::default()).unwrap();
        let k = s.genome.gene(GenePos(0)).param(0) as usize;
        counts[k] += 1;
        // Expression follows the chosen alternative.
        let mut scene = Scene::new();
        g.express(&s.genome, &Limits::default(), &mut scene).unwrap();
        assert_eq!(scene.instances.len(), 1);
    }
    within_3_sigma(counts[0], N, 0.5);
    within_3_sigma(counts[1], N, 0.25);
    within_3_sigma(counts[2], N, 0.25);
}

#[test]
fn sampling_only_grows_links_the_program_reaches() {
    // The child is only invoked in the first alternative: P = 0.5 · 0.6.
    let g = grammar("S { slot c: C p 0.6; alt { 1: { c; } 1: { box; } } } C { sphere; }");
    let mut hits = 0;
    for seed in 0..N as u64 {
        let s = g.sample(&mut Rng::stream(23, &[seed]), &Limits::default()).unwrap();
        let root = s.genome.gene(GenePos(0));
        let chose_first = root.param(0) == 0.0;
        let child = matches!(root.link(0), Link::Child(_));
        assert!(chose_first || !child, "a link in an alternative not taken was grown");
        hits += child as usize;
    }
    within_3_sigma(hits, N, 0.3);
}

#[test]
fn conditions_on_parameters_gate_children() {
    let g = grammar("S { param h: uniform(0, 1); slot c: C p 1; if (h < 0.25) { c; } } C { box; }");
    let mut hits = 0;
    for seed in 0..N as u64 {
        let s = g.sample(&mut Rng::stream(24, &[seed]), &Limits::default()).unwrap();
        let root = s.genome.gene(GenePos(0));
        let child = matches!(root.link(0), Link::Child(_));
        assert_eq!(child, root.param(0) < 0.25);
        hits += child as usize;
    }
    within_3_sigma(hits, N, 0.25);
}

#[test]
fn template_chain_continuation_follows_the_index() {
    // Continue with e^{-0.4 i}: the chain reaches C<2> with probability e^{-0.4}.
    let g = grammar("S { C<0>; } C<i: 0..6> { slot next: C<i + 1> p exp(-0.4 * i); box; next; }");
    let mut reach2 = 0;
    for seed in 0..N as u64 {
        let s = g.sample(&mut Rng::stream(25, &[seed]), &Limits::default()).unwrap();
        assert!(s.genome.len() >= 3, "C<0> → C<1> has probability 1");
        reach2 += (s.genome.len() >= 4) as usize;
    }
    within_3_sigma(reach2, N, (-0.4f64).exp());
}

/// Text close to real grammars, so the fuzz reaches deep into the compiler.
fn grammar_text() -> impl Strategy<Value = String> {
    let atoms = prop::sample::select(vec![
        "S { ",
        "A { ",
        "B<i: 0..3>(a) { ",
        "}",
        "; ",
        "box",
        "sphere",
        "mesh(m)",
        "translate(1, sx, 0)",
        "rotate(y, 90)",
        "rotate(q, 1)",
        "scale(2)",
        "size(a, 1, 1)",
        "split(x) { 1: box | 1r: A } ",
        "repeat(z, 0.5) { box; } ",
        "mirror(x) { A; } ",
        "[ box; ] ",
        "alt { 1: { A; } 2: { } } ",
        "if (has(s)) { A; } else { box; } ",
        "param p: vec3 uniform(0, 1); ",
        "param q: choice(1: 0, 2: 1); ",
        "slot s: A p 0.5 x 3; ",
        "slot t: B<i + 1> p exp(-i); ",
        "B<0>(1)",
        "B<i + 1>(a)",
        "let v = p.x * 2; ",
        "A",
        "s",
        "t",
        "const k = 3; ",
        "limits genes = 50; ",
        "axiom S; ",
        "grammar \"g\"; ",
        "(",
        ")",
        "<",
        ">",
        "{",
        "1/0",
        "uniform(1, 0)",
        "tag(\"x\")",
        "\"",
        "/*",
        "//",
        "\n",
        "é",
        "0..",
        ",",
        ":",
        "|",
    ]);
    prop::collection::vec(atoms, 0..40).prop_map(|v| v.concat())
}

/// A random valid rule body over the slots `s` (→ A) and `t` (→ B) and the
/// parameter `p`.
fn body() -> impl Strategy<Value = String> {
    let leaf = prop::sample::select(vec![
        "box;",
        "sphere;",
        "cone;",
        "frustum(p.y);",
        "taper_box(0.5);",
        "s;",
        "t(index);",
        "translate(1, sx, 0);",
        "rotate(y, p.x * 90);",
        "rotate(z, 30);",
        "scale(p);",
        "scale(0.5);",
        "size(1, 2, 3);",
        "tag(\"k\");",
        "let v = sx * depth;",
        "translate(0, count, index);",
    ])
    .prop_map(String::from);
    leaf.prop_recursive(4, 40, 4, |inner| {
        let block = prop::collection::vec(inner, 0..4).prop_map(|v| v.join(" "));
        (prop::sample::select(vec![0u8, 1, 2, 3, 4, 5, 6]), block.clone(), block).prop_map(|(k, a, b)| match k {
            0 => format!("[ {a} ]"),
            1 => format!("mirror(x) {{ {a} }}"),
            2 => format!("split(y) {{ 0.5: {{ {a} }} | 1r: {{ {b} }} | 2r: box }}"),
            3 => format!("repeat(x, 0.4) {{ {a} }}"),
            4 => format!("alt {{ 1: {{ {a} }} 2: {{ {b} }} }}"),
            5 => format!("if (has(s) || p.z > 1) {{ {a} }} else {{ {b} }}"),
            _ => format!("{a} {b}"),
        })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn valid_grammars_sample_and_express_consistently(sb in body(), ab in body(), seed in 0u64..1000) {
        let src = format!(
            "S {{ param p: vec3 uniform(0.5, 1.5); slot s: A p 0.5 x 3; slot t: B p 0.7; {sb} }}
             A {{ param p: vec3 uniform(0.5, 1.5); slot s: A p 0.3 x 3; slot t: B p 0.5; {ab} }}
             B(w) {{ size(w + 1, 1, 1); box; }}"
        );
        let g = grammar(&src);
        let limits = Limits { max_genes: 300, max_depth: 12, max_primitives: 3000 };
        let a = g.sample(&mut Rng::from_seed(seed), &limits).unwrap();
        let b = g.sample(&mut Rng::from_seed(seed), &limits).unwrap();
        prop_assert_eq!(&a.genome, &b.genome);
        prop_assert!(a.genome.validate(g.graph()).is_ok());
        let mut s1 = Scene::new();
        let r1 = g.express(&a.genome, &limits, &mut s1);
        match &r1 {
            // A run cut at the primitive limit while sampling hits it again when expressed.
            Ok(()) => prop_assert_ne!(a.truncated, Some(genform_core::LimitKind::Primitives)),
            Err(genform_core::ExpressError::Limit { .. }) => {}
            Err(e) => prop_assert!(false, "{e}"),
        }
        let mut s2 = Scene::new();
        let r2 = g.express(&a.genome, &limits, &mut s2);
        prop_assert_eq!(r1, r2);
        prop_assert_eq!(s1.instances, s2.instances);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(600))]

    #[test]
    fn compile_sample_and_express_never_panic(text in grammar_text()) {
        let file = SourceFile::new("fuzz.sg", text);
        if let Ok((g, _)) = genform_shape::compile(&file, &NoAssets) {
            let limits = Limits { max_genes: 200, max_depth: 30, max_primitives: 500 };
            if let Ok(s) = g.sample(&mut Rng::from_seed(1), &limits) {
                prop_assert!(s.genome.validate(g.graph()).is_ok());
                let _ = g.express(&s.genome, &limits, &mut Scene::new());
            }
        }
    }

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,200}") {
        let _ = genform_shape::compile(&SourceFile::new("fuzz.sg", text), &NoAssets);
    }

    #[test]
    fn mutated_examples_never_panic(cut in 0usize..4000, len in 0usize..40, insert in "\\PC{0,8}") {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/shape/spaceship_ritchie.sg");
        let mut text = std::fs::read_to_string(path).unwrap();
        let mut at = cut.min(text.len());
        while !text.is_char_boundary(at) { at -= 1; }
        let mut end = (at + len).min(text.len());
        while !text.is_char_boundary(end) { end -= 1; }
        text.replace_range(at..end, &insert);
        let file = SourceFile::new("m.sg", text);
        if let Ok((g, _)) = genform_shape::compile(&file, &NoAssets) {
            let limits = Limits { max_genes: 200, max_depth: 30, max_primitives: 500 };
            if let Ok(s) = g.sample(&mut Rng::from_seed(2), &limits) {
                let _ = g.express(&s.genome, &limits, &mut Scene::new());
            }
        }
    }
}
