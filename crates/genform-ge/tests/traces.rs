//! The standard mapper against the golden GE traces of
//! `tests/data/golden-traces` (finchge 1.0.1b16 cross-checked with an
//! independent mapper; see SOURCE.md there): every line of every `.jsonl` must come out equal,
//! field by field, including each step's non-terminal, position, codon,
//! modulus, choice and depth.

use genform_core::SourceFile;
use genform_ge::{MapOptions, Mapper};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn reference_dir() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/golden-traces")).to_path_buf()
}

/// Maps every genome of `name.jsonl` over `name.bnf`; returns the number of
/// lines checked, or every mismatch.
fn check(name: &str) -> usize {
    let dir = reference_dir();
    let read = |file: &str| {
        let path = dir.join(file);
        std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    };
    let bnf = match genform_ge::compile(&SourceFile::new(format!("{name}.bnf"), read(&format!("{name}.bnf")))) {
        Ok((bnf, warnings)) => {
            assert!(warnings.items.is_empty(), "{}", warnings.short());
            bnf
        }
        Err(e) => panic!("{}", e.short()),
    };
    // The copy shipped to users must be the same grammar.
    let shipped = std::fs::read_to_string(format!("{}/../../examples/ge/{name}.bnf", env!("CARGO_MANIFEST_DIR")))
        .expect("examples/ge copy");
    assert_eq!(shipped, read(&format!("{name}.bnf")), "examples/ge/{name}.bnf differs from the reference");

    let mut failures = Vec::new();
    let mut lines = 0;
    for (i, line) in read(&format!("{name}.jsonl")).lines().enumerate() {
        let mut expected: Value = serde_json::from_str(line).expect("json line");
        let obj = expected.as_object_mut().expect("object");
        let genome: Vec<u32> = serde_json::from_value(obj.remove("genome").expect("genome")).expect("codons");
        let max_wraps = obj.remove("max_wraps").and_then(|v| v.as_u64()).expect("max_wraps") as u32;
        let depth = obj.remove("max_tree_depth").expect("max_tree_depth").as_u64().map(|d| d as u32);
        let id = obj.remove("id").and_then(|v| v.as_u64()).expect("id");
        assert_eq!(id, i as u64);
        let mut mapper = Mapper::new(&bnf, MapOptions::standard(max_wraps, depth)).expect("options");
        let got = serde_json::to_value(mapper.trace(&genome)).expect("serialize");
        if got != expected {
            failures.push(format!("{name}.jsonl line {}:\n  expected {expected}\n  got      {got}", i + 1));
        }
        // The fast path agrees with the trace.
        let quick = mapper.map(&genome);
        assert_eq!(Some(quick.valid()), expected["valid"].as_bool(), "{name} line {}", i + 1);
        assert_eq!(Some(quick.used_codons as u64), expected["used_codons"].as_u64());
        assert_eq!(mapper.phenotype(), expected["phenotype"].as_str());
        lines += 1;
    }
    assert!(failures.is_empty(), "{} of {lines} lines differ:\n{}", failures.len(), failures.join("\n"));
    lines
}

#[test]
fn arith_trace_is_reproduced_line_by_line() {
    assert_eq!(check("arith"), 50);
}

#[test]
fn wrap_trace_is_reproduced_line_by_line() {
    assert_eq!(check("wrap"), 50);
}

#[test]
fn invalid_trace_is_reproduced_line_by_line() {
    assert_eq!(check("invalid"), 50);
}

#[test]
fn lsys_trace_is_reproduced_line_by_line() {
    assert_eq!(check("lsys"), 50);
}
