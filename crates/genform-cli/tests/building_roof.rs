//! End-to-end: `examples/scenes/building_roof.toml` is a building envelope
//! that evolution can tell apart (issue 42, item 6). Its target is a house
//! the grammar builds exactly (score 1, the reachable maximum); the best of
//! generation 0 stays far below it; at equal evaluations the GA ends
//! clearly above random search and its best carries the target's pyramid
//! roof. The scene's own budget (60 generations of 50, 2,450 evaluations)
//! runs in about a second per run in a debug build.

mod common;

use common::{json, ok, root, s, scored};
use std::path::Path;

/// The roof kinds whose tags the OBJ of a run's best model names (one
/// object per roof, `o roof_pyramid#9c4a3c_1`).
fn roof_kinds(obj: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(obj).unwrap();
    text.lines()
        .filter_map(|l| l.strip_prefix("o roof_"))
        .map(|l| l.split(['#', '_']).next().unwrap().to_string())
        .collect()
}

/// The best fitness of generation 0 (the first row of `stats.csv`).
fn generation_zero_best(run: &Path) -> f64 {
    let csv = std::fs::read_to_string(run.join("stats.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let column = header.iter().position(|c| *c == "max_fitness").unwrap();
    csv.lines().nth(1).unwrap().split(',').nth(column).unwrap().parse().unwrap()
}

#[test]
fn the_ga_beats_random_search_at_equal_evaluations_and_finds_the_pyramid_roof() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let scene = root().join("examples/scenes/building_roof.toml");
    let target = root().join("examples/scenes/targets/pyramid_house.json");
    let (fitness, said) = scored(dir, &scene, s(&target));
    assert!(fitness > 0.9999, "the target's own genome scores the maximum\n{said}");
    assert!(said.contains("max reachable 1"), "{said}");
    for seed in ["1", "3"] {
        let (ga, random) = (format!("ga-{seed}"), format!("random-{seed}"));
        ok(dir, &["evolve", s(&scene), "--seed", seed, "--threads", "1", "--out", &ga, "-q"]);
        let ga_run = json(&dir.join(&ga).join("run.json"));
        let evaluations = ga_run["evaluations"].as_u64().unwrap().to_string();
        let args = ["--algorithm", "random", "--evaluations", &evaluations, "--out", &random, "-q"];
        ok(dir, &[&["evolve", s(&scene), "--seed", seed, "--threads", "1"][..], &args].concat());
        let random_run = json(&dir.join(&random).join("run.json"));
        assert_eq!(random_run["evaluations"], ga_run["evaluations"], "seed {seed}: equal evaluations");

        let (ga_best, random_best) =
            (ga_run["best_fitness"].as_f64().unwrap(), random_run["best_fitness"].as_f64().unwrap());
        let first = generation_zero_best(&dir.join(&ga));
        // Far from the maximum at the start, so there is something to win.
        assert!(first < 0.8, "seed {seed}: generation 0's best {first}");
        // Measured: seed 1 0.9467 against 0.8928, seed 3 0.9674 against 0.8855.
        assert!(ga_best > random_best + 0.03, "seed {seed}: GA {ga_best}, random search {random_best}");
        assert!(ga_best > 0.93, "seed {seed}: GA {ga_best}");
        let kinds = roof_kinds(&dir.join(&ga).join("best.obj"));
        assert_eq!(kinds, ["pyramid"], "seed {seed}: the GA's best roof");
    }
}
