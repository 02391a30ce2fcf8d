//! End-to-end tests of how the binary reports bad input files: each
//! diagnostic has exactly one `Error:` header (ariadne's), the summary one
//! `error:` prefix, and a file that is not UTF-8 names the line, column and
//! byte, whatever kind of file it is.

mod common;

use common::{fails, root, s};
use std::path::Path;

/// Lines of `stderr` that start with an error prefix of either spelling.
fn error_lines(stderr: &str) -> Vec<&str> {
    stderr.lines().filter(|l| l.trim_start().to_lowercase().starts_with("error")).collect()
}

#[test]
fn each_diagnostic_has_one_error_prefix() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("bad.sg"), "Start {\n    boxx;\n    translate(1, 2;\n}\n").unwrap();
    let err = fails(dir, &["info", "bad.sg"]);
    assert!(!err.contains("error: Error"), "{err}");
    assert_eq!(
        error_lines(&err),
        [
            "Error: unknown operation or rule `boxx` (bad.sg:2:5)",
            "Error: expected `)` to close the arguments of `translate`, found `;` (bad.sg:3:19)",
            "error: 2 errors in bad.sg",
        ],
        "{err}"
    );
    // The same for another formalism.
    std::fs::write(dir.join("bad.gr8"), "Edge0 + Edge0 + Edge0\nEdge0 -> Edge0 [ + Edge0\nAngle 60\n").unwrap();
    let err = fails(dir, &["info", "bad.gr8"]);
    let lines = error_lines(&err);
    assert_eq!(lines.len(), 2, "one header per diagnostic and one summary: {err}");
    assert!(lines[0].starts_with("Error: ") && lines[0].contains("bad.gr8:2:16"), "{err}");
    assert_eq!(lines[1], "error: 1 error in bad.gr8", "{err}");
}

#[test]
fn warnings_and_errors_look_alike() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // An unreachable rule is a warning; the grammar still samples.
    std::fs::write(dir.join("warn.sg"), "Start { box; }\nOrphan { box; }\n").unwrap();
    let run = common::ok(dir, &["info", "warn.sg"]);
    let err = run.stderr();
    assert!(err.lines().any(|l| l.starts_with("Warning: rule `Orphan` is unreachable")), "{err}");
    assert!(!err.contains("warning: Warning"), "{err}");
}

#[test]
fn an_unterminated_rule_reports_only_the_real_error() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("open.sg"), "axiom Start;\n\nStart {\n    box;\n    Leaf;\n\nLeaf {\n    box;\n}\n")
        .unwrap();
    let err = fails(dir, &["info", "open.sg"]);
    assert!(!err.contains("unknown rule"), "no cascade: {err}");
    let lines = error_lines(&err);
    assert_eq!(lines.len(), 3, "{err}");
    assert!(lines[0].contains("expected `;` after the statement, found `{` (open.sg:7:6)"), "{err}");
    assert!(lines[1].contains("expected `}` to close the block, found the end of the file"), "{err}");
    assert!(err.contains("the body of rule `Start` starts here"), "{err}");
    assert_eq!(lines[2], "error: 2 errors in open.sg", "{err}");
}

/// Writes `bytes` to `dir/name` and returns the one `error:` line of
/// running `args` on it.
fn utf8_error(dir: &Path, name: &str, bytes: &[u8], args: &[&str]) -> String {
    std::fs::write(dir.join(name), bytes).unwrap();
    let err = fails(dir, args);
    let lines = error_lines(&err);
    assert_eq!(lines.len(), 1, "{err}");
    lines[0].to_string()
}

#[test]
fn invalid_utf8_names_line_column_and_byte_in_every_kind_of_file() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // Latin-1 'é' (0xe9) where UTF-8 was expected: line 2, after "    b".
    let sg = b"Start {\n    b\xe9x;\n}\n";
    assert_eq!(
        utf8_error(dir, "latin.sg", sg, &["info", "latin.sg"]),
        "error: latin.sg:2:6: not valid UTF-8 (byte 0xe9 at byte offset 13)"
    );
    let gr8 = b"Edge0 + Edge0 + Edge0\nEdge0 -> Edge0 + Edge0 \xff\nAngle 60\n";
    assert_eq!(
        utf8_error(dir, "latin.gr8", gr8, &["info", "latin.gr8"]),
        "error: latin.gr8:2:24: not valid UTF-8 (byte 0xff at byte offset 45)"
    );
    let bnf = b"<e> ::= \"x\" | \"\xe9\"\n";
    assert_eq!(
        utf8_error(dir, "latin.bnf", bnf, &["map", "latin.bnf", "--genome", "1,2"]),
        "error: latin.bnf:1:16: not valid UTF-8 (byte 0xe9 at byte offset 15)"
    );
    let t4 = root().join("examples/hemls/tiles4.gr8");
    let env = b"steps = 3\n# caf\xe9\n";
    assert_eq!(
        utf8_error(dir, "env.toml", env, &["sample", s(&t4), "--env", "env.toml", "--out", "x.obj"]),
        "error: env.toml:2:6: not valid UTF-8 (byte 0xe9 at byte offset 15)"
    );
    let scene = b"grammar = \"g.sg\"\n\xc3\xa9\xc3\n";
    assert_eq!(
        utf8_error(dir, "scene.toml", scene, &["score", "scene.toml", "--genome", "g.json"]),
        "error: scene.toml:2:2: not valid UTF-8 (byte 0xc3 at byte offset 19)"
    );
}
