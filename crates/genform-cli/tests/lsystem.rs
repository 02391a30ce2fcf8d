//! End-to-end tests of the L-system verbs: the real binary on the shipped
//! `examples/lsystem` files, in a temporary folder.

mod common;

use common::{Run, genform, root, s};
use std::path::PathBuf;

fn ls(name: &str) -> PathBuf {
    root().join("examples/lsystem").join(format!("{name}.ls"))
}

fn read(dir: &tempfile::TempDir, name: &str) -> Vec<u8> {
    std::fs::read(dir.path().join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn koch_svg_png_and_string_are_deterministic() {
    let tmp = tempfile::tempdir().unwrap();
    let koch = ls("koch_snowflake");
    for out in ["a.svg", "b.svg", "a.png"] {
        genform(tmp.path(), &["sample", s(&koch), "--out", out]).ok();
    }
    let svg = read(&tmp, "a.svg");
    assert_eq!(svg, read(&tmp, "b.svg"), "same input, same bytes");
    let text = String::from_utf8(svg).unwrap();
    assert!(text.starts_with("<svg") || text.starts_with("<?xml"), "{}", &text[..80.min(text.len())]);
    assert!(text.contains("<path"));
    assert_eq!(&read(&tmp, "a.png")[1..4], b"PNG");
    // --steps overrides the file's derivation length.
    let run = genform(tmp.path(), &["sample", s(&koch), "--steps", "2", "--string-out", "k.txt"]).ok();
    assert!(run.stdout().contains("2 steps: 112 modules (not drawn"), "{}", run.stdout());
    let run =
        genform(tmp.path(), &["sample", s(&koch), "--steps", "2", "--string-out", "k2.txt", "--out", "k2.svg"]).ok();
    assert!(run.stderr().contains("2 steps: 112 modules, 48 segments"), "{}", run.show());
    assert_eq!(read(&tmp, "k.txt"), read(&tmp, "k2.txt"), "the string does not depend on drawing");
    let string = String::from_utf8(read(&tmp, "k.txt")).unwrap();
    assert_eq!(string.trim_end().len(), 112);
    assert!(string.starts_with("F-F++F-F-F-F++F-F++F-F++F-F"), "{string}");
}

#[test]
fn a_string_alone_is_not_drawn_and_a_drawing_is_limited_by_memory_not_a_fixed_count() {
    let tmp = tempfile::tempdir().unwrap();
    let plant = ls("abop_1_24e");
    // 3.18 M modules, 1.05 M segments: drawn within the default memory
    // budget, refused under a small one (or an explicit limit).
    let drawn = genform(tmp.path(), &["sample", s(&plant), "--steps", "12", "--out", "p.svg"]).ok();
    assert!(drawn.stderr().contains("1054690 segments"), "{}", drawn.show());
    for extra in [&["--max-memory", "200M"][..], &["--max-primitives", "200000"][..]] {
        let args = [&["sample", s(&plant), "--steps", "12", "--out", "q.svg"][..], extra].concat();
        let refused = genform(tmp.path(), &args).fails();
        assert!(refused.stderr().contains("more than 200000 primitives"), "{}", refused.show());
    }
    assert!(!tmp.path().join("q.svg").exists());
    let run = genform(tmp.path(), &["sample", s(&plant), "--steps", "12", "--string-out", "p.txt"]).ok();
    assert!(run.stdout().contains("12 steps: 3180451 modules (not drawn"), "{}", run.show());
    assert_eq!(std::fs::metadata(tmp.path().join("p.txt")).unwrap().len(), 3180451 + 1);
}

#[test]
fn stochastic_plants_differ_by_seed_and_repeat_by_seed() {
    let tmp = tempfile::tempdir().unwrap();
    let plant = ls("stochastic_plant");
    for (seed, out) in [("1", "a.txt"), ("1", "b.txt"), ("2", "c.txt")] {
        genform(tmp.path(), &["sample", s(&plant), "--seed", seed, "--string-out", out]).ok();
    }
    assert_eq!(read(&tmp, "a.txt"), read(&tmp, "b.txt"));
    assert_ne!(read(&tmp, "a.txt"), read(&tmp, "c.txt"));
}

#[test]
fn runaway_growth_stops_with_the_step_and_the_flag() {
    let tmp = tempfile::tempdir().unwrap();
    let run = genform(tmp.path(), &["sample", s(&ls("abop_1_24a")), "--steps", "40", "--out", "x.svg"]).fails();
    let err = run.stderr();
    assert!(err.contains("step 10 of 40") && err.contains("--max-modules"), "{err}");
    assert!(!tmp.path().join("x.svg").exists(), "nothing written on failure");
    let run = genform(tmp.path(), &["sample", s(&ls("koch_snowflake")), "--max-modules", "100"]).fails();
    assert!(run.stderr().contains("past 100 modules"), "{}", run.stderr());
}

#[test]
fn grammar_errors_name_file_line_and_column() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("bad.ls"), "axiom: A(1)\nproduction:\nA(x) : y > 1 -> B\nA(x) => C\n").unwrap();
    let run: Run = genform(tmp.path(), &["sample", "bad.ls"]).fails();
    let err = run.stderr();
    assert!(err.contains("bad.ls:4:1") && err.contains("expected a production"), "{err}");
    assert!(err.contains("1 error"), "parse errors come first, all of them: {err}");
    std::fs::write(tmp.path().join("bad.ls"), "axiom: A(1)\nproduction:\nA(x) : y > 1 -> B\nA(x) -> C(sqr(x))\n")
        .unwrap();
    let err = genform(tmp.path(), &["info", "bad.ls"]).fails().stderr();
    assert!(err.contains("bad.ls:3:8") && err.contains("unknown name `y`"), "{err}");
    assert!(err.contains("bad.ls:4:11") && err.contains("did you mean `sqrt`"), "{err}");
    assert!(err.contains("2 errors"), "{err}");
}

#[test]
fn info_describes_modules_growth_and_the_generator() {
    let tmp = tempfile::tempdir().unwrap();
    let out = genform(tmp.path(), &["info", s(&ls("koch_snowflake"))]).ok().stdout();
    assert!(out.contains("modules per step (seed 0): 0: 7, 1: 28, 2: 112, 3: 448, 4: 1792"), "{out}");
    assert!(out.contains("draw forward") && out.contains("generator: 2 symbols"), "{out}");
    let out = genform(tmp.path(), &["info", s(&ls("hogeweg"))]).ok().stdout();
    assert!(out.contains("generator: none") && out.contains("context-sensitive"), "{out}");
}

#[test]
fn a_saved_genome_replays_the_same_model() {
    let tmp = tempfile::tempdir().unwrap();
    let tree = ls("evolvable_tree");
    genform(tmp.path(), &["sample", s(&tree), "--seed", "2", "--genome-out", "g.json", "--out", "a.glb"]).ok();
    genform(tmp.path(), &["derive", s(&tree), "--genome", "g.json", "--out", "b.glb"]).ok();
    assert_eq!(read(&tmp, "a.glb"), read(&tmp, "b.glb"));
    let run = genform(tmp.path(), &["sample", s(&ls("hogeweg")), "--genome-out", "h.json"]).fails();
    assert!(run.stderr().contains("context-free"), "{}", run.stderr());
}

#[test]
fn evolve_steers_the_lsystem_tree() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = root().join("examples/scenes/lsystem_tree_volume.toml");
    genform(tmp.path(), &["evolve", s(&scene), "--generations", "4", "--seed", "3", "--out", "run", "-q"]).ok();
    let run: serde_json::Value = serde_json::from_slice(&read(&tmp, "run/run.json")).unwrap();
    assert!(run["best_fitness"].as_f64().unwrap() > 0.0, "{run}");
    assert!(tmp.path().join("run/best.glb").exists());
}

#[test]
fn declared_surfaces_load_meshes_beside_the_file() {
    let tmp = tempfile::tempdir().unwrap();
    let mesh = "v -0.5 0 0\nv 0.5 0 0\nv 0 1 0\nf 1 2 3\n";
    std::fs::write(tmp.path().join("petal.obj"), mesh).unwrap();
    let file = tmp.path().join("petals.ls");
    std::fs::write(&file, "surface petal = \"petal.obj\"\naxiom: F ~petal(2) + ~petal\n").unwrap();
    genform(tmp.path(), &["sample", s(&file), "--out", "p.obj"]).ok();
    let obj = String::from_utf8(read(&tmp, "p.obj")).unwrap();
    // Two placed copies of the one-triangle petal.
    assert!(obj.lines().filter(|l| l.starts_with("f ")).count() >= 2, "{obj}");
    let missing = tmp.path().join("missing.ls");
    std::fs::write(&missing, "surface petal = \"nope.obj\"\naxiom: ~petal\n").unwrap();
    let run = genform(tmp.path(), &["sample", s(&missing), "--out", "m.obj"]).fails();
    assert!(run.stderr().contains("missing.ls:1:"), "{}", run.stderr());
}
