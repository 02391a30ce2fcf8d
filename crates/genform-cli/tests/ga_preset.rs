//! The GA presets from the command line: `--preset thesis` and
//! `preset = "thesis"` reproduce the thesis GA as it was before the
//! default GA got drift and duplicate avoidance; bad settings name the file,
//! the position and the range.

use std::path::{Path, PathBuf};

mod common;
use common::{fails, ok, small_scene};

/// The small spaceship of `tests/evolve.rs`, run for 12 generations.
fn ship(dir: &Path, extra: &[(&str, &str)]) -> PathBuf {
    let mut edits = vec![
        ("voxels = [100, 200, 100]", "voxels = [25, 25, 50]"),
        ("population = 150", "population = 24\nelitism = 4"),
        ("initial_length = [50, 50]", "initial_length = [10, 30]"),
        ("generations = 130", "generations = 12"),
    ];
    edits.extend_from_slice(extra);
    small_scene(dir, "spaceship_volume.toml", &edits)
}

/// Best fitness per generation of `stats.csv`, as written.
fn best_column(run: &Path) -> Vec<String> {
    let csv = std::fs::read_to_string(run.join("stats.csv")).unwrap();
    csv.lines().skip(1).map(|l| l.split(',').nth(3).unwrap().to_string()).collect()
}

/// `max_fitness` of this scene with seed 3, computed by the GA before the
/// default GA changed (the thesis GA was then the only GA).
const THESIS_SNAPSHOT: [&str; 13] = [
    "0.32801473939484416",
    "0.34677340364423526",
    "0.34677340364423526",
    "0.40484965296911146",
    "0.4126392116832547",
    "0.44846265740810964",
    "0.47223529450419005",
    "0.49306055519541725",
    "0.4934034043687608",
    "0.4934034043687608",
    "0.5089703180199295",
    "0.5258002330512258",
    "0.7811185698747519",
];

#[test]
fn the_thesis_preset_reproduces_the_old_ga_from_the_flag_and_from_the_scene() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path(), &[]);
    let s = scene.to_str().unwrap();
    ok(tmp.path(), &["evolve", s, "--seed", "3", "--preset", "thesis", "--out", "flag", "--quiet", "--threads", "1"]);
    assert_eq!(best_column(&tmp.path().join("flag")), THESIS_SNAPSHOT);

    let in_scene = ship(tmp.path(), &[("[ga]\n", "[ga]\npreset = \"thesis\"\n")]);
    let s2 = in_scene.to_str().unwrap();
    ok(tmp.path(), &["evolve", s2, "--seed", "3", "--out", "scene", "--quiet", "--threads", "3"]);
    assert_eq!(best_column(&tmp.path().join("scene")), THESIS_SNAPSHOT);
    let genome = |d: &str| std::fs::read_to_string(tmp.path().join(d).join("best-genome.json")).unwrap();
    assert_eq!(genome("flag"), genome("scene"));

    // The flag overrides the scene. (The default GA equals the thesis GA
    // until its tuning phase, so start that at once.)
    let eager = ship(tmp.path(), &[("[ga]\n", "[ga]\npreset = \"thesis\"\ntune_after = 0\n")]);
    let s3 = eager.to_str().unwrap();
    ok(tmp.path(), &["evolve", s3, "--seed", "3", "--out", "eager", "--quiet"]);
    assert_eq!(best_column(&tmp.path().join("eager")), THESIS_SNAPSHOT);
    ok(tmp.path(), &["evolve", s3, "--seed", "3", "--preset", "default", "--out", "default", "--quiet"]);
    assert_ne!(best_column(&tmp.path().join("default")), THESIS_SNAPSHOT);
}

#[test]
fn bad_ga_settings_name_the_position_and_the_range() {
    let tmp = tempfile::tempdir().unwrap();
    let bad = ship(tmp.path(), &[("[ga]\n", "[ga]\npreset = \"modern\"\n")]);
    let err = fails(tmp.path(), &["evolve", bad.to_str().unwrap()]);
    assert!(err.contains("spaceship_volume.toml:") && err.contains("modern"), "{err}");

    let bad = ship(tmp.path(), &[("cut = 45 }", "cut = 45, drift_scale = -0.5 }")]);
    let err = fails(tmp.path(), &["evolve", bad.to_str().unwrap()]);
    assert!(err.contains("[ga]") && err.contains("mutation.drift_scale must be finite and > 0, got -0.5"), "{err}");

    let err = fails(tmp.path(), &["evolve", bad.to_str().unwrap(), "--preset", "fast"]);
    assert!(err.contains("fast") && err.contains("thesis"), "{err}");
}
