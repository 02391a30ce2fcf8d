//! Shared helpers of the end-to-end tests: run the real `genform` binary in
//! a folder and print everything it said when an expectation fails.
#![allow(dead_code)]

pub mod server;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").canonicalize().unwrap()
}

pub fn example(name: &str) -> PathBuf {
    root().join("examples/shape").join(name)
}

pub struct Run {
    pub out: Output,
}

impl Run {
    /// Everything the run printed, for assertion messages.
    pub fn show(&self) -> String {
        format!("stdout:\n{}\nstderr:\n{}", self.stdout(), self.stderr())
    }
    pub fn stdout(&self) -> String {
        String::from_utf8_lossy(&self.out.stdout).into_owned()
    }
    pub fn stderr(&self) -> String {
        String::from_utf8_lossy(&self.out.stderr).into_owned()
    }
    pub fn ok(self) -> Self {
        assert!(self.out.status.success(), "genform failed\nstdout:\n{}\nstderr:\n{}", self.stdout(), self.stderr());
        self
    }
    pub fn fails(self) -> Self {
        assert!(
            !self.out.status.success(),
            "genform should have failed\nstdout:\n{}\nstderr:\n{}",
            self.stdout(),
            self.stderr()
        );
        self
    }
}

pub fn genform(dir: &Path, args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_genform")).current_dir(dir).args(args).output().unwrap();
    Run { out }
}

pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs `genform args` in `dir` and asserts it succeeded.
pub fn ok(dir: &Path, args: &[&str]) -> Run {
    let run = genform(dir, args);
    assert!(run.out.status.success(), "genform {args:?} failed\n{}", run.show());
    run
}

/// Runs `genform args` in `dir`, asserts it failed and returns its stderr.
pub fn fails(dir: &Path, args: &[&str]) -> String {
    let run = genform(dir, args);
    assert!(!run.out.status.success(), "genform {args:?} should fail\n{}", run.show());
    run.stderr()
}

/// A shipped scene of `examples/scenes` with `edits` (each `from` must
/// occur), its relative paths made absolute, written into `dir`.
pub fn small_scene(dir: &Path, name: &str, edits: &[(&str, &str)]) -> PathBuf {
    let scenes = root().join("examples/scenes");
    let mut text = std::fs::read_to_string(scenes.join(name)).unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "{name} has no `{from}`");
        text = text.replace(from, to);
    }
    for rel in ["../", "targets/"] {
        text = text.replace(&format!("\"{rel}"), &format!("\"{}/{rel}", scenes.display()));
    }
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// The spaceship scene made small (a 25×25×50 grid, 24 individuals, 6
/// generations, 8 MH chains, 40 SMC particles) with `more` edits after
/// those, written into `dir` (created).
pub fn small_ship(dir: &Path, more: &[(&str, &str)]) -> PathBuf {
    let mut edits = vec![
        ("voxels = [100, 200, 100]", "voxels = [25, 25, 50]"),
        ("population = 150", "population = 24\nelitism = 4"),
        ("initial_length = [50, 50]", "initial_length = [10, 30]"),
        ("generations = 130", "generations = 6"),
        ("chains = 70", "chains = 8"),
        ("particles = 500", "particles = 40"),
    ];
    edits.extend_from_slice(more);
    std::fs::create_dir_all(dir).unwrap();
    small_scene(dir, "spaceship_volume.toml", &edits)
}

/// The JSON file at `path`.
pub fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap_or_else(|_| panic!("{} missing", path.display())))
        .unwrap()
}

/// The fitness `genform score` prints for `genome` in `scene`, with all it printed.
pub fn scored(dir: &Path, scene: &Path, genome: &str) -> (f64, String) {
    let text = ok(dir, &["score", s(scene), "--genome", genome]).stdout();
    let value = text.split_whitespace().nth(1).unwrap().parse().unwrap();
    (value, text)
}

/// Each line of a `stats.csv` without its timing columns (seconds,
/// eval_seconds, reproduction_seconds), so runs can be compared.
pub fn fitness_columns(csv: &str) -> Vec<String> {
    csv.lines()
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            [&c[0..2], &c[3..7], &c[9..]].concat().join(",")
        })
        .collect()
}

/// Whether a process ended as one interrupted by Ctrl-C does: killed by
/// SIGINT (a shell's `$?` is then 130).
pub fn ended_by_sigint(status: &std::process::ExitStatus) -> bool {
    use std::os::unix::process::ExitStatusExt as _;
    status.signal() == Some(2)
}

/// Starts `genform evolve scene` into `dir/run` with a long budget, sends
/// it Ctrl-C after `after`, and asserts that it ends as interrupted, soon.
pub fn interrupt_evolve(dir: &Path, scene: &Path, after: Duration) {
    let child = Command::new(env!("CARGO_BIN_EXE_genform"))
        .current_dir(dir)
        .args(["evolve", s(scene), "--budget", "10m", "--out", "run", "-q"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(after);
    let started = Instant::now();
    assert!(Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap().success());
    let run = Run { out: child.wait_with_output().unwrap() };
    assert!(ended_by_sigint(&run.out.status), "Ctrl-C should end the run as interrupted\n{}", run.show());
    assert!(started.elapsed() < Duration::from_secs(30), "the run must stop soon after Ctrl-C");
}

/// A chart as `charts_svg` lays it out: the image size, each data area
/// (`<rect class="plot">`: `[x, y, w, h]`, x-axis and y-axis ranges) and
/// each legend frame (`<rect class="legend">`: `[x, y, w, h]`).
pub struct ChartLayout {
    pub size: (f64, f64),
    pub plots: Vec<([f64; 4], [f64; 2], [f64; 2])>,
    pub legends: Vec<[f64; 4]>,
}

/// Reads a chart's layout back from its SVG text.
pub fn chart_layout(svg: &str) -> ChartLayout {
    let doc = roxmltree::Document::parse(svg).expect("the chart is well-formed XML");
    let num = |n: roxmltree::Node, a: &str| -> f64 { n.attribute(a).unwrap().parse().unwrap() };
    let pair = |n: roxmltree::Node, a: &str| -> [f64; 2] {
        let v: Vec<f64> = n.attribute(a).unwrap().split(' ').map(|x| x.parse().unwrap()).collect();
        [v[0], v[1]]
    };
    let rect = |n: roxmltree::Node| [num(n, "x"), num(n, "y"), num(n, "width"), num(n, "height")];
    let class =
        |c: &'static str| doc.descendants().filter(move |n| n.has_tag_name("rect") && n.attribute("class") == Some(c));
    let root = doc.root_element();
    ChartLayout {
        size: (num(root, "width"), num(root, "height")),
        plots: class("plot").map(|n| (rect(n), pair(n, "data-x-range"), pair(n, "data-y-range"))).collect(),
        legends: class("legend").map(rect).collect(),
    }
}

/// Asserts that a chart has a legend, and that every legend lies inside
/// the image and off every data area.
pub fn assert_legends_clear(name: &str, svg: &str) -> ChartLayout {
    let layout = chart_layout(svg);
    let (w, h) = layout.size;
    assert!(!layout.plots.is_empty() && !layout.legends.is_empty(), "{name}: no data area or no legend");
    for l in &layout.legends {
        assert!(
            l[0] >= 0.0 && l[1] >= 0.0 && l[0] + l[2] <= w && l[1] + l[3] <= h,
            "{name}: legend {l:?} leaves {w}×{h}"
        );
        for (p, _, _) in &layout.plots {
            let apart = l[0] >= p[0] + p[2] || p[0] >= l[0] + l[2] || l[1] >= p[1] + p[3] || p[1] >= l[1] + l[3];
            assert!(apart, "{name}: legend {l:?} covers the data area {p:?}");
        }
    }
    layout
}
