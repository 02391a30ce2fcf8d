//! End-to-end tests of codon scenes (grammatical evolution of `.gr8` and
//! `.ls` phenotypes, codon-driven box-split and graph grammars): the real
//! binary on small versions of the shipped scenes, in a temporary folder.

use std::path::Path;
use std::time::Duration;

mod common;
use common::{fails, fitness_columns, interrupt_evolve, json, ok, root, scored, small_scene};

/// Edits that shrink any GE scene's run.
const FEW: &[(&str, &str)] = &[("population = 100", "population = 14"), ("generations = 100", "generations = 3")];

/// Runs `scene` into `dir/out` and checks that every result file is there.
fn run_and_check(dir: &Path, scene: &Path, grammar_file: Option<&str>, generations: usize) -> serde_json::Value {
    ok(dir, &["evolve", scene.to_str().unwrap(), "--seed", "2", "--out", "run", "-q"]);
    let run = dir.join("run");
    for f in
        ["best-codons.json", "best.glb", "best.obj", "best.png", "gallery.png", "stats.csv", "fitness.svg", "run.json"]
    {
        let meta = std::fs::metadata(run.join(f)).unwrap_or_else(|_| panic!("{f} missing"));
        assert!(meta.len() > 0, "{f} is empty");
    }
    for ext in ["gr8", "ls"] {
        assert_eq!(run.join(format!("best.{ext}")).exists(), grammar_file == Some(ext), "best.{ext}");
    }
    let stats = std::fs::read_to_string(run.join("stats.csv")).unwrap();
    assert_eq!(stats.lines().count(), generations + 2, "header + generations 0..={generations}\n{stats}");
    assert!(stats.lines().next().unwrap().contains(",invalid_parse,"), "{stats}");
    let r = json(&run.join("run.json"));
    let best = json(&run.join("best-codons.json"));
    assert_eq!(r["best_fitness"], best["fitness"]);
    assert!(r["best_fitness"].as_f64().unwrap().is_finite());
    assert_eq!(r["algorithm"], "ge");
    assert!(r["invalid"].is_object() && r["invalid_by_generation"].as_array().unwrap().len() == generations + 1);
    assert!(best["codons"].as_array().unwrap().len() == r["best_length"].as_u64().unwrap() as usize);
    r
}

/// `genform sample` of `args` (the run's `best.gr8` or `best.ls`) writes
/// the very `run/best.obj` the run wrote.
fn regrows_into_best(dir: &Path, args: &[&str]) {
    // Named best.obj too: the OBJ names its material library `best.mtl`.
    ok(dir, &[&["sample"], args, &["--out", "again/best.obj"]].concat());
    for f in ["best.obj", "best.mtl"] {
        assert_eq!(
            std::fs::read(dir.join("again").join(f)).unwrap(),
            std::fs::read(dir.join("run").join(f)).unwrap(),
            "{f}"
        );
    }
}

/// `genform score` of the run's `best-codons.json` gives the run's best
/// fitness `r` to the bit; returns what it printed.
fn rescores_exactly(dir: &Path, scene: &Path, r: &serde_json::Value) -> String {
    let (fitness, text) = scored(dir, scene, "run/best-codons.json");
    assert_eq!(fitness.to_bits(), r["best_fitness"].as_f64().unwrap().to_bits(), "{text}");
    text
}

#[test]
fn genr8_canopy_runs_regrows_and_rescores() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = small_scene(tmp.path(), "genr8_canopy.toml", FEW);
    let r = run_and_check(tmp.path(), &scene, Some("gr8"), 3);
    // Four criteria, each with its contribution, summing to the fitness.
    let parts = r["best_components"].as_array().unwrap();
    assert_eq!(parts.len(), 4);
    let sum: f64 = parts.iter().map(|c| c["contribution"].as_f64().unwrap()).sum();
    assert!((sum - r["best_fitness"].as_f64().unwrap()).abs() < 1e-12);
    // best.gr8 re-grows into the same surface (the scene grows 4 steps, no environment).
    regrows_into_best(tmp.path(), &["run/best.gr8", "--steps", "4"]);
    // `score` gives the run's best fitness exactly, and every criterion.
    let text = rescores_exactly(tmp.path(), &scene, &r);
    for c in ["size", "smoothness", "subdivisions", "symmetry"] {
        assert!(text.contains(c), "{text}");
    }
    let svg = std::fs::read_to_string(tmp.path().join("run/fitness.svg")).unwrap();
    assert!(svg.contains("contribution") && svg.contains("subdivisions") && svg.contains("total"));
}

#[test]
fn genr8_paper_form_evolves_and_rescores_to_the_bit() {
    let tmp = tempfile::tempdir().unwrap();
    let scene =
        small_scene(tmp.path(), "genr8_canopy.toml", &[FEW, &[("[surface]", "[surface]\nform = \"paper\"")]].concat());
    let r = run_and_check(tmp.path(), &scene, Some("gr8"), 3);
    assert_eq!(r["max_reachable_fitness"], 0.0, "the paper form is 0 on every target");
    // −Σ w·e: each contribution is minus its weight times its error.
    let best = r["best_fitness"].as_f64().unwrap();
    let parts = r["best_components"].as_array().unwrap();
    assert_eq!(parts.len(), 4);
    let f = |c: &serde_json::Value, k: &str| c[k].as_f64().unwrap();
    for c in parts {
        assert_eq!(f(c, "contribution"), 0.0 - f(c, "weight") * f(c, "error"), "{c}");
    }
    let sum: f64 = parts.iter().map(|c| f(c, "contribution")).sum();
    assert!(best < 0.0 && (sum - best).abs() < 1e-12, "{best} vs {sum}");
    let text = rescores_exactly(tmp.path(), &scene, &r);
    assert!(text.contains("(paper form, max reachable 0)"), "{text}");
    let svg = std::fs::read_to_string(tmp.path().join("run/fitness.svg")).unwrap();
    assert!(svg.contains("contribution −w·e per criterion"));
    // Deterministic: the same seed evolves the same best genome.
    let first = std::fs::read(tmp.path().join("run/best-codons.json")).unwrap();
    ok(tmp.path(), &["evolve", scene.to_str().unwrap(), "--seed", "2", "--out", "again", "-q", "--threads", "2"]);
    assert_eq!(std::fs::read(tmp.path().join("again/best-codons.json")).unwrap(), first);
    // The bounded form of the same scene scores the same genome in (0, max].
    let bounded = small_scene(tmp.path(), "genr8_canopy.toml", FEW);
    let (b, _) = scored(tmp.path(), &bounded, "run/best-codons.json");
    assert!(b > 0.0 && b <= 4.0, "{b}");
    // An unknown form names the file, the key and both valid forms.
    let bad = small_scene(tmp.path(), "genr8_canopy.toml", &[("[surface]", "[surface]\nform = \"papr\"")]);
    let err = fails(tmp.path(), &["evolve", bad.to_str().unwrap()]);
    assert!(err.contains("genr8_canopy.toml:") && err.contains("papr"), "{err}");
    assert!(err.contains("`bounded`") && err.contains("`paper`"), "{err}");
}

#[test]
fn genr8_in_an_environment_regrows_with_the_environment() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = small_scene(tmp.path(), "genr8_undulating_box.toml", FEW);
    let r = run_and_check(tmp.path(), &scene, Some("gr8"), 3);
    let env = root().join("examples/hemls/boxes_attractors.toml");
    regrows_into_best(tmp.path(), &["run/best.gr8", "--env", env.to_str().unwrap()]);
    rescores_exactly(tmp.path(), &scene, &r);
}

#[test]
fn genr8_symmetric_scene_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = small_scene(tmp.path(), "genr8_symmetric_repellers.toml", FEW);
    let r = run_and_check(tmp.path(), &scene, Some("gr8"), 3);
    assert!(r["best_phenotype"].as_str().unwrap().contains("Angle 45"));
}

#[test]
fn ge_lsystem_scene_writes_an_ls_that_samples_into_the_same_model() {
    let tmp = tempfile::tempdir().unwrap();
    let edits = [
        ("population = 100", "population = 14"),
        ("generations = 100", "generations = 3"),
        ("voxels = [80, 80, 80]", "voxels = [24, 24, 24]"),
    ];
    let scene = small_scene(tmp.path(), "ge_lsystem_tree.toml", &edits);
    let r = run_and_check(tmp.path(), &scene, Some("ls"), 3);
    assert!(r["best_components"]["good"].as_f64().is_some());
    regrows_into_best(tmp.path(), &["run/best.ls"]);
    let text = rescores_exactly(tmp.path(), &scene, &r);
    assert!(text.contains("good") && text.contains("target"), "{text}");
}

#[test]
fn codon_box_split_scene_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let edits = [("population = 20", "population = 6"), ("generations = 30", "generations = 2")];
    let scene = small_scene(tmp.path(), "ge_castle_volume.toml", &edits);
    let r = run_and_check(tmp.path(), &scene, None, 2);
    assert_eq!(r["kind"], "box-split");
    rescores_exactly(tmp.path(), &scene, &r);
}

#[test]
fn codon_graph_scene_runs_and_draws_a_silhouette() {
    let tmp = tempfile::tempdir().unwrap();
    let edits = [("population = 50", "population = 6"), ("generations = 40", "generations = 2")];
    let scene = small_scene(tmp.path(), "ge_graph_tree_sketch.toml", &edits);
    let r = run_and_check(tmp.path(), &scene, None, 2);
    assert_eq!(r["kind"], "graph");
    assert!(r["best_components"]["good"].as_f64().unwrap() > 0.0, "the scorer sees the drawing");
    assert!(tmp.path().join("run/best-silhouette.png").exists());
}

/// Every output file but the timing fields: `stats.csv` without its
/// seconds columns, `run.json` without its timing keys; the rest byte by
/// byte (`fitness.svg` holds a fitness-by-seconds panel, so it is left out).
fn comparable(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let bytes = std::fs::read(&path).unwrap();
        let bytes = match name.as_str() {
            "fitness.svg" => continue,
            "stats.csv" => fitness_columns(&String::from_utf8(bytes).unwrap()).join("\n").into_bytes(),
            "run.json" => {
                let mut v: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
                let o = v.as_object_mut().unwrap();
                for k in [
                    "seconds",
                    "evaluations_per_second",
                    "eval_seconds",
                    "reproduction_seconds",
                    "eval_split",
                    "threads",
                ] {
                    assert!(o.remove(k).is_some(), "run.json has no {k}");
                }
                serde_json::to_vec(&v).unwrap()
            }
            _ => bytes,
        };
        files.push((name, bytes));
    }
    files.sort();
    files
}

#[test]
fn same_seed_same_bytes_at_one_and_two_threads() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = small_scene(
        tmp.path(),
        "genr8_undulating_box.toml",
        &[("population = 100", "population = 16"), ("generations = 100", "generations = 4")],
    );
    let s = scene.to_str().unwrap();
    ok(tmp.path(), &["evolve", s, "--seed", "5", "--threads", "1", "--out", "one", "-q"]);
    ok(tmp.path(), &["evolve", s, "--seed", "5", "--threads", "2", "--out", "two", "-q"]);
    ok(tmp.path(), &["evolve", s, "--seed", "6", "--threads", "2", "--out", "other", "-q"]);
    let (one, two) = (comparable(&tmp.path().join("one")), comparable(&tmp.path().join("two")));
    let names: Vec<&str> = one.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "best-codons.json",
            "best.glb",
            "best.gr8",
            "best.mtl",
            "best.obj",
            "best.png",
            "gallery.png",
            "run.json",
            "stats.csv"
        ]
    );
    for ((n, a), (_, b)) in one.iter().zip(&two) {
        assert!(a == b, "{n} differs between --threads 1 and 2");
    }
    let other = comparable(&tmp.path().join("other"));
    assert_ne!(one[0].1, other[0].1, "the seed matters");
}

#[test]
fn an_invalid_heavy_run_still_finishes_and_counts_the_reasons() {
    let tmp = tempfile::tempdir().unwrap();
    // Four growth steps of most grammars pass 40 vertices.
    let mut edits = FEW.to_vec();
    edits.push(("vertices = 20000", "vertices = 40"));
    let scene = small_scene(tmp.path(), "genr8_canopy.toml", &edits);
    ok(tmp.path(), &["evolve", scene.to_str().unwrap(), "--out", "run", "-q"]);
    let r = json(&tmp.path().join("run/run.json"));
    let limited = r["invalid"]["element_limit"].as_u64().unwrap_or(0);
    assert!(limited > 10, "{}", r["invalid"]);
    let stats = std::fs::read_to_string(tmp.path().join("run/stats.csv")).unwrap();
    let header: Vec<&str> = stats.lines().next().unwrap().split(',').collect();
    let col = header.iter().position(|h| *h == "invalid_element_limit").unwrap();
    let per_generation: u64 =
        stats.lines().skip(1).map(|l| l.split(',').nth(col).unwrap().parse::<u64>().unwrap()).sum();
    assert_eq!(per_generation, limited);

    // Nothing valid at all (genomes of 1–3 codons, no wrapping): the run
    // still ends and says so.
    let edits = [
        ("population = 100", "population = 6"),
        ("generations = 100", "generations = 1"),
        ("initial_length = [50, 200]", "initial_length = [1, 3]"),
        ("[limits]", "[mapper]\nmax_wraps = 0\n\n[limits]"),
    ];
    let scene = small_scene(tmp.path(), "genr8_canopy.toml", &edits);
    ok(tmp.path(), &["evolve", scene.to_str().unwrap(), "--out", "none", "-q"]);
    let r = json(&tmp.path().join("none/run.json"));
    assert!(r["best_fitness"].is_null());
    assert_eq!(r["invalid"]["wrap_limit"], r["evaluations"], "{}", r["invalid"]);
    assert!(!tmp.path().join("none/best.gr8").exists());
    assert!(tmp.path().join("none/gallery.png").exists());
}

#[test]
fn scene_mistakes_name_the_file_and_the_key() {
    let tmp = tempfile::tempdir().unwrap();
    let bad = small_scene(tmp.path(), "genr8_canopy.toml", &[("[ge]", "[ga]")]);
    let err = fails(tmp.path(), &["evolve", bad.to_str().unwrap()]);
    assert!(err.contains("genr8_canopy.toml:") && err.contains("[ga] sets optimizers of derivation trees"), "{err}");
    assert!(err.contains("its optimizer settings go in [ge]"), "{err}");
    let bad = small_scene(
        tmp.path(),
        "genr8_canopy.toml",
        &[("symmetry = { target = 1, weight = 1 }", "symetry = { target = 1 }")],
    );
    let err = fails(tmp.path(), &["evolve", bad.to_str().unwrap()]);
    assert!(err.contains("genr8_canopy.toml:") && err.contains("symetry"), "{err}");
    let bad = small_scene(tmp.path(), "genr8_canopy.toml", &[("phenotype = \"gr8\"", "phenotype = \"gr9\"")]);
    assert!(fails(tmp.path(), &["evolve", bad.to_str().unwrap()]).contains("gr9"));
    let bad = small_scene(tmp.path(), "ge_castle_volume.toml", &[("box = [-12, 0, -12, 11, 11, 11]", "")]);
    assert!(fails(tmp.path(), &["evolve", bad.to_str().unwrap()]).contains("box = [x0, y0, z0, x1, y1, z1]"));
    let bad = small_scene(tmp.path(), "ge_lsystem_tree.toml", &[("max_depth = 14", "max_depth = 14\nmax_dpeth = 3")]);
    let err = fails(tmp.path(), &["evolve", bad.to_str().unwrap()]);
    assert!(err.contains("ge_lsystem_tree.toml:") && err.contains("max_dpeth"), "{err}");
}

#[test]
fn tree_and_codon_algorithms_are_not_mixed() {
    let tmp = tempfile::tempdir().unwrap();
    let codon = small_scene(tmp.path(), "genr8_canopy.toml", FEW);
    let err = fails(tmp.path(), &["evolve", codon.to_str().unwrap(), "--algorithm", "ga"]);
    assert!(err.contains("codon scene") && err.contains("ge or random"), "{err}");
    let err = fails(tmp.path(), &["compare", codon.to_str().unwrap(), "--algorithms", "ge,mh"]);
    assert!(err.contains("--algorithm mh"), "{err}");
    let err = fails(tmp.path(), &["evolve", codon.to_str().unwrap(), "--max-genes", "9"]);
    assert!(err.contains("[limits]"), "{err}");
    let tree = root().join("examples/scenes/tree_volume.toml");
    let err = fails(tmp.path(), &["evolve", tree.to_str().unwrap(), "--algorithm", "ge"]);
    assert!(err.contains("tree scene"), "{err}");
    // Random search is the codon baseline here.
    ok(tmp.path(), &["evolve", codon.to_str().unwrap(), "--algorithm", "random", "--out", "r", "-q"]);
    assert_eq!(json(&tmp.path().join("r/run.json"))["algorithm"], "random");
}

#[test]
fn compare_races_ge_and_random_search() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = small_scene(tmp.path(), "genr8_canopy.toml", &[]);
    let out = ok(
        tmp.path(),
        &[
            "compare",
            scene.to_str().unwrap(),
            "--budget",
            "300ms",
            "--runs",
            "2",
            "--threads",
            "1",
            "--out",
            "cmp",
            "-q",
        ],
    );
    let table = out.stdout();
    assert!(table.lines().any(|l| l.starts_with("ge ")) && table.lines().any(|l| l.starts_with("random ")), "{table}");
    let csv = std::fs::read_to_string(tmp.path().join("cmp/comparison.csv")).unwrap();
    assert!(csv.lines().any(|l| l.starts_with("ge,1,")) && csv.lines().any(|l| l.starts_with("random,0,")), "{csv}");
    for f in ["comparison.svg", "best-ge-codons.json", "best-random-codons.json"] {
        assert!(tmp.path().join("cmp").join(f).exists(), "{f}");
    }
}

#[test]
fn ctrl_c_ends_a_codon_run_and_writes_the_results() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = small_scene(tmp.path(), "genr8_canopy.toml", &[]);
    interrupt_evolve(tmp.path(), &scene, Duration::from_millis(1000));
    assert_eq!(json(&tmp.path().join("run/run.json"))["stopped_by"], "interrupted");
    assert!(tmp.path().join("run/best.gr8").exists());
}
