//! End-to-end tests of the limits that stop hostile settings cleanly: the
//! memory budget that optimizer sizes, target grids and derivation limits
//! are checked against before anything is allocated (`--max-memory`), run
//! by the real binary under an address-space cap as a user would hit them.

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

mod common;
use common::{Run, fails, ok, s, small_scene, small_ship};

/// Runs `genform args` in `dir` under a 3 GB address-space cap (`ulimit -v`),
/// returning the run and how long it took.
fn capped(dir: &Path, args: &[&str]) -> (Run, Duration) {
    let started = Instant::now();
    let out = Command::new("sh")
        .current_dir(dir)
        .arg("-c")
        .arg("ulimit -v 3000000 && exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_genform"))
        .args(args)
        .output()
        .unwrap();
    (Run { out }, started.elapsed())
}

/// Asserts that `run` failed cleanly (exit 1, no abort, no panic) within
/// 20 s with a refusal naming `at` (`FILE:LINE:COL: [section] key`).
fn refused(run: &Run, took: Duration, at: &str) -> String {
    let err = run.stderr();
    assert_eq!(run.out.status.code(), Some(1), "expected a clean failure\n{}", run.show());
    assert!(!err.contains("panicked") && !err.contains("memory allocation"), "{}", run.show());
    assert!(took < Duration::from_secs(20), "took {took:?}");
    assert!(err.contains(at), "no `{at}` in\n{err}");
    assert!(err.contains("more than the memory budget"), "{err}");
    err
}

#[test]
fn huge_optimizer_sizes_are_refused_before_allocating() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let scene = |name: &str, from: &str, to: &str| {
        let sub = dir.join(name);
        std::fs::create_dir_all(&sub).unwrap();
        small_scene(&sub, "city_skyline.toml", &[(from, to)])
    };
    let cases = [
        (scene("ga", "population = 100\n", "population = 99999999999999999\n"), "ga", "17:14: [ga] population"),
        (scene("ga8", "population = 100\n", "population = 100000000\n"), "ga", "17:14: [ga] population"),
        (scene("mh", "chains = 50\n", "chains = 10000000000\n"), "mh", "29:10: [mh] chains"),
        (scene("smc", "particles = 100\n", "particles = 10000000000\n"), "smc", "35:13: [smc] particles"),
    ];
    for (path, algorithm, at) in &cases {
        let (run, took) = capped(dir, &["evolve", s(path), "--algorithm", algorithm, "--out", "run", "-q"]);
        let err = refused(&run, took, &format!("{}:{at} = ", path.display()));
        assert!(err.contains("lower `"), "{err}");
        assert!(!dir.join("run").exists(), "a refused run left a folder");
    }
    // 10⁸ could fit some machine: the refusal says how to raise the budget.
    let (run, took) = capped(dir, &["evolve", s(&cases[1].0), "--out", "run"]);
    let err = refused(&run, took, "[ga] population = 100000000 needs about 619.9 GiB");
    assert!(err.contains("or raise the budget with --max-memory 620G if the machine has the memory"), "{err}");
    assert!(err.contains("(half of the address-space limit (ulimit -v)"), "{err}");
}

#[test]
fn codon_scenes_grids_and_limits_are_checked_too() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let ge = small_scene(dir, "ge_lsystem_tree.toml", &[("population = 100", "population = 1000000000000")]);
    let (run, took) = capped(dir, &["evolve", s(&ge), "--out", "run"]);
    refused(&run, took, ":36:14: [ge] population = 1000000000000 needs about");

    let grid = small_ship(&dir.join("grid"), &[("voxels = [25, 25, 50]", "voxels = [100000, 100000, 100000]")]);
    let (run, took) = capped(dir, &["evolve", s(&grid), "--out", "run"]);
    refused(&run, took, "[volume] voxels = 1000000000000000 needs about 14.2 PiB");

    let limits = small_ship(&dir.join("limits"), &[("[ga]", "[limits]\ngenes = 100000000000\n\n[ga]")]);
    let (run, took) = capped(dir, &["evolve", s(&limits), "--out", "run"]);
    refused(&run, took, "[limits] genes = 100000000000 needs about 5.8 TiB (100000000000 genes of about 64 B each");
}

#[test]
fn max_memory_sets_the_budget() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let scene = small_ship(&dir.join("ship"), &[]);
    // The small ship's 40 SMC particles of up to 100 genes need about 0.5 MiB.
    let err = fails(dir, &["evolve", s(&scene), "--max-memory", "256K", "--out", "run"]);
    assert!(err.contains("more than the memory budget of 256.0 KiB (--max-memory 256.0 KiB)"), "{err}");
    assert!(err.contains("raise the budget with --max-memory 1G"), "{err}");
    ok(dir, &["evolve", s(&scene), "--max-memory", "64M", "--generations", "1", "--out", "run", "-q"]);
    assert!(dir.join("run/best-genome.json").exists());
    // The flag is global: it may come before the verb, and takes sizes only.
    ok(dir, &["--max-memory", "1G", "evolve", s(&scene), "--generations", "1", "--out", "run2", "-q"]);
    let err = fails(dir, &["evolve", s(&scene), "--max-memory", "lots"]);
    assert!(err.contains("`lots` is not a size such as 512M, 3G or 1.5GB"), "{err}");
}

#[test]
fn sample_limits_past_the_budget_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let koch = common::root().join("examples/graph/koch.gg.yaml");
    let (run, took) = capped(dir, &["sample", s(&koch), "--max-modules", "100000000000", "--out", "k.svg"]);
    let err = run.stderr();
    assert_eq!(run.out.status.code(), Some(1), "{}", run.show());
    assert!(took < Duration::from_secs(20));
    assert!(err.contains("--max-modules 100000000000 lets a derivation grow to about 5.8 TiB"), "{err}");
    assert!(err.contains("lower --max-modules, or raise the budget with --max-memory 5961G"), "{err}");
    ok(dir, &["sample", s(&koch), "--max-modules", "100000000000", "--max-memory", "8T", "--out", "k.svg"]);
}

#[test]
fn limits_set_in_grammar_files_are_checked_against_the_budget_with_their_position() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // A shape grammar whose `limits` would let one derivation take terabytes,
    // with a repeat that would place ten million boxes.
    std::fs::write(dir.join("h.sg"), "limits primitives = 999999999999;\nA { repeat(x, 0.0000001) { box; } }\n")
        .unwrap();
    let (run, took) = capped(dir, &["sample", "h.sg", "--out", "h.glb"]);
    let err = refused(&run, took, "`limits primitives = 999999999999` (h.sg:1:21)");
    assert!(err.contains("lower `primitives` in the grammar's `limits`, or give --max-primitives"), "{err}");
    // A flag overrides the file's limit, and so is what is checked.
    let (run, _) = capped(dir, &["sample", "h.sg", "--max-primitives", "100", "--out", "h.glb"]);
    assert!(run.stderr().contains("primitive") && !run.stderr().contains("memory budget"), "{}", run.show());
    // An L-system's `max_modules:` (it aborted allocating 2 GB before).
    std::fs::write(
        dir.join("h.ls"),
        "name: h\nderivation: 60\nmax_modules: 99999999999\naxiom: F\nproduction:\nF -> FF\n",
    )
    .unwrap();
    let (run, took) = capped(dir, &["sample", "h.ls", "--string-out", "h.txt"]);
    let err = refused(&run, took, "`max_modules: 99999999999` (h.ls:3:14)");
    assert!(err.contains("lower `max_modules:` in the file, or give --max-modules"), "{err}");
    assert!(!dir.join("h.txt").exists());
}

/// A star that grows one random spoke a step while a hexagon pattern,
/// which never matches a tree, is searched first at every step: the
/// searches grow with the graph until the derivation's time guard ends it.
const NEVER_MATCHING_HEXAGON: &str = r#"name: hexsearch
steps: 3000
time_limit: 0.5
host:
  vertices:
    c: {x: 0, y: 0}
    d: {x: 1, y: 0}
  edges:
    - {from: c, to: d}
productions:
  - name: hexagon
    mother:
      vertices: {A: {}, B: {}, C: {}, D: {}, E: {}, F: {}}
      edges: [{from: A, to: B}, {from: B, to: C}, {from: C, to: D}, {from: D, to: E}, {from: E, to: F}, {from: F, to: A}]
    daughter:
      vertices: {A: {}, B: {}, C: {}, D: {}, E: {}, F: {}}
  - name: grow
    priority: 1
    mother:
      vertices: {A: {}}
    daughter:
      vertices:
        A: {}
        N: {x: "A.x + uniform(-5, 5)", y: "A.y + uniform(-5, 5)"}
      edges: [{from: A, to: N}]
"#;

#[test]
fn graph_derivations_stop_at_their_time_limit() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let g = dir.join("hex.gg.yaml");
    std::fs::write(&g, NEVER_MATCHING_HEXAGON).unwrap();
    let info = ok(dir, &["info", s(&g)]).stdout();
    assert!(info.contains("time limit: 0.5 s per derivation"), "{info}");
    let started = Instant::now();
    let err = fails(dir, &["sample", s(&g), "--out", "h.svg"]);
    let took = started.elapsed();
    assert!(err.contains("its time limit of 0.5 s passed at step "), "{err}");
    assert!(err.contains("while matching production `hexagon`; raise `time_limit:`"), "{err}");
    assert!(took < Duration::from_secs(5), "took {took:?}");
    assert!(!dir.join("h.svg").exists());
    // Within its limit the same grammar derives (50 steps take milliseconds).
    ok(dir, &["sample", s(&g), "--steps", "50", "--out", "h.svg"]);
    // The limit is checked like every other key.
    std::fs::write(&g, NEVER_MATCHING_HEXAGON.replace("time_limit: 0.5", "time_limit: -2")).unwrap();
    let err = fails(dir, &["sample", s(&g)]);
    assert!(
        err.contains("hex.gg.yaml:3:13") && err.contains("`time_limit` must be a number of seconds above 0"),
        "{err}"
    );
}

/// `sample --world W --out R.mca` killed with SIGKILL at a spread of
/// moments (with jitter, so runs probe different ones) leaves either no
/// region or the complete one, byte for byte, and no other visible file.
#[test]
fn a_region_killed_mid_write_is_absent_or_complete() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let root = common::root();
    let world = root.join("examples/terrain/prismarine-1.21.1/r.0.0.mca");
    let bridge = root.join("examples/boxsplit/bridge.bsg");
    let args = ["sample", s(&bridge), "--world", s(&world), "--box", "6,50,3,62,65,5", "--seed", "2", "--out"];
    let started = Instant::now();
    ok(dir, &[&args[..], &["whole.mca"]].concat());
    let took = started.elapsed();
    let whole = std::fs::read(dir.join("whole.mca")).unwrap();
    let jitter = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).unwrap().subsec_micros() % 5000;
    let (mut absent, mut complete, mut temporaries) = (0, 0, 0);
    for k in 0..12u32 {
        let run = dir.join(format!("k{k}"));
        std::fs::create_dir(&run).unwrap();
        // From the start to twice the length of an undisturbed run.
        let at = took * k / 6 + Duration::from_micros(u64::from(jitter));
        let mut child = Command::new(env!("CARGO_BIN_EXE_genform"))
            .current_dir(&run)
            .args([&args[..], &["R.mca"]].concat())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(at);
        child.kill().unwrap(); // SIGKILL; an error would mean it had already been reaped
        child.wait().unwrap();
        match std::fs::read(run.join("R.mca")) {
            Ok(bytes) => {
                assert!(bytes == whole, "killed after {at:?}: a region of {} bytes, not the whole one", bytes.len());
                complete += 1;
            }
            Err(_) => absent += 1,
        }
        for entry in std::fs::read_dir(&run).unwrap() {
            let name = entry.unwrap().file_name().to_string_lossy().into_owned();
            assert!(name == "R.mca" || (name.starts_with(".R.mca.") && name.ends_with(".tmp")), "left {name}");
            temporaries += usize::from(name != "R.mca");
        }
    }
    eprintln!(
        "12 kills over {took:?} (jitter {jitter} µs): {absent} left no region, {complete} the complete one, {temporaries} a hidden temporary file"
    );
}
