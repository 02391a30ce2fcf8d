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

/// The L-Py tree whose editor scalars are ranged constants.
fn scalar_tree() -> PathBuf {
    root().join("examples/lsystem/lpy_scalar_tree.lpy")
}

/// The root gene's values (the ranged constants) in a genome file.
fn constants(genome: &serde_json::Value) -> serde_json::Map<String, serde_json::Value> {
    assert_eq!(genome["genes"][0]["symbol"], "axiom", "{genome}");
    genome["genes"][0]["params"].as_object().unwrap().clone()
}

#[test]
fn lpy_scalars_are_genes_that_replay_and_change_the_geometry() {
    let tmp = tempfile::tempdir().unwrap();
    let tree = scalar_tree();
    let info = genform(tmp.path(), &["info", s(&tree)]).ok();
    assert!(
        info.stdout().contains("ANGLE = 35 in 10..90, DIV = 137 in 60..180, DECAY = 0.75 in [0.5, 1]"),
        "{}",
        info.show()
    );
    genform(tmp.path(), &["sample", s(&tree), "--seed", "4", "--genome-out", "g.json", "--out", "a.glb"]).ok();
    genform(tmp.path(), &["derive", s(&tree), "--genome", "g.json", "--out", "b.glb"]).ok();
    assert!(read(&tmp, "a.glb") == read(&tmp, "b.glb"), "derive replays the sampled genome");
    let mut genome: serde_json::Value = serde_json::from_slice(&read(&tmp, "g.json")).unwrap();
    // Drawn from the prior: inside the sliders' ranges, whole where Integer or Bool.
    let c = constants(&genome);
    let names: Vec<&str> = c.keys().map(String::as_str).collect();
    assert_eq!(names, ["ANGLE", "DECAY", "DIV", "LEAFY", "TRUNK"]);
    let v = |k: &str| c[k].as_f64().unwrap();
    assert!((10.0..=90.0).contains(&v("ANGLE")) && v("ANGLE").fract() == 0.0, "{c:?}");
    assert!((60.0..=180.0).contains(&v("DIV")) && v("DIV").fract() == 0.0, "{c:?}");
    assert!((0.5..=1.0).contains(&v("DECAY")) && (0.2..=2.5).contains(&v("TRUNK")), "{c:?}");
    assert!(v("LEAFY") == 0.0 || v("LEAFY") == 1.0, "{c:?}");
    // Another angle or trunk length draws another tree.
    for (key, value) in [("ANGLE", 50.0), ("TRUNK", 2.0)] {
        let mut other = genome.clone();
        other["genes"][0]["params"][key] = value.into();
        std::fs::write(tmp.path().join("o.json"), serde_json::to_vec(&other).unwrap()).unwrap();
        genform(tmp.path(), &["derive", s(&tree), "--genome", "o.json", "--out", "o.glb"]).ok();
        assert!(read(&tmp, "o.glb") != read(&tmp, "b.glb"), "{key} = {value} draws the same tree");
    }
    // The written values through the genome give what a plain sample
    // (which reads the written values) draws.
    for (key, value) in [("ANGLE", 35.0), ("DIV", 137.0), ("DECAY", 0.75), ("TRUNK", 1.2), ("LEAFY", 1.0)] {
        genome["genes"][0]["params"][key] = value.into();
    }
    std::fs::write(tmp.path().join("w.json"), serde_json::to_vec(&genome).unwrap()).unwrap();
    genform(tmp.path(), &["derive", s(&tree), "--genome", "w.json", "--out", "w.glb"]).ok();
    genform(tmp.path(), &["sample", s(&tree), "--out", "p.glb"]).ok();
    assert!(read(&tmp, "w.glb") == read(&tmp, "p.glb"), "the written values differ from a plain sample");
    // A hand-edited value outside its slider is refused.
    genome["genes"][0]["params"]["ANGLE"] = 120.0.into();
    std::fs::write(tmp.path().join("bad.json"), serde_json::to_vec(&genome).unwrap()).unwrap();
    let run = genform(tmp.path(), &["derive", s(&tree), "--genome", "bad.json", "--out", "x.glb"]).fails();
    assert!(run.stderr().contains("`ANGLE` = 120 is outside"), "{}", run.show());
}

#[test]
fn evolving_the_lpy_scalars_is_the_same_at_any_thread_count() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = root().join("examples/scenes/lpy_scalar_tree_volume.toml");
    for (out, threads) in [("one", "1"), ("three", "3")] {
        let args = ["evolve", s(&scene), "--generations", "3", "--seed", "5", "--threads", threads, "--out", out, "-q"];
        genform(tmp.path(), &args).ok();
    }
    assert_eq!(read(&tmp, "one/best-genome.json"), read(&tmp, "three/best-genome.json"));
    assert!(read(&tmp, "one/best.glb") == read(&tmp, "three/best.glb"), "best.glb differs");
    let best: serde_json::Value = serde_json::from_slice(&read(&tmp, "one/best-genome.json")).unwrap();
    assert_eq!(constants(&best).len(), 5);
    let run: serde_json::Value = serde_json::from_slice(&read(&tmp, "one/run.json")).unwrap();
    assert!(run["best_fitness"].as_f64().unwrap() > 0.0, "{run}");
}
