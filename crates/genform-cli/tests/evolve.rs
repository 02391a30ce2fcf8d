//! End-to-end tests of `genform evolve`: the real binary on small versions
//! of the shipped scenes, in a temporary folder.

use std::path::{Path, PathBuf};
use std::time::Duration;

mod common;
use common::{fails, fitness_columns, interrupt_evolve, json, ok, root, s, scored, small_scene, small_ship};

/// The small spaceship of the end-to-end tests, in `dir`.
fn ship(dir: &Path) -> PathBuf {
    small_ship(dir, &[])
}

#[test]
fn evolve_writes_every_result_file() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path());
    ok(tmp.path(), &["evolve", scene.to_str().unwrap(), "--seed", "3", "--out", "run", "--quiet"]);
    let run = tmp.path().join("run");
    for f in
        ["best.glb", "best.obj", "best.png", "best-genome.json", "stats.csv", "fitness.svg", "gallery.png", "run.json"]
    {
        let meta = std::fs::metadata(run.join(f)).unwrap_or_else(|_| panic!("{f} missing"));
        assert!(meta.len() > 0, "{f} is empty");
    }
    let csv = std::fs::read_to_string(run.join("stats.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 7, "header + generations 0..=6:\n{csv}");
    let json = json(&run.join("run.json"));
    assert_eq!(json["generations"], 6);
    assert_eq!(json["stopped_by"], "generations");
    assert_eq!(json["seed"], 3);
    let best = json["best_fitness"].as_f64().unwrap();
    let last_max: f64 = csv.lines().last().unwrap().split(',').nth(3).unwrap().parse().unwrap();
    assert_eq!(best, last_max, "with elitism the last generation holds the best individual");
    // The saved genome replays into the saved model.
    let ship_sg = root().join("examples/shape/spaceship.sg");
    // Named best.obj too: the OBJ names its material library `best.mtl`.
    ok(
        tmp.path(),
        &["derive", ship_sg.to_str().unwrap(), "--genome", "run/best-genome.json", "--out", "replay/best.obj"],
    );
    for f in ["best.obj", "best.mtl"] {
        assert_eq!(
            std::fs::read(run.join(f)).unwrap(),
            std::fs::read(tmp.path().join("replay").join(f)).unwrap(),
            "{f}"
        );
    }
    // `genform score` re-evaluates it to the same fitness.
    let (scored, text) = scored(tmp.path(), &scene, "run/best-genome.json");
    assert_eq!(scored, best, "{text}");
}

#[test]
fn same_seed_same_results_at_any_thread_count() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path());
    let s = scene.to_str().unwrap();
    ok(tmp.path(), &["evolve", s, "--seed", "9", "--threads", "1", "--out", "one", "-q"]);
    ok(tmp.path(), &["evolve", s, "--seed", "9", "--threads", "3", "--out", "three", "-q"]);
    ok(tmp.path(), &["evolve", s, "--seed", "10", "--threads", "3", "--out", "other", "-q"]);
    let read = |d: &str, f: &str| std::fs::read_to_string(tmp.path().join(d).join(f)).unwrap();
    assert_eq!(fitness_columns(&read("one", "stats.csv")), fitness_columns(&read("three", "stats.csv")));
    assert_eq!(read("one", "best-genome.json"), read("three", "best-genome.json"));
    assert_ne!(read("one", "best-genome.json"), read("other", "best-genome.json"), "the seed matters");
}

#[test]
fn image_scenes_write_a_silhouette() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = small_scene(
        tmp.path(),
        "city_skyline.toml",
        &[
            ("population = 100", "population = 12"),
            ("elitism = 30", "elitism = 2"),
            ("generations = 100", "generations = 2"),
        ],
    );
    ok(tmp.path(), &["evolve", scene.to_str().unwrap(), "--out", "run", "-q"]);
    assert!(tmp.path().join("run/best-silhouette.png").exists());
}

#[test]
fn random_search_runs_on_the_same_scene() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path());
    ok(
        tmp.path(),
        &["evolve", scene.to_str().unwrap(), "--algorithm", "random", "--evaluations", "60", "--out", "r", "-q"],
    );
    let json = json(&tmp.path().join("r/run.json"));
    assert_eq!(json["algorithm"], "random");
    assert!(json["evaluations"].as_u64().unwrap() >= 60);
}

#[test]
fn config_mistakes_name_the_file_and_the_key() {
    let tmp = tempfile::tempdir().unwrap();
    let bad = small_scene(tmp.path(), "spaceship_volume.toml", &[("population = 150", "populaton = 150")]);
    let err = fails(tmp.path(), &["evolve", bad.to_str().unwrap()]);
    assert!(err.contains("spaceship_volume.toml:") && err.contains("populaton"), "{err}");

    let bad =
        small_scene(tmp.path(), "spaceship_volume.toml", &[("population = 150", "population = 150\nelitism = 150")]);
    let err = fails(tmp.path(), &["evolve", bad.to_str().unwrap()]);
    assert!(err.contains("elitism"), "{err}");

    let bad = small_scene(tmp.path(), "spaceship_volume.toml", &[("targets/spaceship_target.obj", "targets/nope.obj")]);
    let err = fails(tmp.path(), &["evolve", bad.to_str().unwrap()]);
    assert!(err.contains("nope.obj"), "{err}");
}

#[test]
fn set_patches_the_scene_for_one_run_with_the_files_checks() {
    let tmp = tempfile::tempdir().unwrap();
    let ship = ship(tmp.path());
    let args = ["evolve", s(&ship), "--generations", "1", "-q", "--out", "run", "--set", "ga.population=12"];
    ok(tmp.path(), &[&args[..], &["--set", "ga.elitism=2"]].concat());
    let run = json(&tmp.path().join("run/run.json"));
    assert_eq!(
        (run["config"]["ga"]["population"].as_u64(), run["config"]["ga"]["elitism"].as_u64()),
        (Some(12), Some(2))
    );
    let stats = std::fs::read_to_string(tmp.path().join("run/stats.csv")).unwrap();
    assert!(stats.lines().nth(1).unwrap().starts_with("0,12,"), "generation 0 evaluates the 12 set: {stats}");
    let err = fails(tmp.path(), &["evolve", s(&ship), "--generations", "1", "--set", "ga.populaton=12"]);
    assert!(err.contains("--set ga.populaton=12") && err.contains("did you mean `population`"), "{err}");
    let err = fails(tmp.path(), &["score", s(&ship), "--genome", "run/best-genome.json", "--set", "ga.population=1,2"]);
    assert!(err.contains("give one value here"), "{err}");
}

/// Two Ctrl-Cs 5 ms apart (a key pressed twice): the results are written
/// all the same and the process ends as interrupted.
#[test]
fn a_double_ctrl_c_keeps_the_results_and_ends_as_interrupted() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path());
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_genform"))
        .current_dir(tmp.path())
        .args(["evolve", scene.to_str().unwrap(), "--budget", "10m", "--out", "run", "-q"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    let pid = child.id().to_string();
    for _ in 0..2 {
        assert!(std::process::Command::new("kill").args(["-INT", &pid]).status().unwrap().success());
        std::thread::sleep(Duration::from_millis(5));
    }
    let out = child.wait_with_output().unwrap();
    assert!(common::ended_by_sigint(&out.status), "{:?} {}", out.status, String::from_utf8_lossy(&out.stderr));
    assert_eq!(json(&tmp.path().join("run/run.json"))["stopped_by"], "interrupted");
    assert!(json(&tmp.path().join("run/best-genome.json")).is_object());
    assert!(std::fs::read_to_string(tmp.path().join("run/stats.csv")).unwrap().lines().count() > 1);
}

#[test]
fn ctrl_c_ends_the_run_and_writes_the_results() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path());
    // Give it time to load and run a generation (the first checkpoint is
    // not guaranteed).
    interrupt_evolve(tmp.path(), &scene, Duration::from_millis(1500));
    assert_eq!(json(&tmp.path().join("run/run.json"))["stopped_by"], "interrupted");
    assert!(tmp.path().join("run/best-genome.json").exists());
}

#[test]
fn every_algorithm_runs_from_the_cli_and_is_deterministic() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path());
    let s = scene.to_str().unwrap();
    let read = |d: &str, f: &str| std::fs::read_to_string(tmp.path().join(d).join(f)).unwrap();
    for alg in ["mh", "smc", "sosmc", "hybrid"] {
        let (one, two) = (format!("{alg}-1"), format!("{alg}-2"));
        for (out, threads) in [(&one, "1"), (&two, "2")] {
            let args =
                ["evolve", s, "--algorithm", alg, "--evaluations", "600", "--threads", threads, "--out", out, "-q"];
            ok(tmp.path(), &args);
        }
        assert_eq!(read(&one, "best-genome.json"), read(&two, "best-genome.json"), "{alg}");
        assert_eq!(fitness_columns(&read(&one, "stats.csv")), fitness_columns(&read(&two, "stats.csv")), "{alg}");
        let json = json(&tmp.path().join(&one).join("run.json"));
        assert_eq!(json["algorithm"], alg);
        assert!(json["evaluations"].as_u64().unwrap() >= 600, "{alg}");
        assert!(json["best_fitness"].as_f64().is_some(), "{alg}");
    }
}

#[test]
fn compare_writes_the_table_the_csv_and_the_plot() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path());
    let args = [
        "compare",
        scene.to_str().unwrap(),
        "--budget",
        "0.4s",
        "--runs",
        "2",
        "--algorithms",
        "ga,sosmc",
        "--out",
        "c",
    ];
    let out = ok(tmp.path(), &args);
    let table = out.stdout();
    let rows: Vec<&str> = table.lines().collect();
    assert_eq!(rows.len(), 3, "{table}");
    assert!(rows[1].starts_with("ga ") && rows[2].starts_with("sosmc "), "{table}");
    let csv = std::fs::read_to_string(tmp.path().join("c/comparison.csv")).unwrap();
    assert_eq!(csv.lines().next().unwrap(), "algorithm,run,seed,seconds,evaluations,best_fitness");
    for (alg, run, seed) in [("ga", 0, 1), ("ga", 1, 2), ("sosmc", 0, 1), ("sosmc", 1, 2)] {
        let last = csv.lines().rfind(|l| l.starts_with(&format!("{alg},{run},{seed},")));
        let cols: Vec<&str> = last.unwrap_or_else(|| panic!("no {alg} run {run}\n{csv}")).split(',').collect();
        let seconds: f64 = cols[3].parse().unwrap();
        assert!((0.4..3.0).contains(&seconds), "{alg} ran {seconds} s");
        assert!(cols[4].parse::<u64>().unwrap() > 0 && cols[5].parse::<f64>().is_ok());
    }
    let svg = std::fs::read_to_string(tmp.path().join("c/comparison.svg")).unwrap();
    assert_eq!(svg.matches("<polyline").count(), 2);
    assert!(svg.contains(">ga<") && svg.contains(">sosmc<"));
    common::assert_legends_clear("comparison.svg", &svg);
    assert!(tmp.path().join("c/best-ga-genome.json").exists() && tmp.path().join("c/best-sosmc-genome.json").exists());
}

#[test]
fn mcmc_and_smc_settings_are_checked() {
    let tmp = tempfile::tempdir().unwrap();
    let bad = small_scene(tmp.path(), "spaceship_volume.toml", &[("chains = 70", "chains = 70\njump = 2")]);
    let err = fails(tmp.path(), &["evolve", bad.to_str().unwrap(), "--algorithm", "mh"]);
    assert!(err.contains("[mh]") && err.contains("jump must be in [0, 1], got 2"), "{err}");
    let bad =
        small_scene(tmp.path(), "spaceship_volume.toml", &[("particles = 500", "particles = 500\nweight = \"exp\"")]);
    let err = fails(tmp.path(), &["evolve", bad.to_str().unwrap()]);
    assert!(err.contains("spaceship_volume.toml:") && err.contains("exp"), "{err}");
}
