//! Golden figures from ABOP and L-Py (`shared/reference/lsystems.md`),
//! semantics tests, and the generator.

use crate::compile::{LSystem, compile_text};
use crate::string::ModuleString;
use genform_core::{Rng, Scene, SourceFile};
use glam::DVec3;

fn system(text: &str) -> LSystem {
    match compile_text(text) {
        Ok((s, _)) => s,
        Err(e) => panic!("{e:?}"),
    }
}

fn derive(text: &str, n: u32) -> (LSystem, ModuleString) {
    let s = system(text);
    let out = s.derive(n, &mut Rng::from_seed(7)).unwrap();
    (s, out)
}

/// Draws and returns the scene's 2D bounds and the turtle's end point.
fn draw(s: &LSystem, m: &ModuleString) -> (DVec3, DVec3, DVec3) {
    let mut scene = Scene::new();
    let end = s.interpret(m, &mut Rng::from_seed(0), usize::MAX, &mut scene).unwrap();
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for l in &scene.polylines {
        for p in l.points {
            lo = lo.min(p.as_dvec3());
            hi = hi.max(p.as_dvec3());
        }
    }
    (lo, hi, end.position)
}

const KOCH: &str = "angle: 60\nheading: +x\naxiom: F++F++F\nproduction:\nF -> F-F++F-F\n";

#[test]
fn koch_snowflake_lengths_counts_and_bounds() {
    for (n, len, f) in [(0, 7, 3), (1, 28, 12), (2, 112, 48), (3, 448, 192), (4, 1792, 768)] {
        let (s, m) = derive(KOCH, n);
        assert_eq!((m.len(), m.count(&s.alphabet, "F")), (len, f), "n = {n}");
    }
    let (s, m) = derive(KOCH, 4);
    let (lo, hi, end) = draw(&s, &m);
    // f32 scene coordinates: compare to 1e-3.
    assert!((lo.x - 0.0).abs() < 1e-3 && (hi.x - 81.0).abs() < 1e-3, "{lo} {hi}");
    assert!((lo.y + 23.383).abs() < 1e-3 && (hi.y - 70.148).abs() < 1e-3, "{lo} {hi}");
    assert!(end.length() < 1e-9, "a closed curve ends where it starts: {end}");
}

#[test]
fn quadratic_koch_island() {
    let text = "angle: 90\nheading: +x\naxiom: F-F-F-F\nproduction:\nF -> F-F+F+FF-F-F+F\n";
    for (n, len, f) in [(1, 59, 32), (2, 475, 256), (3, 3803, 2048)] {
        let (s, m) = derive(text, n);
        assert_eq!((m.len(), m.count(&s.alphabet, "F")), (len, f), "n = {n}");
    }
    let (s, m) = derive(text, 3);
    let (lo, hi, end) = draw(&s, &m);
    assert_eq!([lo.x, lo.y, hi.x, hi.y].map(f64::round), [-21.0, -85.0, 85.0, 21.0]);
    assert!(end.length() < 1e-9);
}

#[test]
fn signal_propagates_one_cell_per_step() {
    let text = "axiom: baaaaaaaa\nproduction:\nb < a -> b\nb -> a\n";
    let s = system(text);
    let mut rng = Rng::from_seed(0);
    for n in 0..9 {
        let m = s.derive(n, &mut rng).unwrap();
        let expect: String = (0..9).map(|i| if i == n as usize { 'b' } else { 'a' }).collect();
        assert_eq!(m.display(&s.alphabet, false), expect);
    }
}

pub(crate) const HOGEWEG: &str = "angle: 22.5\nignore: + - F\naxiom: F1F1F1\nproduction:\n\
    0 < 0 > 0 -> 0\n0 < 0 > 1 -> 1[+F1F1]\n0 < 1 > 0 -> 1\n0 < 1 > 1 -> 1\n\
    1 < 0 > 0 -> 0\n1 < 0 > 1 -> 1F1\n1 < 1 > 0 -> 0\n1 < 1 > 1 -> 0\n+ -> -\n- -> +\n";

#[test]
fn hogeweg_context_sensitive_strings() {
    let s = system(HOGEWEG);
    let at = |n| s.derive(n, &mut Rng::from_seed(0)).unwrap();
    assert_eq!(at(1).display(&s.alphabet, false), "F1F0F1");
    assert_eq!(at(2).display(&s.alphabet, false), "F1F1F1F1");
    assert_eq!(at(5).display(&s.alphabet, false), "F1F1F1F1[-F0F1]F1");
    assert_eq!(at(10).display(&s.alphabet, false), "F1F0F0F0[+F1F1F1]F1F1[-F1F0F1][+F1F0F0F1F1F1]F1");
    let m = at(30);
    assert_eq!((m.len(), m.count(&s.alphabet, "F"), m.count(&s.alphabet, "[")), (6910, 2501, 636));
}

#[test]
fn left_context_skips_sibling_branches_and_right_context_stops_at_branch_end() {
    // B's left neighbour across the sibling branch [C] is A; D inside a
    // branch has no right context past `]`.
    let text = "axiom: A[C]B[DE]\nproduction:\nA < B -> X\nD > E -> Y\nE > A -> Z\nC > B -> W\n";
    let (s, m) = derive(text, 1);
    assert_eq!(m.display(&s.alphabet, false), "A[C]X[YE]");
    // The left context steps out of a branch to its parent.
    let (s, m) = derive("axiom: A[B]\nproduction:\nA < B -> X\n", 1);
    assert_eq!(m.display(&s.alphabet, false), "A[X]");
}

/// One step of `rules` on `axiom`, displayed without parameters.
fn step(axiom: &str, rules: &str) -> String {
    let (s, m) = derive(&format!("axiom: {axiom}\nproduction:\n{rules}\n"), 1);
    m.display(&s.alphabet, false)
}

#[test]
fn bracketed_right_context_matches_a_branch_then_the_axis() {
    // ABOP §1.8: `[B]` must match a branch at that node, `C` the axis after it.
    assert_eq!(step("A[B]C", "A > [B]C -> X"), "X[B]C");
    assert_eq!(step("A[B]C", "A > C -> Y"), "Y[B]C", "a plain context skips the branch");
    assert_eq!(step("A[B]C", "A > [C] -> Z"), "A[B]C", "C is on the axis, not in a branch");
    assert_eq!(step("A[B]C", "A > [C] -> Z\nA > [B]C -> X"), "X[B]C", "the first rule fails, the second applies");
    // Non-matching branches are skipped; branches match in string order.
    assert_eq!(step("A[D][B]C", "A > [B]C -> X"), "X[D][B]C");
    assert_eq!(step("A[D][B]C", "A > [D][B]C -> X"), "X[D][B]C");
    assert_eq!(step("A[D][B]C", "A > [B][D] -> X"), "A[D][B]C");
    // The branch must grow from A's end node, not further along the axis.
    assert_eq!(step("AD[B]", "A > [B] -> X"), "AD[B]");
    // Nested branches; a branch ends at its `]`.
    assert_eq!(step("A[B[C]]", "A > [B[C]] -> X"), "X[B[C]]");
    assert_eq!(step("A[B[D]]", "A > [B[C]] -> X"), "A[B[D]]");
    assert_eq!(step("A[B]C", "A > [BC] -> X"), "A[B]C");
}

#[test]
fn abop_axial_tree_context_example() {
    // ABOP §1.8: BC < S > G[H]M applies to S in ABC[DE][SG[HI[JK]L]MNO];
    // `[H]` matches the larger branch [HI[JK]L].
    assert_eq!(step("ABC[DE][SG[HI[JK]L]MNO]", "BC < S > G[H]M -> X"), "ABC[DE][XG[HI[JK]L]MNO]");
    assert_eq!(step("ABC[DE][SG[HI[JK]L]MNO]", "BC < S > G[I]M -> X"), "ABC[DE][SG[HI[JK]L]MNO]");
}

#[test]
fn ignore_and_consider_apply_inside_bracketed_contexts() {
    assert_eq!(step("A[+B]C", "A > [B]C -> X"), "A[+B]C", "`+` blocks the branch's first module");
    let ignoring = |axiom: &str| {
        let (s, m) = derive(&format!("ignore: + f\naxiom: {axiom}\nproduction:\nA > [B]C -> X\n"), 1);
        m.display(&s.alphabet, false)
    };
    assert_eq!(ignoring("A[+B]C"), "X[+B]C");
    assert_eq!(ignoring("Af[+fB]fC"), "Xf[+fB]fC");
    let (s, m) = derive("consider: A B C\naxiom: A+[-B]DC\nproduction:\nA > [B]C -> X\n", 1);
    assert_eq!(m.display(&s.alphabet, false), "X+[-B]DC");
}

#[test]
fn bracketed_context_binds_parameters_in_pattern_order() {
    let (s, m) = derive("axiom: A(1)[B(2)]C(3)\nproduction:\nA(x) > [B(y)]C(z) -> X(x + 10*y + 100*z)\n", 1);
    assert_eq!(m.display(&s.alphabet, true), "X(321)[B(2)]C(3)");
}

#[test]
fn consider_matches_only_listed_modules() {
    let (s, m) = derive("consider: A B\naxiom: A+-fB\nproduction:\nA < B -> X\n", 1);
    assert_eq!(m.display(&s.alphabet, false), "A+-fX");
    let (s, m) = derive("axiom: A+B\nproduction:\nA < B -> X\n", 1);
    assert_eq!(m.display(&s.alphabet, false), "A+B", "without ignore, `+` blocks the context");
}

#[test]
fn parametric_koch_construction_sums() {
    // ABOP's form (δ = 86°, `--` for the 172° turn): the reference's module
    // count 2388 counts both `-`.
    let text = "define p = 0.3\ndefine q = 1 - p\ndefine h = sqrt(p*q)\nangle: 86\nheading: +x\naxiom: F(1)\n\
                production:\nF(x) -> F(x*p) + F(x*h) - - F(x*h) + F(x*q)\n";
    let s = system(text);
    let sum = |m: &ModuleString| -> f64 {
        m.modules(&s.alphabet).filter(|(sym, _)| s.alphabet.symbols[*sym as usize].name == "F").map(|(_, p)| p[0]).sum()
    };
    let m1 = s.derive(1, &mut Rng::from_seed(0)).unwrap();
    assert!((sum(&m1) - 1.9165151390).abs() < 1e-9, "{}", sum(&m1));
    let m5 = s.derive(5, &mut Rng::from_seed(0)).unwrap();
    assert_eq!((m5.len(), m5.count(&s.alphabet, "F")), (2388, 1024));
    assert!((sum(&m5) - 25.8559959446).abs() < 1e-9, "{}", sum(&m5));
}

#[test]
fn conditions_choose_the_first_matching_production() {
    let text = "axiom: A(0)\nproduction:\nA(t) : t < 2 -> A(t+1)\nA(t) : t >= 2 -> B(t*10)\n";
    let (s, m) = derive(text, 4);
    assert_eq!(m.display(&s.alphabet, true), "B(20)");
}

#[test]
fn empty_successor_deletes_and_identity_keeps() {
    let (s, m) = derive("axiom: ABC\nproduction:\nB ->\n", 1);
    assert_eq!(m.display(&s.alphabet, false), "AC");
}

#[test]
fn cut_removes_the_rest_of_the_branch() {
    let (s, m) = derive("axiom: A[BCD]E\nproduction:\nB -> %\n", 1);
    assert_eq!(m.display(&s.alphabet, false), "A[]E");
    let (s, m) = derive("axiom: A[B[C]D]E\nproduction:\nB -> X%\n", 1);
    assert_eq!(m.display(&s.alphabet, false), "A[X]E");
}

#[test]
fn decomposition_applies_recursively_up_to_its_depth() {
    let text = "axiom: A\nproduction:\nA -> B\ndecomposition:\nmaxdepth: 2\nB -> CC\nC -> DD\nD -> E\n";
    let (s, m) = derive(text, 1);
    assert_eq!(m.display(&s.alphabet, false), "DDDD", "depth 2 stops before D -> E");
}

#[test]
fn interpretation_rules_draw_without_changing_the_string() {
    let text = "heading: +x\naxiom: L\nproduction:\ninterpretation:\nL -> F+F\n";
    let (s, m) = derive(text, 3);
    assert_eq!(m.display(&s.alphabet, false), "L");
    let (_, hi, end) = draw(&s, &m);
    assert!((end - DVec3::new(1.0, 1.0, 0.0)).length() < 1e-9, "{end}");
    assert!((hi.y - 1.0).abs() < 1e-6);
}

#[test]
fn stochastic_expectation_matches_3_66_to_the_n() {
    let text = "axiom: F\nproduction:\nF -(0.33)-> F[+F]F[-F]F\nF -(0.33)-> F[+F]F\nF -(0.34)-> F[-F]F\n";
    let s = system(text);
    let runs = 2000;
    // n = 5: E[#F] = 3.66^5 = 656.7581. Each F also adds on average
    // 0.33·6 + 0.33·3 + 0.34·3 = 3.99 other modules, which stay, so
    // E[length] = 3.66^5 + 3.99·(3.66^5 − 1)/2.66 ≈ 1640.4. (The reference's
    // 1805.5674 counts 7 modules for `F[+F]F`; these productions have 6.)
    // The mean of 2000 seeded runs lies within 3 standard errors of both.
    let f5 = 3.66f64.powi(5);
    let len5 = f5 + 3.99 * (f5 - 1.0) / 2.66;
    let (mut f, mut len) = (Vec::with_capacity(runs), Vec::with_capacity(runs));
    for seed in 0..runs as u64 {
        let m = s.derive(5, &mut Rng::from_seed(seed)).unwrap();
        f.push(m.count(&s.alphabet, "F") as f64);
        len.push(m.len() as f64);
    }
    for (values, expect) in [(&f, f5), (&len, len5)] {
        let mean = values.iter().sum::<f64>() / runs as f64;
        let var = values.iter().map(|c| (c - mean).powi(2)).sum::<f64>() / (runs - 1) as f64;
        let se = (var / runs as f64).sqrt();
        assert!((mean - expect).abs() < 3.0 * se, "mean {mean} vs {expect} (se {se})");
    }
    // Fixed seeds pin the strings.
    let m = s.derive(2, &mut Rng::from_seed(42)).unwrap();
    assert_eq!(m.display(&s.alphabet, false), "F[+F]F[-F]F[-F[-F]F]F[-F]F");
}

#[test]
fn module_limit_stops_with_the_step_and_count() {
    let text = "axiom: F\nproduction:\nF -> FF\n";
    let s = system(text);
    let e = s.derive_limited(30, &mut Rng::from_seed(0), 1000, |_, _| {}).unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("step 10 of 30") && msg.contains("1000 modules") && msg.contains("512"), "{msg}");
    // Many steps over a long string stop too.
    let s = system("axiom: A\nproduction:\nA -> A\n");
    let e = s.derive_limited(1_000_000, &mut Rng::from_seed(0), 10, |_, _| {}).unwrap_err();
    assert!(e.to_string().contains("step 2001 of 1000000"), "{e}");
    // The parametric path checks the limit too.
    let s = system("axiom: A(1)\nproduction:\nA(x) -> A(x)A(x)\n");
    let e = s.derive_limited(30, &mut Rng::from_seed(0), 1000, |_, _| {}).unwrap_err();
    assert!(e.to_string().contains("step 10 of 30"), "{e}");
}

#[test]
fn turtle_3d_frame_rotations() {
    // Heading +y, U = +z: `&` pitches H down towards −U, `/` rolls, `|`
    // turns around, `+` turns towards L = −x.
    let at = |text: &str| {
        let s = system(&format!("angle: 90\naxiom: {text}\n"));
        let (_, _, end) = draw(&s, &s.axiom);
        end
    };
    assert!((at("+F") - DVec3::new(-1.0, 0.0, 0.0)).length() < 1e-9);
    assert!((at("-F") - DVec3::new(1.0, 0.0, 0.0)).length() < 1e-9);
    assert!((at("&F") - DVec3::new(0.0, 0.0, -1.0)).length() < 1e-9);
    assert!((at("^F") - DVec3::new(0.0, 0.0, 1.0)).length() < 1e-9);
    assert!((at("/+F") - DVec3::new(0.0, 0.0, 1.0)).length() < 1e-9, "{}", at("/+F"));
    assert!((at("|F") - DVec3::new(0.0, -1.0, 0.0)).length() < 1e-9);
    assert!((at("F(2.5)") - DVec3::new(0.0, 2.5, 0.0)).length() < 1e-9);
    assert!((at("+(45)F") - DVec3::new(-0.5f64.sqrt(), 0.5f64.sqrt(), 0.0)).length() < 1e-9);
}

#[test]
fn tropism_bends_towards_the_vector() {
    let s = system("angle: 90\ntropism: 0, -1, 0\nelasticity: 0.3\naxiom: -FFFF\n");
    let (_, _, end) = draw(&s, &s.axiom);
    assert!(end.y < -0.5, "heading +x bends down under gravity: {end}");
    let straight = system("angle: 90\naxiom: -FFFF\n");
    let (_, _, e2) = draw(&straight, &straight.axiom);
    assert!((e2 - DVec3::new(4.0, 0.0, 0.0)).length() < 1e-9);
}

#[test]
fn solid_view_makes_frusta_with_taper_and_polygons() {
    let s = system("view: 3d\nwidth: 0.4\naxiom: F!(0.2)F[{.f.+f.}]\n");
    let mut scene = Scene::new();
    s.interpret(&s.axiom, &mut Rng::from_seed(0), 1000, &mut scene).unwrap();
    assert_eq!(scene.instances.len(), 2);
    assert_eq!(scene.polygons.len(), 1);
    match scene.instances[1].primitive {
        genform_core::scene::Primitive::Frustum { top } => assert!((top - 0.5).abs() < 1e-6, "{top}"),
        p => panic!("{p:?}"),
    }
    // The first cylinder: 0.4 wide, unit long, centred at y = 0.5.
    let t = scene.instances[0].transform;
    assert!((t.translation.y - 0.5).abs() < 1e-6);
    assert!((t.matrix3.x_axis.length() - 0.4).abs() < 1e-6 && t.matrix3.determinant() > 0.0);
}

#[test]
fn flat_view_joins_segments_into_polylines() {
    let s = system("axiom: FF[+F]F!(0.5)F\n");
    let mut scene = Scene::new();
    s.interpret(&s.axiom, &mut Rng::from_seed(0), 1000, &mut scene).unwrap();
    let lens: Vec<usize> = scene.polylines.iter().map(|l| l.points.len()).collect();
    assert_eq!(lens, [3, 2, 2, 2], "FF joined; the branch; F after the branch; F after the width change");
}

#[test]
fn primitive_limit_is_an_error() {
    let s = system("axiom: F+F+F+F\n");
    let mut scene = Scene::new();
    let e = s.interpret(&s.axiom, &mut Rng::from_seed(0), 0, &mut scene).unwrap_err();
    assert!(e.to_string().contains("more than 0 primitives"));
}

/// Interpretation rules that double a straight line 25 times would draw 2²⁵
/// segments into one polyline (one primitive): segments count against the
/// limit, so the turtle stops at it.
#[test]
fn segments_of_one_line_count_against_the_primitive_limit() {
    let s = system("axiom: F\ninterpretation:\nmaxdepth: 25\nF -> FF\n");
    let mut scene = Scene::new();
    let e = s.interpret(&s.axiom, &mut Rng::from_seed(0), 1000, &mut scene).unwrap_err();
    assert!(e.to_string().contains("more than 1000 primitives"), "{e}");
    let short = system("axiom: F\ninterpretation:\nmaxdepth: 9\nF -> FF\n");
    let end = short.interpret(&short.axiom, &mut Rng::from_seed(0), 1000, &mut Scene::new()).unwrap();
    assert_eq!(end.segments, 512);
}

mod generator {
    use super::*;
    use crate::generator::{GeneratorError, LsGenerator};
    use genform_core::genome::{GenePos, Link};
    use genform_core::{Generator, Limits};
    use std::sync::Arc;

    fn generator(text: &str) -> LsGenerator {
        LsGenerator::new(Arc::new(system(text))).unwrap()
    }

    #[test]
    fn a_full_prior_derivation_is_the_plain_derivation() {
        let text = "angle: 20\naxiom: X\nproduction:\nX -> F[+X]F[-X]+X\nF -> FF\n";
        let g = generator(text);
        let limits = Limits { max_depth: 5, ..g.limits() };
        let sampled = g.sample(&mut Rng::from_seed(3), &limits).unwrap();
        assert!(sampled.truncated.is_none());
        let from_genome = g.derive(&sampled.genome, &limits).unwrap();
        let plain = g.system().derive(5, &mut Rng::from_seed(0)).unwrap();
        assert_eq!(from_genome, plain);
        // One gene per rewrite: the axiom's, then every X and F rewritten.
        assert_eq!(sampled.genome.len(), 1 + count_rewrites(g.system(), 5));
        sampled.genome.validate(g.graph()).unwrap();
    }

    /// Modules rewritten over `n` steps of a deterministic system.
    fn count_rewrites(s: &LSystem, n: u32) -> usize {
        let mut total = 0;
        let rewritable = |name: &str| name == "X" || name == "F";
        let mut cur = s.axiom.clone();
        for _ in 0..n {
            total += cur.syms.iter().filter(|&&m| rewritable(&s.alphabet.symbols[m as usize].name)).count();
            cur = {
                let mut tmp = s.clone();
                tmp.axiom = cur.clone();
                tmp.derive(1, &mut Rng::from_seed(0)).unwrap()
            };
        }
        total
    }

    #[test]
    fn a_pruned_link_leaves_the_module_unrewritten() {
        let g = generator("axiom: A\nproduction:\nA -> F[+A][-A]\n");
        let limits = Limits { max_depth: 2, ..g.limits() };
        let mut genome = g.sample(&mut Rng::from_seed(1), &limits).unwrap().genome;
        assert_eq!(
            g.derive(&genome, &limits).unwrap().display(&g.system().alphabet, false),
            "F[+F[+A][-A]][-F[+A][-A]]"
        );
        // Cut the first branch's rewrite: its A stays.
        let mut positions = Vec::new();
        genome.positions_into(&mut positions);
        let first = match genome.gene(positions[1]).link(0) {
            Link::Child(c) => c,
            l => panic!("{l:?}"),
        };
        genome.cut(first);
        assert_eq!(g.derive(&genome, &limits).unwrap().display(&g.system().alphabet, false), "F[+A][-F[+A][-A]]");
    }

    #[test]
    fn genes_hold_the_choice_and_the_random_draws() {
        let text = "growth: 0.9\naxiom: A(1)\nproduction:\nA(x) -(1)-> F(x * uniform(1, 2)) A(x)\nA(x) -(3)-> F(x)\n";
        let g = generator(text);
        let spec = g.graph().symbol(1);
        let names: Vec<&str> = spec.params.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["rule", "u0"]);
        assert_eq!(spec.slots.len(), 1, "only the first production's A is rewritable");
        assert!((spec.slots[0].prob - 0.9).abs() < 1e-12);
        // rule < 1/4 picks the first production; u0 = 0.5 draws 1.5.
        let mut genome = genform_core::Genome::with_root(g.graph(), 0, &[]);
        let a = genome.grow(GenePos(0), 0, 1, &[0.1, 0.5], 1);
        let limits = g.limits();
        let s = g.derive(&genome, &limits).unwrap();
        assert_eq!(s.display(&g.system().alphabet, true), "F(1.5)A(1)");
        genome.set_params(a, &[0.3, 0.5]);
        assert_eq!(g.derive(&genome, &limits).unwrap().display(&g.system().alphabet, true), "F(1)");
    }

    #[test]
    fn prior_choices_follow_the_weights() {
        let g = generator("growth: 0.5\naxiom: A\nproduction:\nA -(1)-> B\nA -(3)-> C\n");
        let limits = g.limits();
        let runs = 4000;
        let (mut b, mut rewritten) = (0, 0);
        for seed in 0..runs {
            let s = g.sample(&mut Rng::from_seed(seed), &limits).unwrap();
            let m = g.derive(&s.genome, &limits).unwrap().display(&g.system().alphabet, false);
            if m != "A" {
                rewritten += 1;
                b += usize::from(m == "B");
            }
        }
        let p = b as f64 / rewritten as f64;
        let se = (0.25 * 0.75 / rewritten as f64).sqrt();
        assert!((p - 0.25).abs() < 3.0 * se, "P(B) = {p}");
        let q = rewritten as f64 / runs as f64;
        assert!((q - 0.5).abs() < 3.0 * (0.25 / runs as f64).sqrt(), "growth {q}");
    }

    #[test]
    fn systems_that_cannot_be_generators_say_why() {
        let ctx = LsGenerator::new(Arc::new(system(HOGEWEG))).unwrap_err();
        assert!(matches!(ctx, GeneratorError::Context(_)));
        let dec =
            LsGenerator::new(Arc::new(system("axiom: A\nproduction:\nA -> B\ndecomposition:\nB -> C\n"))).unwrap_err();
        assert!(matches!(dec, GeneratorError::Decomposition(_)));
        let growth = LsGenerator::new(Arc::new(system("axiom: A\nproduction:\nA -(1)-> B\nA -(1)-> C\n"))).unwrap_err();
        assert!(growth.to_string().contains("growth"), "{growth}");
    }

    #[test]
    fn express_draws_and_respects_limits() {
        let g = generator("view: 3d\nwidth: 0.1\naxiom: A\nproduction:\nA -> F[+A][-A]\n");
        let limits = Limits { max_depth: 6, ..g.limits() };
        let s = g.sample(&mut Rng::from_seed(0), &limits).unwrap();
        let mut scene = Scene::new();
        g.express(&s.genome, &limits, &mut scene).unwrap();
        assert_eq!(scene.instances.len(), 63);
        let tight = Limits { max_primitives: 10, ..limits };
        assert!(g.express(&s.genome, &tight, &mut Scene::new()).is_err());
        let shallow = Limits { max_depth: 3, ..limits };
        assert!(g.express(&s.genome, &shallow, &mut Scene::new()).is_err(), "genes deeper than the depth limit");
    }
}

mod properties {
    use super::{Rng, Scene, compile_text};
    use proptest::prelude::{ProptestConfig, prop_assert, proptest};

    proptest! {
        #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

        /// Python's float `repr` reads back to the same double and always
        /// shows it is a float (a point or an exponent).
        #[test]
        fn python_floats_read_back(bits in proptest::prelude::any::<u64>()) {
            let v = f64::from_bits(bits);
            let mut out = String::new();
            crate::string::python_float(&mut out, v);
            if v.is_finite() {
                prop_assert!(out.parse::<f64>().ok() == Some(v), "{v:e} printed {out}");
                prop_assert!(out.contains(['.', 'e']), "{out}");
                // Python's exponent has a sign and at least two digits.
                if let Some((_, exp)) = out.split_once('e') {
                    prop_assert!(exp.len() >= 3 && exp.starts_with(['+', '-']), "{out}");
                }
            }
        }

        /// Any text compiles or fails with diagnostics; nothing panics.
        #[test]
        fn compiling_never_panics(text in "[A-Fa-f0-9+\\-\\[\\](){}<>:,.!'%&^/|$@O#= \n*]{0,160}") {
            let _ = compile_text(&text);
            let _ = compile_text(&format!("axiom: A\nproduction:\n{text}"));
        }

        /// Statement fragments (globals, hooks, produce bodies, queries,
        /// surfaces) in any order compile or fail with diagnostics, and what
        /// compiles derives and draws without panicking.
        #[test]
        fn statements_never_panic(
            body in "(global |Start:|EndEach:|StartEach:|End:|if |elif |else:|produce |nproduce |x|y|=|1|0|/|\\+|\\{|\\}|\n|  | |A|F|\\(|\\)|\\[|\\]|:|<|iteration|~l|\\?P|,){0,40}",
            steps in 0u32..5,
        ) {
            let texts = [
                format!("global x = 0\naxiom: A ?P(0,0,0)\nStart:\n{body}\nproduction:\nA -> {{\n{body}\n}}\n"),
                format!("global x = 1\naxiom: A\nEndEach:\n  {body}\nproduction:\nA -> F ~l(x) A\n"),
            ];
            for text in texts {
                if let Ok((s, _)) = compile_text(&text)
                    && let Ok(m) = s.derive_limited(steps, &mut Rng::from_seed(1), 2000, |_, _| {})
                {
                    let _ = s.interpret(&m, &mut Rng::from_seed(1), 500, &mut Scene::new());
                }
            }
        }

        /// Deterministic, parameter-free systems take the table path (fixed
        /// 16-symbol blocks for short successors, slices for longer ones):
        /// the string is the textbook parallel rewrite of every character.
        #[test]
        fn table_rewriting_is_the_parallel_rewrite(
            axiom in "[ABF+]{1,6}",
            a in "[ABF+\\-]{0,24}",
            b in "[ABF+\\-]{0,12}",
            steps in 0u32..6,
        ) {
            let text = format!("axiom: {axiom}\nproduction:\nA -> {a}\nB -> {b}\n");
            let (s, _) = compile_text(&text).expect("compiles");
            let mut want = axiom.clone();
            for _ in 0..steps {
                want = want.chars().map(|c| match c { 'A' => a.clone(), 'B' => b.clone(), c => c.to_string() }).collect();
                if want.len() > 20_000 {
                    return Ok(());
                }
            }
            let m = s.derive_limited(steps, &mut Rng::from_seed(1), 20_000, |_, _| {}).expect("within the cap");
            prop_assert!(m.display(&s.alphabet, false) == want);
        }

        /// Random (possibly unbalanced, context-sensitive, cutting) systems
        /// derive and draw within their limits without panicking.
        #[test]
        fn deriving_and_drawing_never_panic(
            axiom in "[ABF+\\-\\[\\]f!{}.%]{1,10}",
            succ in "[ABF+\\-\\[\\]f!{}.%&^/|$]{0,10}",
            ctx in "[ABF+\\-\\[\\]f!{}.%]{0,6}",
            steps in 0u32..8,
        ) {
            let text = format!("view: 3d\nwidth: 0.1\nignore: +\naxiom: {axiom}\nproduction:\nB < A > B -> {ctx}\nA -> {succ}\nB -(1)-> {ctx}\nB -(2)-> A\n");
            if let Ok((s, _)) = compile_text(&text) {
                let cap = 2000;
                if let Ok(m) = s.derive_limited(steps, &mut Rng::from_seed(1), cap, |_, _| {}) {
                    prop_assert!(m.len() <= cap);
                    let _ = s.interpret(&m, &mut Rng::from_seed(1), 500, &mut Scene::new());
                }
            }
        }
    }
}

#[test]
fn a_non_finite_parameter_stops_the_derivation_naming_the_production_and_step() {
    let text = "axiom: A(1)\nproduction:\nA(x) : x < 3 -> A(x+1)\nA(x) -> A(x/0)F(x)\n";
    let (s, _) = crate::compile(&SourceFile::new("div.ls", text)).unwrap();
    // Steps 1 and 2 rewrite with the first production; step 3 divides by zero.
    assert_eq!(s.derive(2, &mut Rng::from_seed(1)).unwrap().params, vec![3.0]);
    let e = s.derive(5, &mut Rng::from_seed(1)).unwrap_err();
    match &e {
        crate::DeriveError::NonFinite { step, at, rule, value, .. } => {
            assert_eq!(
                (*step, at.as_str(), rule.as_str(), value.as_str()),
                (3, "div.ls:4:1", "A(x) -> A(x/0)F(x)", "inf")
            );
        }
        other => panic!("expected NonFinite, got {other}"),
    }
    assert!(e.to_string().starts_with("step 3 of 5: the production at div.ls:4:1"), "{e}");
}

#[test]
fn a_non_finite_parameter_in_a_decomposition_rule_is_an_error_too() {
    let text = "axiom: A(0)\nproduction:\nA(x) -> A(x)\ndecomposition:\nA(x) -> B(0/x)\n";
    let (s, _) = crate::compile(&SourceFile::new("dec.ls", text)).unwrap();
    let e = s.derive(1, &mut Rng::from_seed(1)).unwrap_err();
    assert!(
        matches!(&e, crate::DeriveError::NonFinite { step: 1, at, value, .. } if at == "dec.ls:5:1" && value == "NaN"),
        "{e:?}"
    );
}

/// Draws the axiom of `text` into a fresh scene.
fn scene_of(text: &str) -> (Scene, DVec3) {
    let s = system(text);
    let mut scene = Scene::new();
    let end = s.interpret(&s.axiom, &mut Rng::from_seed(0), 1000, &mut scene).unwrap();
    (scene, end.position)
}

#[test]
fn underscore_increases_the_width_as_the_inverse_of_bang() {
    // 0.49 / 0.7 = 0.7; `_(2)` sets 2; `!` then gives 1.4.
    let (scene, _) = scene_of("width: 0.49\naxiom: F _ F _(2) F ! F\n");
    let widths: Vec<f32> = scene.polylines.iter().map(|l| l.width).collect();
    let want = [0.49f32, 0.7, 2.0, 1.4];
    assert_eq!(widths.len(), want.len(), "{widths:?}");
    for (w, e) in widths.iter().zip(want) {
        assert!((w - e).abs() < 1e-6, "{widths:?}");
    }
}

#[test]
fn semicolon_and_comma_step_the_colour_index() {
    // `,` is a module now, not a parse error; it never goes below 0.
    let (scene, _) = scene_of("axiom: F ; F ; F , F , , F ;(3) F ,(1) F\n");
    let colors: Vec<&str> =
        scene.polylines.iter().map(|l| scene.tags[l.tag as usize].split('#').next().unwrap()).collect();
    assert_eq!(colors, ["color0", "color1", "color2", "color1", "color0", "color3", "color1"]);
}

#[test]
fn set_head_orients_the_frame() {
    // From +y, `@R(1,0,0, 0,0,1)` heads along +x: F ends at (1, 0, 0).
    let (_, end) = scene_of("axiom: @R(1, 0, 0, 0, 0, 1) F\n");
    assert!((end - DVec3::X).length() < 1e-12, "{end}");
    // H = (0,0,2)/2 = +z; U = (0,1,1) made perpendicular = +y; L = U × H =
    // +x, so `+(90)` turns H to +x: (0,0,1) + (1,0,0).
    let (_, end) = scene_of("axiom: @R(0, 0, 2, 0, 1, 1) F +(90) F\n");
    assert!((end - DVec3::new(1.0, 0.0, 1.0)).length() < 1e-12, "{end}");
    // A degenerate frame leaves the turtle as it was.
    let (_, end) = scene_of("axiom: @R(1, 0, 0, 2, 0, 0) F\n");
    assert!((end - DVec3::Y).length() < 1e-12, "{end}");
}

#[test]
fn scale_multiplies_lengths_and_widths_and_is_branch_local() {
    // L-Py's @D / @Di / @Dd: 2 + 2·0.5 + (1/4)·1 along +x.
    let (_, end) = scene_of("heading: +x\naxiom: @D(2) F @Di(0.5) F @Dd(4) F\n");
    assert!((end - DVec3::new(3.25, 0.0, 0.0)).length() < 1e-12, "{end}");
    let (scene, end) = scene_of("heading: +x\nwidth: 0.5\naxiom: [@D(3) F] F\n");
    assert!((end - DVec3::X).length() < 1e-12, "the scale is popped with the branch: {end}");
    assert_eq!(scene.polylines.iter().map(|l| l.width).collect::<Vec<_>>(), [1.5, 0.5]);
}

#[test]
fn width_unit_multiplies_every_given_width() {
    // 10 px · 0.01 = 0.1; !(20) → 0.2; `!` → 0.14; `_(5)` → 0.05.
    let (scene, _) = scene_of("width_unit: 0.01\nwidth: 10\naxiom: F !(20) F ! F _(5) F\n");
    let widths: Vec<f32> = scene.polylines.iter().map(|l| l.width).collect();
    for (w, e) in widths.iter().zip([0.1f32, 0.2, 0.14, 0.05]) {
        assert!((w - e).abs() < 1e-6, "{widths:?}");
    }
    assert_eq!(widths.len(), 4);
    assert!(compile_text("width_unit: 0\naxiom: F\n").is_err());
}

/// Long strings are handed over in bounded pieces that add up to the whole
/// text, with one-letter names and with parameters; an error stops it.
#[test]
fn display_pieces_add_up_to_the_text() {
    for (text, steps) in [
        ("axiom: F\nproduction:\nF -> F+F--F+F\n", 8),
        ("axiom: A(1)\nproduction:\nA(x) -> A(x + 0.5) B(x, 2) A(x * 3)\n", 14),
    ] {
        let (s, m) = derive(text, steps);
        let whole = m.display(&s.alphabet, true);
        let mut pieces = Vec::new();
        m.display_pieces(&s.alphabet, true, |p| {
            pieces.push(p.to_string());
            Ok::<(), ()>(())
        })
        .unwrap();
        assert!(pieces.len() > 2, "{} pieces of {} bytes", pieces.len(), whole.len());
        assert!(pieces.iter().all(|p| !p.is_empty() && p.len() < (1 << 16) + 64));
        assert_eq!(pieces.concat(), whole);
        let mut taken = 0;
        let stopped = m.display_pieces(&s.alphabet, true, |_| {
            taken += 1;
            if taken == 2 { Err("full") } else { Ok(()) }
        });
        assert_eq!((stopped, taken), (Err("full"), 2));
    }
}

#[test]
fn several_module_predecessors_replace_the_whole_sequence() {
    // Left to right without overlap: A A A A A → B B A.
    let (s, m) = derive("axiom: AAAAA\nproduction:\nA A -> B\n", 1);
    assert_eq!(m.display(&s.alphabet, true), "BBA");
    // Every predecessor module binds its parameters, a condition reads them
    // all, and a failed match leaves the first module to the next rule.
    let text = "axiom: A(1)B(2)A(3)B(1)\nproduction:\nA(x) B(y) : x < y -> C(x, y)\nA(x) -> D(x)\n";
    let (s, m) = derive(text, 1);
    assert_eq!(m.display(&s.alphabet, true), "C(1,2)D(3)B(1)");
    // A stochastic group of two-module rules: either way the pair goes.
    let text = "axiom: ABABAB\nproduction:\nA B -(1)-> X\nA B -(1)-> Y\n";
    let (s, m) = derive(text, 1);
    assert_eq!(m.len(), 3);
    assert_eq!(m.count(&s.alphabet, "X") + m.count(&s.alphabet, "Y"), 3);
    // The right context starts after the last predecessor module; the
    // string ends right there, so nothing matches.
    let (s, m) = derive("axiom: ABAB\nproduction:\nA B > A -> C\n", 1);
    assert_eq!(m.display(&s.alphabet, true), "CAB");
    // Evolutionary control needs a module's rewrite to depend on it alone.
    let s = system("axiom: AB\nproduction:\nA B -> C\n");
    assert!(crate::LsGenerator::new(std::sync::Arc::new(s)).is_err());
}

#[test]
fn interpretation_rules_read_contexts_and_several_modules() {
    // L-Py's lsystem1.lpy (paper 2012): an internode after another draws
    // without a width change. Here a left context and a two-module
    // predecessor choose how many segments each module draws.
    let text = "axiom: A A A P Q A\ninterpretation:\nA < A -> F F\nA -> F\nP Q -> F F F\n";
    let s = system(text);
    let mut scene = Scene::new();
    let end = s.interpret(&s.axiom, &mut Rng::from_seed(0), usize::MAX, &mut scene).unwrap();
    // A: 1, A A: 2 each, P Q: 3, the last A (after Q) 1.
    assert_eq!(end.segments, 1 + 2 + 2 + 3 + 1);
    // Queries see the same rules (the position after the segments).
    let text = "heading: +x\naxiom: A A P Q ?P(0,0,0)\nproduction:\nA -> A\ninterpretation:\nA < A -> F F\nP Q -> F F F\nA -> F\n";
    let s = system(text);
    let m = s.derive(1, &mut Rng::from_seed(0)).unwrap();
    let p = m.modules(&s.alphabet).last().unwrap().1.to_vec();
    assert!((p[0] - 6.0).abs() < 1e-9 && p[1].abs() < 1e-9, "{p:?}");
}

#[test]
fn or_patterns_bind_the_other_alternatives_to_nan() {
    // The parameters of the alternatives that did not match are NaN (a
    // module may not carry one: that is a derivation error); a name shared
    // by two alternatives binds from whichever matched.
    let text = "axiom: AB(1) AC(2) AD(3,4)\nproduction:\n\
                A > or(B(x), C(x), D(y, z)) -> K(x == x ? x : 0, y == y ? y : 0)\n";
    let (s, m) = derive(text, 1);
    assert_eq!(m.display(&s.alphabet, true), "K(1,0)B(1)K(2,0)C(2)K(0,3)D(3,4)");
    let s = system("axiom: AB(1)\nproduction:\nA > or(B(x), C(y)) -> K(y)\n");
    assert!(s.derive(1, &mut Rng::from_seed(0)).is_err());
    // Declared names are read first: `Color(…)` is no `or(…)`.
    let (s, m) = derive("module: Color\naxiom: A Color(1)\nproduction:\nA > Color(c) -> B(c)\n", 1);
    assert_eq!(m.display(&s.alphabet, true), "B(1)Color(1)");
}

#[test]
fn or_patterns_warn_only_when_no_alternative_can_apply() {
    let (_, w) = compile_text("axiom: A B\nproduction:\nor(A, Z) B -> C\n").unwrap();
    assert!(w.is_empty(), "{w:?}");
    let (_, w) = compile_text("axiom: A B\nproduction:\nor(Y, Z) B -> C\n").unwrap();
    assert_eq!(w.len(), 1, "{w:?}");
}

#[test]
fn floats_print_as_python_repr_prints_them() {
    // Each pair as CPython 3's `repr(float)` writes it.
    let cases = [
        (0.0, "0.0"),
        (-0.0, "-0.0"),
        (1e-05, "1e-05"),
        (1.5e-07, "1.5e-07"),
        (123456789012345678.0, "1.2345678901234568e+17"),
        (1e16, "1e+16"),
        (9999999999999998.0, "9999999999999998.0"),
        (0.1 + 0.2, "0.30000000000000004"),
        (1e300, "1e+300"),
        (5e-324, "5e-324"),
        (0.0001, "0.0001"),
        (-2.5e-05, "-2.5e-05"),
        (1e15, "1000000000000000.0"),
        (-3.0, "-3.0"),
        // Either side of the bounds (math.nextafter).
        (9.999999999999999e-05, "9.999999999999999e-05"),
        (0.00010000000000000002, "0.00010000000000000002"),
        // A tie between two shortest strings goes to the even digit.
        (631_496_354_690_342.0 + 0.25, "631496354690342.2"),
        (-(100_052_969_090_562.0 + 0.125), "-100052969090562.12"),
        (-9.999999999999999e-05, "-9.999999999999999e-05"),
        (f64::INFINITY, "inf"),
        (f64::NAN, "nan"),
    ];
    for (v, want) in cases {
        let mut out = String::new();
        crate::string::python_float(&mut out, v);
        assert_eq!(out, want, "{v:e}");
    }
}
