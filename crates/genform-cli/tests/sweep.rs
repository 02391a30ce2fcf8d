//! End-to-end tests of `genform sweep` and of the pictures `genform evolve`
//! draws with the target (best.png, evolution.png): the real binary on a
//! small spaceship scene in a temporary folder.

use std::path::{Path, PathBuf};

mod common;
use common::{fails, ok, small_scene};

fn ship(dir: &Path) -> PathBuf {
    small_scene(
        dir,
        "spaceship_volume.toml",
        &[
            ("voxels = [100, 200, 100]", "voxels = [25, 25, 50]"),
            ("population = 150", "population = 16\nelitism = 2"),
            ("initial_length = [50, 50]", "initial_length = [10, 20]"),
            ("generations = 130", "generations = 3"),
        ],
    )
}

fn read(dir: &Path, file: &str) -> String {
    std::fs::read_to_string(dir.join(file)).unwrap_or_else(|_| panic!("{file} missing"))
}

#[test]
fn sweep_writes_a_row_per_generation_of_every_value_and_run() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path());
    let run = ok(
        tmp.path(),
        &["sweep", scene.to_str().unwrap(), "--set", "ga.population=8,12", "--runs", "2", "--generations", "3", "-q"],
    );
    let out = tmp.path().join("sweep-out");
    let csv = read(&out, "sweep.csv");
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], "variant,ga.population,run,seed,generation,evaluations,best_fitness,max_fitness,mean_fitness");
    assert_eq!(lines.len(), 1 + 2 * 2 * 4, "header + 2 values × 2 runs × generations 0..=3:\n{csv}");
    let keyed: Vec<(String, String, String)> = lines[1..]
        .iter()
        .filter(|l| l.split(',').nth(4) == Some("3"))
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            (c[1].to_string(), c[2].to_string(), c[3].to_string())
        })
        .collect();
    let want = [("8", "0", "1"), ("8", "1", "2"), ("12", "0", "1"), ("12", "1", "2")];
    assert_eq!(keyed, want.map(|(a, b, c)| (a.into(), b.into(), c.into())), "value, run, seed (seed 1 + run)");
    // Evaluations grow with the population: 8 per generation against 12.
    let evals =
        |v: &str| lines.iter().find(|l| l.starts_with(&format!("{v},")) && l.contains(",0,1,0,")).unwrap().to_string();
    assert!(evals("0").contains(",0,8,"), "{}", evals("0"));
    assert!(evals("1").contains(",0,12,"), "{}", evals("1"));
    let svg = read(&out, "sweep.svg");
    assert!(svg.contains("ga.population=8") && svg.contains("ga.population=12"), "one line per value");
    let layout = common::assert_legends_clear("sweep.svg", &svg);
    assert_eq!((layout.plots.len(), layout.legends.len()), (2, 1), "both panels share one legend");
    let summary = read(&out, "summary.md");
    assert_eq!(summary.lines().count(), 2 + 2, "{summary}");
    assert!(run.stdout().contains("| 12 | 2 |"), "the summary is printed:\n{}", run.show());
}

#[test]
fn sweep_output_is_the_same_at_any_thread_count() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path());
    let s = scene.to_str().unwrap();
    let common = ["--set", "ga.mutation_rate=0.1,0.9", "--set", "ga.initial_length=[5,10];[10,20]", "--runs", "2"];
    for (threads, out) in [("1", "one"), ("2", "two")] {
        let mut args = vec!["sweep", s, "--threads", threads, "--out", out, "-q", "--generations", "2"];
        args.extend(common);
        ok(tmp.path(), &args);
    }
    let (one, two) = (read(&tmp.path().join("one"), "sweep.csv"), read(&tmp.path().join("two"), "sweep.csv"));
    assert_eq!(one.lines().count(), 1 + 4 * 2 * 3);
    assert_eq!(one, two, "byte-identical at 1 and 2 threads");
    assert!(one.contains(",0.9,\"[10,20]\","), "values with commas are quoted:\n{one}");
}

#[test]
fn sweep_settings_are_checked_like_the_scene() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path());
    let s = scene.to_str().unwrap();
    let typo = fails(tmp.path(), &["sweep", s, "--set", "ga.populaton=8,12", "--runs", "1"]);
    assert!(typo.contains("--set ga.populaton=8"), "{typo}");
    assert!(typo.contains("unknown key `populaton` in [ga]; did you mean `population`?"), "{typo}");
    let range = fails(tmp.path(), &["sweep", s, "--set", "ga.mutation_rate=0.5,1.5", "--runs", "1"]);
    assert!(range.contains("--set ga.mutation_rate=1.5") && range.contains("1.5"), "{range}");
    let crossed = fails(
        tmp.path(),
        &["sweep", s, "--set", "ga.elitism=1,2", "--set", "ga.population=8,9", "--set", "ga.mutation_rate=0,1"],
    );
    assert!(crossed.contains("at most 2 keys"), "{crossed}");
    // One-value settings fix a setting for every run: elitism 30 needs population 40.
    ok(
        tmp.path(),
        &[
            "sweep",
            s,
            "--set",
            "ga.elitism=30",
            "--set",
            "ga.population=40,41",
            "--runs",
            "1",
            "--generations",
            "1",
            "-q",
        ],
    );
}

#[test]
fn the_readmes_population_sweep_runs_on_the_shipped_scene_with_elites_a_fifth_of_each_population() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = common::root().join("examples/scenes/spaceship_volume.toml");
    let s = scene.to_str().unwrap();
    let args = ["sweep", s, "--set", "ga.population=10,50", "--runs", "1", "--generations", "5", "-q"];
    ok(tmp.path(), &args);
    let csv = read(&tmp.path().join("sweep-out"), "sweep.csv");
    assert_eq!(csv.lines().count(), 1 + 2 * 6, "header + 2 values × generations 0..=5:\n{csv}");
    // Generation 1 evaluates population − elites children: 10 − 2 and 50 − 10.
    let evaluations = |v: &str, g: &str| {
        let row = csv.lines().find(|l| l.starts_with(&format!("{v},")) && l.split(',').nth(4) == Some(g)).unwrap();
        row.split(',').nth(5).unwrap().parse::<u64>().unwrap()
    };
    assert_eq!(evaluations("0", "1") - evaluations("0", "0"), 8, "{csv}");
    assert_eq!(evaluations("1", "1") - evaluations("1", "0"), 40, "{csv}");
    // An elitism the user gives stays strict, and the message says how to get the default.
    let err = fails(tmp.path(), &["sweep", s, "--set", "ga.population=10", "--set", "ga.elitism=30", "--runs", "1"]);
    assert!(err.contains("elitism (30) must be smaller than the population (10)"), "{err}");
    assert!(err.contains("leave `elitism` out"), "{err}");
}

/// The frames of an animated PNG.
fn apng_frames(bytes: &[u8]) -> u32 {
    let reader = png::Decoder::new(std::io::Cursor::new(bytes)).read_info().unwrap();
    reader.info().animation_control.map_or(1, |a| a.num_frames)
}

#[test]
fn evolve_draws_the_target_behind_the_best_and_animates_the_run() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path());
    ok(tmp.path(), &["evolve", scene.to_str().unwrap(), "--generations", "12", "--seed", "4", "-o", "run", "-q"]);
    let run = tmp.path().join("run");
    let best = std::fs::read(run.join("best.png")).unwrap();
    let model = std::fs::read(run.join("best-model.png")).unwrap();
    assert_ne!(best, model, "best.png shows the target too");
    let decode = |bytes: &[u8]| {
        let mut reader = png::Decoder::new(std::io::Cursor::new(bytes)).read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        buf.truncate(info.buffer_size());
        (buf, info.width, info.height)
    };
    let (rgb, w, h) = decode(&best);
    assert_eq!((w, h), (800, 600));
    // The target glass is blue: many pixels are bluer than the model's or the background's.
    let blue = rgb.chunks(3).filter(|p| p[2] > p[0].saturating_add(40) && p[2] > p[1].saturating_add(20)).count();
    let (plain, _, _) = decode(&model);
    let blue_plain =
        plain.chunks(3).filter(|p| p[2] > p[0].saturating_add(40) && p[2] > p[1].saturating_add(20)).count();
    assert!(blue > blue_plain + 1000, "{blue} bluish pixels with the target, {blue_plain} without");
    let evolution = std::fs::read(run.join("evolution.png")).expect("evolution.png");
    let frames = apng_frames(&evolution);
    assert!((2..=31).contains(&frames), "{frames} frames");
}
