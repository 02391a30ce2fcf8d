//! `genform map`: the codon-by-codon view of a GE mapping, checked against
//! the golden traces (crates/genform-ge/tests/data/golden-traces) through
//! the real binary.

mod common;

use common::*;
use serde_json::Value;

fn traces(name: &str) -> Vec<Value> {
    let path = root().join("crates/genform-ge/tests/data/golden-traces").join(format!("{name}.jsonl"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines().map(|l| serde_json::from_str(l).unwrap()).collect()
}

/// The trace fields `genform map --json` prints.
const FIELDS: [&str; 7] = ["valid", "fail", "phenotype", "used_codons", "wraps", "choices", "steps"];

#[test]
fn json_output_reproduces_golden_trace_lines() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["wrap", "invalid"] {
        let bnf = root().join("examples/ge").join(format!("{name}.bnf"));
        // Every fifth line keeps the test short; the library test checks all.
        for line in traces(name).iter().step_by(5) {
            let genome: Vec<String> =
                line["genome"].as_array().unwrap().iter().map(|c| c.as_u64().unwrap().to_string()).collect();
            let mut args = vec!["map".to_string(), s(&bnf).to_string(), "--json".into(), "--genome".into()];
            args.push(genome.join(","));
            args.push("--max-wraps".into());
            args.push(line["max_wraps"].to_string());
            if let Some(d) = line["max_tree_depth"].as_u64() {
                args.push("--max-depth".into());
                args.push(d.to_string());
            }
            let argv: Vec<&str> = args.iter().map(String::as_str).collect();
            let run = genform(dir.path(), &argv).ok();
            let got: Value = serde_json::from_str(run.stdout().trim()).unwrap();
            for f in FIELDS {
                assert_eq!(got[f], line[f], "{name} id {}: field {f}\n{}", line["id"], run.stdout());
            }
        }
    }
}

#[test]
fn text_output_shows_the_worked_example_of_the_paper() {
    let dir = tempfile::tempdir().unwrap();
    let bnf = root().join("examples/ge/genr8.bnf");
    let genome = "212,187,632,832,800,517,338,39,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20";
    let run = genform(dir.path(), &["map", s(&bnf), "--genr8", "--genome", genome]).ok();
    let out = run.stdout();
    let lines: Vec<&str> = out.lines().collect();
    assert!(lines[2].contains("632") && lines[2].ends_with("Edge2"), "{out}");
    assert!(lines[5].contains("517") && lines[5].ends_with("repeat"), "{out}");
    assert!(lines[7].contains("39") && lines[7].ends_with("stop"), "{out}");
    assert!(lines[8].contains("<RewriteRule>"), "{out}");
}

#[test]
fn bad_grammars_and_genomes_are_refused_with_a_position() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.bnf"), "<a> ::= <b> | \"x\"\n").unwrap();
    let run = genform(dir.path(), &["map", "bad.bnf", "--genome", "1,2"]).fails();
    assert!(run.stderr().contains("bad.bnf:1:9"), "{}", run.stderr());
    let bnf = root().join("examples/ge/arith.bnf");
    genform(dir.path(), &["map", s(&bnf), "--genome", "1,x"]).fails();
    // A genome that never terminates is an invalid individual, not a hang.
    let run = genform(dir.path(), &["map", s(&bnf), "--genome", "0", "--max-wraps", "50"]).ok();
    assert!(run.stdout().contains("invalid (wrap_limit)"), "{}", run.stdout());
}

#[test]
fn per_choice_layout_gives_each_nonterminal_its_own_codons() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("g.bnf"), "<s> ::= <a> <b> <a>\n<a> ::= \"x\" | \"y\"\n<b> ::= \"p\" | \"q\"\n")
        .unwrap();
    let map = |layout: &str| {
        let run = genform(dir.path(), &["map", "g.bnf", "--genome", "0,1,1,9,9,0", "--layout", layout, "--json"]).ok();
        serde_json::from_str::<Value>(run.stdout().trim()).unwrap()
    };
    // Sequential: codons 0..3 in order; per choice: <s>, <a>, <b> read
    // codons 0, 1, 2 and the second <a> reads 1 + K = 5 (K = 4 kinds).
    let (seq, per) = (map("sequential"), map("per-choice"));
    assert_eq!(seq["phenotype"], "yqy");
    assert_eq!(per["phenotype"], "yqx");
    let pos = |v: &Value| v["steps"].as_array().unwrap().iter().map(|s| s["pos"].as_u64().unwrap()).collect::<Vec<_>>();
    assert_eq!((pos(&seq), pos(&per)), (vec![0, 1, 2, 3], vec![0, 1, 2, 5]));
    let run = genform(dir.path(), &["map", "g.bnf", "--genome", "1", "--layout", "zigzag"]).fails();
    assert!(run.stderr().contains("per-choice"), "{}", run.stderr());
}
