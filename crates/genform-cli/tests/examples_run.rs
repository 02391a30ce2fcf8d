//! Every shipped grammar runs as it is: `genform sample FILE --out x.png`
//! with no other flag, for each file under `examples/` whose name ends with
//! an extension of the formalism table. Grammars that need settings (a box,
//! a world, a step count) declare them in the file.

mod common;

use common::{genform, root};
use genform_app::ends_with_any;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Grammar files under `dir`, recursively, in a stable order.
fn grammar_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            grammar_files(&path, out);
        } else if genform_app::formalisms().iter().any(|f| f.draws_models() && ends_with_any(&path, f.extensions())) {
            out.push(path);
        }
    }
}

/// Samples `grammar` into a PNG in a fresh folder; the problem if any.
fn sample_png(grammar: &Path) -> Result<(), String> {
    let tmp = tempfile::tempdir().unwrap();
    let run = genform(tmp.path(), &["sample", grammar.to_str().unwrap(), "--out", "x.png"]);
    if !run.out.status.success() {
        return Err(format!("failed\n{}", run.show()));
    }
    let png = std::fs::read(tmp.path().join("x.png")).map_err(|e| format!("wrote no x.png: {e}\n{}", run.show()))?;
    if png.len() <= 8 || !png.starts_with(b"\x89PNG\r\n\x1a\n") {
        return Err(format!("x.png is not a PNG ({} bytes)", png.len()));
    }
    Ok(())
}

/// One example's run: the file, how long it took, and what went wrong.
type Outcome = (PathBuf, Duration, Result<(), String>);

#[test]
fn every_shipped_grammar_samples_a_png_with_no_flags() {
    let mut files = Vec::new();
    grammar_files(&root().join("examples"), &mut files);
    // Each formalism ships examples; a walk that finds none of one is broken.
    for f in genform_app::formalisms().into_iter().filter(|f| f.draws_models()) {
        assert!(files.iter().any(|p| ends_with_any(p, f.extensions())), "no {} under examples/", f.name());
    }
    let queue = Mutex::new(files.clone());
    let results: Mutex<Vec<Outcome>> = Mutex::new(Vec::new());
    // The binary does the work; a few runs at a time keep the test short.
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get()).min(4);
    std::thread::scope(|scope| {
        for _ in 0..threads {
            scope.spawn(|| {
                while let Some(path) = queue.lock().unwrap().pop() {
                    let start = Instant::now();
                    let result = sample_png(&path);
                    results.lock().unwrap().push((path, start.elapsed(), result));
                }
            });
        }
    });
    let mut results = results.into_inner().unwrap();
    results.sort_by_key(|r| std::cmp::Reverse(r.1));
    let base = root();
    let name = |p: &Path| p.strip_prefix(&base).unwrap_or(p).display().to_string();
    // The slowest runs, for whoever wonders why this test takes its time.
    eprintln!("{} examples ran; the slowest:", results.len());
    for (path, took, _) in results.iter().take(5) {
        eprintln!("{:>8.2} s  {}", took.as_secs_f64(), name(path));
    }
    let failures: Vec<String> =
        results.iter().filter_map(|(p, _, r)| r.as_ref().err().map(|e| format!("{}: {e}", name(p)))).collect();
    assert_eq!(results.len(), files.len());
    assert!(
        failures.is_empty(),
        "{} of {} examples do not run as they are:\n{}",
        failures.len(),
        files.len(),
        failures.join("\n\n")
    );
}

#[test]
fn a_declared_box_and_world_are_defaults_the_flags_override() {
    let tmp = tempfile::tempdir().unwrap();
    let bridge = root().join("examples/boxsplit/bridge.bsg");
    let bridge = bridge.to_str().unwrap();
    // The declared world is found relative to the grammar, not the working folder.
    let run = genform(tmp.path(), &["sample", bridge, "--out", "b.schem"]).ok();
    assert!(run.show().contains("in [6, 50, 3]..[62, 65, 5]"), "{}", run.show());
    let run = genform(tmp.path(), &["sample", bridge, "--box", "6,50,3,30,65,5", "--out", "b.schem"]).ok();
    assert!(run.show().contains("in [6, 50, 3]..[30, 65, 5]"), "{}", run.show());
    let run = genform(tmp.path(), &["sample", bridge, "--world", "nowhere/r.0.0.mca", "--out", "b.schem"]).fails();
    assert!(run.stderr().contains("nowhere"), "--world replaces the declared world\n{}", run.show());
}
