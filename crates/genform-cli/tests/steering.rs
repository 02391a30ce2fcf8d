//! `genform evolve --steering`: once a change of weights took effect,
//! everything the run reports is scored under the new weights (the
//! population and the best are re-scored), and a replay is the same run.

mod common;

use common::{fitness_columns, json, ok, s, scored, small_scene, small_ship};
use std::path::Path;

/// Runs `evolve scene` with `extra` arguments into `dir/out`; returns
/// `run.json` and the stats without their timing columns.
fn evolve(dir: &Path, scene: &Path, out: &str, extra: &[&str]) -> (serde_json::Value, Vec<String>) {
    let args = [&["evolve", s(scene), "--seed", "7", "--generations", "6", "--out", out, "-q"], extra].concat();
    ok(dir, &args);
    let csv = std::fs::read_to_string(dir.join(out).join("stats.csv")).unwrap();
    (json(&dir.join(out).join("run.json")), fitness_columns(&csv))
}

/// The `max` column of the last stats row.
fn last_max(stats: &[String]) -> f64 {
    stats.last().unwrap().split(',').nth(2).unwrap().parse().unwrap()
}

#[test]
fn after_steering_the_best_is_scored_under_the_new_weights() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let scene = small_ship(dir, &[]);
    // Lower weights: individuals scored before the change would keep
    // fitness no one can reach after it.
    let log = dir.join("log.json");
    std::fs::write(&log, r#"[{"generation": 3, "set": {"weights": {"good": 0.5, "length": 1.0}}}]"#).unwrap();
    let steered = small_ship(&dir.join("steered"), &[("good = 2.0", "good = 0.5"), ("length = 0.1", "length = 1.0")]);
    for algorithm in ["ga", "mh"] {
        let out = format!("run-{algorithm}");
        let (run, stats) = evolve(dir, &scene, &out, &["--algorithm", algorithm, "--steering", s(&log)]);
        assert_eq!(run["steering"][0]["generation"], 3, "{algorithm}");
        let best = run["best_fitness"].as_f64().unwrap();
        let (fitness, text) = scored(dir, &steered, &format!("{out}/best-genome.json"));
        assert_eq!(fitness.to_bits(), best.to_bits(), "{algorithm}: the best is scored under the new weights: {text}");
        let (old, _) = scored(dir, &scene, &format!("{out}/best-genome.json"));
        assert!(old != fitness, "{algorithm}: the change matters to the best");
        assert!(last_max(&stats) <= best, "{algorithm}: nothing in the last generation outranks the best");
        if algorithm == "ga" {
            assert_eq!(last_max(&stats), best, "with elitism the last generation holds the best");
        }
        // The replay is the same run, to the byte.
        let again = format!("again-{algorithm}");
        let (rerun, restats) = evolve(dir, &scene, &again, &["--algorithm", algorithm, "--steering", s(&log)]);
        assert_eq!((&rerun["best_fitness"], &rerun["evaluations"]), (&run["best_fitness"], &run["evaluations"]));
        assert_eq!(restats, stats);
        let genome = |d: &str| std::fs::read(dir.join(d).join("best-genome.json")).unwrap();
        assert_eq!(genome(&out), genome(&again));
    }
}

#[test]
fn a_steered_genr8_run_rescores_its_surfaces() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let few = [("population = 100", "population = 14")];
    let scene = small_scene(dir, "genr8_canopy.toml", &few);
    let log = dir.join("log.json");
    std::fs::write(&log, r#"[{"generation": 2, "set": {"weights": {"symmetry": 0.2}, "targets": {"size": 4.0}}}]"#)
        .unwrap();
    std::fs::create_dir_all(dir.join("steered")).unwrap();
    let edits = [
        few[0],
        ("size = { target = 10, weight = 1 }", "size = { target = 4.0, weight = 1 }"),
        ("symmetry = { target = 1, weight = 1 }", "symmetry = { target = 1, weight = 0.2 }"),
    ];
    let steered = small_scene(&dir.join("steered"), "genr8_canopy.toml", &edits);
    let (run, stats) = evolve(dir, &scene, "run", &["--steering", s(&log)]);
    let best = run["best_fitness"].as_f64().unwrap();
    let (fitness, text) = scored(dir, &steered, "run/best-codons.json");
    assert_eq!(fitness.to_bits(), best.to_bits(), "the best is scored under the new goals: {text}");
    assert_eq!(last_max(&stats), best, "with elitism the last generation holds the best");
    let (rerun, restats) = evolve(dir, &scene, "again", &["--steering", s(&log)]);
    assert_eq!((rerun["best_fitness"].clone(), restats), (run["best_fitness"].clone(), stats));
}
