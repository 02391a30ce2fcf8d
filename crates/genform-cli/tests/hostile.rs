//! The hostile-input suite: what a careless user or a hostile script can
//! hand the real binary, class by class — outputs over inputs (by identity,
//! through other spellings and links), region files under another region's
//! name, impossible settings at their positions, runaway mappings, and
//! Ctrl-C as shells expect. Each case must end in a clear refusal (or, for
//! Ctrl-C, the process killed by SIGINT with every result written) and
//! leave every input as it was. The studio's cases (roots, planted links,
//! one memory budget) are in `hostile_studio.rs` and `hostile_budget.rs`.

mod common;

use common::{fails, genform, json, ok, root, s, small_ship};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// The bytes of every file below `dir`, to show that a refused command
/// changed none.
fn snapshot(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut all = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else {
                all.push((p.clone(), std::fs::read(&p).unwrap()));
            }
        }
    }
    all.sort();
    all
}

/// A copy of `examples/shape` in `dir` (grammars with their meshes).
fn shapes(dir: &Path) -> PathBuf {
    let to = dir.join("shape");
    copy_dir(&root().join("examples/shape"), &to);
    to
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap().flatten() {
        let target = to.join(e.file_name());
        if e.path().is_dir() {
            copy_dir(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), target).unwrap();
        }
    }
}

#[test]
fn sample_never_replaces_a_file_the_grammar_reads() {
    let tmp = tempfile::tempdir().unwrap();
    let shape = shapes(tmp.path());
    let before = snapshot(&shape);
    let d = tmp.path();
    // The grammar's own mesh asset, spelled three ways and through a link.
    std::os::unix::fs::symlink(shape.join("assets/trunk.obj"), d.join("link.obj")).unwrap();
    for out in ["shape/assets/trunk.obj", "shape/assets/../assets/trunk.obj", "./shape/assets/trunk.obj", "link.obj"] {
        let e = fails(d, &["sample", "shape/tree_v1.sg", "--out", out]);
        assert!(e.contains(&format!("--out {out} is the mesh")) && e.contains("an input of this command"), "{e}");
    }
    // The context mesh of a grammar, from the grammar's own folder.
    let e = fails(&shape, &["sample", "infill.sg", "--out", "infill_neighbours.obj"]);
    assert!(e.contains("is the mesh infill_neighbours.obj"), "{e}");
    // The grammar itself, through any output flag.
    let e = fails(d, &["sample", "shape/spaceship.sg", "--genome-out", "shape/spaceship.sg"]);
    assert!(e.contains("--genome-out shape/spaceship.sg is the grammar"), "{e}");
    let koch = shape.join("koch.ls");
    std::fs::copy(root().join("examples/lsystem/koch_snowflake.ls"), &koch).unwrap();
    let e = fails(d, &["sample", "shape/koch.ls", "--string-out", "shape/../shape/koch.ls"]);
    assert!(e.contains("is the grammar shape/koch.ls"), "{e}");
    std::fs::remove_file(koch).unwrap();
    assert!(snapshot(&shape) == before, "a refused command changed an input");
}

#[test]
fn an_environments_boundary_mesh_is_not_replaced() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    std::fs::copy(root().join("examples/shape/assets/trunk.obj"), d.join("walls.obj")).unwrap();
    std::fs::write(d.join("env.toml"), "steps = 2\n\n[[boundary]]\nmesh = \"walls.obj\"\n").unwrap();
    let walls = std::fs::read(d.join("walls.obj")).unwrap();
    let tiles = root().join("examples/hemls/tiles4.gr8");
    let e = fails(d, &["sample", s(&tiles), "--env", "env.toml", "--out", "walls.obj"]);
    assert!(e.contains("would replace the mesh walls.obj"), "{e}");
    assert_eq!(std::fs::read(d.join("walls.obj")).unwrap(), walls);
    // A missing boundary mesh is named at the line that names it.
    std::fs::write(d.join("gone.toml"), "steps = 2\n\n[[boundary]]\nmesh = \"gone.obj\"\n").unwrap();
    let e = fails(d, &["sample", s(&tiles), "--env", "gone.toml", "--out", "m.obj"]);
    assert!(e.contains("gone.toml:4:8: boundary 1 (mesh `gone.obj`)"), "{e}");
    // A scale that would overflow every coordinate is refused where it is written.
    std::fs::write(d.join("huge.toml"), "steps = 2\nscale = 1e308\n").unwrap();
    let e = fails(d, &["sample", s(&tiles), "--env", "huge.toml", "--out", "m.obj"]);
    assert!(e.contains("huge.toml:2:9") && e.contains("`scale` must lie from 0.01 to 10"), "{e}");
}

#[test]
fn a_run_never_replaces_its_target_or_the_log_it_replays() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let scene = small_ship(d, &[]);
    // The scene's target where the run would write best.obj.
    std::fs::create_dir_all(d.join("D")).unwrap();
    std::fs::copy(root().join("examples/scenes/targets/spaceship_target.obj"), d.join("D/best.obj")).unwrap();
    let text = std::fs::read_to_string(&scene).unwrap();
    let target = root().join("examples/scenes/targets/spaceship_target.obj");
    std::fs::write(&scene, text.replace(s(&target), "D/best.obj")).unwrap();
    let before = snapshot(&d.join("D"));
    let e = fails(d, &["evolve", s(&scene), "--out", "D", "--generations", "1", "-q"]);
    assert!(e.contains("--out D would replace its best.obj, which is the mesh"), "{e}");
    assert!(snapshot(&d.join("D")) == before, "nothing is written into D");
    // A finished run's log replayed into its own folder.
    let scene = small_ship(&d.join("other"), &[]);
    ok(d, &["evolve", s(&scene), "--out", "R", "--generations", "2", "-q"]);
    let before = snapshot(&d.join("R"));
    let e = fails(d, &["evolve", s(&scene), "--steering", "R/run.json", "--out", "R", "--generations", "2", "-q"]);
    assert!(e.contains("would replace its run.json, which is the steering log"), "{e}");
    assert!(snapshot(&d.join("R")) == before);
}

#[test]
fn a_region_file_is_written_only_under_its_own_name() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    std::fs::create_dir_all(d.join("w")).unwrap();
    std::fs::copy(root().join("examples/terrain/prismarine-1.21.1/r.0.0.mca"), d.join("w/r.0.0.mca")).unwrap();
    let bridge = root().join("examples/boxsplit/bridge.bsg");
    let args = ["sample", s(&bridge), "--world", "w/r.0.0.mca", "--box", "6,50,3,62,65,5", "--out"];
    let e = fails(d, &[&args[..], &["w/r.5.5.mca"]].concat());
    assert!(e.contains("names region 5,5, but the box lies in region 0,0") && e.contains("r.0.0.mca"), "{e}");
    assert!(!d.join("w/r.5.5.mca").exists());
    // The observed region itself, by another spelling.
    let e = fails(d, &[&args[..], &["./w/r.0.0.mca"]].concat());
    assert!(e.contains("input of this command") || e.contains("observed region itself"), "{e}");
    // A new file in the world's folder replaces nothing.
    ok(d, &["sample", s(&bridge), "--world", "w", "--box", "6,50,3,62,65,5", "--out", "w/copy.schem"]);
    // Another name is written, with a word on how Minecraft reads it.
    let run = ok(d, &[&args[..], &["copy.mca"]].concat());
    assert!(run.stderr().contains("copy it into a world as r.0.0.mca"), "{}", run.show());
}

#[test]
fn impossible_settings_are_refused_at_their_positions() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    // (edit of the small spaceship scene, where the refused value is (`^`
    // marks it), message)
    let cases: [(&str, &str, &str, &str); 6] = [
        ("generations = 6", "evaluations = 0", "evaluations = ^0", "[run] evaluations must be at least 1"),
        (
            "generations = 6",
            "generations = 18446744073709551615",
            "generations = ^1844",
            "18446744073709551615 is beyond TOML's integers",
        ),
        ("alter = 10, grow = 45, cut = 45", "alter = 0, grow = 0, cut = 0", "mutation = ^{", "not all 0"),
        ("particles = 40", "particles = 1", "particles = ^1", "[smc] particles must be at least 2, got 1"),
        ("bad = 15.0", "bad = -1e308", "bad = ^-1e308", "[fitness] `bad` = -1e308 is past ±1e9"),
        (
            "selection = { first = { tournament = 10 }",
            "selection = { first = { tournament = 1000000 }",
            "first = ^{ tournament",
            "tournament size 1000000 in selection.first is larger than the population (24)",
        ),
    ];
    for (k, (from, to, marked, message)) in cases.into_iter().enumerate() {
        let scene = small_ship(&d.join(k.to_string()), &[(from, to)]);
        let text = std::fs::read_to_string(&scene).unwrap();
        let caret = marked.find('^').unwrap();
        let at = text.find(&marked.replace('^', "")).unwrap() + caret;
        let line = text[..at].matches('\n').count() + 1;
        let col = at - text[..at].rfind('\n').map_or(0, |i| i + 1) + 1;
        let e = fails(d, &["evolve", s(&scene), "--out", "never", "-q"]);
        let want = format!("{}:{line}:{col}: ", scene.display());
        assert!(e.contains(&want) && e.contains(message), "case {k}: want `{want}…{message}`, got {e}");
        assert!(!d.join("never").exists(), "case {k}: nothing ran");
    }
    // Patches and flags are refused as the file is, naming themselves.
    let scene = small_ship(&d.join("p"), &[]);
    let e = fails(d, &["evolve", s(&scene), "--set", "run.evaluations=0", "-q"]);
    assert!(e.contains("--set run.evaluations=0: [run] evaluations must be at least 1"), "{e}");
    let e = fails(d, &["evolve", s(&scene), "--generations", "2000000000", "-q"]);
    assert!(e.contains("--generations = 2000000000 is past the cap"), "{e}");
    let e = fails(d, &["compare", s(&scene), "--runs", "18446744073709551615", "--out", "c"]);
    assert!(e.contains("--runs = 18446744073709551615 is past the cap of 10,000"), "{e}");
    let e = fails(d, &["sweep", s(&scene), "--set", "ga.population=10,20", "--runs", "0"]);
    assert!(e.contains("--runs must be at least 1"), "{e}");
}

#[test]
fn a_runaway_mapping_stops_at_the_memory_budget_instead_of_aborting() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    std::fs::write(d.join("double.bnf"), "<s> ::= <s><s> | \"x\"\n").unwrap();
    let run = genform(d, &["map", "double.bnf", "--genome", "0,0", "--max-wraps", "1000000000"]).fails();
    assert_eq!(run.out.status.code(), Some(1), "a refusal, not an abort\n{}", run.show());
    assert!(run.stderr().contains("--max-wraps 1000000000 lets a derivation grow to about"), "{}", run.show());
    let small = ok(d, &["map", "double.bnf", "--genome", "0,0", "--max-wraps", "100"]);
    assert!(small.stdout().contains("invalid (wrap_limit): 202 codons read, 100 wraps"), "{}", small.show());
}

/// One Ctrl-C: the results are written, then the process dies of SIGINT,
/// so a `set -e` script stops instead of carrying on as after a success.
#[test]
fn ctrl_c_writes_the_results_and_stops_a_set_e_script() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let scene = small_ship(d, &[("generations = 6", "generations = 1000000")]);
    let script =
        format!("set -e\n'{}' evolve '{}' --out run -q\necho carried-on\n", env!("CARGO_BIN_EXE_genform"), s(&scene));
    let mut shell = std::process::Command::new("bash")
        .current_dir(d)
        .args(["-c", &script])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Wait for the first results, then interrupt genform (not the shell).
    let stats = d.join("run/stats.csv");
    let start = std::time::Instant::now();
    while !stats.exists() && start.elapsed() < Duration::from_secs(60) {
        std::thread::sleep(Duration::from_millis(100));
    }
    // The shell's child is genform (pkill -P: only this test's process).
    let pkill = std::process::Command::new("pkill").args(["-INT", "-P", &shell.id().to_string()]).status().unwrap();
    assert!(pkill.success());
    let out = shell.wait_with_output_or_kill();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(!stdout.contains("carried-on"), "the script went on after Ctrl-C");
    assert_eq!(out.status.code(), Some(130), "the shell reports 130: {:?}", out.status);
    assert_eq!(json(&d.join("run/run.json"))["stopped_by"], "interrupted");
    assert!(d.join("run/best-genome.json").exists() && d.join("run/fitness.svg").exists());
}

trait WaitOrKill {
    fn wait_with_output_or_kill(&mut self) -> std::process::Output;
}

impl WaitOrKill for std::process::Child {
    /// The child's output, killing it after a minute (a hung test must not
    /// hang the suite).
    fn wait_with_output_or_kill(&mut self) -> std::process::Output {
        let start = std::time::Instant::now();
        while self.try_wait().unwrap().is_none() {
            if start.elapsed() > Duration::from_secs(60) {
                let _ = self.kill();
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        let mut stdout = Vec::new();
        let mut stderr = Vec::new();
        use std::io::Read as _;
        self.stdout.take().unwrap().read_to_end(&mut stdout).unwrap();
        self.stderr.take().unwrap().read_to_end(&mut stderr).unwrap();
        std::process::Output { status: self.wait().unwrap(), stdout, stderr }
    }
}
