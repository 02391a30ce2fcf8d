//! MAP-Elites end to end: `genform evolve --algorithm map-elites` on a
//! small spaceship scene (its archive files, reproducibility, positioned
//! setting errors). The acceptance test of issue #18 (against the GA at
//! equal evaluations) is genform-app's (`run::tree`).

use std::path::{Path, PathBuf};

mod common;
use common::{fails, json, ok, s, scored, small_scene};

fn ship(dir: &Path, extra: &str) -> PathBuf {
    let scene = small_scene(
        dir,
        "spaceship_volume.toml",
        &[
            ("voxels = [100, 200, 100]", "voxels = [25, 25, 50]"),
            ("population = 150", "population = 24\nelitism = 4"),
            ("initial_length = [50, 50]", "initial_length = [10, 30]"),
        ],
    );
    let text = std::fs::read_to_string(&scene).unwrap();
    std::fs::write(&scene, format!("{text}\n[map_elites]\ninitial = 30\nbatch = 20\n{extra}")).unwrap();
    scene
}

fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read(&p).unwrap()))
        .collect();
    out.sort();
    out
}

#[test]
fn map_elites_writes_its_archive_and_every_run_file() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path(), "");
    let args = ["evolve", s(&scene), "--algorithm", "map-elites", "--evaluations", "400", "--seed", "4", "-q"];
    ok(tmp.path(), &[&args[..], &["--out", "one", "--threads", "1"]].concat());
    let run = tmp.path().join("one");
    for f in ["best.glb", "best.obj", "best.png", "best-genome.json", "stats.csv", "gallery.png", "run.json"] {
        assert!(run.join(f).exists(), "{f} missing");
    }
    assert_eq!(json(&run.join("run.json"))["algorithm"], "map-elites");
    let csv = std::fs::read_to_string(run.join("archive.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], "column,row,length,aspect,fitness,genes");
    let elites = files(&run.join("elites"));
    assert_eq!(elites.len(), lines.len() - 1, "one genome per archive line");
    assert!(elites.len() > 5, "the archive spreads over cells:\n{csv}");
    let png = std::fs::read(run.join("archive.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG"));
    // Each elite's genome replays to the fitness the archive lists, and the
    // best line is best-genome.json's.
    let best: f64 = json(&run.join("run.json"))["best_fitness"].as_f64().unwrap();
    let mut top = f64::NEG_INFINITY;
    for line in &lines[1..4] {
        let cols: Vec<&str> = line.split(',').collect();
        let genome = format!("one/elites/cell-{}-{}.json", cols[0], cols[1]);
        let (fitness, text) = scored(tmp.path(), &scene, &genome);
        assert_eq!(fitness, cols[4].parse::<f64>().unwrap(), "{genome}: {text}");
    }
    for line in &lines[1..] {
        top = top.max(line.split(',').nth(4).unwrap().parse().unwrap());
    }
    assert_eq!(top, best);
    // Byte-identical archive at another thread count.
    ok(tmp.path(), &[&args[..], &["--out", "three", "--threads", "3"]].concat());
    let three = tmp.path().join("three");
    assert_eq!(csv, std::fs::read_to_string(three.join("archive.csv")).unwrap());
    assert_eq!(elites, files(&three.join("elites")));
    assert_eq!(png, std::fs::read(three.join("archive.png")).unwrap());
    assert_eq!(std::fs::read(run.join("gallery.png")).unwrap(), std::fs::read(three.join("gallery.png")).unwrap());
}

#[test]
fn bad_map_elites_settings_name_file_line_and_column() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path(), "descriptors = [{ name = \"lenght\" }, { name = \"aspect\" }]\n");
    let err = fails(tmp.path(), &["evolve", s(&scene), "--algorithm", "map-elites", "--evaluations", "100"]);
    let line = std::fs::read_to_string(&scene).unwrap().lines().position(|l| l.contains("lenght")).unwrap() + 1;
    assert!(
        err.contains(&format!("spaceship_volume.toml:{line}:25: [map_elites] descriptor `lenght` is unknown")),
        "{err}"
    );
    assert!(err.contains("did you mean `length`?"), "{err}");
    let scene = ship(tmp.path(), "descriptors = [{ name = \"length\", bins = 0 }, { name = \"aspect\" }]\n");
    let err = fails(tmp.path(), &["evolve", s(&scene), "--evaluations", "100"]);
    assert!(err.contains(&format!("spaceship_volume.toml:{line}:42: bins must be in [1, 256], got 0")), "{err}");
}

#[test]
fn compare_races_map_elites() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path(), "");
    let args = ["compare", s(&scene), "--algorithms", "ga,map-elites", "--budget", "300ms", "--out", "cmp", "-q"];
    ok(tmp.path(), &args);
    assert!(tmp.path().join("cmp/best-map-elites-genome.json").exists());
}
