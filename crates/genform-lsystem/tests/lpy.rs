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
fn comments_and_parameters() {
    // `Axiom: A(1)#(3)`: `#` starts a comment; A(x) --> A(x+1), 5 steps.
    let c = load("comments.lpy");
    assert_eq!(derive(&c).display(&c.alphabet, true), "A(6)");
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
    for name in ["nF", "SetColor", "Sphere", "Leaf"] {
        assert_eq!(count(&s, &d, name), 2, "{name}");
    }
    assert_eq!(
        d.display(&s.alphabet, true),
        "nF(2,0.5)SetColor(2)Sphere(0.3)LeafnF(2,0.5)SetColor(2)Sphere(0.3)LeafApex(3)"
    );
    // `Sphere` draws as `@O`.
    let sphere = s.alphabet.named("Sphere").next().unwrap();
    assert_eq!(s.alphabet.command(sphere), genform_lsystem::Command::Sphere);
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
    // `?H` is filled with the turtle's heading: (0, 0, 1) in L-Py's axes,
    // and `+` turns it towards the left (0, −1, 0).
    let s = compile_text("Axiom: ?H(0,0,0) +(90) ?H(0,0,0) ?U(0,0,0) ?L(0,0,0)\nderivation length: 1\n").unwrap();
    let d = derive(&s);
    let v: Vec<glam::DVec3> = d
        .modules(&s.alphabet)
        .filter(|(_, p)| p.len() == 3)
        .map(|(_, p)| to_lpy_axes(glam::DVec3::new(p[0], p[1], p[2])))
        .collect();
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
    let Err(d) = compile_lpy(&SourceFile::new("fibonacci.lpy", text)) else { panic!("fibonacci.lpy compiled") };
    let first = &d.items[0];
    assert_eq!(d.file.location(first.span.unwrap().start), "fibonacci.lpy:15:2");
    assert!(first.message.contains("a Python assignment in a production body"), "{}", first.message);
    assert!(first.hints[0].contains("L-Py (the Python package) runs it"));
    let cases = [
        ("import random\nAxiom: A\n", "1:1", "the Python import `import random`"),
        ("Axiom: A\nproduction:\nA :\n  if True:\n    produce B\n", "4:3", "a Python `if`"),
        ("Axiom: A\nproduction:\nA :\n  nproduce B\n  produce C\n", "4:3", "`nproduce`"),
        ("Axiom: A\ndef StartEach():\n  pass\n", "2:1", "a Python function `def StartEach`"),
        ("Axiom: A\nproduction:\nA >> B --> C\n", "3:3", "new-context operator `>>`"),
    ];
    for (text, at, what) in cases {
        let e = compile_text(text).unwrap_err();
        assert!(e.contains(&format!("t.lpy:{at}")) && e.contains(what), "{text:?}: {e}");
    }
}

#[test]
fn ls_errors_point_into_the_lpy_text() {
    // An unknown name in a successor is reported by the `.ls` compiler at
    // its place in the `.lpy` file.
    let e = compile_text("x = 2\nAxiom: A(1)\nproduction:\nA(a) --> A(a ** x + y)\n").unwrap_err();
    assert!(e.contains("unknown name `y`") && e.contains("t.lpy:4:21"), "{e}");
}

/// Runs the reader over every `.lpy` file under `LPY_CORPUS` and counts
/// the outcomes (`LPY_CORPUS=/path/to/lpy cargo test -p genform-lsystem
/// --test lpy corpus -- --ignored --nocapture`).
#[test]
#[ignore]
fn corpus() {
    let Ok(root) = std::env::var("LPY_CORPUS") else { return };
    let mut files = Vec::new();
    let mut stack = vec![std::path::PathBuf::from(root)];
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
    let (mut ok, mut outside, mut other) = (0, 0, 0);
    for p in &files {
        let text = String::from_utf8_lossy(&std::fs::read(p).unwrap()).into_owned();
        match compile_lpy(&SourceFile::new(p.display().to_string(), text)) {
            Ok(_) => {
                ok += 1;
                println!("OK {}", p.display());
            }
            Err(d) => {
                let first = &d.items[0];
                let loc = first.span.map(|s| d.file.location(s.start)).unwrap_or_default();
                if first.message.contains("Python outside the pure") {
                    outside += 1;
                    println!("OUTSIDE {} {loc}: {}", p.display(), first.message);
                } else {
                    other += 1;
                    println!("OTHER {} {loc}: {}", p.display(), first.message);
                }
            }
        }
    }
    println!("files {} ok {ok} outside {outside} other {other}", files.len());
}
