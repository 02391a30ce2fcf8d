//! End-to-end tests of graph grammars: the real binary on the shipped
//! `examples/graph` grammars.

mod common;

use common::{genform, root, s};
use std::path::PathBuf;

fn gg(name: &str) -> PathBuf {
    root().join("examples/graph").join(format!("{name}.gg.yaml"))
}

#[test]
fn koch_has_the_papers_element_count_and_is_deterministic() {
    let tmp = tempfile::tempdir().unwrap();
    let koch = gg("koch");
    let run = genform(tmp.path(), &["sample", s(&koch), "--seed", "3"]).ok();
    assert!(run.stdout().contains("192 steps, 579 vertices, 579 edges, 1158 elements"), "{}", run.stdout());
    for out in ["a.svg", "b.svg", "a.yaml", "b.yaml", "a.png"] {
        genform(tmp.path(), &["sample", s(&koch), "--seed", "3", "--out", out]).ok();
    }
    let read = |n: &str| std::fs::read(tmp.path().join(n)).unwrap();
    assert_eq!(read("a.svg"), read("b.svg"));
    assert_eq!(read("a.yaml"), read("b.yaml"));
    let svg = String::from_utf8(read("a.svg")).unwrap();
    assert!(svg.contains("cm\""), "1 unit = 1 cm: {}", &svg[..200.min(svg.len())]);
    assert_eq!(&read("a.png")[1..4], b"PNG");
    let run = genform(tmp.path(), &["sample", s(&koch), "--steps", "4"]).ok();
    assert!(run.stdout().contains("4 steps"), "{}", run.stdout());
}

#[test]
fn every_example_derives() {
    let tmp = tempfile::tempdir().unwrap();
    for name in ["koch", "square_pattern", "circle_pattern", "tree", "facade"] {
        let run = genform(tmp.path(), &["sample", s(&gg(name)), "--seed", "1", "--out", "x.svg"]).ok();
        assert!(run.stderr().contains("elements"), "{name}: {}", run.stderr());
    }
    let out = genform(tmp.path(), &["info", s(&gg("facade"))]).ok().stdout();
    assert!(out.contains("productions:"), "{out}");
}

#[test]
fn bad_grammars_name_the_position() {
    let tmp = tempfile::tempdir().unwrap();
    let text = "host:\n  vertices: {a: {x: 0, y: 0}}\n  edges: [{from: a, to: zz}]\nproductions: []\n";
    std::fs::write(tmp.path().join("bad.gg.yaml"), text).unwrap();
    let err = genform(tmp.path(), &["sample", "bad.gg.yaml"]).fails().stderr();
    assert!(err.contains("bad.gg.yaml:3:") && err.contains("zz"), "{err}");
}
