//! L-Py files read as they are (`.lpy`, the pure L-system subset): real
//! files from openalea/lpy (tests/lpy/README.md), checked against module
//! counts computed by hand and L-Py's own conventions.

use genform_core::{Rng, SourceFile};
use genform_lsystem::lpy::to_lpy_axes;
use genform_lsystem::{LSystem, ModuleString, compile_lpy};
use std::path::Path;

fn load(name: &str) -> LSystem {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/lpy").join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    match compile_lpy(&SourceFile::new(name, text)) {
        Ok((system, _)) => system,
        Err(d) => panic!("{name}: {}", d.render(false)),
    }
}

fn derive(system: &LSystem) -> ModuleString {
    system.derive(system.settings.derivation, &mut Rng::from_seed(1)).unwrap()
}

fn count(system: &LSystem, s: &ModuleString, name: &str) -> usize {
    s.count(&system.alphabet, name)
}

fn compile_text(text: &str) -> Result<LSystem, String> {
    compile_lpy(&SourceFile::new("t.lpy", text)).map(|(s, _)| s).map_err(|d| d.render(false))
}

#[test]
fn koch_curves_have_four_to_the_n_segments() {
    // F(x) → 4 F(x/3) per step, written as a `produce` body; 5 steps.
    let k = load("koch-curve.lpy");
    assert_eq!(k.settings.derivation, 5);
    assert_eq!(k.settings.angle, 60.0, "PlantGL's default angle");
    let s = derive(&k);
    assert_eq!(count(&k, &s, "F"), 4usize.pow(5));
    let text = s.display(&k.alphabet, true);
    assert!(text.starts_with("_(0.001)-(90)F(0.004115226337448559)+F(0.004115226337448559)"), "{}", &text[..80]);
    // F → 8 F per step from 4 F; the angle comes from
    // `execContext().turtle.setAngleIncrement(90)`.
    let q = load("quadratic-koch-island.lpy");
    assert_eq!(q.settings.angle, 90.0);
    assert_eq!(count(&q, &derive(&q), "F"), 4 * 8usize.pow(3));
    // ABOP Fig. 1.37: constants (with `**`) and 4 F per F, 5 steps.
    let f = load("lsystem-fig1.37.lpy");
    assert_eq!(count(&f, &derive(&f), "F"), 4usize.pow(5));
}

#[test]
fn branching_and_space_filling_counts() {
    // ABOP 1.9: A(s) → F(s)[+(a)A(s/R)][-(a)A(s/R)], 11 steps.
    let t = load("lsystem1.9.lpy");
    let s = derive(&t);
    assert_eq!((count(&t, &s, "F"), count(&t, &s, "A")), (2047, 2048));
    // 3D Hilbert curve: 8^n − 1 segments.
    let h = load("hilbert3d.lpy");
    assert_eq!(count(&h, &derive(&h), "F"), 63);
    // Sierpinski: L and R each become three of them.
    let z = load("sierpinski.lpy");
    let s = derive(&z);
    assert_eq!(count(&z, &s, "L") + count(&z, &s, "R"), 3usize.pow(5));
}

#[test]
fn contexts_with_ignore_match_lpy() {
    // `B < A --> B`, `ignore: +-`: the signal reaches every apex in 3 steps.
    let b = load("13-branched-signal.lpy");
    assert_eq!(derive(&b).display(&b.alphabet, true), "B[-B]B[+B]B[-B]B");
    // `A > B --> B` on A[-A]A[+A]A[-A]B: the signal climbs down the main axis.
    let a = load("branched-signal-acropetal.lpy");
    assert_eq!(derive(&a).display(&a.alphabet, true), "B[-A]B[+A]B[-A]B");
}

#[test]
fn subdivision_circle_rewrites_three_module_predecessors() {
    // `F(x)+(a)F(y) : … produce F(x*rl)+(a/2)F(v1)F(v1)+(a/2)F(y*rl)`: each
    // corner of the square (F + F, matched left to right without overlap)
    // becomes two, 10 times over: 4·2^10 turns of 90/2^10 degrees.
    let c = load("02b-subdivision-circle.lpy");
    let s = derive(&c);
    assert_eq!((count(&c, &s, "F"), count(&c, &s, "+")), (8 * 1024, 4 * 1024));
    let turns = values(&c, &s, "+");
    assert!(turns.iter().all(|&a| a == 90.0 / 1024.0), "{:?}", &turns[..4]);
    // The polygon still closes on itself.
    let mut scene = genform_core::Scene::new();
    let end = c.interpret(&s, &mut Rng::from_seed(1), usize::MAX, &mut scene).unwrap();
    assert!(end.position.length() < 1e-9, "{}", end.position);
}

#[test]
fn interpretation_rules_with_contexts_and_several_modules() {
    // `Pt1(x,y,z)` is three modules in L-Py (`P`, `t`, `1(x,y,z)`: names
    // not declared are one character), so its interpretation rules have a
    // three-module predecessor; each draws two spheres.
    let m = load("MoveToBug.lpy");
    let s = derive(&m);
    assert_eq!(s.len(), 6);
    let mut scene = genform_core::Scene::new();
    m.interpret(&s, &mut Rng::from_seed(1), usize::MAX, &mut scene).unwrap();
    assert_eq!(scene.instances.len(), 4);
    // L-Py's paper example: `Internode(lp,rp) < Internode(l,r) --> F(l,r)`
    // under `interpretation:`; 15 internodes after 4 steps, one segment each.
    let p = load("paper12-lsystem1.lpy");
    let s = derive(&p);
    assert_eq!(count(&p, &s, "Internode"), 15);
    let end = p.interpret(&s, &mut Rng::from_seed(1), usize::MAX, &mut genform_core::Scene::new()).unwrap();
    assert_eq!(end.segments, 15);
}

#[test]
fn or_patterns_take_the_first_alternative_that_matches() {
    // `A > or( B(x)C(y)D(z), E(i), F(j)G(k) ) : … produce H`: every A
    // followed by one of the three becomes H.
    let o = load("or.lpy");
    assert_eq!(derive(&o).display(&o.alphabet, true), "HB(0)C(1)D(2)HE(4)HF(5)G(6)");
}

#[test]
fn comments_and_parameters() {
    // `Axiom: A(1)#(3)`: `#` starts a comment; A(x) --> A(x+1), 5 steps.
    let c = load("comments.lpy");
    assert_eq!(derive(&c).display(&c.alphabet, true), "A(6)");
}

#[test]
fn module_declarations_with_parameters_declare_only_the_modules() {
    // `module Apex(age), Internode(length, radius)`: two modules; before,
    // the comma inside the parentheses made `radius)` a third name.
    let t = genform_lsystem::lpy::translate(
        "module Apex(age), Internode(length,radius)\nAxiom: Apex(1)\nderivation length: 1\nproduction:\n\
         Apex(a) --> Internode(1, 0.1) Apex(a+1)\nendlsystem\n",
    )
    .unwrap();
    let decl = t.text.lines().find(|l| l.starts_with("module:")).unwrap();
    assert_eq!(decl.split_whitespace().collect::<Vec<_>>(), ["module:", "Apex", "Internode"], "{}", t.text);
    let s = compile_text(
        "module Apex(age), Internode(length,radius)\nAxiom: Apex(1)\nderivation length: 1\nproduction:\n\
         Apex(a) --> Internode(1, 0.1) Apex(a+1)\nendlsystem\n",
    )
    .unwrap();
    assert_eq!(derive(&s).display(&s.alphabet, true), "Internode(1,0.1)Apex(2)");
}

#[test]
fn long_names_are_one_module() {
    let f = load("Frame.lpy");
    assert_eq!(f.axiom.len(), 1);
    let s = compile_text(
        "module Apex, Leaf\nAxiom: Apex(1)\nderivation length: 2\nproduction:\n\
         Apex(x) --> nF(2, 0.5) SetColor(2) Sphere(0.3) Leaf Apex(x+1)\nendlsystem\n",
    )
    .unwrap();
    let d = derive(&s);
    assert_eq!(d.len(), 9);
    // `Sphere` is L-Py's other spelling of `@O`: one module, kept (and
    // printed) as `@O`; `SetColor` is a module of its own.
    for name in ["nF", "SetColor", "@O", "Leaf"] {
        assert_eq!(count(&s, &d, name), 2, "{name}");
    }
    assert_eq!(d.display(&s.alphabet, true), "nF(2,0.5)SetColor(2)@O(0.3)LeafnF(2,0.5)SetColor(2)@O(0.3)LeafApex(3)");
    let sphere = s.alphabet.named("@O").next().unwrap();
    assert_eq!(s.alphabet.command(sphere), genform_lsystem::Command::Sphere);
    // So a rule for one spelling rewrites the other.
    let s = compile_text("Axiom: Left(30) +(20)\nderivation length: 1\nproduction:\n+(a) --> Right(a)\n").unwrap();
    assert_eq!(derive(&s).display(&s.alphabet, true), "-(30)-(20)");
}

#[test]
fn produce_star_and_empty_successors_erase() {
    let s = compile_text(
        "Axiom: A B C D\nderivation length: 1\nproduction:\nA --> *\nB -->\nC :\n    produce\nD :\n    produce *\n",
    )
    .unwrap();
    assert_eq!(derive(&s).len(), 0);
}

#[test]
fn plantgl_start_frame() {
    // `?H` is filled with the turtle's heading, in L-Py's axes: (0, 0, 1),
    // and `+` turns it towards the left (0, −1, 0).
    let s = compile_text("Axiom: ?H(0,0,0) +(90) ?H(0,0,0) ?U(0,0,0) ?L(0,0,0)\nderivation length: 1\n").unwrap();
    let d = derive(&s);
    let v: Vec<glam::DVec3> =
        d.modules(&s.alphabet).filter(|(_, p)| p.len() == 3).map(|(_, p)| glam::DVec3::new(p[0], p[1], p[2])).collect();
    let near = |a: glam::DVec3, b: [f64; 3]| (a - glam::DVec3::from(b)).length() < 1e-9;
    assert!(near(v[0], [0.0, 0.0, 1.0]), "start heading {:?}", v[0]);
    assert!(near(v[1], [0.0, -1.0, 0.0]), "heading after +(90) {:?}", v[1]);
    assert!(near(v[2], [1.0, 0.0, 0.0]), "up {:?}", v[2]);
    assert!(near(v[3], [0.0, 0.0, -1.0]), "left after +(90) (the old −H) {:?}", v[3]);
    // Genform's frame: H = +y (L-Py's +z), so plants grow up in every export.
    let [h, l, u] = s.settings.heading.frame();
    assert_eq!((to_lpy_axes(h), to_lpy_axes(l), to_lpy_axes(u)), (glam::DVec3::Z, glam::DVec3::NEG_Y, glam::DVec3::X));
}

#[test]
fn python_outside_the_subset_is_an_error_at_its_position() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/lpy/fibonacci.lpy");
    let text = std::fs::read_to_string(path).unwrap();
    // test/fibonacci.lpy: `I(k) >> I(i)I(j)` (L-Py's new right context)
    // and `backward()` in a decomposition body.
    let Err(d) = compile_lpy(&SourceFile::new("fibonacci.lpy", text)) else { panic!("fibonacci.lpy compiled") };
    let first = &d.items[0];
    assert_eq!(d.file.location(first.span.unwrap().start), "fibonacci.lpy:13:6");
    assert!(first.message.contains("new-context operator `>>` is not read"), "{}", first.message);
    let python = d.items.iter().find(|i| i.message.contains("backward")).expect("backward() refused");
    assert_eq!(d.file.location(python.span.unwrap().start), "fibonacci.lpy:28:3");
    assert!(python.hints[0].contains("L-Py (the Python package) runs it"));
    let cases = [
        ("import numpy\nAxiom: A\n", "1:1", "the Python import `import numpy`"),
        ("Axiom: A\nproduction:\nA :\n  for i in range(3):\n    nproduce B\n", "4:3", "a Python `for` loop"),
        ("Axiom: A\nproduction:\nA :\n  global g\n  produce C\n", "4:3", "the Python `global` in a production body"),
        ("Axiom: A\ndef EndEach(lstring):\n  assert len(lstring) == 1\n", "2:1", "reads the derived string"),
        ("Axiom: A\nproduction:\nA --> B(x[0])\n", "3:10", "a Python subscript"),
        ("Axiom: A\nproduction:\nA --> Label('x')\n", "3:13", "a Python string"),
        ("Axiom: A\nproduction:\nA --> B(Vector3(1,0,0))\n", "3:9", "the Python call `Vector3(…)`"),
        ("Axiom: A\nproduction:\nA >> B --> C\n", "3:3", "new-context operator `>>`"),
    ];
    for (text, at, what) in cases {
        let e = compile_text(text).unwrap_err();
        assert!(e.contains(&format!("t.lpy:{at}")) && e.contains(what), "{text:?}: {e}");
    }
}

/// The values of the modules named `name`, first parameter each.
fn values(system: &LSystem, s: &ModuleString, name: &str) -> Vec<f64> {
    let syms: Vec<_> = system.alphabet.named(name).collect();
    s.modules(&system.alphabet).filter(|(m, p)| syms.contains(m) && !p.is_empty()).map(|(_, p)| p[0]).collect()
}

#[test]
fn pascal_triangles_derive_the_binomial_row() {
    // Both files grow row 10 of Pascal's triangle from U(1) in 10 steps
    // (contexts `U(x) < U(y)`, and `E` separators in the second).
    let binomial = |n: u64, k: u64| (0..k).fold(1u64, |c, i| c * (n - i) / (i + 1));
    let row: Vec<f64> = (0..=10).map(|k| binomial(10, k) as f64).collect();
    for name in ["pascaltriangle1.lpy", "pascaltriangle2.lpy"] {
        let p = load(name);
        assert_eq!(values(&p, &derive(&p), "U"), row, "{name}");
    }
}

#[test]
fn fibonacci_numbers_come_from_a_two_module_left_context() {
    // `I(j)I(k) < I(i)` with a decomposition `A(i) → I(1)A(i-1)` and
    // `derivation length: nbValue+1`: the Fibonacci numbers F(1)..F(20),
    // ending with 6765, the number L-Py's test_fibonacci.py asserts.
    let f = load("13-fibonacci.lpy");
    assert_eq!(f.settings.derivation, 21);
    let mut want = vec![1.0, 1.0];
    while want.len() < 20 {
        want.push(want[want.len() - 1] + want[want.len() - 2]);
    }
    let got = values(&f, &derive(&f), "I");
    assert_eq!(got, want);
    assert_eq!(got.last(), Some(&6765.0));
}

#[test]
fn if_bodies_and_constants_match_a_recurrence() {
    // ABOP Fig. 1.37b: `G(x,t): if t == 0: produce G(x*p,2) +(a) G(x*h,1)
    // -(2*a) G(x*h,1) +(a) G(x*q,0) / else: produce G(x,t-1)`. Modules
    // grown by one G(t) in n steps, counted independently:
    fn grown(t: u32, n: u32) -> u64 {
        match (t, n) {
            (_, 0) => 1,
            (0, n) => grown(2, n - 1) + 2 * grown(1, n - 1) + grown(0, n - 1) + 3,
            (t, n) => grown(t - 1, n - 1),
        }
    }
    let g = load("lsystem-fig1.37b.lpy");
    let s = derive(&g);
    // The axiom `_(0.002) -(90) G(1,0)`.
    assert_eq!(s.len() as u64, 2 + grown(0, 10));
    assert_eq!(s.len(), 6681);
    // h = (p*q) ** 0.5 with p = 0.3, q = 0.7: the first step's lengths.
    let first = g.derive(1, &mut Rng::from_seed(1)).unwrap();
    let h = (0.3f64 * 0.7).sqrt();
    assert_eq!(values(&g, &first, "G"), vec![0.3, h, h, 0.7]);
}

#[test]
fn doubling_curves_count_their_segments() {
    // Dragon curve: X → X+YF+, Y → -FX-Y from FX: 2^n F after n = 10 steps.
    let d = load("dragoncurve.lpy");
    assert_eq!(count(&d, &derive(&d), "F"), 1 << 10);
    // Cantor set: F(x) → F(x/3) f(x/3) F(x/3), 5 steps: 2^5 pieces of 3^-5.
    let c = load("cantorset.lpy");
    let s = derive(&c);
    let f = values(&c, &s, "F");
    assert_eq!(f.len(), 32);
    assert!(f.iter().all(|x| (x - 3f64.powi(-5)).abs() < 1e-15));
    assert_eq!(count(&c, &s, "f"), 31);
}

#[test]
fn module_aliases_draw_as_their_module() {
    // test/extension/alias.lpy: `module A = F`, A(x) --> A(x+1), 5 steps.
    let a = load("alias.lpy");
    let s = derive(&a);
    assert_eq!(s.display(&a.alphabet, true), "A(6)");
    let sym = a.alphabet.named("A").next().unwrap();
    assert_eq!(a.alphabet.command(sym), genform_lsystem::Command::Draw);
}

#[test]
fn python_bodies_hooks_and_random_draws_read() {
    // Nested `if` blocks, `random.random()`, `min`, `**` (10-random-tree),
    // hooks assigning a global and `from random import *`
    // (11a-markov-1stem), hooks, `%` and long bodies (ex_lsystem1): all
    // derive, and the same seed gives the same string.
    for name in ["10-random-tree.lpy", "11a-markov-1stem.lpy", "ex_lsystem1.lpy"] {
        let system = load(name);
        let a = derive(&system);
        let b = derive(&system);
        assert_eq!(a.display(&system.alphabet, true), b.display(&system.alphabet, true), "{name}");
        assert!(a.len() > 1, "{name}");
    }
    // Markov chain: I[M(x)]A(1-x) or IB(1-x); each step adds one I.
    let m = load("11a-markov-1stem.lpy");
    let s = derive(&m);
    assert_eq!(count(&m, &s, "I"), 99, "one I per step after S(1) → A|B");
    assert_eq!(count(&m, &s, "A") + count(&m, &s, "B"), 1);
}

/// The derived string of an inline `.lpy` text, seed 1.
fn run(text: &str) -> String {
    let s = compile_text(text).unwrap_or_else(|e| panic!("{e}"));
    derive(&s).display(&s.alphabet, true)
}

#[test]
fn the_python_subset_keeps_python_meaning() {
    // Precedence, `//`, `%` (divisor's sign), `**`, chained comparisons,
    // ternaries, True/False, n-ary max, int(); a comparison and `not` are
    // booleans, printed as L-Py prints them.
    let text = "x = 7\nAxiom: A(-7)\nderivation length: 1\nproduction:\n\
                A(a) --> B(x // 2, a % 3, -2 ** 2, 1 < x <= 7, 3 if a > 0 else 4, not a < 0, max(1, x, 3), int(-2.5))\n";
    assert_eq!(run(text), "B(3,2,-4,True,4,False,7,-2)");
    // Small functions are written out at each call, `if`/`return` included.
    let text = "def f(a, b):\n  c = a * b\n  if c > 10:\n    return c\n  return -c\n\
                def g(t): return f(t, 2) + 1\nAxiom: A(3) A(6)\nderivation length: 1\nproduction:\nA(t) --> B(g(t))\n";
    assert_eq!(run(text), "B(-5)B(13)");
    // getIterationNb() is the step being made (0 first).
    let text = "Axiom: A\nderivation length: 3\nproduction:\nA --> N(getIterationNb()) A\n";
    assert_eq!(run(text), "N(0)N(1)N(2)A");
}

#[test]
fn multi_statement_branches_and_nproduce() {
    // Branches of several statements, `elif`, nested `if`, locals,
    // augmented assignment, `nproduce` and `produce *`.
    let text = "Axiom: A(0) A(1) A(2) A(3)\nderivation length: 1\nproduction:\nA(x) :\n\
                \ty = x * 10\n\tif x == 0:\n\t\ty += 1\n\t\tnproduce N(y)\n\t\tproduce M\n\
                \telif x == 1:\n\t\tif y > 5:\n\t\t\tproduce *\n\telse:\n\t\tnproduce P(y)\n\
                \t\ty = y - 1\n\t\tnproduce P(y)\n";
    assert_eq!(run(text), "N(1)MP(20)P(19)P(30)P(29)");
}

#[test]
fn hooks_assign_globals_and_groups_switch() {
    // `def EndEach(): global n; n += 1` makes `n` a global; the
    // production reads it at every step.
    let text = "n = 0\ndef EndEach():\n  global n\n  n += 1\nAxiom: A\nderivation length: 3\n\
                production:\nA --> N(n) A\n";
    assert_eq!(run(text), "N(0)N(1)N(2)A");
    // A hook's branch of several statements (a hidden global records the
    // branch).
    let text = "n = 0\nm = 0\ndef EndEach():\n  global n, m\n  if n < 2:\n    n += 1\n    m += 10\n  else:\n\
                \x20   m = -1\nAxiom: A\nderivation length: 4\nproduction:\nA --> N(n, m) A\n";
    assert_eq!(run(text), "N(0,0)N(1,10)N(2,20)N(2,-1)A");
    // `useGroup` in StartEach alternates groups 1 and 2; group 0 always
    // applies.
    let text = "def StartEach():\n  if getIterationNb() % 2 == 0: useGroup(1)\n  else: useGroup(2)\n\
                Axiom: A C\nderivation length: 4\nproduction:\nC --> C c\ngroup 1:\nA --> B\n\
                group 2:\nB --> A\nendgroup\n";
    assert_eq!(run(text), "ACcccc");
    // Without `useGroup`, only group 0 is active.
    let text = "Axiom: A\nderivation length: 2\nproduction:\ngroup 1:\nA --> B\nendgroup\nA --> C\n";
    assert_eq!(run(text), "C");
}

#[test]
fn random_draws_come_from_the_one_stream() {
    // `random()`, `uniform`, `gauss`, `randint` map onto the `.ls` random
    // functions: same seed, same values; draws in range.
    let text = "from random import *\nimport random as rd\nseed(3)\nAxiom: A\nderivation length: 1\n\
                production:\nA --> R(random(), uniform(2, 3), rd.randint(1, 6), gauss(0, 1))\n";
    let s = compile_text(text).unwrap();
    let a = derive(&s);
    let v: Vec<f64> = a.modules(&s.alphabet).flat_map(|(_, p)| p.to_vec()).collect();
    assert!((0.0..1.0).contains(&v[0]) && (2.0..3.0).contains(&v[1]), "{v:?}");
    assert!(v[2].fract() == 0.0 && (1.0..=6.0).contains(&v[2]), "{v:?}");
    assert!(v[3].is_finite());
    assert_eq!(a.display(&s.alphabet, true), derive(&s).display(&s.alphabet, true));
    // `seed(…)` is a warning: genform's seed decides.
    let (_, w) = compile_lpy(&SourceFile::new("t.lpy", text)).unwrap();
    assert!(w.items.iter().any(|d| d.message.contains("`seed(…)` is not followed")));
}

#[test]
fn editor_scalars_and_empty_axioms() {
    let text = "Axiom: A(N)\nderivation length: 1\nproduction:\nA(x) --> A(x + 1)\nendlsystem\n\
                def __initialiseContext__(context):\n\tscalars = [('N', 'Integer', 5, 0, 9), ('B', 'Bool', True)]\n\
                \tcontext[\"__scalars__\"] = scalars\n";
    assert_eq!(run(text), "A(6)");
    // With the loop L-Py's editor writes after them (old and new editor),
    // the block holds only scalars: nothing left out, no warning.
    for lp in [
        "\tfor s in scalars:\n\t\tif not s[1] == \"Category\" : context[s[0]] = s[2]\n",
        "\tfor n,v,mnv,mxv in scalars:\n\t\tcontext[n] = v\n",
    ] {
        let file = SourceFile::new("t.lpy", format!("{text}{lp}"));
        let (_, warnings) = compile_lpy(&file).unwrap();
        assert!(warnings.items.is_empty(), "{}", warnings.short());
    }
    let s = compile_text("Axiom: \nderivation length: 2\nproduction:\nA --> B\n").unwrap();
    assert_eq!(s.axiom.len(), 0);
    assert_eq!(derive(&s).len(), 0);
    // No `Axiom:` at all (a part L-Py composes into another L-system).
    let s = compile_text("derivation length: 1\nproduction:\nI(d) --> S(d)\n").unwrap();
    assert_eq!(derive(&s).len(), 0);
}

#[test]
fn editor_scalars_with_ranges_become_ranged_constants() {
    let text = "Axiom: A(N)\nderivation length: 1\nproduction:\nA(x) --> A(x + angle)\nendlsystem\n\
                def __initialiseContext__(context):\n\tscalars = [('N', 'Integer', 5, 0, 9), ('angle', 'Float', 30.0, 0.0, 90.0, 2), \
                ('B', 'Bool', True), ('X', 18, -100, 100), ('bad', 'Integer', 12, 0, 9), ('C', 'Category')]\n";
    let t = genform_lsystem::lpy::translate(text).unwrap();
    for line in [
        "define N = 5 in 0..9\n",
        "define angle = 30 in [0, 90]\n",
        "define B = 1 in 0..1\n",
        "define X = 18 in -100..100\n",
    ] {
        assert!(t.text.contains(line), "{line:?} in\n{}", t.text);
    }
    // A value outside its slider is a plain constant, with a warning.
    assert!(t.text.contains("define bad = 12\n"), "{}", t.text);
    assert!(t.warnings.iter().any(|w| w.message.contains("range of the scalar `bad` is not used")));
    let s = compile_text(text).unwrap();
    let names: Vec<&str> = s.ranged_constants().iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["N", "angle", "B", "X"]);
    assert_eq!(genform_lsystem::lpy::translate(text).map(|t| t.text.matches("define").count()).unwrap(), 5);
    // An Integer plus a Float is a Python float.
    assert_eq!(run(text), "A(35.0)");
}

#[test]
fn no_prefix_of_a_file_panics() {
    // Every prefix of the copied files (cut at every 3rd character)
    // compiles or fails with located errors.
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/lpy");
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_none_or(|x| x != "lpy") {
            continue;
        }
        let text = std::fs::read_to_string(&p).unwrap();
        let cuts: Vec<usize> = text.char_indices().map(|(i, _)| i).step_by(3).collect();
        for k in cuts {
            let file = SourceFile::new("cut.lpy", &text[..k]);
            match compile_lpy(&file) {
                Ok((s, _)) => {
                    let _ = s.derive_limited(3, &mut Rng::from_seed(1), 2000, |_, _| {});
                }
                Err(d) => assert!(d.items.iter().all(|i| i.span.is_some()), "{}", d.render(false)),
            }
        }
    }
}

#[test]
fn ls_errors_point_into_the_lpy_text() {
    // An unknown name in a successor is reported by the `.ls` compiler at
    // its place in the `.lpy` file.
    let e = compile_text("x = 2\nAxiom: A(1)\nproduction:\nA(a) --> A(a ** x + y)\n").unwrap_err();
    assert!(e.contains("unknown name `y`") && e.contains("t.lpy:4:21"), "{e}");
}

/// Runs the reader over every `.lpy` file under `LPY_CORPUS` (a copy of
/// L-Py's repository, or its `.lpy` files with their paths), derives
/// every file it reads, and classifies the rest by their errors; with
/// `LPY_TABLE=docs/lpy-files.md` it writes the table of all files:
///
/// ```sh
/// LPY_CORPUS=/path/to/lpy LPY_TABLE=docs/lpy-files.md \
///   cargo test -p genform-lsystem --test lpy corpus -- --ignored --nocapture
/// ```
#[test]
#[ignore]
fn corpus() {
    let Ok(root) = std::env::var("LPY_CORPUS") else { return };
    let root = std::path::PathBuf::from(root);
    let mut files = Vec::new();
    let mut stack = vec![root.clone()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "lpy") {
                files.push(p);
            }
        }
    }
    files.sort();
    let mut rows = Vec::new();
    let mut counts = std::collections::BTreeMap::<&str, usize>::new();
    for p in &files {
        let rel = p.strip_prefix(&root).unwrap_or(p).display().to_string();
        let text = String::from_utf8_lossy(&std::fs::read(p).unwrap()).into_owned();
        let (kind, detail) = match compile_lpy(&SourceFile::new(rel.clone(), text.clone())) {
            Ok((system, _)) => match system.derive(system.settings.derivation, &mut Rng::from_seed(1)) {
                Ok(s) => {
                    let mut detail = format!("{} steps, {} modules", system.settings.derivation, s.len());
                    // Scalars with slider ranges are genes when the file is a generator.
                    let genes: Vec<&str> = system.ranged_constants().iter().map(|c| c.name.as_str()).collect();
                    if !genes.is_empty() {
                        let generator = genform_lsystem::LsGenerator::new(std::sync::Arc::new(system.clone()));
                        let what = if generator.is_ok() { "genes" } else { "ranged, not a generator" };
                        detail.push_str(&format!("; scalars {what}: {}", genes.join(", ")));
                    }
                    ("read", detail)
                }
                Err(e) => ("derivation error", e.to_string()),
            },
            Err(d) => {
                let located = |i: &genform_core::Diagnostic| {
                    let loc = i.span.map(|s| d.file.location(s.start)).unwrap_or_default();
                    let loc = loc.rsplit_once(".lpy:").map_or(loc.clone(), |(_, l)| l.to_string());
                    let msg = i.message.replace(": Python outside the subset genform reads from .lpy files", "");
                    format!("{loc}: {msg}")
                };
                let python = d.items.iter().find(|i| i.message.contains("Python outside the subset"));
                let editor = d.items.iter().find(|i| {
                    i.message.starts_with("unknown name `")
                        && text.contains("__initialiseContext__")
                        && i.message
                            .split('`')
                            .nth(1)
                            .is_some_and(|n| text.contains(&format!("'{n}'")) || text.contains(&format!("\"{n}\"")))
                });
                match (python, editor) {
                    (Some(i), _) => ("Python", located(i)),
                    (None, Some(i)) => ("editor", located(i)),
                    (None, None) => ("L-Py feature", located(&d.items[0])),
                }
            }
        };
        *counts.entry(kind).or_default() += 1;
        println!("{kind}\t{rel}\t{detail}");
        rows.push((rel, kind, detail));
    }
    println!("files {} {counts:?}", files.len());
    if let Ok(out) = std::env::var("LPY_TABLE") {
        let mut md = String::from(
            "# L-Py's `.lpy` files and genform's reader\n\n\
             Generated by the ignored test `corpus` of `crates/genform-lsystem/tests/lpy.rs` over the \\\n\
             `.lpy` files of openalea/lpy at commit 4a365a3 (see docs/lsystem.md, *Reading L-Py files*):\n\n\
             ```sh\n\
             LPY_CORPUS=/path/to/lpy LPY_TABLE=docs/lpy-files.md \\\n  \
             cargo test -p genform-lsystem --test lpy corpus -- --ignored --nocapture\n\
             ```\n\n\
             - **read**: translated, compiled and derived (its `derivation length`, seed 1) by the Rust reader;\n\
             - **Python**: needs Python outside the subset (the first such construct; L-Py, the Python package, runs it);\n\
             - **editor**: uses a curve, patch or function that L-Py's editor stores in the file's \\\n  \
             `__initialiseContext__` (genform reads only the editor's scalars);\n\
             - a read file's scalars with slider ranges are ranged constants: *scalars genes* when the file is \\\n  \
             a generator (context-free, no bodies or hooks), so `genform evolve` steers them; *ranged, not a \\\n  \
             generator* otherwise (docs/lsystem.md, *Evolutionary control*);\n\
             - **L-Py feature**: no Python beyond the subset, but an L-system construct the `.ls` language lacks \\\n  \
             (`<<`/`>>` contexts, `*`/`all(…)` patterns) or another error.\n\n",
        );
        md.push_str(&format!("Of {} files: ", files.len()));
        let parts: Vec<String> = counts.iter().map(|(k, n)| format!("{n} {k}")).collect();
        md.push_str(&parts.join(", "));
        md.push_str(".\n\n| file | outcome | detail |\n|---|---|---|\n");
        for (rel, kind, detail) in &rows {
            let detail = detail.replace('|', "\\|").replace('\n', " ");
            md.push_str(&format!("| `{rel}` | {kind} | {detail} |\n"));
        }
        std::fs::write(out, md).unwrap();
    }
}

/// Prints the `.ls` translation of the file `LPY_FILE` (`LPY_FILE=x.lpy
/// cargo test -p genform-lsystem --test lpy show -- --ignored --nocapture`).
#[test]
#[ignore]
fn show() {
    let Ok(path) = std::env::var("LPY_FILE") else { return };
    let text = String::from_utf8_lossy(&std::fs::read(&path).unwrap()).into_owned();
    match genform_lsystem::lpy::translate(&text) {
        Ok(t) => println!("{}", t.text),
        Err(e) => println!("{e:?}"),
    }
    match compile_lpy(&SourceFile::new(path, text)) {
        Ok((system, w)) => {
            println!("{}", w.render(false));
            let s = derive(&system);
            let text = s.display(&system.alphabet, true);
            println!("{} modules: {}", s.len(), text.chars().take(600).collect::<String>());
        }
        Err(d) => println!("{}", d.render(false)),
    }
}

/// The string of an inline `.lpy` text after `steps` steps.
fn run_steps(text: &str, steps: u32) -> String {
    let s = compile_text(text).unwrap_or_else(|e| panic!("{e}"));
    let m = s.derive(steps, &mut Rng::from_seed(1)).unwrap();
    m.display(&s.alphabet, true)
}

#[test]
fn the_string_prints_floats_and_booleans_as_python_does() {
    // `/`, float literals and `math` functions give floats, which L-Py
    // prints with their point even when whole; `//` of ints, `int`,
    // `floor` and `round(x)` give ints; comparisons give booleans.
    let text = "from math import *\nAxiom: A(4)\nderivation length: 1\nproduction:\n\
                A(x) --> B(x / 2, x // 2, 2.0 * x, sqrt(x), floor(x / 3), round(x / 3), x > 1, x + 1)\n";
    assert_eq!(run(text), "B(2.0,2,8.0,2.0,1,1,True,5)");
    // Types follow the steps: the axiom's int is gone after one step, a
    // float in a predecessor stays one through the steps that copy it.
    let text = "Axiom: A(1)\nderivation length: 3\nproduction:\nA(x) --> A(x * 2.0) C(x / 2)\nC(y) --> C(y)\n";
    assert_eq!(run(text), "A(8.0)C(2.0)C(1.0)C(0.5)");
    assert_eq!(run_steps(text, 0), "A(1)");
    assert_eq!(run_steps(text, 1), "A(2.0)C(0.5)");
    // Python's exponent notation: below 1e-4 and from 1e16.
    let text = "Axiom: A(1)\nderivation length: 1\nproduction:\nA(x) --> A(x / 100000) A(x * 1e16) A(x / 10000)\n";
    assert_eq!(run(text), "A(1e-05)A(1e+16)A(0.0001)");
    // A body's local and a module-level constant carry their type.
    let text = "dl = 0.5\nAxiom: A(3)\nderivation length: 1\nproduction:\nA(x):\n  y = x + dl\n  z = x * 2\n  produce B(y, z)\n";
    assert_eq!(run(text), "B(3.5,6)");
    // A slot that holds ints and floats prints whole values as ints (L-Py
    // would print a float's `.0`; genform keeps one number per parameter).
    let text = "Axiom: A(1) A(0.5)\nderivation length: 1\nproduction:\nA(x) --> A(x * 2)\n";
    assert_eq!(run(text), "A(2)A(1)");
    // A constant read in its own assignment keeps its type; chained
    // constants are typed once each (60 links: 2⁶⁰ reads if typed by
    // recursion).
    let text = "R = 2\nR *= R\nAxiom: A(R)\nderivation length: 0\n";
    assert_eq!(run(text), "A(4)");
    let mut text = String::from("a0 = 1.5\n");
    for i in 1..60 {
        text += &format!("a{i} = a{k} + a{k}\n", k = i - 1);
    }
    text += "Axiom: A(a59)\nderivation length: 0\n";
    assert_eq!(run(&text), "A(8.646911284551352e+17)");
    // Interpretation rules write nothing into the string.
    let text =
        "Axiom: F(1)\nderivation length: 1\nproduction:\nF(x) --> F(x + 1)\ninterpretation:\nF(x) --> F(x / 2)\n";
    assert_eq!(run(text), "F(2)");
}

#[test]
fn a_cut_acts_when_the_next_step_reads_it() {
    // L-Py cuts a branch while scanning the string, so the `%` the last
    // step wrote stays in the string, and the turtle skips what follows it.
    let s = compile_text("Axiom: A\nderivation length: 2\nproduction:\nA --> F[+X%F]A\n").unwrap();
    let d = derive(&s);
    assert_eq!(d.display(&s.alphabet, true), "F[+X]F[+X%F]A");
    let mut scene = genform_core::Scene::new();
    let end = s.interpret(&d, &mut Rng::from_seed(1), 1000, &mut scene).unwrap();
    assert_eq!(end.segments, 2, "the F after `%` is not drawn");
}

mod edited_files {
    //! L-Py's files with random edits: the reader never panics, every
    //! error has a place in the file, and what compiles derives and draws
    //! within limits.
    use super::{Path, Rng, SourceFile, compile_lpy};
    use genform_core::fixtures::assert_located;
    use proptest::prelude::{ProptestConfig, any, proptest};

    /// The repository's L-Py files.
    fn files() -> Vec<String> {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/lpy");
        let mut names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "lpy"))
            .collect();
        names.sort();
        names.iter().map(|p| std::fs::read_to_string(p).unwrap()).collect()
    }

    /// Pieces an edit inserts: L-Py's syntax, Python's, and non-ASCII.
    const PIECES: &[&str] = &[
        "(",
        ")",
        "[",
        "]",
        ":",
        "=",
        "-->",
        "+",
        "*",
        "/",
        "//",
        "**",
        ",",
        ".",
        "#",
        "\n",
        "\t",
        "  ",
        "'",
        "\"",
        "x",
        "1",
        "1.5",
        "1e-5",
        "if ",
        "else:",
        "produce ",
        "A(",
        "Sphere(",
        "Left",
        "%",
        "?P(",
        "True",
        "é",
        "→",
        "def ",
        "global ",
        "Axiom:",
        "production:",
        "endlsystem",
        "module ",
    ];

    #[test]
    fn an_error_at_the_end_of_the_file_points_at_its_end() {
        // Found by the proptest below: the missing value's span ran one
        // byte past the file.
        let text = "Axiom: A\nx =";
        let diags = compile_lpy(&SourceFile::new("end.lpy", text)).unwrap_err();
        assert_located(text, &diags);
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]
        #[test]
        fn an_edited_file_never_panics_and_locates_its_errors(
            file in 0usize..64,
            edits in proptest::collection::vec((any::<u16>(), 0usize..PIECES.len(), 0u8..3), 1..6),
        ) {
            let all = files();
            let mut text = all[file % all.len()].clone();
            for (at, piece, kind) in edits {
                let mut at = at as usize % (text.len() + 1);
                while !text.is_char_boundary(at) {
                    at -= 1;
                }
                match kind {
                    0 => text.insert_str(at, PIECES[piece]),
                    1 => {
                        let end = (at + PIECES[piece].len()).min(text.len());
                        let end = (end..=text.len()).find(|&e| text.is_char_boundary(e)).unwrap_or(text.len());
                        text.replace_range(at..end, "");
                    }
                    _ => {
                        let end = (at..=text.len()).find(|&e| e > at + 8 && text.is_char_boundary(e)).unwrap_or(text.len());
                        let copy = text[at..end].to_string();
                        text.insert_str(at, &copy);
                    }
                }
            }
            let file = SourceFile::new("edited.lpy", text.clone());
            match compile_lpy(&file) {
                Ok((s, _)) => {
                    let mut rng = Rng::from_seed(1);
                    if let Ok(m) = s.derive_limited(3, &mut rng, 5000, |_, _| {}) {
                        let _ = m.display(&s.alphabet, true);
                        let _ = s.interpret(&m, &mut rng, 5000, &mut genform_core::Scene::new());
                    }
                }
                Err(diags) => assert_located(&text, &diags),
            }
        }
    }
}
